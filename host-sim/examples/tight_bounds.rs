//! Prints the tight a-priori bounds beside the paper's (Lemma 1, Theorem 2) for the paper's
//! set-up, or for a scenario file: `cargo run --release -p host-sim --example tight_bounds --
//! [scenario.toml|paper] [relative gap] [boxes per search]`.

use std::path::Path;
use std::time::Instant;

use anyhow::{anyhow, Context, Result};
use controller_core::{certify, FilterStart, Trajectory};
use host_sim::bounds::tight::{tight_bounds, TightOptions};
use host_sim::model::scenario::{describe, Scenario};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scenario = match args.first() {
        Some(path) if path != "paper" => Scenario::load(Path::new(path))?,
        _ => Scenario::paper(),
    };
    let mut options = TightOptions::default();
    if let Some(cap) = args.get(2) {
        options.max_boxes = cap
            .parse()
            .with_context(|| format!("box budget {cap:?} is not a whole number"))?;
    }
    if let Some(gap) = args.get(1) {
        options.relative_gap = gap
            .parse()
            .with_context(|| format!("relative gap {gap:?} is not a number"))?;
    }
    let (vehicle, gains) = (scenario.vehicle::<f64>(), scenario.gains::<f64>());
    let constants = scenario.trajectory::<f64>().constants();
    let paper = certify(
        &vehicle,
        &scenario.limits::<f64>(),
        &gains,
        &constants,
        FilterStart::Zero,
    )
    .map_err(|e| anyhow!(describe(&e)))?
    .bounds;
    let start = Instant::now();
    let tight = tight_bounds(&vehicle, &gains, &constants, FilterStart::Zero, &options)
        .map_err(|e| anyhow!(describe(&e)))?;
    let elapsed = start.elapsed();
    println!(
        "relative gap {}, {} boxes, {:.3} s",
        options.relative_gap,
        tight.boxes,
        elapsed.as_secs_f64()
    );
    println!(
        "{:<22} {:>10} {:>10} {:>8} {:>10} {:>8}",
        "quantity", "paper", "tight", "ratio", "best seen", "gap"
    );
    // Four significant digits, whatever the scale (the small vehicles' torques are ~1e-3 N m).
    let sig = |x: f64| {
        let decimals = (3 - x.abs().log10().floor() as i32).clamp(0, 9) as usize;
        format!("{x:.decimals$}")
    };
    let row = |name: &str, paper: f64, tight: f64, seen: f64| {
        println!(
            "{name:<22} {:>10} {:>10} {:>8.3} {:>10} {:>7.2}%",
            sig(paper),
            sig(tight),
            tight / paper,
            sig(seen),
            100.0 * (tight - seen) / tight
        );
    };
    row(
        "|w_d| [rad/s]",
        paper.angular_velocity,
        tight.angular_velocity,
        tight.lower.angular_velocity,
    );
    row(
        "|w_d dot| [rad/s2]",
        paper.angular_acceleration,
        tight.angular_acceleration,
        tight.lower.angular_acceleration,
    );
    row(
        "H12 [rad/s2]",
        paper.angular_acceleration,
        tight.horizontal_acceleration,
        tight.lower.horizontal_acceleration,
    );
    row(
        "H3 [rad/s2]",
        paper.angular_acceleration,
        tight.yaw_acceleration,
        tight.lower.yaw_acceleration,
    );
    for i in 0..3 {
        row(
            &format!("tau_{} [N m]", i + 1),
            paper.torque_max[i],
            tight.torque_max[i],
            tight.lower.torque_max[i],
        );
    }
    Ok(())
}
