#![no_main]
//! Fuzz target `case_file`: see `sweetspot_fuzz::case_file` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::case_file(data));
