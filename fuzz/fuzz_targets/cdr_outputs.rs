#![no_main]
//! Fuzz target `cdr_outputs`: see `sweetspot_fuzz::cdr_outputs` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::cdr_outputs(data));
