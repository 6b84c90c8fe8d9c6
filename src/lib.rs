//! The workspace root package: it owns the integration and property tests in
//! `tests/` and the criterion benchmarks in `benches/`. The library itself is
//! in `core/` (`laminar-core`) and the command-line runner in `std-runner/`.
