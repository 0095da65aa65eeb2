#![no_main]
//! Fuzz target `cdr_bat_params`: see `sweetspot_fuzz::cdr_bat_params` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::cdr_bat_params(data));
