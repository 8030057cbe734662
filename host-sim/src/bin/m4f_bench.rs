//! `m4f-bench`: Cortex-M4F instruction counts of the firmware's control step under QEMU, and the
//! ARM-vs-host agreement of its outputs (see `host_sim::harness::m4f`). Usually run through
//! `bash firmware/qemu/bench.sh [--budget N]`, which builds the plugin and the ELF first.
//!
//! Exit status: 0 when everything agrees (and the largest full step is within `--budget`),
//! 1 on a disagreement or an exceeded budget, 2 when the bench could not run.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::Parser;
use host_sim::harness::m4f::{self, BenchOptions};

/// Count the instructions of the firmware's control step on an emulated Cortex-M4F (QEMU
/// mps2-an386 + the insn_count TCG plugin) and check its f32 outputs against the host.
#[derive(Parser, Debug)]
#[command(name = "m4f-bench")]
struct Args {
    /// The step-bench ELF (default: $CARGO_TARGET_DIR or ./target, then
    /// thumbv7em-none-eabihf/release/step-bench).
    #[arg(long)]
    elf: Option<PathBuf>,
    /// The TCG plugin (default: $CARGO_TARGET_DIR or ./target, then qemu/libinsn_count.so).
    #[arg(long)]
    plugin: Option<PathBuf>,
    /// The QEMU executable.
    #[arg(long, default_value = "qemu-system-arm")]
    qemu: PathBuf,
    /// Fail (exit 1) when a flight tick's full step exceeds this many instructions.
    #[arg(long)]
    budget: Option<u64>,
    /// Write the figures as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Also recount the first regions (the empty ones, the arming tick and the first flight
    /// tick) from QEMU's single-step execution trace and require the same counts.
    #[arg(long)]
    cross_check: bool,
    /// Also print a per-function profile of the measured regions (top N functions).
    #[arg(long, value_name = "N")]
    profile: Option<usize>,
    /// Write this build's host outputs here, in the bench's output format: a reference for
    /// `--host-reference` after a change to the step.
    #[arg(long, value_name = "FILE")]
    write_host: Option<PathBuf>,
    /// Also compare this build's host outputs with a reference written by `--write-host`,
    /// with the ARM-vs-host tolerance and floors (exit 1 on a disagreement): a change to the
    /// step must keep every output within them of the reference's.
    #[arg(long, value_name = "FILE")]
    host_reference: Option<PathBuf>,
    /// Only the host side (`--write-host`, `--host-reference`): no QEMU, no ELF.
    #[arg(long)]
    host_only: bool,
    /// Give up on a QEMU run after this many seconds.
    #[arg(long, default_value_t = 300)]
    timeout_s: u64,
}

fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target"))
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("m4f-bench: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// The host-side options: writes the host records, compares them with a reference. Returns
/// false on a disagreement with the reference.
fn host_side(args: &Args, host: &[firmware::step_inputs::Record]) -> Result<bool> {
    if let Some(path) = &args.write_host {
        std::fs::write(path, m4f::format_records(host))
            .with_context(|| format!("writing {}", path.display()))?;
    }
    let Some(path) = &args.host_reference else {
        return Ok(true);
    };
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let regions = m4f::parse_bench_output(&text)
        .with_context(|| format!("parsing {}", path.display()))?
        .into_iter()
        .map(m4f::Region::from)
        .collect();
    let reference = m4f::ArmRun {
        regions,
        overhead: 0,
        total_instructions: 0,
    };
    let a = m4f::compare(&reference, host, &m4f::Floors::paper()?)?;
    println!(
        "host vs reference {}: {} values, {} bit-identical, largest relative difference {:.2e} \
         ({}), {:.2e} leaving out the {} values that needed their floor; {} outside the tolerance",
        path.display(),
        a.compared,
        a.bit_identical,
        a.max_relative_difference,
        a.worst,
        a.max_relative_difference_within_tolerance,
        a.passed_by_floor,
        a.failures.len()
    );
    for line in a.failures.iter().take(20) {
        println!("  disagreement (reference = \"ARM\"): {line}");
    }
    Ok(a.failures.is_empty())
}

fn run(args: &Args) -> Result<bool> {
    let host = m4f::host_records()?;
    let host_ok = host_side(args, &host)?;
    if args.host_only {
        return Ok(host_ok);
    }
    let q = BenchOptions {
        program: args.qemu.clone(),
        elf: args
            .elf
            .clone()
            .unwrap_or_else(|| target_dir().join("thumbv7em-none-eabihf/release/step-bench")),
        plugin: args
            .plugin
            .clone()
            .unwrap_or_else(|| target_dir().join("qemu/libinsn_count.so")),
        timeout: Duration::from_secs(args.timeout_s),
    };
    let markers = m4f::markers(&q.elf)?;
    let profile_path = args.profile.map(|_| {
        std::env::temp_dir().join(format!("m4f-bench-profile-{}.txt", std::process::id()))
    });
    let arm = m4f::run_arm(&q, &markers, profile_path.as_deref())?;
    let floors = m4f::Floors::paper()?;
    let agreement = m4f::compare(&arm, &host, &floors)?;
    let agree = agreement.failures.is_empty();
    let f = m4f::figures(&q.elf, &arm, agreement, floors, args.budget)?;
    print!("{}", m4f::render(&f));
    for line in f.agreement.failures.iter().take(20) {
        println!("  disagreement: {line}");
    }
    if let (Some(top), Some(p)) = (args.profile, &profile_path) {
        let text = std::fs::read_to_string(p).context("reading the plugin profile")?;
        let _ = std::fs::remove_file(p);
        print!("{}", m4f::profile(&q.elf, &text, top)?);
    }
    let mut ok = agree && host_ok;
    if args.cross_check {
        let n = arm
            .regions
            .iter()
            .position(|r| r.kind == m4f::Kind::Full)
            .map_or(arm.regions.len(), |i| i + 1);
        let traced = m4f::cross_check(&q, &markers, n)?;
        let plugin: Vec<u64> = arm.regions[..n]
            .iter()
            .map(|r| r.raw_instructions)
            .collect();
        let same = traced == plugin;
        println!(
            "cross-check against `-singlestep -d exec,nochain` (first {n} regions, raw counts): \
             trace {traced:?}, plugin {plugin:?}: {}",
            if same { "identical" } else { "DIFFERENT" }
        );
        ok &= same;
    }
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_string_pretty(&f)? + "\n")
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(b) = &f.budget {
        ok &= b.within;
    }
    Ok(ok)
}
