//! Earliest mode keeps a bounded set of the earliest pairs (issue 43): a sheet that falls flat
//! through another touches it with hundreds of pairs at one time, t = 1/2. Under a cap below
//! that count the earliest time is still exact, the report holds the cap's earliest pairs (a
//! subset of the uncapped report's, the same on one and two threads), and it says that its
//! list is not complete; with a cap above, nothing changes.

use topoccd::{query, Method, Mode, QueryOptions, Report, Step};

/// Two `n x n` grids over the unit square, one at z=0 held still, one falling from z=1 to z=-1
/// (shifted by a third of a cell, so that its vertices fall inside the other's triangles).
fn falling_sheet(n: u32) -> Step<'static> {
    let mut x0 = Vec::new();
    let mut x1 = Vec::new();
    let mut tris = Vec::new();
    for (z0, z1, shift) in [(0.0, 0.0, 0.0), (1.0, -1.0, 1.0 / 3.0)] {
        let base = x0.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = ((i as f64 + shift) / n as f64, (j as f64 + shift) / n as f64);
                x0.push([x, y, z0]);
                x1.push([x, y, z1]);
            }
        }
        let id = |i: u32, j: u32| base + j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    Step::new(x0, x1, tris).expect("a valid step")
}

fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// A report's vertex-face and edge-edge pairs, each with its time's bits.
type Pairs = (Vec<(u32, u32, u64)>, Vec<([u32; 2], [u32; 2], u64)>);

fn pairs(r: &Report) -> Pairs {
    (
        r.vf.iter()
            .map(|c| (c.vertex, c.face, c.toi.to_bits()))
            .collect(),
        r.ee.iter().map(|c| (c.a, c.b, c.toi.to_bits())).collect(),
    )
}

#[test]
fn earliest_under_a_cap_keeps_the_earliest_pairs_and_says_so() {
    let step = falling_sheet(8);
    for method in [Method::Bvh, Method::Brute, Method::Cluster] {
        let options = |cap| QueryOptions {
            mode: Mode::Earliest,
            max_contacts: cap,
            ..QueryOptions::default()
        };
        let full = query(&step, method, &options(None)).unwrap();
        let n = full.contact_count();
        assert!(n > 200, "{method}: {n}");
        assert!(
            full.earliest_complete && full.truncated.is_none(),
            "{method}"
        );
        // The exact first contact is at 1/2; every reported pair within the tolerance.
        let t = full.earliest_toi().expect("contacts");
        assert!(t <= 0.5 && t > 0.5 - 1e-5, "{method}: {t}");
        for cap in [1, 50] {
            let one = on_threads(1, || query(&step, method, &options(Some(cap))).unwrap());
            let two = on_threads(2, || query(&step, method, &options(Some(cap))).unwrap());
            assert_eq!(pairs(&one), pairs(&two), "{method} cap {cap}");
            assert_eq!(one.earliest, full.earliest, "{method} cap {cap}");
            assert_eq!(one.contact_count(), cap, "{method} cap {cap}");
            assert!(
                !one.earliest_complete && one.truncated.is_none(),
                "{method} cap {cap}"
            );
            let (fv, fe) = pairs(&full);
            let (ov, oe) = pairs(&one);
            assert!(ov.iter().all(|c| fv.contains(c)), "{method} cap {cap}");
            assert!(oe.iter().all(|c| fe.contains(c)), "{method} cap {cap}");
        }
        let above = query(&step, method, &options(Some(n))).unwrap();
        assert_eq!(pairs(&above), pairs(&full), "{method}");
        assert!(above.earliest_complete, "{method}");
    }
}
