//! The collapsed input of the address-space tests (`memory_limit`, `bounded_entry_points`):
//! the integer-cast cloth-funnel step.

use std::path::PathBuf;

use topoccd::io::sequence::Sequence;

/// The step's positions at t=0 and t=1 and its triangles.
pub type Frames = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[u32; 3]>);

/// The cloth-funnel step with its coordinates cast to `i32`, as `x.astype(np.int32)` does.
pub fn collapsed_funnel() -> Option<Frames> {
    let dir = std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
        .join("scenes/cloth-funnel");
    if !dir.is_dir() {
        assert!(
            std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
            "TOPOCCD_REQUIRE_DATA is set but the shared data is absent: {}",
            dir.display()
        );
        eprintln!(
            "SKIPPED, NOT TESTED: the shared scenes are not at {}",
            dir.display()
        );
        return None;
    }
    let steps = Sequence::open(&dir).expect("cloth-funnel opens");
    let frames = steps.load(0).expect("cloth-funnel's step reads");
    let cast = |x: Vec<[f64; 3]>| -> Vec<[f64; 3]> {
        x.into_iter().map(|p| p.map(|c| c as i32 as f64)).collect()
    };
    Some((cast(frames.x0), cast(frames.x1), frames.triangles))
}
