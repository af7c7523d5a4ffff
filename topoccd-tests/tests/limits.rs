//! Bounded queries: a cap on the contacts (`QueryOptions::max_contacts`), a deadline, a cancel
//! token, and the streaming form, on collapsed input (positions cast to integers: a few points
//! carry every vertex, and almost every feature pair touches at t=0) and on generated scenes.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use topoccd::{
    query, Ccd, Contact, Method, Mode, OptionsError, Phase, QueryOptions, Report, Step, StopReason,
};
use topoccd_scenes::SceneKind;

/// A crumpled `n x n` grid whose coordinates were cast to integers (truncated towards 0): its
/// vertices collapse onto a few lattice points, as `x.astype(np.int32)` does to a cloth. Static.
fn collapsed(n: u32) -> Step<'static> {
    let mut x = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let p = [
                2.5 * u - 1.25 + 0.3 * (7.0 * v).sin(),
                2.5 * v - 1.25,
                -1.0 + 0.9 * (5.0 * u).cos() * (3.0 * v).sin(),
            ];
            x.push(p.map(f64::trunc));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Step::new(x.clone(), x, tris).expect("a valid step")
}

fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// The pairs with their times' bits.
type Key = (Vec<(u32, u32, u64)>, Vec<([u32; 2], [u32; 2], u64)>);

fn key(r: &Report) -> Key {
    (
        r.vf.iter()
            .map(|c| (c.vertex, c.face, c.toi.to_bits()))
            .collect(),
        r.ee.iter().map(|c| (c.a, c.b, c.toi.to_bits())).collect(),
    )
}

/// Every contact of `part` is one of `whole`'s, with the same time (both sorted).
fn assert_subset(part: &Report, whole: &Report, what: &str) {
    let (pv, pe) = key(part);
    let (wv, we) = key(whole);
    for c in &pv {
        assert!(
            wv.binary_search(c).is_ok(),
            "{what}: {c:?} is not a contact"
        );
    }
    for c in &pe {
        assert!(
            we.binary_search(c).is_ok(),
            "{what}: {c:?} is not a contact"
        );
    }
}

const METHODS: [Method; 3] = [Method::Bvh, Method::Cluster, Method::Brute];

#[test]
fn a_cap_keeps_the_same_contacts_on_one_and_two_threads() {
    let step = collapsed(16);
    let all = query(&step, Method::Brute, &QueryOptions::default()).unwrap();
    assert!(all.truncated.is_none());
    assert!(all.contact_count() > 100_000, "{}", all.contact_count());
    for method in METHODS {
        for cap in [0, 1, 777, 40_000] {
            let options = QueryOptions {
                max_contacts: Some(cap),
                ..QueryOptions::default()
            };
            let one = on_threads(1, || query(&step, method, &options).unwrap());
            let two = on_threads(2, || query(&step, method, &options).unwrap());
            let what = format!("{method} cap {cap}");
            assert_eq!(key(&one), key(&two), "{what}");
            assert_eq!(one.truncated, two.truncated, "{what}");
            assert_eq!(
                (one.stats.vf_tests, one.stats.ee_tests),
                (two.stats.vf_tests, two.stats.ee_tests),
                "{what}"
            );
            let t = one.truncated.expect("truncated");
            assert_eq!(
                (t.reason, t.phase),
                (StopReason::MaxContacts, Phase::Candidates)
            );
            assert!(t.tasks >= 1, "{what}");
            assert_eq!(one.contact_count(), cap, "{what}");
            assert_subset(&one, &all, &what);
            assert_eq!(one.earliest_toi(), (cap > 0).then_some(0.0), "{what}");
        }
    }
}

/// On a collapsed grid every pair of subtrees overlaps, so the per-step hierarchy's search for
/// its front gives up (it would look at every pair of triangles before the query could stop)
/// and the traversal starts from the root: the same contacts as brute force, on the first step
/// and on the next, whose tree is refitted (and the search not tried again).
#[test]
fn a_collapsed_step_without_a_front_gives_the_brute_force_pairs() {
    let step = collapsed(24);
    let brute = query(&step, Method::Brute, &QueryOptions::default()).unwrap();
    assert!(brute.contact_count() > 100_000, "{}", brute.contact_count());
    let mut ccd = Ccd::new();
    for round in 0..2 {
        let r = ccd
            .query(&step, Method::Bvh, &QueryOptions::default())
            .unwrap();
        assert_eq!(key(&r), key(&brute), "round {round}");
        assert_eq!(r.earliest.map(|c| c.toi()), Some(0.0));
    }
}

#[test]
fn a_cap_the_step_does_not_reach_changes_nothing() {
    for kind in [SceneKind::ALL[0], SceneKind::ALL[2]] {
        let step = kind.generate(24, 1);
        for method in METHODS {
            let full = query(&step, method, &QueryOptions::default()).unwrap();
            let n = full.contact_count();
            assert!(n > 10, "{} {method}: {n}", kind.name());
            let capped = |cap| {
                let options = QueryOptions {
                    max_contacts: Some(cap),
                    ..QueryOptions::default()
                };
                query(&step, method, &options).unwrap()
            };
            // Exactly as many as the step has: the whole report, not truncated.
            let at = capped(n);
            assert_eq!(key(&at), key(&full), "{} {method}", kind.name());
            assert_eq!((at.truncated, at.earliest), (None, full.earliest));
            assert_eq!(at.stats.vf_tests, full.stats.vf_tests);
            // One fewer: truncated, a subset.
            let below = capped(n - 1);
            assert_eq!(below.contact_count(), n - 1);
            let t = below.truncated.expect("truncated");
            assert_eq!(t.reason, StopReason::MaxContacts);
            assert_subset(&below, &full, &format!("{} {method}", kind.name()));
        }
    }
}

#[test]
fn earliest_with_a_cap_returns_toi_zero_on_collapsed_input() {
    let step = collapsed(16);
    let all = query(&step, Method::Brute, &QueryOptions::default()).unwrap();
    let tolerance = QueryOptions::default().narrow.tolerance;
    for method in METHODS {
        let options = QueryOptions {
            mode: Mode::Earliest,
            max_contacts: Some(3_000),
            ..QueryOptions::default()
        };
        let one = on_threads(1, || query(&step, method, &options).unwrap());
        let two = on_threads(2, || query(&step, method, &options).unwrap());
        assert_eq!(key(&one), key(&two), "{method}");
        assert_eq!(one.earliest_toi(), Some(0.0), "{method}");
        assert_eq!(one.contact_count(), 3_000, "{method}");
        assert!(one.vf.iter().all(|c| c.toi <= tolerance));
        assert!(one.ee.iter().all(|c| c.toi <= tolerance));
        assert_eq!(
            one.truncated.map(|t| t.reason),
            Some(StopReason::MaxContacts)
        );
        assert_subset(&one, &all, &format!("{method}"));
    }
}

#[test]
fn earliest_with_a_cap_above_its_pairs_is_exact() {
    for kind in SceneKind::ALL {
        let step = kind.generate(24, 2);
        for method in [Method::Bvh, Method::Brute] {
            let options = QueryOptions {
                mode: Mode::Earliest,
                ..QueryOptions::default()
            };
            let plain = query(&step, method, &options).unwrap();
            let capped = QueryOptions {
                max_contacts: Some(plain.contact_count() + 1),
                ..options
            };
            let capped = query(&step, method, &capped).unwrap();
            assert_eq!(key(&capped), key(&plain), "{} {method}", kind.name());
            assert_eq!(capped.earliest, plain.earliest);
            assert_eq!(capped.truncated, None);
        }
    }
}

#[test]
fn a_past_deadline_stops_before_any_work() {
    let step = collapsed(8);
    let options = QueryOptions {
        deadline: Some(Instant::now()),
        ..QueryOptions::default()
    };
    for method in METHODS {
        let r = query(&step, method, &options).unwrap();
        let t = r.truncated.expect("truncated");
        assert_eq!(
            (t.reason, t.phase, t.tasks),
            (StopReason::Deadline, Phase::Build, 0)
        );
        assert_eq!(r.contact_count(), 0);
    }
}

/// Without a cap, the collapsed grid has tens of millions of contacts: the query would run for
/// minutes. A deadline (or a cancellation) must end it promptly, whatever the method; the bound
/// asserted is generous (the machine is shared), the figures are in the guide.
#[test]
fn a_deadline_ends_a_long_query() {
    let step = collapsed(60);
    for method in METHODS {
        for mode in [Mode::All, Mode::Earliest] {
            let started = Instant::now();
            let options = QueryOptions {
                mode,
                deadline: Some(started + Duration::from_millis(50)),
                ..QueryOptions::default()
            };
            let r = query(&step, method, &options).unwrap();
            let took = started.elapsed();
            let t = r.truncated.expect("truncated");
            assert_eq!(t.reason, StopReason::Deadline, "{method} {mode:?}");
            assert!(took < Duration::from_secs(5), "{method} {mode:?}: {took:?}");
            // Stopped by time: only the earliest contact found by then (all touch at 0).
            assert_eq!(r.contact_count(), 0);
            assert!(
                r.earliest.is_none_or(|c| c.toi() == 0.0),
                "{:?}",
                r.earliest
            );
        }
    }
}

#[test]
fn a_cancel_token_stops_a_query_from_another_thread() {
    let step = collapsed(60);
    for method in [Method::Bvh, Method::Brute] {
        let mut ccd = Ccd::new();
        let token = ccd.cancel_token();
        let (report, took) = std::thread::scope(|s| {
            let canceller = s.spawn(|| {
                std::thread::sleep(Duration::from_millis(50));
                (token.cancel(), Instant::now()).1
            });
            let r = ccd.query(&step, method, &QueryOptions::default()).unwrap();
            let cancelled_at = canceller.join().unwrap();
            (r, cancelled_at.elapsed())
        });
        let t = report.truncated.expect("truncated");
        assert_eq!(t.reason, StopReason::Cancelled, "{method}");
        assert!(took < Duration::from_secs(5), "{method}: {took:?}");
        // Cancelled stays cancelled until reset.
        let small = collapsed(2);
        let again = ccd.query(&small, method, &QueryOptions::default()).unwrap();
        assert_eq!(
            again.truncated.map(|t| t.reason),
            Some(StopReason::Cancelled)
        );
        ccd.cancel_token().reset();
        let again = ccd.query(&small, method, &QueryOptions::default()).unwrap();
        assert_eq!(again.truncated, None);
        assert_eq!(
            key(&again),
            key(&query(&small, method, &QueryOptions::default()).unwrap())
        );
    }
}

#[test]
fn streaming_hands_over_every_contact_once() {
    for (step, name) in [
        (collapsed(6), "collapsed"),
        (SceneKind::ALL[1].generate(24, 0), SceneKind::ALL[1].name()),
    ] {
        for method in METHODS {
            let full = query(&step, method, &QueryOptions::default()).unwrap();
            let seen = Mutex::new(Vec::new());
            let mut ccd = Ccd::new();
            let options = QueryOptions::default();
            let r = ccd
                .for_each_contact(&step, method, &options, |c| seen.lock().unwrap().push(*c))
                .unwrap();
            let mut streamed = Report::default();
            for c in seen.into_inner().unwrap() {
                match c {
                    Contact::Vf(c) => streamed.vf.push(c),
                    Contact::Ee(c) => streamed.ee.push(c),
                    Contact::Ve(c) => streamed.ve.push(c),
                    Contact::Vv(c) => streamed.vv.push(c),
                }
            }
            streamed.vf.sort_by_key(|c| (c.vertex, c.face));
            streamed.ee.sort_by_key(|c| (c.a, c.b));
            assert_eq!(key(&streamed), key(&full), "{name} {method}");
            assert!(r.vf.is_empty() && r.ee.is_empty());
            assert_eq!(
                (r.earliest, r.truncated),
                (full.earliest, None),
                "{name} {method}"
            );
            assert_eq!(r.unresolved, full.unresolved);
        }
    }
    // With a cap: that many handed over, then the query stops.
    let step = collapsed(16);
    let count = std::sync::atomic::AtomicUsize::new(0);
    let options = QueryOptions {
        max_contacts: Some(1_000),
        ..QueryOptions::default()
    };
    let r = Ccd::new()
        .for_each_contact(&step, Method::Bvh, &options, |_| {
            count.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap();
    assert_eq!(count.into_inner(), 1_000);
    assert_eq!(r.truncated.map(|t| t.reason), Some(StopReason::MaxContacts));
    // Earliest cannot stream.
    let earliest = QueryOptions {
        mode: Mode::Earliest,
        ..QueryOptions::default()
    };
    let refused = Ccd::new().for_each_contact(&step, Method::Bvh, &earliest, |_| {});
    assert_eq!(refused.unwrap_err(), OptionsError::Streaming);
}
