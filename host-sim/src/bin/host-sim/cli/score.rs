//! `host-sim score`: a scenario file judged as `design` judges its candidates.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use host_sim::design::fit_binding::FitBinding;
use host_sim::design::integral::IntegralSpec;
use host_sim::design::score::score_scenario;
use host_sim::model::scenario::{KeyEdit, Scenario};

/// Options of `host-sim score`.
#[derive(Debug, Args, Clone)]
pub struct ScoreArgs {
    /// Scenario file with a `[rotors]` table (a design's `scenario.toml`, edited or not).
    #[arg(long, value_name = "FILE")]
    pub scenario: PathBuf,
    /// Fit margin: fraction of each rotor's thrust range kept free at both ends (`design`'s
    /// `--margin`).
    #[arg(long, default_value_t = 0.05)]
    pub margin: f64,
    /// Largest plant mass error of the disturbed hover, fraction of the vehicle's mass
    /// (`design`'s `--integral-mass-error`; flown only when the scenario has
    /// `[gains.integral]`).
    #[arg(long, value_name = "FRACTION", default_value_t = 0.1)]
    pub integral_mass_error: f64,
    /// Largest constant force of the disturbed hover, fraction of the plant's weight
    /// (`design`'s `--integral-force-fraction`).
    #[arg(long, value_name = "FRACTION", default_value_t = 0.05)]
    pub integral_force_fraction: f64,
    /// Edit a key of the scenario before scoring it, `TABLE.KEY=VALUE` (repeatable; e.g.
    /// `--set gains.local.kp=36 --set gains.local.kv=12`): the file is not changed.
    #[arg(long = "set", value_name = "TABLE.KEY=VALUE")]
    pub set: Vec<KeyEdit>,
    /// Also write the whole score (certificate, binding pairs, every run's figures) as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// Scores the scenario and prints the verdict and the objective's terms.
pub fn run(args: &ScoreArgs) -> Result<()> {
    let scenario = Scenario::load_with_edits(&args.scenario, &args.set)?;
    let spec = scenario
        .gains
        .integral
        .is_some()
        .then(|| {
            IntegralSpec::covering(
                scenario.vehicle.gravity_m_s2,
                args.integral_mass_error,
                args.integral_force_fraction,
            )
        })
        .transpose()
        .map_err(anyhow::Error::msg)?;
    let s = score_scenario(&scenario, spec.as_ref(), args.margin)?;
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&s)?;
        std::fs::write(path, text + "\n")
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    println!(
        "Certified: {} (the firmware's gate: {}); smallest fit headroom {:.2} % of the rotor \
         range (margin {:.2} %)",
        s.certified,
        s.gate_certified,
        100.0 * s.fit_headroom,
        100.0 * s.margin
    );
    if let Some(h) = s.local_fit_headroom {
        println!("  the local regime's torque set: {:.2} %", 100.0 * h);
    }
    if let Some(a) = s.aligned_fit_headroom {
        let case = if a >= s.margin {
            "at least the margin: airmode leaves the thrust alone near convergence, and the \
             position loop's convergence is proven"
        } else {
            "below the margin: the position loop's convergence under airmode is shown by \
             simulation only"
        };
        println!(
            "  the aligned feedforward over Theorem 1's thrust interval: {:.2} % ({case}; \
             docs/airmode.md)",
            100.0 * a
        );
    }
    let named = [
        ("certified set", &s.binding),
        ("local regime's set", &s.local_binding),
    ];
    for (name, b) in named {
        if let Some(b) = b {
            print_binding(name, b, s.margin);
        }
        if name == "certified set" {
            if let Some(a) = &s.attitude_terms {
                let m = a.at_mrp;
                println!(
                    "    its attitude terms (radial, trace, turn-over) together: {:.3} N at most \
                     on a grid of the flow set (at the MRP error ({:.3}, {:.3}, {:.3}); a \
                     sample, not a bound) where the set charges them {:.3} N apart",
                    a.sampled_n, m[0], m[1], m[2], a.charged_n
                );
                if let Some(j) = a.joint_bound_n {
                    println!(
                        "    the certified joint bound of the three takes {j:.3} N (what the \
                         set's support uses where it is below the charge apart)"
                    );
                }
            }
        }
    }
    for v in &s.violated {
        println!(
            "  violated: {} ({:.6} > {:.6} does not hold)",
            v.name, v.lhs, v.rhs
        );
    }
    if !s.certified && s.violated.is_empty() {
        println!("  every condition holds, but a certified set does not fit with the margin");
    }
    let e = &s.evaluation;
    let secs = |t: Option<f64>| t.map_or("not settled".to_owned(), |t| format!("{t:.2} s"));
    println!(
        "Objective: {:.3} (lower is better; constraints met: {}, runs not converged: {})",
        e.cost, e.feasible, e.failures
    );
    println!(
        "  half turns, worst settling: {}; upside down at hover: {:.2} m lost",
        secs(e.worst_settling_180_s),
        e.altitude_loss_upside_down_m
    );
    println!(
        "  1 m step: {}; 30 deg roll: {}",
        secs(e.nominal_tasks.step_settling_time_s),
        secs(e.nominal_tasks.tilt_settling_time_s)
    );
    if let Some(d) = &e.disturbed_hover {
        println!(
            "  covered disturbance from rest: {}, {:.3} m lost",
            secs(d.settling_time_s),
            d.altitude_loss_m
        );
    }
    Ok(())
}

/// The binding rotor pair of one set and the newtons each part of the set takes of it.
fn print_binding(name: &str, b: &FitBinding, margin: f64) {
    let [r, p, y] = b.newtons_per_newton_metre;
    let q = &b.parts;
    println!(
        "  the {name} binds rotors {} and {} (shadow fit, headroom {:.2} %): it asks {:.3} N of \
         their {:.3} N ({:.3} N with the margin); 1 N m of roll, pitch, yaw asks {:.3}, {:.3}, \
         {:.3} N",
        b.rotors.0,
        b.rotors.1,
        100.0 * b.margin,
        b.asked_n,
        b.capacity_n,
        b.capacity_n - margin * b.margin_unit_n,
        r.abs(),
        p.abs(),
        y.abs()
    );
    println!(
        "    feedforward {:.3} N (its yaw axis {:.3} N), gyroscopic {:.3} N, feedback ball \
         {:.3} N, box {:.3} N, disks {:.3} N, aligned feedforward {:.3} N, less {:.3} N the \
         joint bound of the attitude terms frees",
        q.feedforward_n,
        q.feedforward_yaw_n,
        q.gyroscopic_n,
        q.feedback_ball_n,
        q.feedback_box_n,
        q.feedback_disks_n,
        q.aligned_n,
        q.joint_saving_n
    );
}
