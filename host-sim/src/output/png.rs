//! PNG files: the embedded font registered once for plotters, and a drawing written to a file
//! whose errors name it.

use super::chart::FONT;
use anyhow::{bail, Context, Result};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::Path;
use std::sync::OnceLock;

/// plotters' `ab_glyph` text renderer draws nothing until a font is registered; registering is
/// global, so it happens once per process.
pub(crate) fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok());
    if !ok {
        bail!("plotters refused the embedded DejaVu Sans font");
    }
    Ok(())
}

/// Creates a PNG of `size` at `path`, lets `paint` fill it, and saves it.
pub(crate) fn write_png(
    path: &Path,
    size: (u32, u32),
    paint: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    let context = || format!("writing {}", path.display());
    let root = BitMapBackend::new(path, size).into_drawing_area();
    paint(&root).with_context(context)?;
    // Saving explicitly: the backend's drop would swallow an I/O error.
    root.present().with_context(context)?;
    Ok(())
}
