#![no_main]
//! Fuzz target `bat_toml`: see `sweetspot_fuzz::bat_toml` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::bat_toml(data));
