#![no_main]
//! Fuzz target `bag_hostile`: see `sweetspot_fuzz::bag_hostile` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::bag_hostile(data));
