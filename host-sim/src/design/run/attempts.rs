//! One heading's design after every attempt it takes (docs/design.md, "The fallback"): both
//! attitude laws on the requested reference, then, when no design converges, the same path with
//! the heading held, then the velocity-limited feedback on long runs.

use std::time::Instant;

use anyhow::Result;

use super::{design_with, load_reference, Designed};
use crate::design::evaluate::Evaluation;
use crate::design::options::*;
use crate::design::report::LawCandidate;

/// One heading's design after every fallback it took, not yet written.
pub(super) struct Attempts {
    /// The design kept: the better law's, after the fallbacks.
    pub(super) design: Designed,
    /// Whether it fell back to the long runs ([`FALLBACK_DURATION_S`]).
    pub(super) long_runs: bool,
    /// Each law's design on the requested reference (for the report).
    pub(super) law_search: Vec<LawCandidate>,
}

/// The laws searched under `o` (one heading), then the fallbacks when no design converges (the
/// heading held, then the velocity-limited feedback on long runs); `started`: when the whole
/// job started, for the report's fallback line. Errors: as [`super::run_design`], except writing.
pub(super) fn design_every_attempt(o: &DesignOptions, started: Instant) -> Result<Attempts> {
    let mut designs = Vec::new();
    for law in o.law.laws() {
        designs.push(design_with(o, law)?);
    }
    let searched: Vec<LawCandidate> = designs
        .iter()
        .map(|d| LawCandidate {
            law: d.law(),
            objective: d.best.evaluation.cost,
            constraints_met: d.best.evaluation.feasible,
        })
        .collect();
    let mut chosen = designs
        .into_iter()
        .min_by(|a, b| {
            let key = |d: &Designed| (!d.best.evaluation.feasible, d.best.evaluation.cost);
            key(a)
                .partial_cmp(&key(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .ok_or_else(|| anyhow::anyhow!("no attitude law to search (bug)"))?;
    let fallback = o.fallback == Fallback::VelocityLimited;
    // What the heading-held attempt gave when it did not converge either (for the report).
    let mut held_too = None;
    if !chosen.best.evaluation.feasible
        && fallback
        && load_reference(o.reference.as_ref())?
            .0
            .heading_held()
            .is_some()
    {
        // The heading's swing costs the most where yaw is weak (its rate multiplies the tilt
        // rate in ω̇_d, at any attitude error): the same path with the heading held, same runs.
        let why = not_converged(o, &chosen.best.evaluation);
        eprintln!(
            "design: {why}; designing again for the same path with the heading held at its \
             initial value ({}, {} s runs)",
            chosen.law().name(),
            o.duration_s
        );
        let held = DesignOptions {
            heading_held: Some(why),
            ..o.clone()
        };
        let attempt = design_with(&held, chosen.law())?;
        if attempt.best.evaluation.feasible {
            chosen = attempt;
        } else {
            held_too = Some(not_converged(o, &attempt.best.evaluation));
        }
    }
    let long_runs = !chosen.best.evaluation.feasible && fallback;
    if long_runs {
        let mut why = not_converged(o, &chosen.best.evaluation);
        if let Some(held) = held_too {
            why = format!("{why}; for the same path with the heading held, {held}");
        }
        let speed_limit = o.speed_limit.unwrap_or(DEFAULT_SPEED_LIMIT_M_S);
        eprintln!(
            "design: {why}; designing again with the velocity-limited position feedback \
             ({speed_limit} m/s) on {FALLBACK_DURATION_S} s runs"
        );
        let again = DesignOptions {
            speed_limit: Some(speed_limit),
            duration_s: FALLBACK_DURATION_S,
            fallback: Fallback::Taken {
                why,
                seconds: started.elapsed().as_secs_f64(),
            },
            ..o.clone()
        };
        chosen = design_with(&again, chosen.law())?;
    }
    Ok(Attempts {
        design: chosen,
        long_runs,
        law_search: searched,
    })
}

/// Why a first attempt was set aside: no design met the convergence constraints, with its
/// feedback, run length and best figures (for the report and the log).
fn not_converged(o: &DesignOptions, e: &Evaluation) -> String {
    let feedback = match o.speed_limit {
        Some(v) => format!("the velocity-limited position feedback ({v} m/s)"),
        None => "the paper's position feedback".to_owned(),
    };
    format!(
        "with {feedback} on {} s runs no design met the convergence \
         constraints (the best: worst settling from 180 degrees {}, {:.1} m lost upside down)",
        o.duration_s,
        e.worst_settling_180_s
            .map_or("not settled".to_owned(), |t| format!("{t:.1} s")),
        e.altitude_loss_upside_down_m
    )
}
