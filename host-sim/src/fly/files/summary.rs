//! `summary.json`: the a-priori bounds, observed extremes, final errors and settling times.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

use crate::fly::sim::Summary;

/// Writes `summary` to `path` as pretty-printed JSON followed by a newline. Overwrites `path`.
///
/// Units are in the field names (see [`Summary`]); non-finite numbers become `null`.
///
/// Errors: `path` cannot be created or written (the error names it).
pub fn write_summary(path: &Path, summary: &Summary) -> Result<()> {
    let context = || format!("writing {}", path.display());
    let file = std::fs::File::create(path).with_context(context)?;
    let mut out = std::io::BufWriter::new(file);
    serde_json::to_writer_pretty(&mut out, summary).with_context(context)?;
    out.write_all(b"\n").with_context(context)?;
    // Flushing explicitly: BufWriter's drop swallows write errors.
    out.flush().with_context(context)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::files::test_support::{synthetic_summary, temp_dir};

    #[test]
    fn writes_pretty_json_with_the_serde_names() {
        let dir = temp_dir("summary");
        let path = dir.join("summary.json");
        write_summary(&path, &synthetic_summary()).expect("write");
        let text = std::fs::read_to_string(&path).expect("read");
        assert!(text.ends_with("}\n"));
        assert!(text.contains("\n  \"a_priori\": {"), "{text}");
        let v: serde_json::Value = serde_json::from_str(&text).expect("json");
        assert_eq!(v["a_priori"]["thrust_min_N"], 3.51);
        assert_eq!(v["final"]["time_s"], 0.02);
        assert_eq!(v["precision"], "f32");
        assert!(v["settling"]["mrp_error_below_1e_4_from_s"].is_null());
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn error_names_the_file() {
        let path = temp_dir("summary-err").join("missing-dir").join("s.json");
        let e = write_summary(&path, &synthetic_summary()).expect_err("no such directory");
        assert!(
            format!("{e:#}").contains(&path.display().to_string()),
            "{e:#}"
        );
    }
}
