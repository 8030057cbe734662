//! Parsers of what a bench run prints: the bench's semihosting output (region outputs as `f32`
//! bit patterns) and the counting plugin's file.

use anyhow::{anyhow, bail, ensure, Context, Result};

use firmware::step_inputs::Record;

use super::regions::Kind;

/// Parses the bench's semihosting output: one `(kind, index, outputs)` per region.
/// Errors: a malformed line, a missing `DONE`, a flight step off the flight path.
pub fn parse_bench_output(text: &str) -> Result<Vec<(Kind, u32, Vec<f32>)>> {
    let mut regions = Vec::new();
    let mut done = None;
    for line in text.lines() {
        let mut f = line.split_whitespace();
        let tag = match f.next() {
            Some(t) => t,
            None => continue,
        };
        let (kind, n) = match tag {
            "Z" => (Kind::Empty, 0),
            "A" => (Kind::Arm, 8),
            "F" => (Kind::Full, 8),
            "C" => (Kind::Controller, 4),
            "DONE" => {
                done = Some(line.to_string());
                continue;
            }
            "PANIC" | "HARDFAULT" => bail!("the bench failed on the MCU: {line}"),
            _ => continue,
        };
        let index: u32 = f
            .next()
            .ok_or_else(|| anyhow!("no index in {line:?}"))?
            .parse()
            .with_context(|| format!("bad index in {line:?}"))?;
        let outputs = f
            .map(|h| u32::from_str_radix(h, 16).map(f32::from_bits))
            .collect::<Result<Vec<f32>, _>>()
            .with_context(|| format!("bad bit pattern in {line:?}"))?;
        ensure!(outputs.len() == n, "expected {n} values in {line:?}");
        regions.push((kind, index, outputs));
    }
    let done = done.ok_or_else(|| anyhow!("the bench did not finish (no DONE line)"))?;
    ensure!(
        done.contains(&format!("regions={}", regions.len())),
        "region count mismatch: {done} vs {} lines",
        regions.len()
    );
    ensure!(
        done.contains("off_path=0"),
        "some flight steps did not run the flight path: {done}"
    );
    Ok(regions)
}

/// Formats host records the way the bench prints its regions (without the empty ones), so that
/// [`parse_bench_output`] reads them back: a reference of today's host outputs to compare later
/// builds against (`m4f-bench --write-host`, `--host-reference`).
pub fn format_records(records: &[Record]) -> String {
    let mut text = String::new();
    for r in records {
        let (t, i, v): (&str, u32, &[f32]) = match r {
            Record::Arm(i, o) => ("A", *i, o),
            Record::Full(i, o) => ("F", *i, o),
            Record::Controller(i, o) => ("C", *i, o),
        };
        text.push_str(&format!("{t} {i}"));
        for x in v {
            text.push_str(&format!(" {:08x}", x.to_bits()));
        }
        text.push('\n');
    }
    text.push_str(&format!("DONE regions={} off_path=0\n", records.len()));
    text
}

/// Parses the plugin's output: the count of every region, and the total.
pub fn parse_plugin_output(text: &str) -> Result<(Vec<u64>, u64)> {
    let mut counts = Vec::new();
    let mut total = None;
    for line in text.lines() {
        let mut f = line.split_whitespace();
        if f.next() != Some("insn_count") {
            continue;
        }
        match f.next() {
            Some("region") => {
                let i: usize = f.next().unwrap_or("").parse()?;
                ensure!(i == counts.len(), "plugin regions out of order");
                counts.push(f.next().unwrap_or("").parse()?);
            }
            Some("done") => {
                for kv in f {
                    if let Some(v) = kv.strip_prefix("unmatched=") {
                        ensure!(v == "0", "unmatched markers: {line}");
                    }
                    if let Some(v) = kv.strip_prefix("total=") {
                        total = Some(v.parse()?);
                    }
                }
            }
            _ => {}
        }
    }
    let total = total.ok_or_else(|| anyhow!("no summary line from the plugin"))?;
    Ok((counts, total))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_bench_and_plugin_output() {
        let out = "Z 0\nA 110 3f800000 0 0 0 40000000 0 0 0\nF 1 3f800000 3f800000 3f800000 3f800000 40900000 0 0 80000000\nC 1 40900000 0 0 0\nDONE regions=4 off_path=0\n";
        let r = parse_bench_output(out).unwrap();
        assert_eq!(r.len(), 4);
        assert_eq!(r[1].0, Kind::Arm);
        assert_eq!(r[2].2[4], 4.5);
        assert!(r[2].2[7] == 0.0 && r[2].2[7].is_sign_negative());
        assert!(parse_bench_output("Z 0\nDONE regions=1 off_path=3\n").is_err());
        assert!(parse_bench_output("Z 0\n").is_err());
        let records = [
            Record::Arm(110, [1.0, 0.5, -0.0, 0.0, 4.5, 1e-3, -2e-3, 3e-3]),
            Record::Controller(1, [4.5, 0.0, f32::MIN_POSITIVE, -1.0]),
        ];
        let back = parse_bench_output(&format_records(&records)).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!((back[0].0, back[0].1), (Kind::Arm, 110));
        assert_eq!((back[1].0, back[1].1), (Kind::Controller, 1));
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        match records[0] {
            Record::Arm(_, o) => assert_eq!(bits(&back[0].2), bits(&o)),
            _ => unreachable!(),
        }
        let (c, t) = parse_plugin_output(
            "insn_count region 0 5\ninsn_count region 1 70\ninsn_count done regions=2 unmatched=0 total=99\n",
        )
        .unwrap();
        assert_eq!((c, t), (vec![5, 70], 99));
        assert!(parse_plugin_output("insn_count done regions=0 unmatched=1 total=9\n").is_err());
    }
}
