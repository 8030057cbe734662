//! libFuzzer entry point of [`fuzz::targets::scenario_toml`] (its invariants are documented there).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::targets::scenario_toml::run(data));
