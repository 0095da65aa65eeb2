#![no_main]
//! Fuzz target `cdr_ball_params`: see `sweetspot_fuzz::cdr_ball_params` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::cdr_ball_params(data));
