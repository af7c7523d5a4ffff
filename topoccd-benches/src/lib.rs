//! Benchmarks of topoccd live in `benches/`; this crate has no library code.
