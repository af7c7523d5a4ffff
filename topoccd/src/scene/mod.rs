//! Seeded scene generators used by the tests, the benchmarks and the command line.
