//! The workspace's own tests of `topoccd`, kept out of the published crate: `tests/` holds
//! the tests that need the scene generators (`topoccd-scenes`) or the library's internals
//! (the feature `internals`), and this file runs every Rust code block of the repository's
//! README and of the user guide (`docs/guide/src/*.md`) as doctests.

/// The README's code blocks.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct Readme;
