//! The README's simulator loop (`examples/falling_halves.rs`): a sphere cut in two halves that
//! fall onto a sheet with an earliest-time line search.

#[allow(dead_code)]
#[path = "../examples/falling_halves.rs"]
mod example;

#[test]
fn the_cut_is_no_contact_and_the_halves_land_on_the_sheet() {
    let log = example::simulate(14);
    assert!(log[0].cut && log.iter().skip(1).all(|s| !s.cut));
    // The fresh cut never stops the line search: no earliest time of 0 on any step.
    for s in &log {
        assert_ne!(s.earliest, Some(0.0), "step {}: {s:?}", s.step);
        // Nothing passes through the sheet at y = -2 (the sphere's lowest point stays above).
        assert!(s.lowest > -2.0, "step {}: {s:?}", s.step);
    }
    // Both halves land: two steps stop at a contact, and then the sphere rests.
    let landings: Vec<_> = log.iter().filter(|s| s.earliest.is_some()).collect();
    assert_eq!(landings.len(), 2, "{log:?}");
    let last = log.last().expect("steps");
    assert!(last.lowest > -2.0 && last.lowest < -1.9, "{last:?}");
}
