//! Cortex-M4F instruction counts of the firmware's control step, and the agreement of its `f32`
//! outputs on ARM with the same computation on the host.
//!
//! The firmware's `step-bench` binary (`firmware/src/bin/step_bench`) runs the deterministic
//! sequence of [`firmware::step_inputs`] on QEMU's `mps2-an386` (Cortex-M4 with FPU) and
//! brackets every measured step with calls to `step_bench_begin` / `step_bench_end`. The TCG
//! plugin `firmware/qemu/insn_count.c`, given those functions' addresses (read here from the
//! ELF's symbol table), counts the guest instructions executed from the entry of the first to
//! the entry of the second. The first regions are empty: their count is the brackets' own
//! overhead, subtracted from every step. The binary prints each step's outputs as `f32` bit
//! patterns over semihosting; [`compare`] checks them against [`step_inputs::run_sequence`] run
//! natively.
//!
//! Instructions are not cycles: at 1 instruction per cycle, 168 MHz (the STM32F405's clock)
//! gives a **lower bound** on the time (flash wait states, FPU divide/square-root latencies,
//! load-use stalls and taken branches all add cycles on the real MCU).
//!
//! [`cross_check`] recounts the first regions independently from QEMU's own execution trace
//! (`-singlestep -d exec,nochain`: one translation block per instruction, one `Trace` line per
//! executed block).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, ensure, Context, Result};
use firmware::config::FlightConfig;
use firmware::step_inputs::{self, Record};
use serde::Serialize;

/// The STM32F405's core clock \[Hz\] (the time implied by an instruction count assumes one
/// instruction per cycle: a lower bound).
pub const CORE_HZ: f64 = 168e6;
/// Relative tolerance between the ARM and the host outputs.
pub const RELATIVE_TOLERANCE: f64 = 1e-5;
/// Symbol of the function that opens a measured region.
pub const BEGIN_SYMBOL: &str = "step_bench_begin";
/// Symbol of the function that closes a measured region.
pub const END_SYMBOL: &str = "step_bench_end";

/// What a measured region is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Kind {
    /// Nothing between the brackets: their own overhead.
    Empty,
    /// The arming tick's full step (IMU, pose + arm + mission-start commands, tick).
    Arm,
    /// A flight tick's full step.
    Full,
    /// A controller-core step alone.
    Controller,
}

/// One region measured on the MCU.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// What it is.
    pub kind: Kind,
    /// Tick (arming), flight tick `1..=FLIGHT_TICKS` (full, controller) or index (empty).
    pub index: u32,
    /// Instructions counted between the brackets, overhead included.
    pub raw_instructions: u64,
    /// Outputs (see [`step_inputs::FullOutputs`], [`step_inputs::ControllerOutputs`]).
    pub outputs: Vec<f32>,
}

/// Everything one QEMU run of the bench gave.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmRun {
    /// The regions, in execution order.
    pub regions: Vec<Region>,
    /// The brackets' overhead [instructions] (the empty regions' count; they must agree).
    pub overhead: u64,
    /// Instructions executed by the whole program.
    pub total_instructions: u64,
}

impl ArmRun {
    /// Instruction counts of the regions of `kind`, overhead removed.
    pub fn instructions(&self, kind: Kind) -> Vec<u64> {
        self.regions
            .iter()
            .filter(|r| r.kind == kind)
            .map(|r| r.raw_instructions.saturating_sub(self.overhead))
            .collect()
    }
}

/// The marker functions' addresses (Thumb bit cleared).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Markers {
    /// Entry of [`BEGIN_SYMBOL`].
    pub begin: u64,
    /// Entry of [`END_SYMBOL`].
    pub end: u64,
}

/// How to run QEMU.
#[derive(Clone, Debug)]
pub struct Qemu {
    /// The `qemu-system-arm` executable.
    pub program: PathBuf,
    /// The step-bench ELF.
    pub elf: PathBuf,
    /// The plugin (`libinsn_count.so`).
    pub plugin: PathBuf,
    /// Give up after this long.
    pub timeout: Duration,
}

fn u16_at(b: &[u8], o: usize) -> Result<u16> {
    Ok(u16::from_le_bytes(
        b.get(o..o + 2)
            .ok_or_else(|| anyhow!("ELF truncated"))?
            .try_into()?,
    ))
}

fn u32_at(b: &[u8], o: usize) -> Result<u32> {
    Ok(u32::from_le_bytes(
        b.get(o..o + 4)
            .ok_or_else(|| anyhow!("ELF truncated"))?
            .try_into()?,
    ))
}

/// The function symbols of a little-endian ELF32 file (`.symtab`): `(name, address)` with the
/// Thumb bit cleared. Errors: not an ELF32 little-endian file, or no symbol table.
pub fn elf32_functions(elf: &[u8]) -> Result<Vec<(String, u64)>> {
    ensure!(
        elf.len() > 52 && &elf[..4] == b"\x7fELF" && elf[4] == 1 && elf[5] == 1,
        "not a little-endian ELF32 file"
    );
    let shoff = u32_at(elf, 0x20)? as usize;
    let shentsize = u16_at(elf, 0x2e)? as usize;
    let shnum = u16_at(elf, 0x30)? as usize;
    let section = |i: usize| -> Result<(u32, usize, usize, u32, usize)> {
        let o = shoff + i * shentsize;
        Ok((
            u32_at(elf, o + 4)?,           // sh_type
            u32_at(elf, o + 16)? as usize, // sh_offset
            u32_at(elf, o + 20)? as usize, // sh_size
            u32_at(elf, o + 24)?,          // sh_link
            u32_at(elf, o + 36)? as usize, // sh_entsize
        ))
    };
    let mut out = Vec::new();
    for i in 0..shnum {
        let (kind, off, size, link, entsize) = section(i)?;
        if kind != 2 {
            continue; // SHT_SYMTAB only
        }
        let (_, str_off, str_size, _, _) = section(link as usize)?;
        let strtab = elf
            .get(str_off..str_off + str_size)
            .ok_or_else(|| anyhow!("ELF string table truncated"))?;
        let entsize = if entsize == 0 { 16 } else { entsize };
        for s in (off..off + size).step_by(entsize) {
            let name_off = u32_at(elf, s)? as usize;
            let value = u32_at(elf, s + 4)?;
            let info = *elf.get(s + 12).ok_or_else(|| anyhow!("ELF truncated"))?;
            if info & 0xf != 2 {
                continue; // STT_FUNC only
            }
            let end = strtab[name_off..]
                .iter()
                .position(|&c| c == 0)
                .map_or(strtab.len(), |p| name_off + p);
            let name = String::from_utf8_lossy(&strtab[name_off..end]).into_owned();
            out.push((name, u64::from(value & !1)));
        }
    }
    ensure!(
        !out.is_empty(),
        "the ELF has no function symbols (stripped?)"
    );
    Ok(out)
}

/// The addresses of the bench's marker functions in `elf`.
pub fn markers(elf: &Path) -> Result<Markers> {
    let bytes = std::fs::read(elf).with_context(|| format!("reading {}", elf.display()))?;
    let functions = elf32_functions(&bytes)?;
    // mps2-an386 runs code from SSRAM1 at 0; an entry in the STM32's flash (0x0800_0000)
    // means the ELF was linked with the wrong memory map and would lock up at reset.
    let entry = u32_at(&bytes, 0x18)?;
    ensure!(
        entry < 0x0040_0000,
        "{}: entry point {entry:#010x} is outside mps2-an386's code memory (0..4 MiB): \
         linked with another board's memory.x?",
        elf.display()
    );
    let find = |name: &str| {
        functions
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, a)| *a)
            .ok_or_else(|| anyhow!("{} has no symbol {name}", elf.display()))
    };
    Ok(Markers {
        begin: find(BEGIN_SYMBOL)?,
        end: find(END_SYMBOL)?,
    })
}

fn qemu_command(q: &Qemu) -> Command {
    let mut c = Command::new(&q.program);
    c.args(["-M", "mps2-an386", "-nographic", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .arg("-kernel")
        .arg(&q.elf);
    c
}

/// Runs `c` to completion (killing it after `timeout`), returning its exit code, stdout and
/// stderr.
fn run_with_timeout(mut c: Command, timeout: Duration) -> Result<(Option<i32>, String, String)> {
    let mut child = c
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .context("starting qemu-system-arm (is QEMU installed?)")?;
    let mut out = child.stdout.take().expect("piped");
    let mut err = child.stderr.take().expect("piped");
    let out_thread = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out.read_to_string(&mut s);
        s
    });
    let err_thread = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait()? {
            break s;
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            bail!("QEMU did not finish within {} s", timeout.as_secs());
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stdout = out_thread.join().unwrap_or_default();
    let stderr = err_thread.join().unwrap_or_default();
    Ok((status.code(), stdout, stderr))
}

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

/// Runs the bench under QEMU with the counting plugin (and, if `profile` is given, writes the
/// plugin's per-block profile there). Errors: QEMU fails or times out, the bench fails, the
/// counts do not match the regions, the empty regions disagree.
pub fn run_arm(q: &Qemu, m: &Markers, profile: Option<&Path>) -> Result<ArmRun> {
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
    let mut c = qemu_command(q);
    c.arg("-plugin").arg(plugin);
    let (code, stdout, stderr) = run_with_timeout(c, q.timeout)?;
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

/// The same records computed natively (see [`step_inputs::run_sequence`]). Errors: a host
/// flight step left the flight path.
pub fn host_records() -> Result<Vec<Record>> {
    let mut records = Vec::new();
    let ok = step_inputs::run_sequence(|r| records.push(r));
    ensure!(
        ok,
        "on the host, some flight steps did not run the flight path"
    );
    Ok(records)
}

/// Absolute floors of the comparison, for outputs that can be close to zero (torques): the
/// tolerance `1e-5` applied to the magnitude of the terms the value is a sum of, instead of to
/// the value itself. Two computations that agree to `1e-5` relative in every term agree to
/// `1e-5 Σ|terms|` in the sum; when the terms cancel, the value alone says nothing.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Floors {
    /// Controller torque, per axis [N m]: `1e-5 ×` Theorem 2's a-priori bound on `|τ_i|` (the
    /// certificate of the paper set-up, a sum of bounds of the law's terms).
    pub controller_torque: [f64; 3],
    /// Mixer torque, per axis, per unit of `Σ_k |B_ik| f_k` [N m / N m]: the achieved torque is
    /// `Σ_k B_ik f_k` over the rotor thrusts `f_k` (recovered from the step's throttles).
    pub mixer_torque_relative: f64,
}

impl Floors {
    /// The floors of the paper set-up.
    pub fn paper() -> Result<Self> {
        let p = firmware::pipeline::FlightPipeline::new(&FlightConfig::paper())
            .map_err(|e| anyhow!("paper pipeline refused: {e:?}"))?;
        let b = p.boot_report().certificate.bounds.torque_max;
        Ok(Self {
            controller_torque: [b.x, b.y, b.z].map(|x| RELATIVE_TOLERANCE * f64::from(x)),
            mixer_torque_relative: RELATIVE_TOLERANCE,
        })
    }
}

/// The outcome of the ARM-vs-host comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Agreement {
    /// Values compared.
    pub compared: usize,
    /// Largest `|a − b| / max(|a|, |b|)` over all values (0 when both are 0).
    pub max_relative_difference: f64,
    /// Where it was (`"F 12 throttle[2]"`).
    pub worst: String,
    /// Largest relative difference among the full steps (arming tick included).
    pub max_relative_difference_full: f64,
    /// Largest relative difference among the controller steps.
    pub max_relative_difference_controller: f64,
    /// Largest relative difference among the values within the relative tolerance (that is,
    /// leaving out those that needed their floor: cancellations).
    pub max_relative_difference_within_tolerance: f64,
    /// Values that passed only thanks to their absolute floor.
    pub passed_by_floor: usize,
    /// Those values (first 20): where, both values, the difference and the floor.
    pub floor_cases: Vec<String>,
    /// Values outside the tolerance (empty when everything agrees).
    pub failures: Vec<String>,
    /// Values whose bits are identical.
    pub bit_identical: usize,
}

const FULL_NAMES: [&str; 8] = [
    "throttle[0]",
    "throttle[1]",
    "throttle[2]",
    "throttle[3]",
    "mixer thrust",
    "mixer torque x",
    "mixer torque y",
    "mixer torque z",
];
const CONTROLLER_NAMES: [&str; 4] = ["thrust", "torque x", "torque y", "torque z"];

/// Compares the ARM regions with the host records, value by value:
/// `|a − b| ≤ 1e-5 · max(|a|, |b|)`, or below the value's absolute floor ([`Floors`]).
/// Errors: the two sequences do not line up (different kinds or indices).
pub fn compare(arm: &ArmRun, host: &[Record], floors: &Floors) -> Result<Agreement> {
    let measured: Vec<&Region> = arm
        .regions
        .iter()
        .filter(|r| r.kind != Kind::Empty)
        .collect();
    ensure!(
        measured.len() == host.len(),
        "{} regions on ARM, {} records on the host",
        measured.len(),
        host.len()
    );
    let rotors = FlightConfig::paper().rotors;
    let b = firmware::mixer::Mixer::new(&rotors)
        .map_err(|e| anyhow!("paper mixer refused: {e:?}"))?
        .effectiveness()
        .cast::<f64>();
    let mut a = Agreement {
        compared: 0,
        max_relative_difference: 0.0,
        worst: String::new(),
        max_relative_difference_full: 0.0,
        max_relative_difference_controller: 0.0,
        max_relative_difference_within_tolerance: 0.0,
        passed_by_floor: 0,
        floor_cases: Vec::new(),
        failures: Vec::new(),
        bit_identical: 0,
    };
    for (r, h) in measured.iter().zip(host) {
        let (kind, index, values, names): (Kind, u32, Vec<f32>, &[&str]) = match h {
            Record::Arm(i, o) => (Kind::Arm, *i, o.to_vec(), &FULL_NAMES),
            Record::Full(i, o) => (Kind::Full, *i, o.to_vec(), &FULL_NAMES),
            Record::Controller(i, o) => (Kind::Controller, *i, o.to_vec(), &CONTROLLER_NAMES),
        };
        ensure!(
            r.kind == kind && r.index == index,
            "sequence mismatch: ARM {:?} {} vs host {kind:?} {index}",
            r.kind,
            r.index
        );
        // Per-value floors.
        let mut floor = vec![0.0f64; values.len()];
        match kind {
            Kind::Controller => floor[1..4].copy_from_slice(&floors.controller_torque),
            Kind::Arm | Kind::Full => {
                let f: Vec<f64> = r.outputs[..4]
                    .iter()
                    .map(|&u| {
                        if u > 0.0 {
                            f64::from(rotors.thrust_from_throttle(u))
                        } else {
                            0.0
                        }
                    })
                    .collect();
                for axis in 0..3 {
                    let scale: f64 = (0..4).map(|k| b[(axis + 1, k)].abs() * f[k]).sum();
                    floor[5 + axis] = floors.mixer_torque_relative * scale;
                }
            }
            Kind::Empty => {}
        }
        for (i, (&x, &y)) in r.outputs.iter().zip(&values).enumerate() {
            a.compared += 1;
            let name = || format!("{} {} {}", tag(kind), index, names[i]);
            if x.to_bits() == y.to_bits() {
                a.bit_identical += 1;
                continue;
            }
            let (x, y) = (f64::from(x), f64::from(y));
            let diff = (x - y).abs();
            let scale = x.abs().max(y.abs());
            let rel = if scale > 0.0 { diff / scale } else { 0.0 };
            if rel.is_nan() || rel > a.max_relative_difference {
                a.max_relative_difference = rel;
                a.worst = name();
            }
            let per_kind = if kind == Kind::Controller {
                &mut a.max_relative_difference_controller
            } else {
                &mut a.max_relative_difference_full
            };
            *per_kind = per_kind.max(rel);
            if diff <= RELATIVE_TOLERANCE * scale {
                a.max_relative_difference_within_tolerance =
                    a.max_relative_difference_within_tolerance.max(rel);
                continue;
            }
            if diff <= floor[i] {
                a.passed_by_floor += 1;
                if a.floor_cases.len() < 20 {
                    a.floor_cases.push(format!(
                        "{}: ARM {x:e} vs host {y:e} (|diff| {diff:.3e}, floor {:.3e})",
                        name(),
                        floor[i]
                    ));
                }
                continue;
            }
            a.failures.push(format!(
                "{}: ARM {x:e} vs host {y:e} (|diff| {diff:.3e}, relative {rel:.3e}, floor {:.3e})",
                name(),
                floor[i]
            ));
        }
    }
    Ok(a)
}

fn tag(kind: Kind) -> &'static str {
    match kind {
        Kind::Empty => "Z",
        Kind::Arm => "A",
        Kind::Full => "F",
        Kind::Controller => "C",
    }
}

/// Min / median / max / mean of a set of instruction counts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stats {
    /// Number of steps.
    pub count: usize,
    /// Fewest instructions.
    pub min: u64,
    /// Median (lower median for an even count).
    pub median: u64,
    /// Most instructions.
    pub max: u64,
    /// Mean.
    pub mean: f64,
}

impl Stats {
    /// Statistics of `v`. Errors: `v` is empty.
    pub fn of(v: &[u64]) -> Result<Self> {
        ensure!(!v.is_empty(), "no steps");
        let mut s = v.to_vec();
        s.sort_unstable();
        Ok(Self {
            count: s.len(),
            min: s[0],
            median: s[(s.len() - 1) / 2],
            max: s[s.len() - 1],
            mean: s.iter().sum::<u64>() as f64 / s.len() as f64,
        })
    }
}

/// The figures of one step kind, with the implied times.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StepFigures {
    /// Instruction counts (overhead removed).
    pub instructions: Stats,
    /// Implied time at [`CORE_HZ`], 1 instruction per cycle (a lower bound) \[µs\]:
    /// min, median, max.
    pub lower_bound_us: [f64; 3],
    /// Share of the CPU at 100 Hz, worst step (lower bound), in percent.
    pub cpu_percent_100hz: f64,
    /// Share of the CPU at 1 kHz, worst step (lower bound), in percent.
    pub cpu_percent_1khz: f64,
}

impl StepFigures {
    /// The figures of counts `v`.
    pub fn of(v: &[u64]) -> Result<Self> {
        let s = Stats::of(v)?;
        let us = |n: u64| n as f64 / CORE_HZ * 1e6;
        Ok(Self {
            instructions: s,
            lower_bound_us: [us(s.min), us(s.median), us(s.max)],
            cpu_percent_100hz: us(s.max) / 10_000.0 * 100.0,
            cpu_percent_1khz: us(s.max) / 1_000.0 * 100.0,
        })
    }
}

/// The budget check.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Budget {
    /// Most instructions allowed for a flight tick's full step.
    pub limit: u64,
    /// The largest full step measured.
    pub max_full_step: u64,
    /// `max_full_step ≤ limit`.
    pub within: bool,
}

/// Everything the bench reports (the `--json` file).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Figures {
    /// The ELF measured.
    pub elf: String,
    /// Core clock assumed for the implied times \[Hz\].
    pub core_hz: f64,
    /// Bracket overhead subtracted from every count [instructions].
    pub overhead_instructions: u64,
    /// One flight tick: 10 IMU samples, a pose frame, `control_tick`.
    pub full_step: StepFigures,
    /// `Controller::step` alone.
    pub controller_step: StepFigures,
    /// The arming tick (also decodes the arm and mission-start commands: two certificates).
    pub arm_tick_instructions: u64,
    /// Instructions executed by the whole bench program.
    pub total_instructions: u64,
    /// ARM vs host.
    pub agreement: Agreement,
    /// The floors used.
    pub floors: Floors,
    /// The budget check, when one was given.
    pub budget: Option<Budget>,
}

/// Builds the figures of a run and its comparison.
pub fn figures(
    elf: &Path,
    arm: &ArmRun,
    agreement: Agreement,
    floors: Floors,
    budget: Option<u64>,
) -> Result<Figures> {
    let full = StepFigures::of(&arm.instructions(Kind::Full))?;
    let controller = StepFigures::of(&arm.instructions(Kind::Controller))?;
    let arm_tick = arm
        .instructions(Kind::Arm)
        .first()
        .copied()
        .ok_or_else(|| anyhow!("no arming tick measured"))?;
    Ok(Figures {
        elf: elf.display().to_string(),
        core_hz: CORE_HZ,
        overhead_instructions: arm.overhead,
        full_step: full,
        controller_step: controller,
        arm_tick_instructions: arm_tick,
        total_instructions: arm.total_instructions,
        agreement,
        floors,
        budget: budget.map(|limit| Budget {
            limit,
            max_full_step: full.instructions.max,
            within: full.instructions.max <= limit,
        }),
    })
}

/// The human-readable table.
pub fn render(f: &Figures) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Cortex-M4F (QEMU mps2-an386) instructions per step, bracket overhead ({} instructions) \
         removed; time at {:.0} MHz assuming 1 instruction/cycle is a LOWER BOUND (flash wait \
         states, FPU divide/sqrt latency and branches add cycles on the MCU)",
        f.overhead_instructions,
        f.core_hz / 1e6
    );
    let _ = writeln!(
        s,
        "| step | steps | instructions min / median / max | mean | µs min / median / max (≥) | CPU at 100 Hz (worst, ≥) | CPU at 1 kHz (worst, ≥) |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | --- | --- | --- |");
    for (name, x) in [
        (
            "full step (10 IMU samples + pose frame + control_tick)",
            &f.full_step,
        ),
        ("controller step (Controller::step)", &f.controller_step),
    ] {
        let i = &x.instructions;
        let _ = writeln!(
            s,
            "| {name} | {} | {} / {} / {} | {:.0} | {:.1} / {:.1} / {:.1} | {:.2} % | {:.1} % |",
            i.count,
            i.min,
            i.median,
            i.max,
            i.mean,
            x.lower_bound_us[0],
            x.lower_bound_us[1],
            x.lower_bound_us[2],
            x.cpu_percent_100hz,
            x.cpu_percent_1khz
        );
    }
    let _ = writeln!(
        s,
        "arming tick (arm + mission start: two certificates): {} instructions ({:.1} µs ≥)",
        f.arm_tick_instructions,
        f.arm_tick_instructions as f64 / f.core_hz * 1e6
    );
    let a = &f.agreement;
    let _ = writeln!(
        s,
        "ARM vs host: {} values, {} bit-identical, largest relative difference {:.3e} ({}; \
         full steps {:.3e}, controller steps {:.3e}; {:.3e} leaving out the floored ones), \
         {} within their absolute floor only, {} outside tolerance (1e-5 relative)",
        a.compared,
        a.bit_identical,
        a.max_relative_difference,
        if a.worst.is_empty() { "-" } else { &a.worst },
        a.max_relative_difference_full,
        a.max_relative_difference_controller,
        a.max_relative_difference_within_tolerance,
        a.passed_by_floor,
        a.failures.len()
    );
    for c in &a.floor_cases {
        let _ = writeln!(s, "  within the floor only: {c}");
    }
    if let Some(b) = &f.budget {
        let _ = writeln!(
            s,
            "budget: largest full step {} instructions, limit {} ({})",
            b.max_full_step,
            b.limit,
            if b.within { "ok" } else { "EXCEEDED" }
        );
    }
    s
}

/// Recounts the first `regions` regions from QEMU's execution trace, without the plugin:
/// `-singlestep` makes every translation block one instruction and `-d exec,nochain` logs
/// every executed block (`Trace …[flags/PC/…]`); a region is the number of trace lines from
/// the begin marker's entry (inclusive) to the end marker's entry (exclusive). QEMU is stopped
/// once the regions are counted.
pub fn cross_check(q: &Qemu, m: &Markers, regions: usize) -> Result<Vec<u64>> {
    let mut c = qemu_command(q);
    c.args(["-singlestep", "-d", "exec,nochain"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let mut child = c.spawn().context("starting qemu-system-arm")?;
    let err = child.stderr.take().expect("piped");
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
    let _ = child.kill();
    let _ = child.wait();
    ensure!(
        counts.len() == regions,
        "the trace gave {} regions of {regions} (timeout?)",
        counts.len()
    );
    Ok(counts)
}

/// A per-function profile of the measured regions from the plugin's block profile
/// (`tb <addr> <insns> <execs>` lines): instructions per function (the innermost symbol
/// covering each block; inlined code counts for its caller), most first. Function names are
/// demangled with `nm -C` when binutils is installed.
pub fn profile(elf: &Path, profile: &str, top: usize) -> Result<String> {
    let mut functions: Vec<(u64, String)> = match Command::new("nm").arg("-nC").arg(elf).output() {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter_map(|l| {
                let mut p = l.splitn(3, ' ');
                let a = u64::from_str_radix(p.next()?, 16).ok()?;
                let t = p.next()?;
                let name = p.next()?;
                (matches!(t, "t" | "T" | "w" | "W") && !name.starts_with('$'))
                    .then(|| (a & !1, name.to_string()))
            })
            .collect(),
        _ => {
            let bytes = std::fs::read(elf)?;
            elf32_functions(&bytes)?
                .into_iter()
                .map(|(n, a)| (a, n))
                .collect()
        }
    };
    functions.sort();
    let mut per: BTreeMap<String, u64> = BTreeMap::new();
    let mut total = 0u64;
    for line in profile.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() != 4 || f[0] != "tb" {
            continue;
        }
        let pc = u64::from_str_radix(f[1].trim_start_matches("0x"), 16)?;
        let n: u64 = f[2].parse::<u64>()? * f[3].parse::<u64>()?;
        total += n;
        let i = functions.partition_point(|(a, _)| *a <= pc);
        let name = if i == 0 {
            "?".to_string()
        } else {
            functions[i - 1].1.clone()
        };
        *per.entry(name).or_default() += n;
    }
    let mut v: Vec<(String, u64)> = per.into_iter().collect();
    v.sort_by_key(|e| std::cmp::Reverse(e.1));
    let mut s = format!("profile of all measured regions: {total} instructions\n");
    for (name, n) in v.into_iter().take(top) {
        let _ = writeln!(
            s,
            "{n:>10} {:>5.1} %  {}",
            100.0 * n as f64 / total.max(1) as f64,
            name.chars().take(140).collect::<String>()
        );
    }
    Ok(s)
}

impl From<(Kind, u32, Vec<f32>)> for Region {
    fn from((kind, index, outputs): (Kind, u32, Vec<f32>)) -> Self {
        Self {
            kind,
            index,
            raw_instructions: 0,
            outputs,
        }
    }
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
        let (c, t) = parse_plugin_output(
            "insn_count region 0 5\ninsn_count region 1 70\ninsn_count done regions=2 unmatched=0 total=99\n",
        )
        .unwrap();
        assert_eq!((c, t), (vec![5, 70], 99));
        assert!(parse_plugin_output("insn_count done regions=0 unmatched=1 total=9\n").is_err());
    }

    #[test]
    fn stats_and_times() {
        let s = Stats::of(&[5, 1, 3, 4]).unwrap();
        assert_eq!((s.min, s.median, s.max), (1, 3, 5));
        let f = StepFigures::of(&[168_000]).unwrap();
        assert!((f.lower_bound_us[2] - 1000.0).abs() < 1e-9);
        assert!((f.cpu_percent_100hz - 10.0).abs() < 1e-9);
        assert!((f.cpu_percent_1khz - 100.0).abs() < 1e-9);
    }

    /// The host records compare equal to themselves, and a perturbed value is caught.
    #[test]
    fn comparison() {
        let host = host_records().unwrap();
        let regions = std::iter::once(Region {
            kind: Kind::Empty,
            index: 0,
            raw_instructions: 5,
            outputs: vec![],
        })
        .chain(host.iter().map(|r| {
            match r {
                Record::Arm(i, o) => (Kind::Arm, *i, o.to_vec()),
                Record::Full(i, o) => (Kind::Full, *i, o.to_vec()),
                Record::Controller(i, o) => (Kind::Controller, *i, o.to_vec()),
            }
            .into()
        }))
        .collect();
        let mut arm = ArmRun {
            regions,
            overhead: 5,
            total_instructions: 0,
        };
        let floors = Floors::paper().unwrap();
        let a = compare(&arm, &host, &floors).unwrap();
        assert!(a.failures.is_empty());
        assert_eq!(a.bit_identical, a.compared);
        let x = &mut arm.regions[2].outputs[4];
        *x *= 1.0 + 2e-5;
        let a = compare(&arm, &host, &floors).unwrap();
        assert_eq!(a.failures.len(), 1, "{:?}", a.failures);
    }
}
