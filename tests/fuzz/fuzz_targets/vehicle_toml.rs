//! libFuzzer entry point of [`fuzz::targets::vehicle_toml`] (its invariants are documented there).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::targets::vehicle_toml::run(data));
