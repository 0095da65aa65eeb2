#![no_main]
//! Fuzz target `physics`: see `sweetspot_fuzz::physics` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::physics(data));
