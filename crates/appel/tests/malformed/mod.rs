//! A deterministic mutation fuzzer for the input readers (see `docs/robustness.md`).

pub mod mutate;
pub mod rng;
pub mod runner;
pub mod seeds;
pub mod targets;
