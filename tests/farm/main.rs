//! The render farm (`spar::farm`, `spar render --tile/--samples`, `spar
//! merge`): determinism over any tiling and sample split, checkpoints and
//! signals, every merge error, bad values, fuzzed parts. One test binary;
//! each file is a module.

#[path = "../support/mod.rs"]
mod support;

mod farm_bad_values;
mod farm_cli;
mod farm_determinism;
mod farm_merge_errors;
mod farm_progress;
mod fuzz_parts;
