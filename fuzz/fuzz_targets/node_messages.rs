#![no_main]
//! Fuzz target `node_messages`: see `sweetspot_fuzz::node_messages` in fuzz/harness.rs and docs/fuzzing.md.

libfuzzer_sys::fuzz_target!(|data: &[u8]| sweetspot_fuzz::node_messages(data));
