//! libFuzzer entry point of [`fuzz::targets::link_decoder`] (its invariants are documented there).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::targets::link_decoder::run(data));
