//! The bench on QEMU, through the harnesses' one process runner ([`Qemu`]): the counting run
//! ([`run_arm`]) and the independent recount from QEMU's execution trace ([`cross_check`]).

use std::fmt::Write as _;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{anyhow, ensure, Context, Result};

use super::elf::Markers;
use super::output::{parse_bench_output, parse_plugin_output};
use super::regions::{ArmRun, Kind, Region};
use crate::harness::qemu::{semihosting_args, Io, Qemu};

/// How to run the bench on QEMU.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// The `qemu-system-arm` executable.
    pub program: PathBuf,
    /// The step-bench ELF.
    pub elf: PathBuf,
    /// The plugin (`libinsn_count.so`).
    pub plugin: PathBuf,
    /// Give up after this long.
    pub timeout: Duration,
}

/// Runs the bench under QEMU with the counting plugin (and, if `profile` is given, writes the
/// plugin's per-block profile there). Errors: QEMU fails or times out, the bench fails, the
/// counts do not match the regions, the empty regions disagree.
pub fn run_arm(q: &BenchOptions, m: &Markers, profile: Option<&Path>) -> Result<ArmRun> {
    let dir = std::env::temp_dir().join(format!("m4f-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let counts_path = dir.join("counts.txt");
    let mut plugin = format!(
        "{},begin={:#x},end={:#x},out={}",
        q.plugin.display(),
        m.begin,
        m.end,
        counts_path.display()
    );
    if let Some(p) = profile {
        write!(plugin, ",profile={}", p.display())?;
    }
    let mut args = semihosting_args(&q.elf);
    args.extend(["-plugin".into(), plugin.into()]);
    let finished = Qemu::spawn(&q.program, args, Io::Capture)?.finish(q.timeout)?;
    let (code, stdout, stderr) = (finished.code, finished.stdout, finished.stderr);
    let counts_text = std::fs::read_to_string(&counts_path).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    ensure!(
        code == Some(0),
        "QEMU exited with {code:?}\nstdout tail:\n{}\nstderr:\n{stderr}",
        tail(&stdout, 5)
    );
    let parsed = parse_bench_output(&stdout)?;
    let (counts, total) = parse_plugin_output(&counts_text)
        .with_context(|| format!("plugin output:\n{}", tail(&counts_text, 3)))?;
    ensure!(
        counts.len() == parsed.len(),
        "{} counted regions for {} printed ones",
        counts.len(),
        parsed.len()
    );
    let regions: Vec<Region> = parsed
        .into_iter()
        .zip(counts)
        .map(|((kind, index, outputs), raw_instructions)| Region {
            kind,
            index,
            raw_instructions,
            outputs,
        })
        .collect();
    let empty: Vec<u64> = regions
        .iter()
        .filter(|r| r.kind == Kind::Empty)
        .map(|r| r.raw_instructions)
        .collect();
    ensure!(!empty.is_empty(), "no empty region to measure the overhead");
    ensure!(
        empty.iter().all(|&c| c == empty[0]),
        "the empty regions disagree: {empty:?}"
    );
    Ok(ArmRun {
        regions,
        overhead: empty[0],
        total_instructions: total,
    })
}

fn tail(s: &str, n: usize) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

/// Recounts the first `regions` regions from QEMU's execution trace, without the plugin:
/// `-singlestep` makes every translation block one instruction and `-d exec,nochain` logs
/// every executed block (`Trace …[flags/PC/…]`); a region is the number of trace lines from
/// the begin marker's entry (inclusive) to the end marker's entry (exclusive). QEMU is stopped
/// once the regions are counted.
pub fn cross_check(q: &BenchOptions, m: &Markers, regions: usize) -> Result<Vec<u64>> {
    let mut args = semihosting_args(&q.elf);
    args.extend(["-singlestep", "-d", "exec,nochain"].map(Into::into));
    let mut qemu = Qemu::spawn(&q.program, args, Io::StreamStderr)?;
    let err = qemu.take_stderr().context("QEMU stderr not piped")?;
    let reader = BufReader::with_capacity(1 << 20, err);
    let mut counts = Vec::new();
    let mut current: Option<u64> = None;
    let start = Instant::now();
    for line in reader.lines() {
        let line = line?;
        let Some(rest) = line.strip_prefix("Trace ") else {
            continue;
        };
        // "0: 0x7f.. [00800408/00002c0a/00000010/ff000201] symbol"
        let pc = rest
            .split('[')
            .nth(1)
            .and_then(|x| x.split('/').nth(1))
            .and_then(|h| u64::from_str_radix(h, 16).ok())
            .ok_or_else(|| anyhow!("unexpected trace line {line:?}"))?;
        if pc == m.end {
            if let Some(n) = current.take() {
                counts.push(n);
                if counts.len() == regions {
                    break;
                }
            }
        }
        if pc == m.begin {
            current = Some(0);
        }
        if let Some(n) = current.as_mut() {
            *n += 1;
        }
        if start.elapsed() > q.timeout {
            break;
        }
    }
    qemu.stop();
    ensure!(
        counts.len() == regions,
        "the trace gave {} regions of {regions} (timeout?)",
        counts.len()
    );
    Ok(counts)
}
