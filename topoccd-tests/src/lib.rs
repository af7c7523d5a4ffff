//! The workspace's own tests of `topoccd`, kept out of the published crate: `tests/` holds
//! the tests that need the scene generators (`topoccd-scenes`) or the library's internals
//! (the feature `internals`), and this file runs every Rust code block of the repository's
//! README and of the user guide (`docs/guide/src/*.md`) as doctests. A guide page with Rust
//! blocks must be listed here (`topoccd-py/tests/test_docs.py` checks it).

/// Includes markdown files as doctests, one hidden item each.
macro_rules! doctests {
    ($($name:ident => $path:literal),* $(,)?) => {$(
        #[cfg(doctest)]
        #[doc = include_str!($path)]
        pub struct $name;
    )*};
}

doctests! {
    Readme => "../../README.md",
    GuideCheck => "../../docs/guide/src/check.md",
    GuideCodimensional => "../../docs/guide/src/codimensional.md",
    GuideCuttingAndFracture => "../../docs/guide/src/cutting-and-fracture.md",
    GuideEarliestAndLineSearch => "../../docs/guide/src/earliest-and-line-search.md",
    GuideFileFormats => "../../docs/guide/src/file-formats.md",
    GuideIpcLoop => "../../docs/guide/src/ipc-loop.md",
    GuideLoopRust => "../../docs/guide/src/loop-rust.md",
    GuideMethods => "../../docs/guide/src/methods.md",
    GuidePairs => "../../docs/guide/src/pairs.md",
    GuideProximity => "../../docs/guide/src/proximity.md",
}
