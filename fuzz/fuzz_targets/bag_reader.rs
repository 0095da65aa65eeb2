#![no_main]
//! Fuzz target `bag_reader`: see `sweetspot_fuzz::bag_reader` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::bag_reader(data));
