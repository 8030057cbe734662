//! The `design` job: vehicle and reference in, certified and optimised design out.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context as _, Result};
use controller_core::torque_set::AttitudeJoint;
use controller_core::{Bounds, TorqueSet};

use super::certificate::Certified;
use super::evaluate::{baseline_tasks, evaluate, largest_converging_lag, PENALTY};
use super::feasibility::*;
use super::flight::{scenarios, FlightSettings};
use super::optimise::{minimise, Optimum};
use super::options::*;
use super::outputs::write_outputs;
use super::reference::Reference;
use super::refine::local_loop::refine_local_loop;
use super::refine::turn_over::refine_turn_over;
use super::refine::{refine_local, Refinement};
use super::report::{HeadingCandidate, Report};
use super::thrust::ThrustDesign;
use super::variables::{map, AttitudeLaw, Choices, Context, Layout};
use super::vehicle::DesignVehicle;
use crate::model::scenario::{ControllerConfig, Scenario, ThrustKind};
use attempts::{design_every_attempt, Attempts};
use firmware::mixer::Mixer;

mod attempts;
mod setup;

use setup::Setup;

/// Loads the requested reference and its controller period \[s\].
fn load_reference(path: Option<&PathBuf>) -> Result<(Reference, f64)> {
    let s = match path {
        Some(p) => Scenario::load(p).with_context(|| format!("reference {}", p.display()))?,
        None => Scenario::paper(),
    };
    Ok((
        Reference {
            trajectory: s.trajectory.clone(),
            initial: s.initial.clone(),
        },
        s.simulation.controller_period_s,
    ))
}

/// Maps, certifies and flies one point of the unit box; the tight bounds (when certifying with
/// them) take `boxes` per search. `Err` carries the cost of a refusal.
fn score(
    vehicle: &DesignVehicle,
    (ctx, layout): (&Context<'_>, Layout),
    reference: &Reference,
    (settings, boxes): (FlightSettings, usize),
    x: &[f64],
    trace: bool,
) -> std::result::Result<Scored, f64> {
    let mapped = map(ctx, &Choices::from_unit(x, layout)).ok_or(10.0 * PENALTY)?;
    score_mapped(vehicle, ctx, reference, (settings, boxes), mapped, trace)
}

/// [`score`] of gains already mapped (`mapped`): certifies and flies them. `Err` carries the
/// cost of a refusal.
fn score_mapped(
    vehicle: &DesignVehicle,
    ctx: &Context<'_>,
    reference: &Reference,
    (settings, boxes): (FlightSettings, usize),
    mapped: super::variables::Mapped,
    trace: bool,
) -> std::result::Result<Scored, f64> {
    let certified = certify_mapped(
        vehicle,
        ctx.constants,
        &mapped,
        (ctx.margin, ctx.bounds, boxes, ctx.fit),
    )
    .map_err(|_| 10.0 * PENALTY)?;
    if !certified.ok() {
        return Err(10.0 * PENALTY);
    }
    // Airmode's low margin goes with the thrust below, which turns airmode on.
    let low_margin = settings.controller.airmode_low_margin;
    let settings = FlightSettings {
        controller: ControllerConfig {
            airmode_low_margin: None,
            ..settings.controller
        },
        ..settings
    };
    let (mut scenario, mut hover) = scenarios(
        vehicle,
        &certified.limits,
        &mapped.gains,
        reference,
        settings,
    )
    .map_err(|_| 10.0 * PENALTY)?;
    let firmware = firmware_bounds(&scenario).map_err(|_| 10.0 * PENALTY)?;
    let thrust = match ctx.fit {
        super::authority::RotorFit::Set => thrust_of(
            vehicle,
            &certified,
            &firmware,
            ctx.margin,
            settings.controller.thrust,
        ),
        super::authority::RotorFit::Airmode => ThrustDesign::airmode(
            settings.controller.thrust,
            &certified.certificate.bounds,
            ctx.rotors,
            (ctx.margin, low_margin),
        )
        .map_err(anyhow::Error::msg),
    }
    .map_err(|_| 10.0 * PENALTY)?;
    // The floor is within T_min by construction, so the scenarios stay valid.
    scenario.controller = thrust.controller();
    hover.controller = thrust.controller();
    let evaluation = evaluate(
        &scenario,
        &hover,
        (vehicle.motor_time_constant_s, ctx.position.integral),
        trace,
    )
    .map_err(|_| 10.0 * PENALTY)?;
    Ok(Scored {
        mapped,
        certified,
        thrust,
        evaluation,
    })
}

/// The bounds the firmware's boot certificate computes for `scenario`'s set-up: `certify` in
/// f32, as on the board. With the integral action they are slightly wider than the f64 ones
/// (its reachable-set bound carries the scalar's rounding, `16 ε M_i / h_min`: about 0.5 % of
/// `|u̇|` on the x500 in f32), so a floor bisected on the f64 box alone can leave the firmware's
/// gate a hair under the margin. Errors: `certify` refuses the f32 parameters.
fn firmware_bounds(scenario: &crate::model::scenario::Scenario) -> Result<Bounds<f32>> {
    Ok(firmware_certificate(scenario)?.bounds)
}

/// The whole f32 certificate of [`firmware_bounds`] (the local regime's too).
fn firmware_certificate(
    scenario: &crate::model::scenario::Scenario,
) -> Result<controller_core::Certificate<f32>> {
    use controller_core::Trajectory as _;
    controller_core::certify(
        &scenario.vehicle::<f32>(),
        &scenario.limits::<f32>(),
        &scenario.gains::<f32>(),
        &scenario.trajectory::<f32>().constants(),
        controller_core::FilterStart::Zero,
    )
    .map_err(|e| anyhow::anyhow!("{}", crate::model::scenario::describe(&e)))
}

/// The thrust of a certified candidate: vertical priority's floor is the lowest at which the
/// set the firmware's gate measures (Theorem 1's `T_max`, Theorem 2's torque set, each part
/// the larger of the f64 certificate's and the firmware's f32 one, `firmware`; the design's own
/// box when the paper's set does not fit) leaves the margin free.
fn thrust_of(
    vehicle: &DesignVehicle,
    certified: &Certified,
    firmware: &Bounds<f32>,
    margin: f64,
    kind: ThrustKind,
) -> Result<ThrustDesign> {
    let mixer = Mixer::new(&vehicle.rotors)
        .map_err(|e| anyhow::anyhow!("rotor set refused by the mixer: {e:?}"))?;
    let mut b = certified.certificate.bounds;
    b.thrust_max = b.thrust_max.max(f64::from(firmware.thrust_max));
    let gate_set = if certified.paper_fits_with_margin {
        // Every part of the set grows its support function, so the part-wise larger set
        // contains both the f64 and the f32 one.
        let (d, f) = (
            super::certificate::set_f32(&b.torque_set),
            firmware.torque_set,
        );
        TorqueSet {
            inertia: d.inertia.sup(&f.inertia),
            angular_acceleration: d.angular_acceleration.max(f.angular_acceleration),
            gyroscopic: d.gyroscopic.sup(&f.gyroscopic),
            feedback_radius: d.feedback_radius.max(f.feedback_radius),
            feedback_box: d.feedback_box.sup(&f.feedback_box),
            feedback_disks: d.feedback_disks.sup(&f.feedback_disks),
            aligned_acceleration: d.aligned_acceleration.sup(&f.aligned_acceleration),
            aligned_turn: d.aligned_turn.max(f.aligned_turn),
            // The larger joint values with the smaller turn-over box: the attitude terms'
            // bound and what is left of the box beside it both grow (docs/torque-set.md).
            attitude_joint: match (d.attitude_joint, f.attitude_joint) {
                (Some(a), Some(b)) => Some(AttitudeJoint {
                    support_values: core::array::from_fn(|j| {
                        a.support_values[j].max(b.support_values[j])
                    }),
                    turn_over_box: a.turn_over_box.inf(&b.turn_over_box),
                }),
                _ => None,
            },
        }
    } else {
        // Only the tight bounds' set fits (`--bounds tight`): the floor keeps that set inside.
        super::certificate::set_f32(&certified.set)
    };
    let mut thrust =
        ThrustDesign::new(kind, &b, &mixer, &gate_set, margin).map_err(anyhow::Error::msg)?;
    // The f32 end only bounds the floor's bisection; the interval reported is the certificate's.
    thrust.interval_N[1] = certified.certificate.bounds.thrust_max;
    Ok(thrust)
}

/// Runs `design`. Errors: unreadable or invalid inputs, an impossible vehicle (with the
/// reason), a reference no scaling makes certifiable, or an output that cannot be written.
///
/// With [`LawSearch::Both`] each law is designed on the whole budget and the better design is
/// written (one that meets the convergence constraints before one that does not, then the
/// lower objective); the report lists both. The velocity-limited fallback, when no design
/// converges, designs again with the better law only.
pub fn run_design(o: &DesignOptions) -> Result<DesignOutcome> {
    let started = Instant::now();
    check_options(o)?;
    let mut attempts = Vec::new();
    for compensated in o.heading.modes() {
        let one = DesignOptions {
            heading: HeadingSearch::one(compensated),
            ..o.clone()
        };
        let attempt = design_every_attempt(&one, started)?;
        // Each heading's candidate refined last before they are compared: the local regime's
        // agility is what the step a pilot sees is flown with.
        attempts.push(Attempts {
            design: attempt.design.refine_last()?,
            ..attempt
        });
    }
    let searched: Vec<HeadingCandidate> = attempts
        .iter()
        .map(|a| HeadingCandidate {
            compensated: a.design.best.mapped.gains.heading_compensator.is_some(),
            objective: a.design.best.evaluation.cost,
            constraints_met: a.design.best.evaluation.feasible,
            long_runs: a.long_runs,
        })
        .collect();
    // Constraints met first, then the shorter runs (a 300 s run's objective is not comparable
    // with a 30 s run's), then the lower objective.
    let key = |a: &Attempts| {
        (
            !a.design.best.evaluation.feasible,
            a.long_runs,
            a.design.best.evaluation.cost,
        )
    };
    let chosen = attempts
        .into_iter()
        .min_by(|a, b| {
            key(a)
                .partial_cmp(&key(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .ok_or_else(|| anyhow::anyhow!("no heading to search (bug)"))?;
    let law_search = chosen.law_search;
    // Only the design kept is reported.
    let finished = chosen.design.finish()?;
    let mut report = finished.report;
    report.law_search = law_search;
    if searched.len() > 1 {
        report.heading_search = searched;
    }
    report.wall_time_s = started.elapsed().as_secs_f64();
    let files = write_outputs(
        &o.out,
        &report,
        &finished.vehicle,
        &finished.best,
        &finished.reference,
        finished.period,
    )?;
    Ok(DesignOutcome { report, files })
}

/// Refuses options no design can use (with the option's name and value).
fn check_options(o: &DesignOptions) -> Result<()> {
    if !(o.margin.is_finite() && (0.0..0.5).contains(&o.margin)) {
        bail!("--margin: must lie in [0, 0.5), got {}", o.margin);
    }
    if !(o.duration_s.is_finite() && o.duration_s >= MIN_DURATION_S) {
        bail!(
            "--duration-s: {} s is not a run length (at least {MIN_DURATION_S} s: the last 5 s are the limit-cycle window)",
            o.duration_s
        );
    }
    if o.evaluations == 0 {
        bail!("--evaluations: must be > 0");
    }
    if let Some(v) = o.speed_limit {
        if !(v.is_finite() && v > 0.0) {
            bail!("--speed-limit: must be finite and > 0 m/s, got {v}");
        }
    }
    Ok(())
}

/// One law's design, searched and scored, not yet finished: the candidates are compared on
/// `best` before the one kept is polished and reported ([`Designed::finish`]).
struct Designed {
    setup: Setup,
    optimum: Optimum,
    layout: Layout,
    /// The local regime's refinement, when it ran.
    refinement: Option<Refinement>,
    /// The turn-over term's refinement, when it ran.
    turn_over_refinement: Option<Refinement>,
    /// The local position loop's polish, when it ran ([`Designed::refine_last`]).
    local_loop_refinement: Option<Refinement>,
    /// The local regime's agility refinement, when it ran ([`Designed::refine_last`]).
    local_agility_refinement: Option<Refinement>,
    /// `optimum` flown for the report.
    best: Scored,
}

impl Designed {
    /// The law designed.
    fn law(&self) -> AttitudeLaw {
        self.setup.law
    }

    /// The design refined last, each step kept only where it scores lower (so never worse):
    /// the local position loop polished on a grid, then the local regime's agility
    /// (docs/envelope-design.md, "What `design` searches"). Run on each heading's candidate
    /// before they are compared. Errors: a refined design cannot be flown again (a bug), or
    /// the optimiser's.
    fn refine_last(self) -> Result<Designed> {
        let Designed {
            setup,
            optimum,
            layout,
            refinement,
            turn_over_refinement,
            best,
            ..
        } = self;
        // The local position loop's frequency and damping, on which no bound depends, polished
        // last on a grid: never worse.
        let cost_in = |x: &[f64], layout: Layout| setup.cost_in(x, layout);
        let (optimum, layout, local_loop_refinement) = refine_local_loop(&cost_in, optimum, layout);
        let best = match &local_loop_refinement {
            Some(r) if r.kept => setup.final_score(&optimum.x, layout)?,
            _ => best,
        };
        // The local regime's agility (its filters, level, braking, attitude law, envelope and
        // vertical channel) refined last with every global gain held (docs/envelope-design.md,
        // "What `design` searches"): never worse.
        let (agile, local_agility_refinement) = super::refine::local_agility::refine_local_agility(
            &|gains: &controller_core::Gains<f64>| {
                setup.cost_of(super::variables::Mapped {
                    gains: *gains,
                    ..best.mapped
                })
            },
            &best.mapped.gains,
            &setup.vehicle.body.inertia,
            // Compared on the search's box budget, as its candidates are scored (the
            // report's objective takes the final one).
            setup.cost_of(best.mapped),
            setup.o.seed,
        )?;
        let best = match agile {
            Some(gains) => setup.final_score_mapped(super::variables::Mapped {
                gains,
                ..best.mapped
            })?,
            None => best,
        };
        Ok(Designed {
            setup,
            optimum,
            layout,
            refinement,
            turn_over_refinement,
            local_loop_refinement,
            local_agility_refinement,
            best,
        })
    }

    /// The design kept, finished: what the report shows beside the objective (the largest
    /// motor lag that converges, the baselines' nominal tasks, the helix tracked), computed
    /// once, for this design only. Errors: the baselines cannot be flown.
    fn finish(self) -> Result<Finished> {
        let Designed {
            setup,
            optimum,
            layout,
            refinement,
            turn_over_refinement,
            local_loop_refinement,
            local_agility_refinement,
            best,
        } = self;
        let (vehicle, o, ctx) = (&setup.vehicle, &setup.o, setup.ctx());
        let (scenario, _) = scenarios(
            vehicle,
            &best.certified.limits,
            &best.mapped.gains,
            &setup.reference,
            FlightSettings {
                controller: best.thrust.controller(),
                ..setup.settings
            },
        )?;
        let lag_max = largest_converging_lag(&scenario, vehicle.motor_time_constant_s);
        let baselines = baseline_tasks(&scenario)?;
        let helix = super::evaluate::design_helix_tracking(&scenario)?;
        let choices = Choices::from_unit(&optimum.x, layout);
        let mut report = Report::new(
            vehicle,
            (o, setup.law),
            (
                &setup.asked,
                &setup.reference,
                setup.scale,
                setup.binding.as_deref(),
            ),
            choices,
            &best,
            (lag_max, baselines),
            optimum.evaluations,
            setup.started.elapsed().as_secs_f64(),
        );
        if let Some(own) = report.objective.nominal_tasks.first_mut() {
            own.helix_tracking_error_m = Some(helix);
        }
        report.local_refinement = refinement;
        report.turn_over_refinement = turn_over_refinement;
        report.local_loop_refinement = local_loop_refinement;
        report.local_agility_refinement = local_agility_refinement;
        report.what_binds = Some(super::binding::WhatBinds {
            saturation: super::binding::saturation_cap(
                ctx.bounds,
                ctx.vehicle,
                ctx.constants,
                (ctx.rotors, ctx.margin, ctx.fit),
                (best.mapped.saturation_max, choices.kf, choices.ks),
                super::variables::position_law(&ctx, &choices),
            ),
            iota: best.mapped.iota_cap,
            step: super::binding::StepFloor::of(&best.mapped.gains),
            range_ends: choices.range_ends(super::binding::RANGE_END),
        });
        Ok(Finished {
            report,
            best,
            reference: setup.reference,
            period: setup.period,
            vehicle: setup.vehicle,
        })
    }
}

/// The design kept, finished, not yet written.
struct Finished {
    report: Report,
    vehicle: DesignVehicle,
    best: Scored,
    reference: Reference,
    period: f64,
}

/// Designs with attitude law `law` under `o` (its `fallback` only names this attempt in the
/// report), up to the comparison between candidates. Errors: as [`run_design`], except writing.
fn design_with(o: &DesignOptions, law: AttitudeLaw) -> Result<Designed> {
    let setup = Setup::new(o, law)?;
    let searched = Layout {
        law,
        local: o.envelope,
        vertical: o.vertical,
        narrow_local: false,
        local_vertical: false,
        turn_over: false,
        local_integral: false,
    };
    let cost_in = |x: &[f64], layout: Layout| setup.cost_in(x, layout);
    let cost = |x: &[f64]| cost_in(x, searched);
    let guess = Choices::initial_guess(searched).to_unit();
    let optimum = minimise(&cost, &guess, o.evaluations, o.seed)?;
    // Only with the compensated heading: it is what lets narrow envelopes fit the x500's yaw
    // (docs/heading-compensator.md); without it the refinement moves no preset's step and
    // would move the committed designs.
    let (optimum, layout, refinement) = if o.heading.compensator().is_some() {
        refine_local(&cost_in, optimum, searched, o.evaluations, o.seed)?
    } else {
        (optimum, searched, None)
    };
    // Tilt priority's turn-over term, refined after the search and the local regime's
    // (docs/turn-over.md, "In `design`"): never worse than the design before it.
    let (optimum, layout, turn_over_refinement) =
        refine_turn_over(&cost_in, optimum, layout, o.evaluations, o.seed)?;
    let best = setup.final_score(&optimum.x, layout)?;
    Ok(Designed {
        setup,
        optimum,
        layout,
        refinement,
        turn_over_refinement,
        local_loop_refinement: None,
        local_agility_refinement: None,
        best,
    })
}

/// The margin above the rotors' least thrust `with_idle_airmode` tries (fraction of the
/// range): the least a flight file takes, so the rotors come down to their idle but never sit
/// exactly on it, where the f32 mixer's rounding would clip a rotor.
pub const IDLE_LOW_MARGIN: f64 = flight_files::flight_file::AIRMODE_LEAST_LOW_MARGIN;

/// Airmode's margin above the rotors' least thrust: the design found flown again with
/// [`IDLE_LOW_MARGIN`] (`rescore`, the rotors down to their idle; the fits stay checked with
/// the margin at both ends, so the certificate is the same) and kept that way when it still
/// meets every constraint and scores lower. A rotor that idles spins up through its motor lag when the thrust comes back,
/// so slow motors may do better with the margin; the objective decides per vehicle
/// (docs/airmode.md). Without airmode or with the paper's thrust the design is returned as is.
fn with_idle_airmode(best: Scored, rescore: impl FnOnce(f64) -> Option<Scored>) -> Scored {
    if best.thrust.airmode_margin.is_none()
        || best.thrust.mode != ThrustKind::VerticalPriority.name()
    {
        return best;
    }
    let Some(idle) = rescore(IDLE_LOW_MARGIN) else {
        return best;
    };
    let trial = Some((idle.evaluation.cost, idle.evaluation.feasible));
    let mut kept = if idle.evaluation.feasible && idle.evaluation.cost < best.evaluation.cost {
        idle
    } else {
        best
    };
    kept.thrust.airmode_idle_trial = trial;
    kept
}

/// What `design` produced.
#[derive(Clone, Debug)]
pub struct DesignOutcome {
    /// The report (also written as `design.json`).
    pub report: Report,
    /// Files written.
    pub files: Vec<PathBuf>,
}

#[cfg(test)]
mod firmware_gate_tests {
    use firmware::mixer::Mixer;

    use super::firmware_certificate;
    use crate::model::scenario::Scenario;

    /// Given the committed x500 design (integral action on), when its sets are rebuilt as the
    /// firmware's boot gate builds them (the f32 certificate), then every fit the gate checks
    /// leaves the design's 5 % margin of every rotor's range free: with airmode Theorem 1's
    /// interval at zero torque and the shadows of the certified and the local sets; without it
    /// the set over `[T_floor, T_max]`. The f32 bounds are the wider ones, which is why the design
    /// keeps a slack for them.
    #[test]
    fn the_x500_design_passes_the_firmwares_gate() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/designs/x500/scenario.toml");
        let s = Scenario::load(std::path::Path::new(path)).unwrap();
        assert!(s.gains.integral.is_some());
        let c = firmware_certificate(&s).unwrap();
        let f32_bounds = c.bounds;
        let f64_bounds = crate::fly::sim::certificate(&s).unwrap().bounds;
        for i in 0..3 {
            assert!(f64::from(f32_bounds.torque_max[i]) > f64_bounds.torque_max[i]);
        }
        let vehicle =
            crate::model::vehicle::load(&crate::model::vehicle::preset_path("x500")).unwrap();
        let mixer = Mixer::new(&crate::model::vehicle::airframe(&vehicle).rotors).unwrap();
        let margins = if s.controller.airmode {
            let zero = controller_core::TorqueSet::boxed(nalgebra::Vector3::zeros());
            let mut m = vec![
                mixer.set_margin(f32_bounds.thrust_min, f32_bounds.thrust_max, &zero),
                mixer.shadow_margin(&f32_bounds.torque_set),
            ];
            m.extend(c.local.iter().map(|l| mixer.shadow_margin(&l.torque_set)));
            m
        } else {
            let floor = s.controller.thrust_floor_N as f32;
            vec![mixer.set_margin(floor, f32_bounds.thrust_max, &f32_bounds.torque_set)]
        };
        for margin in margins {
            assert!(margin >= 0.05, "{margin}");
        }
    }
}
