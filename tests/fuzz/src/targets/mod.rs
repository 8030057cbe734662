//! The fuzz targets as plain functions of the input bytes: each panics (with the invariant
//! that failed) on a defect, and returns normally otherwise. The `fuzz_targets/` binaries
//! call them; regression tests replay saved inputs through them.

pub mod link_decoder;
pub mod pipeline;
pub mod scenario_toml;
pub mod vehicle_toml;

/// The input as UTF-8 text, `None` when it is not (the TOML parsers take `&str`: a file that
/// is not UTF-8 is refused before them, by `read_to_string`).
pub(crate) fn text(data: &[u8]) -> Option<&str> {
    std::str::from_utf8(data).ok()
}
