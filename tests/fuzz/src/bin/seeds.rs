//! Writes the seed corpus: `seeds OUT_DIR REPO_ROOT` fills `OUT_DIR/<target>/` for every fuzz
//! target. Deterministic (the SIL flights are seeded), so the corpus is generated, not
//! committed.
//!
//! - `pipeline`: software-in-the-loop captures ([`fuzz::capture`]) of short flights on the
//!   fuzzed flight: arm and take off, then a kill, a landing, the helix mission, a pose loss,
//!   and a kill behind a corrupted length byte;
//! - `link_decoder`: the link bytes of those captures (the motion-capture and ground-station
//!   frames in the SIL loop's random chunks), in pieces of at most 1 KiB;
//! - `vehicle_toml`: the repository's vehicle files and flight files;
//! - `scenario_toml`: its simulation and SIL scenario files.

// Linked for its SanitizerCoverage callbacks: run.sh builds every binary of this crate
// instrumented, and libFuzzer defines them (its `main` is not pulled in: this one is used).
extern crate libfuzzer_sys;

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use firmware::ground_station;
use fuzz::capture::{self, Capture};
use fuzz::script::{self, Op};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> Result<()> {
    fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let path = dir.join(name);
    fs::write(&path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

fn copy_toml(from: &Path, to: &Path) -> Result<usize> {
    let mut n = 0;
    let entries = fs::read_dir(from).with_context(|| format!("cannot list {}", from.display()))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    for p in paths {
        let text = fs::read(&p).with_context(|| format!("cannot read {}", p.display()))?;
        let stem = p
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into());
        let parent = from
            .file_name()
            .map_or_else(String::new, |s| s.to_string_lossy().into());
        write(to, &format!("{parent}-{stem}"), &text)?;
        n += 1;
    }
    Ok(n)
}

/// The link bytes of a capture (its raw byte operations, concatenated).
fn link_bytes(ops: &[Op]) -> Vec<u8> {
    ops.iter()
        .filter_map(|op| match op {
            Op::Bytes(b) => Some(b.as_slice()),
            _ => None,
        })
        .flatten()
        .copied()
        .collect()
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, out, root] = args.as_slice() else {
        bail!("usage: seeds OUT_DIR REPO_ROOT");
    };
    let (out, root) = (Path::new(out), Path::new(root));

    // Held 0.25 s (calibration and the estimator's convergence), then 0.35 s of flight.
    let (hold, fly) = (0.25, 0.35);
    let kill = ground_station::kill();
    let flights: Vec<(&str, Capture)> = vec![
        (
            "takeoff",
            capture::record("takeoff-land", 1, hold, fly, &[])?,
        ),
        (
            "kill",
            capture::record("takeoff-land", 2, hold, fly, &[(0.3, kill.clone())])?,
        ),
        (
            "land",
            capture::record(
                "takeoff-land",
                3,
                hold,
                fly,
                &[(0.25, ground_station::land())],
            )?,
        ),
        ("helix", capture::record("helix", 4, hold, 0.15, &[])?),
        (
            "pose-loss",
            capture::record("pose-loss", 5, hold, fly, &[])?,
        ),
    ];
    for (name, c) in &flights {
        let events: Vec<String> = c
            .summary
            .events
            .iter()
            .map(|(t, e)| format!("{t:.2}s {e}"))
            .collect();
        println!(
            "seed {name}: {} operations, final state {}; {}",
            c.ops.len(),
            c.summary.final_state,
            events.join("; ")
        );
    }

    let pipeline_dir = out.join("pipeline");
    let decoder_dir = out.join("link_decoder");
    for (name, c) in &flights {
        write(
            &pipeline_dir,
            &format!("sil-{name}"),
            &script::encode(&c.ops),
        )?;
        let bytes = link_bytes(&c.ops);
        for (i, piece) in bytes.chunks(1024).enumerate() {
            let mut seed = vec![i as u8];
            seed.extend_from_slice(piece);
            write(&decoder_dir, &format!("sil-{name}-{i}"), &seed)?;
        }
    }
    // A kill behind a corrupted length byte: the decoder waits for a long frame, its CRC
    // fails, and every frame behind it comes out at once.
    let takeoff = &flights[0].1.ops;
    let at = takeoff.len() * 3 / 4;
    let mut corrupted = takeoff[..at].to_vec();
    corrupted.push(Op::Bytes(vec![0xFD, 0xF0, 0, 0, 0, 0, 0, 0, 0, 0]));
    corrupted.extend(takeoff[at..].iter().cloned());
    let mut frame = [0u8; firmware::link::MAX_FRAME];
    let n = firmware::link::encode(&kill, 255, 190, 0, &mut frame);
    corrupted.push(Op::Bytes(frame[..n].to_vec()));
    corrupted.push(Op::Tick {
        dt: 10_000,
        room: 2047,
    });
    write(
        &pipeline_dir,
        "sil-corrupted-length-kill",
        &script::encode(&corrupted),
    )?;
    let mut bytes = vec![7u8];
    bytes.extend(link_bytes(&corrupted[at.saturating_sub(40)..]));
    write(&decoder_dir, "sil-corrupted-length-kill", &bytes)?;

    let mut tomls = 0;
    for dir in ["host-sim/vehicles", "firmware/flights"] {
        tomls += copy_toml(&root.join(dir), &out.join("vehicle_toml"))?;
    }
    for dir in ["host-sim/scenarios", "host-sim/scenarios/sil"] {
        tomls += copy_toml(&root.join(dir), &out.join("scenario_toml"))?;
    }
    println!("seeds: {} flights, {tomls} TOML files", flights.len() + 1);
    Ok(())
}
