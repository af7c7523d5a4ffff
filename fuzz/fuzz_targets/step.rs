//! The whole step on small random meshes: random (possibly out-of-range) indices, coordinates
//! that mix ordinary values with NaN, infinities, huge, tiny and subnormal numbers, repeated
//! points, degenerate and repeated triangles, and edges shared by many triangles.
//!
//! `Step::new` must refuse the invalid ones with an error; for a valid step, the BVH, the
//! cluster method and the brute-force oracle must report the same contacts, every time of
//! impact must be finite and in `[0, t_max]`, and `Mode::Earliest` must find the earliest
//! contact of `Mode::All`. Under a small iteration limit (which the target also draws, for
//! speed and because the limit is itself an answer to check) an unresolved pair is reported
//! as a contact, so the checks weaken to what still holds: BVH equals brute force, the cluster
//! method reports a subset of brute force's contacts (it skips certified pairs without
//! solving them), and Earliest names one of All's contacts.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use topoccd::kdop::DopKind;
use topoccd::math::DVec3;
use topoccd::step::{Ccd, Contact, Method, Mode, QueryOptions, Report, Step};

const MAX_VERTICES: usize = 40;
const MAX_TRIANGLES: usize = 60;

/// One coordinate.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Value {
    /// A coarse grid, so that points coincide and features are coplanar often.
    Grid(i8),
    /// A fine grid.
    Fine(i16),
    Zero,
    NegZero,
    Nan,
    Inf,
    NegInf,
    Huge(bool),
    Tiny(bool),
    /// A subnormal number.
    Subnormal(u16),
    /// Any bit pattern at all.
    Bits(u64),
}

impl Value {
    fn get(self) -> f64 {
        match self {
            Value::Grid(i) => f64::from(i) * 0.25,
            Value::Fine(i) => f64::from(i) / 4096.0,
            Value::Zero => 0.0,
            Value::NegZero => -0.0,
            Value::Nan => f64::NAN,
            Value::Inf => f64::INFINITY,
            Value::NegInf => f64::NEG_INFINITY,
            Value::Huge(neg) => sign(neg) * 1e300,
            Value::Tiny(neg) => sign(neg) * 1e-300,
            Value::Subnormal(m) => f64::from_bits(u64::from(m) + 1),
            Value::Bits(b) => f64::from_bits(b),
        }
    }
}

fn sign(neg: bool) -> f64 {
    if neg {
        -1.0
    } else {
        1.0
    }
}

/// One point.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Point {
    New([Value; 3]),
    /// The same as an earlier point (index taken modulo the points so far).
    Repeat(u8),
    /// An earlier point moved by a small grid offset.
    Near(u8, [i8; 3]),
}

fn points(spec: &[Point], base: &[DVec3]) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::with_capacity(spec.len());
    for p in spec {
        let pool = if out.is_empty() { base } else { &out[..] };
        let earlier = |i: u8| pool.get(usize::from(i) % pool.len().max(1)).copied();
        let q = match *p {
            Point::New(v) => DVec3::new(v[0].get(), v[1].get(), v[2].get()),
            Point::Repeat(i) => earlier(i).unwrap_or(DVec3::ZERO),
            Point::Near(i, d) => {
                earlier(i).unwrap_or(DVec3::ZERO)
                    + DVec3::new(d[0].into(), d[1].into(), d[2].into()) / 64.0
            }
        };
        out.push(q);
    }
    out
}

/// How the vertices move.
#[derive(Arbitrary, Debug)]
enum Motion {
    Still,
    Translate([Value; 3]),
    /// Each vertex moves by its own displacement (cycled if fewer than the vertices).
    Displace(Vec<[i8; 3]>),
    /// Independent end positions (possibly fewer or more than at t=0).
    Free(Vec<Point>),
}

/// Triangles, as written by a simulator that may be broken.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Triangles {
    /// Any indices, possibly out of range or repeated within the triangle.
    Raw([u8; 3]),
    /// Indices reduced modulo the vertex count.
    InRange([u8; 3]),
    /// A copy of an earlier triangle (maybe reordered).
    Repeat(u8, bool),
    /// `count` triangles sharing the edge `(a, b)`: a non-manifold fan.
    Fan(u8, u8, u8),
}

#[derive(Arbitrary, Debug)]
struct Input {
    x0: Vec<Point>,
    motion: Motion,
    triangles: Vec<Triangles>,
    min_separation: u8,
    t_max: u8,
    kdop: u8,
    iterations: u8,
}

fn triangles(spec: &[Triangles], n: usize) -> Vec<[u32; 3]> {
    let m = n.max(1) as u32;
    let mut out: Vec<[u32; 3]> = Vec::new();
    for t in spec {
        match *t {
            Triangles::Raw(i) => out.push(i.map(u32::from)),
            Triangles::InRange(i) => out.push(i.map(|i| u32::from(i) % m)),
            Triangles::Repeat(i, flip) => {
                if let Some(&[a, b, c]) = out.get(usize::from(i) % out.len().max(1)) {
                    out.push(if flip { [b, a, c] } else { [a, b, c] });
                }
            }
            Triangles::Fan(a, b, count) => {
                let (a, b) = (u32::from(a) % m, u32::from(b) % m);
                for c in 0..u32::from(count % 12) {
                    out.push([a, b, c % m]);
                }
            }
        }
        if out.len() >= MAX_TRIANGLES {
            out.truncate(MAX_TRIANGLES);
            break;
        }
    }
    out
}

fn check_report(report: &Report, t_max: f64, what: &str) {
    let tois = report
        .vf
        .iter()
        .map(|c| c.toi)
        .chain(report.ee.iter().map(|c| c.toi));
    for toi in tois.chain(report.earliest_toi()) {
        assert!(
            toi.is_finite() && (0.0..=t_max).contains(&toi),
            "{what}: toi {toi}"
        );
    }
}

fuzz_target!(|input: Input| {
    let x0 = points(&input.x0[..input.x0.len().min(MAX_VERTICES)], &[]);
    let x1 = match &input.motion {
        Motion::Still => x0.clone(),
        Motion::Translate(d) => {
            let d = DVec3::new(d[0].get(), d[1].get(), d[2].get());
            x0.iter().map(|p| *p + d).collect()
        }
        Motion::Displace(d) if d.is_empty() => x0.clone(),
        Motion::Displace(d) => x0
            .iter()
            .zip(d.iter().cycle())
            .map(|(p, d)| *p + DVec3::new(d[0].into(), d[1].into(), d[2].into()) / 16.0)
            .collect(),
        Motion::Free(spec) => points(&spec[..spec.len().min(MAX_VERTICES + 1)], &x0),
    };
    let tris = triangles(&input.triangles, x0.len());
    let Ok(step) = Step::new(x0, x1, tris) else {
        return;
    };

    let mut options = QueryOptions::default();
    options.narrow.min_separation = [0.0, 1e-6, 1e-3, 0.1][usize::from(input.min_separation % 4)];
    options.narrow.t_max = [1.0, 0.5, 1e-3, f64::MIN_POSITIVE][usize::from(input.t_max % 4)];
    // Few iterations keep the fuzzer fast; the iteration limit is itself an answer to check.
    // At the default limit Earliest must name exactly the earliest contact of All.
    let default_iterations = options.narrow.max_iterations;
    options.narrow.max_iterations =
        [1, 64, 4096, default_iterations][usize::from(input.iterations % 4)];
    let exact = options.narrow.max_iterations == default_iterations;
    options.kdop =
        [DopKind::K6, DopKind::K14, DopKind::K18, DopKind::K26][usize::from(input.kdop % 4)];
    let t_max = options.narrow.t_max;

    let mut ccd = Ccd::new();
    let brute = ccd.query(&step, Method::Brute, &options);
    check_report(&brute, t_max, "brute");
    let bvh = ccd.query(&step, Method::Bvh, &options);
    assert!(ccd.validate_tree().is_ok(), "invalid bvh");
    check_report(&bvh, t_max, "bvh");
    assert_eq!(bvh.vf, brute.vf, "vf differs between bvh and brute");
    assert_eq!(bvh.ee, brute.ee, "ee differs between bvh and brute");
    assert_eq!(bvh.earliest, brute.earliest);
    let cluster = ccd.query(&step, Method::Cluster, &options);
    assert!(ccd.validate_tree().is_ok(), "invalid cluster tree");
    check_report(&cluster, t_max, "cluster");
    if exact {
        assert_eq!(cluster.vf, brute.vf, "vf differs between cluster and brute");
        assert_eq!(cluster.ee, brute.ee, "ee differs between cluster and brute");
        assert_eq!(cluster.earliest, brute.earliest);
    } else {
        // Under a small iteration limit brute force may report a pair it could not resolve,
        // which the cluster method skips as proved free of contact by its certificate: the
        // cluster method reports a subset of brute force's contacts, with the same times.
        assert!(
            cluster.vf.iter().all(|c| brute.vf.contains(c)),
            "cluster vf not in brute"
        );
        assert!(
            cluster.ee.iter().all(|c| brute.ee.contains(c)),
            "cluster ee not in brute"
        );
        let toi = |r: &Report| r.earliest_toi().unwrap_or(f64::INFINITY);
        assert!(toi(&cluster) >= toi(&brute));
    }

    options.mode = Mode::Earliest;
    for (method, all) in [
        (Method::Bvh, &bvh),
        (Method::Brute, &brute),
        (Method::Cluster, &cluster),
    ] {
        let earliest = ccd.query(&step, method, &options);
        assert!(earliest.vf.is_empty() && earliest.ee.is_empty());
        check_report(&earliest, t_max, "earliest");
        if exact {
            assert_eq!(
                earliest.earliest, all.earliest,
                "{method}: earliest differs from all's"
            );
            continue;
        }
        // Under a small iteration limit a pair that cannot be resolved over [0, t_max] may be
        // ruled out over the shorter interval Earliest solves first: Earliest may then name
        // another contact of All (both answers are conservative), but never one All lacks.
        assert_eq!(
            earliest.earliest.is_some(),
            all.earliest.is_some(),
            "{method}"
        );
        match earliest.earliest {
            Some(Contact::Vf(c)) => assert!(all.vf.contains(&c), "{method}: {c:?} not in all"),
            Some(Contact::Ee(c)) => assert!(all.ee.contains(&c), "{method}: {c:?} not in all"),
            None => {}
        }
    }
});
