//! The whole step on small random meshes: random (possibly out-of-range) indices, coordinates
//! that mix ordinary values with NaN, infinities, huge, tiny and subnormal numbers, repeated
//! points, degenerate and repeated triangles, and edges shared by many triangles; random
//! options, a few of them out of range.
//!
//! `Step::new` must refuse exactly the invalid steps (lengths, non-finite coordinates, indices
//! out of range or repeated in a triangle), and `Ccd::query` exactly the invalid options, with
//! an error naming an offending option. For a valid step and options, every report must be
//! well formed (sorted, each pair once, no pair of features sharing a vertex, every time of
//! impact finite and in `[0, tmax]`, `unresolved` counting the contacts not `Resolved`,
//! geometry present exactly when asked, `earliest` the first contact), and the BVH and the
//! brute-force oracle must report the same contacts. The cluster method must report them too,
//! but for pairs whose features lie in one intermediate cluster: its certificate proves those
//! never touch, and it skips them without solving them, where the elementary test may report a
//! pair that comes within the tolerance without touching, or that it could not resolve; with
//! its certificates distrusted it must report exactly brute force's contacts. `Mode::Earliest`
//! must report only contacts of `Mode::All`, within the tolerance of its earliest one; when
//! All resolved every contact at the default iteration limit and tolerance, exactly All's
//! contacts within the tolerance of All's earliest, with the same earliest contact. (With a
//! tolerance as large as 0.1, All may report a pair that passes within the tolerance of a touch,
//! which Earliest, searching a shorter interval first, rules out: see
//! `earliest_may_leave_out_a_near_miss_all_reports` in `topoccd/tests/fuzz_regressions.rs`.)
//!
//! Under a small iteration limit (which the target also draws, for speed and because the
//! limit is itself an answer to check) an unresolved pair is reported as a contact, so the
//! checks weaken to what still holds: BVH equals brute force, and Earliest reports a subset of
//! All's contacts, so its earliest is one of All's (see `topoccd/tests/fuzz_regressions.rs`).
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use topoccd::math::DVec3;
use topoccd::{
    Ccd, Certainty, Contact, DopKind, EeContact, Method, Mode, OptionsError, QueryOptions, Report,
    Step, VfContact,
};

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

/// Whether the step's nonzero coordinates span more than 2^40 in magnitude: the elementary
/// test's rounding bounds, relative to a pair's largest coordinate differences, may then
/// exceed the gap between features near the smaller coordinates (1e300 beside 1), and it
/// reports such a pair at a time it cannot rule out, possibly long before it touches.
fn mixed_scales(x0: &[[f64; 3]], x1: &[[f64; 3]]) -> bool {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for c in x0.iter().chain(x1).flatten().map(|c| c.abs()) {
        if c > 0.0 {
            lo = lo.min(c);
            hi = hi.max(c);
        }
    }
    hi > lo * 2f64.powi(40)
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
    min_distance: u8,
    tmax: u8,
    kdop: u8,
    iterations: u8,
    tolerance: u8,
    geometry: bool,
    /// Most values leave the options valid; the others put one option out of its range.
    invalid: u8,
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

/// The step as `Step::new` should judge it: the same lengths at t=0 and t=1, finite
/// coordinates, and triangles of three distinct vertices in range.
fn step_is_valid(x0: &[[f64; 3]], x1: &[[f64; 3]], tris: &[[u32; 3]]) -> bool {
    let n = x0.len();
    n == x1.len()
        && x0.iter().chain(x1).flatten().all(|c| c.is_finite())
        && tris.iter().all(|&[a, b, c]| {
            [a, b, c].iter().all(|&i| (i as usize) < n) && a != b && a != c && b != c
        })
}

/// The options as documented: tolerance in (0, 1), at least one iteration, a finite
/// `min_distance >= 0`, `tmax` in (0, 1].
fn options_are_valid(o: &QueryOptions) -> bool {
    let n = &o.narrow;
    n.tolerance > 0.0
        && n.tolerance < 1.0
        && n.max_iterations >= 1
        && n.min_distance >= 0.0
        && n.min_distance.is_finite()
        && n.tmax > 0.0
        && n.tmax <= 1.0
}

/// Whether the error names an option that is out of its range, with its value.
fn names_a_bad_option(e: &OptionsError, o: &QueryOptions) -> bool {
    let n = &o.narrow;
    let same = |x: f64, y: f64| x.to_bits() == y.to_bits();
    match *e {
        OptionsError::Tolerance(x) => {
            same(x, n.tolerance) && !(n.tolerance > 0.0 && n.tolerance < 1.0)
        }
        OptionsError::MaxIterations => n.max_iterations == 0,
        OptionsError::MinDistance(x) => {
            same(x, n.min_distance) && !(n.min_distance >= 0.0 && n.min_distance.is_finite())
        }
        OptionsError::Tmax(x) => same(x, n.tmax) && !(n.tmax > 0.0 && n.tmax <= 1.0),
        _ => false,
    }
}

/// What every report must satisfy, whatever the method, mode and iteration limit.
fn check_report(report: &Report, tris: &[[u32; 3]], options: &QueryOptions, what: &str) {
    let tmax = options.narrow.tmax;
    let toi_ok = |toi: f64| toi.is_finite() && (0.0..=tmax).contains(&toi);
    let used = |v: u32| tris.iter().any(|t| t.contains(&v));
    let is_edge = |[i, j]: [u32; 2]| {
        tris.iter()
            .any(|t| t.contains(&i) && t.contains(&j) && i != j)
    };
    for c in &report.vf {
        assert!(toi_ok(c.toi), "{what}: toi of {c:?}");
        assert!(used(c.vertex), "{what}: vertex of no triangle in {c:?}");
        let face = tris.get(c.face as usize).expect("face in range");
        assert!(
            !face.contains(&c.vertex),
            "{what}: vertex of its own face in {c:?}"
        );
        assert_eq!(
            c.geometry.is_some(),
            options.geometry,
            "{what}: geometry of {c:?}"
        );
    }
    for c in &report.ee {
        assert!(toi_ok(c.toi), "{what}: toi of {c:?}");
        assert!(
            c.a[0] < c.a[1] && c.b[0] < c.b[1] && c.a < c.b,
            "{what}: order in {c:?}"
        );
        assert!(is_edge(c.a) && is_edge(c.b), "{what}: not an edge in {c:?}");
        assert!(
            !c.a.iter().any(|v| c.b.contains(v)),
            "{what}: edges share a vertex in {c:?}"
        );
        assert_eq!(
            c.geometry.is_some(),
            options.geometry,
            "{what}: geometry of {c:?}"
        );
    }
    assert!(
        report
            .vf
            .windows(2)
            .all(|w| (w[0].vertex, w[0].face) < (w[1].vertex, w[1].face)),
        "{what}: vf not sorted, or a pair twice"
    );
    assert!(
        report
            .ee
            .windows(2)
            .all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b)),
        "{what}: ee not sorted, or a pair twice"
    );
    let contacts = || {
        let vf = report.vf.iter().map(|&c| Contact::Vf(c));
        vf.chain(report.ee.iter().map(|&c| Contact::Ee(c)))
    };
    let unresolved = contacts()
        .filter(|c| c.certainty() != Certainty::Resolved)
        .count();
    assert_eq!(report.unresolved, unresolved, "{what}: unresolved");
    let first = contacts().min_by(Contact::earliest_order);
    assert_eq!(
        report.earliest, first,
        "{what}: earliest is not the first contact"
    );
}

fn subset<T: PartialEq + std::fmt::Debug>(part: &[T], whole: &[T], what: &str) {
    for c in part {
        assert!(whole.contains(c), "{what}: {c:?} missing");
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
    // The public input types, borrowed: `&Vec<[f64; 3]>` and `&Vec<[u32; 3]>`.
    let x0: Vec<[f64; 3]> = x0.iter().map(|p| p.to_array()).collect();
    let x1: Vec<[f64; 3]> = x1.iter().map(|p| p.to_array()).collect();
    let tris = triangles(&input.triangles, x0.len());
    let valid = step_is_valid(&x0, &x1, &tris);
    let step = match Step::new(&x0, &x1, &tris) {
        Ok(step) => step,
        Err(e) => {
            assert!(!valid, "a valid step is refused: {e}");
            return;
        }
    };
    assert!(valid, "an invalid step is accepted");
    assert!(step.is_borrowed());
    let bits = |x: &[[f64; 3]]| -> Vec<u64> { x.iter().flatten().map(|c| c.to_bits()).collect() };
    assert_eq!(bits(step.x0()), bits(&x0));
    assert_eq!(bits(step.x1()), bits(&x1));
    assert_eq!(step.triangles(), &tris[..]);

    let mut options = QueryOptions::default();
    options.narrow.min_distance = [0.0, 1e-6, 1e-3, 0.1][usize::from(input.min_distance % 4)];
    options.narrow.tmax = [1.0, 0.5, 1e-3, f64::MIN_POSITIVE][usize::from(input.tmax % 4)];
    let default_tolerance = options.narrow.tolerance;
    options.narrow.tolerance =
        [default_tolerance, 1e-3, 0.1, 0.5][usize::from(input.tolerance % 4)];
    // Few iterations keep the fuzzer fast; the iteration limit is itself an answer to check.
    // At the default limit and tolerance, on a step of one scale, Earliest reports exactly
    // All's contacts within the tolerance of the earliest.
    let default_iterations = options.narrow.max_iterations;
    options.narrow.max_iterations =
        [1, 64, 4096, default_iterations][usize::from(input.iterations % 4)];
    options.kdop =
        [DopKind::K6, DopKind::K14, DopKind::K18, DopKind::K26][usize::from(input.kdop % 4)];
    options.geometry = input.geometry;
    // One draw in five puts one option out of its range or on its edge (-0.0 separation and a
    // subnormal tmax are valid).
    let n = &mut options.narrow;
    match input.invalid % 80 {
        0 => n.tolerance = 0.0,
        1 => n.tolerance = 1.0,
        2 => n.tolerance = f64::NAN,
        3 => n.tolerance = -1e-6,
        4 => n.tolerance = f64::INFINITY,
        5 => n.max_iterations = 0,
        6 => n.min_distance = -1e-6,
        7 => n.min_distance = f64::NAN,
        8 => n.min_distance = f64::INFINITY,
        9 => n.min_distance = -0.0,
        10 => n.tmax = 0.0,
        11 => n.tmax = 1.0 + f64::EPSILON,
        12 => n.tmax = f64::NAN,
        13 => n.tmax = -0.0,
        14 => n.tmax = f64::INFINITY,
        15 => n.tmax = f64::MIN_POSITIVE / 2.0, // subnormal, in (0, 1]: valid
        _ => {}
    }
    let exact = options.narrow.max_iterations == default_iterations;
    let mixed = mixed_scales(&x0, &x1);
    let mut ccd = Ccd::new();

    if !options_are_valid(&options) {
        assert!(options.validate().is_err());
        for mode in [Mode::All, Mode::Earliest] {
            options.mode = mode;
            for method in [Method::Brute, Method::Bvh, Method::Cluster] {
                match ccd.query(&step, method, &options) {
                    Ok(_) => panic!("{method}: invalid options accepted: {options:?}"),
                    Err(e) => assert!(
                        names_a_bad_option(&e, &options),
                        "{method}: {e} for {options:?}"
                    ),
                }
            }
        }
        return;
    }
    assert_eq!(options.validate(), Ok(()));

    let brute = ccd
        .query(&step, Method::Brute, &options)
        .expect("valid options");
    check_report(&brute, &tris, &options, "brute");
    let bvh = ccd
        .query(&step, Method::Bvh, &options)
        .expect("valid options");
    assert!(ccd.validate_tree(&step).is_ok(), "invalid bvh");
    check_report(&bvh, &tris, &options, "bvh");
    assert_eq!(bvh.vf, brute.vf, "vf differs between bvh and brute");
    assert_eq!(bvh.ee, brute.ee, "ee differs between bvh and brute");
    assert_eq!(bvh.earliest, brute.earliest);
    let cluster = ccd
        .query(&step, Method::Cluster, &options)
        .expect("valid options");
    assert!(ccd.validate_tree(&step).is_ok(), "invalid cluster tree");
    check_report(&cluster, &tris, &options, "cluster");
    // Brute force may report a pair that comes within the tolerance without touching, or that
    // it could not resolve, which the cluster method skips, without solving it, when its
    // certificate proves the pair free of contact: the cluster method reports brute force's
    // contacts, with the same times, but for pairs inside one intermediate cluster.
    subset(&cluster.vf, &brute.vf, "cluster vf in brute");
    subset(&cluster.ee, &brute.ee, "cluster ee in brute");
    for c in brute.vf.iter().filter(|c| !cluster.vf.contains(c)) {
        let face = &tris[c.face as usize];
        let ok = ccd.cluster_holds_both(&step, &[c.vertex], face);
        assert!(ok, "cluster left out {c:?}, not inside one cluster");
    }
    for c in brute.ee.iter().filter(|c| !cluster.ee.contains(c)) {
        let ok = ccd.cluster_holds_both(&step, &c.a, &c.b);
        assert!(ok, "cluster left out {c:?}, not inside one cluster");
    }
    let toi = |r: &Report| r.earliest_toi().unwrap_or(f64::INFINITY);
    assert!(toi(&cluster) >= toi(&brute));
    // Without its certificates the cluster method's candidates are the BVH's.
    ccd.distrust_certificates(true);
    let distrusted = ccd
        .query(&step, Method::Cluster, &options)
        .expect("valid options");
    ccd.distrust_certificates(false);
    assert_eq!(
        distrusted.vf, brute.vf,
        "vf differs between distrusted cluster and brute"
    );
    assert_eq!(
        distrusted.ee, brute.ee,
        "ee differs between distrusted cluster and brute"
    );
    assert_eq!(distrusted.earliest, brute.earliest);

    options.mode = Mode::Earliest;
    let tolerance = options.narrow.tolerance;
    for (method, all) in [
        (Method::Bvh, &bvh),
        (Method::Brute, &brute),
        (Method::Cluster, &cluster),
    ] {
        let earliest = ccd.query(&step, method, &options).expect("valid options");
        assert!(ccd.validate_tree(&step).is_ok(), "{method}: invalid tree");
        check_report(&earliest, &tris, &options, "earliest");
        assert_eq!(
            earliest.earliest.is_some(),
            all.earliest.is_some(),
            "{method}"
        );
        // Earliest solves a pair over a shorter interval first, and again over the whole one
        // if that finds a contact: what it reports is a contact of All, unchanged, within the
        // tolerance of its own earliest (which check_report found among them).
        subset(
            &earliest.vf,
            &all.vf,
            &format!("{method}: earliest vf in all"),
        );
        subset(
            &earliest.ee,
            &all.ee,
            &format!("{method}: earliest ee in all"),
        );
        if let Some(first) = earliest.earliest {
            let cut = first.toi() + tolerance;
            assert!(
                earliest.vf.iter().all(|c| c.toi <= cut),
                "{method}: vf late"
            );
            assert!(
                earliest.ee.iter().all(|c| c.toi <= cut),
                "{method}: ee late"
            );
        }
        if !exact || all.unresolved > 0 || tolerance != default_tolerance || mixed {
            // A pair that cannot be resolved over [0, tmax] (under a small iteration limit,
            // or at the default one with coordinates of 1e298 beside coordinates of 0.01), or
            // that comes within a large tolerance of a touch, or within the rounding of
            // coordinates of 1e300 of a touch it makes only later, may be ruled out over the
            // shorter interval: Earliest may then miss some of All's earliest pairs and name
            // another contact of All (both conservative).
            continue;
        }
        assert_eq!(
            earliest.earliest, all.earliest,
            "{method}: earliest differs from all's"
        );
        let cut = all
            .earliest_toi()
            .map_or(f64::NEG_INFINITY, |t| t + tolerance);
        let vf: Vec<VfContact> = all.vf.iter().filter(|c| c.toi <= cut).copied().collect();
        let ee: Vec<EeContact> = all.ee.iter().filter(|c| c.toi <= cut).copied().collect();
        assert_eq!(
            earliest.vf, vf,
            "{method}: earliest vf are not all's within the tolerance"
        );
        assert_eq!(
            earliest.ee, ee,
            "{method}: earliest ee are not all's within the tolerance"
        );
    }
});
