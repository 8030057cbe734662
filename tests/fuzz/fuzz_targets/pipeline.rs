//! libFuzzer entry point of [`fuzz::targets::pipeline`] (its invariants are documented there).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::targets::pipeline::run(data));
