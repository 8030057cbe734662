//! `timeseries.csv`: one row per controller sample, one column per [`Record`] field.

use std::path::Path;

use anyhow::{Context, Result};

use crate::fly::sim::Record;

/// Writes `records` to `path` as CSV: a header row of the [`Record`] field names (which carry
/// the units, e.g. `thrust_N`), then one row per record in order. Overwrites `path`.
///
/// An empty `records` gives an empty file: the header comes from serialising the first row.
///
/// Errors: `path` cannot be created or written (the error names it).
pub fn write_csv(path: &Path, records: &[Record]) -> Result<()> {
    let context = || format!("writing {}", path.display());
    let mut writer = ::csv::Writer::from_path(path).with_context(context)?;
    for record in records {
        writer.serialize(record).with_context(context)?;
    }
    // Flushing explicitly: errors on drop would be lost.
    writer.flush().with_context(context)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::files::test_support::{synthetic_records, temp_dir};

    #[test]
    fn header_and_values_round_trip() {
        let dir = temp_dir("csv");
        let path = dir.join("t.csv");
        let records = synthetic_records(3);
        write_csv(&path, &records).expect("write");

        let mut reader = ::csv::Reader::from_path(&path).expect("read");
        let header: Vec<String> = reader
            .headers()
            .expect("header")
            .iter()
            .map(str::to_owned)
            .collect();
        assert_eq!(header.len(), 27);
        assert_eq!(header[0], "t_s");
        assert!(header.iter().any(|h| h == "thrust_N"));
        assert!(header.iter().any(|h| h == "torque_x_Nm"));
        assert_eq!(header.last().map(String::as_str), Some("m_flips"));

        let rows: Vec<::csv::StringRecord> = reader.records().map(|r| r.expect("row")).collect();
        assert_eq!(rows.len(), 3);
        let column = |name: &str| header.iter().position(|h| h == name).expect("column");
        for (row, rec) in rows.iter().zip(&records) {
            let value = |name: &str| row[column(name)].parse::<f64>().expect("number");
            // Shortest round-trip formatting: values come back bit for bit.
            assert_eq!(value("t_s"), rec.t_s);
            assert_eq!(value("x_m"), rec.x_m);
            assert_eq!(value("thrust_N"), rec.thrust_N);
            assert_eq!(value("torque_y_Nm"), rec.torque_y_Nm);
            assert_eq!(value("mrp_error"), rec.mrp_error);
            assert_eq!(value("m_flips"), f64::from(rec.m_flips));
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn error_names_the_file() {
        let path = temp_dir("csv-err").join("missing-dir").join("t.csv");
        let e = write_csv(&path, &synthetic_records(2)).expect_err("no such directory");
        assert!(
            format!("{e:#}").contains(&path.display().to_string()),
            "{e:#}"
        );
    }
}
