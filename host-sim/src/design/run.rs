//! The `design` job: vehicle and reference in, certified and optimised design out.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context as _, Result};
use controller_core::{Bounds, Gains};

use super::authority::RotorSet;
use super::certificate::{certify_design_with, Certified};
use super::evaluate::{evaluate, largest_converging_lag, Evaluation, PENALTY};
use super::flight::{scenarios, FlightSettings};
use super::integral::IntegralSpec;
use super::optimise::minimise;
use super::reference::{largest_certifiable_scale, Reference};
use super::report::{write_outputs, Report};
use super::thrust::ThrustDesign;
use super::tight::{tight_torque_box, BoundsKind, SEARCH_BOXES};
use super::variables::{map, AttitudeLaw, Choices, Context, Mapped};
use super::vehicle::DesignVehicle;
use crate::fly::scenario::{ControllerConfig, Scenario, ThrustKind};
use firmware::mixer::Mixer;

/// Default length of each scoring run and of the written scenario \[s\]: the paper's 30 s (the
/// last 5 s are the limit-cycle window; campaigns judge convergence 5 s before the end).
pub const DEFAULT_DURATION_S: f64 = 30.0;
/// Shortest `--duration-s` \[s\]: twice the limit-cycle window.
pub const MIN_DURATION_S: f64 = 2.0 * super::evaluate::TAIL_S;
/// Speed limit [m/s] of the fallback design ([`Fallback::VelocityLimited`]).
pub const FALLBACK_SPEED_LIMIT_M_S: f64 = 20.0;
/// Run length \[s\] of the fallback design ([`Fallback::VelocityLimited`]).
pub const FALLBACK_DURATION_S: f64 = 300.0;

/// What `design` does when no design within the budget meets the convergence constraints.
#[derive(Clone, Debug, PartialEq)]
pub enum Fallback {
    /// Nothing: the best design is written and reported as not converging.
    Off,
    /// Design again, with the velocity-limited position feedback
    /// ([`FALLBACK_SPEED_LIMIT_M_S`], docs/velocity-limit.md) on runs of
    /// [`FALLBACK_DURATION_S`], and write that design (the CLI's default when neither
    /// `--duration-s` nor `--speed-limit` is given): a certified design with a small `M_p`
    /// overshoots a long fall with the paper's feedback and needs minutes to climb back.
    VelocityLimited,
    /// This design is that second attempt: why the first was set aside, and its wall time \[s\].
    Taken {
        /// The first attempt's outcome, for the report.
        why: String,
        /// The first attempt's wall time \[s\].
        seconds: f64,
    },
}

/// Default evaluation budget: sized so one preset finishes in well under 10 minutes on 2 cores
/// (release build).
pub const DEFAULT_EVALUATIONS: usize = 960;

/// What `design` is asked.
#[derive(Clone, Debug)]
pub struct DesignOptions {
    /// Vehicle file.
    pub vehicle: PathBuf,
    /// Scenario file whose `[trajectory]`, `[initial]` and controller period are the requested
    /// reference; `None`: the paper's helix.
    pub reference: Option<PathBuf>,
    /// Seed of the optimiser.
    pub seed: u64,
    /// Box-fit margin, fraction of each rotor's range at both ends.
    pub margin: f64,
    /// Evaluation budget of the optimiser.
    pub evaluations: usize,
    /// Length of the scoring runs and of the written scenario \[s\] (at least
    /// [`MIN_DURATION_S`]): the horizon a run must settle in, 5 s before its end. A vehicle whose
    /// certified authority is small needs longer than the paper's 30 s.
    pub duration_s: f64,
    /// The attitude feedback searched: the paper's law or tilt priority (per-axis levels).
    pub law: AttitudeLaw,
    /// The bounds that certify Theorem 2's torque condition and the box fit.
    pub bounds: BoundsKind,
    /// `Some`: the design carries the bounded integral action sized to cover this disturbance,
    /// certified with the extended bounds (the default, [`super::integral`]; `None` with `--no-integral`).
    pub integral: Option<IntegralSpec>,
    /// The thrust flown and written: the paper's `norm`, or `vertical-priority` with the lowest
    /// floor the certified box allows ([`super::thrust`]).
    pub thrust: ThrustKind,
    /// `Some(V)`: the design flies the velocity-limited position feedback with speed limit `V`
    /// [m/s] (`--speed-limit`, docs/velocity-limit.md); `None`: the paper's.
    pub speed_limit: Option<f64>,
    /// What to do when no design meets the convergence constraints.
    pub fallback: Fallback,
    /// Output directory.
    pub out: PathBuf,
}

/// What `design` produced.
#[derive(Clone, Debug)]
pub struct DesignOutcome {
    /// The report (also written as `design.json`).
    pub report: Report,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// The probe design used to decide whether a reference can be certified at all: slow filters,
/// half the largest `M_p` and half of `ι_max`.
fn probe_choices(law: AttitudeLaw) -> Choices {
    Choices {
        kf: 0.3,
        ks: 0.45,
        saturation_fraction: 0.5,
        iota_fraction: 0.5,
        ..Choices::initial_guess(law)
    }
}

/// Share of the vehicle's hover feedback authority a reference may take: the reference is
/// usable when, as `M_p → 0`, the largest feedback torque level `ι_max` left by its feedforward
/// is at least this share of `ι_max` at hover (without it, a "certified" design has too little
/// torque left to recover from 180 degrees).
pub const AUTHORITY_SHARE: f64 = 0.75;

/// `ι_max` as `M_p → 0` [N m] for `constants` (independent of `k_f`, `k_s` there).
fn iota_floor(
    vehicle: &DesignVehicle,
    set: &RotorSet,
    (margin, bounds, integral): (f64, BoundsKind, Option<&IntegralSpec>),
    constants: &controller_core::TrajectoryConstants<f64>,
) -> f64 {
    super::authority::envelope_with(
        bounds,
        &vehicle.body,
        constants,
        (1e-6, 0.3, 0.45),
        integral,
    )
    .map_or(f64::NEG_INFINITY, |env| {
        super::authority::iota_max(set, &env, margin)
    })
}

/// Certifies `mapped` with the bounds of `kind` (the tight ones with `boxes` per search).
fn certify_mapped(
    vehicle: &DesignVehicle,
    constants: &controller_core::TrajectoryConstants<f64>,
    mapped: &Mapped,
    (margin, kind, boxes): (f64, BoundsKind, usize),
) -> Result<Certified> {
    let tight = match kind {
        BoundsKind::Paper => None,
        BoundsKind::Tight => Some(tight_torque_box(
            &vehicle.body,
            &mapped.gains,
            constants,
            boxes,
        )?),
    };
    certify_design_with(
        &vehicle.body,
        &vehicle.rotors,
        &mapped.gains,
        constants,
        margin,
        tight,
    )
}

/// Why a reference cannot be used (the binding condition with its numbers), or `None`.
fn binding_condition(
    vehicle: &DesignVehicle,
    set: &RotorSet,
    (margin, law, bounds): (f64, AttitudeLaw, BoundsKind),
    integral: Option<&IntegralSpec>,
    r: &Reference,
) -> Option<String> {
    let constants = r.constants();
    let hover = iota_floor(
        vehicle,
        set,
        (margin, bounds, integral),
        &controller_core::TrajectoryConstants::zero(),
    );
    let floor = iota_floor(vehicle, set, (margin, bounds, integral), &constants);
    if floor < AUTHORITY_SHARE * hover {
        let env = super::authority::envelope_with(
            bounds,
            &vehicle.body,
            &constants,
            (1e-6, 0.3, 0.45),
            integral,
        );
        let detail = env.map_or_else(String::new, |env| {
            format!(
                " (thrust interval [{:.4}, {:.4}] N; reference feedforward torque bound \
                 [{:.4e}, {:.4e}, {:.4e}] N m; rotor range [{}, {}] N)",
                env.thrust.0,
                env.thrust.1,
                env.feedforward.x,
                env.feedforward.y,
                env.feedforward.z,
                set.range.0,
                set.range.1
            )
        });
        return Some(if floor <= 0.0 {
            format!(
                "theorem2 + box fit: no feedback torque level iota > 0 fits the rotors with margin {margin} even as \
                 M_p -> 0: iota_max = {floor:.4e} N m{detail}"
            )
        } else {
            format!(
                "authority: the reference's feedforward leaves iota_max = {floor:.4e} N m as M_p -> 0, less than \
                 {AUTHORITY_SHARE} x the hover value {hover:.4e} N m{detail}"
            )
        });
    }
    let probe = probe_choices(law);
    let ctx = Context {
        vehicle: &vehicle.body,
        constants: &constants,
        rotors: set,
        margin,
        bounds,
        integral,
        speed_limit: None,
    };
    let Some(m) = map(&ctx, &probe) else {
        return Some(
            "theorem2 + box fit: no M_p > 0 leaves a positive feedback torque level".to_owned(),
        );
    };
    match certify_mapped(vehicle, &constants, &m, (margin, bounds, SEARCH_BOXES)) {
        Err(e) => Some(format!("{e:#}")),
        Ok(c) if c.ok() => None,
        Ok(c) => {
            let mut why: Vec<String> = c
                .certificate
                .violations()
                .map(|v| {
                    format!(
                        "{} ({}): lhs = {:.6e}, rhs = {:.6e}",
                        v.name, v.statement, v.lhs, v.rhs
                    )
                })
                .collect();
            if !c.fits_with_margin {
                why.push(format!(
                    "box fit with margin {margin}: smallest headroom {:.4}",
                    c.margin
                ));
            }
            Some(why.join("; "))
        }
    }
}

/// Refuses a vehicle that cannot fly at all, with the reason.
fn refuse_impossible(vehicle: &DesignVehicle) -> Result<RotorSet> {
    let r = &vehicle.rotors;
    if !(r.thrust_min.is_finite()
        && r.thrust_max.is_finite()
        && r.thrust_max > r.thrust_min
        && r.thrust_min >= 0.0)
    {
        bail!(
            "{}: rotors: thrust range empty or invalid: thrust_min_N = {}, thrust_max_N = {}",
            vehicle.origin,
            r.thrust_min,
            r.thrust_max
        );
    }
    let set = RotorSet::new(r).map_err(|e| anyhow::anyhow!("{}: rotors: {e}", vehicle.origin))?;
    let weight = vehicle.body.mass * vehicle.body.gravity;
    if set.thrust_total_max() <= weight {
        bail!(
            "{}: the vehicle cannot hover: 4 x thrust_max_N = {:.4} N <= weight m g = {:.4} N",
            vehicle.origin,
            set.thrust_total_max(),
            weight
        );
    }
    if 4.0 * set.range.0 >= weight {
        bail!(
            "{}: the vehicle cannot hover: 4 x thrust_min_N = {:.4} N >= weight m g = {:.4} N (it cannot descend)",
            vehicle.origin,
            4.0 * set.range.0,
            weight
        );
    }
    let hover = iota_floor(
        vehicle,
        &set,
        (0.0, BoundsKind::Paper, None),
        &controller_core::TrajectoryConstants::zero(),
    );
    if hover <= 0.0 {
        bail!(
            "{}: the rotors cannot hold the vehicle's hover thrust and any torque at once \
             (largest feedback torque at hover iota_max = {hover:.4e} N m)",
            vehicle.origin
        );
    }
    Ok(set)
}

/// Refuses an integral action the vehicle cannot carry, with the numbers: the extended
/// Theorem 1 needs `T_min = m(g − K_a3 − M_p − M_i,z) > 0`, and the rotors must at least hold
/// the covered plant, `m(g + M_i,z)`.
fn refuse_uncoverable(vehicle: &DesignVehicle, set: &RotorSet, spec: &IntegralSpec) -> Result<()> {
    let (m, g) = (vehicle.body.mass, vehicle.body.gravity);
    let level = spec.level_m_s2[2];
    if level >= g {
        bail!(
            "integral action: covering a mass error of {} and a force of {} of the weight needs a vertical \
             level M_i,z = {level:.4} m/s^2 >= g = {g} m/s^2, which leaves the extended Theorem 1 no \
             thrust floor T_min = m(g - K_a3 - M_p - M_i,z) > 0",
            spec.mass_error_fraction,
            spec.force_fraction
        );
    }
    let needed = m * (g + level);
    if set.thrust_total_max() <= needed {
        bail!(
            "integral action: {}: the rotors' 4 x thrust_max_N = {:.4} N cannot hold the covered plant \
             (mass error {}, force {} of the weight): m (g + M_i,z) = {needed:.4} N",
            vehicle.origin,
            set.thrust_total_max(),
            spec.mass_error_fraction,
            spec.force_fraction
        );
    }
    Ok(())
}

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

/// A scored candidate.
pub struct Scored {
    /// Its mapped gains.
    pub mapped: Mapped,
    /// Its certificate.
    pub certified: Certified,
    /// Its thrust (the floor of vertical priority depends on its box).
    pub thrust: ThrustDesign,
    /// Its simulations.
    pub evaluation: Evaluation,
}

/// Maps, certifies and flies one point of the unit box; the tight bounds (when certifying with
/// them) take `boxes` per search. `Err` carries the cost of a refusal.
fn score(
    vehicle: &DesignVehicle,
    ctx: &Context<'_>,
    reference: &Reference,
    (settings, boxes): (FlightSettings, usize),
    x: &[f64],
    trace: bool,
) -> std::result::Result<Scored, f64> {
    let mapped = map(ctx, &Choices::from_unit(x)).ok_or(10.0 * PENALTY)?;
    let certified = certify_mapped(
        vehicle,
        ctx.constants,
        &mapped,
        (ctx.margin, ctx.bounds, boxes),
    )
    .map_err(|_| 10.0 * PENALTY)?;
    if !certified.ok() {
        return Err(10.0 * PENALTY);
    }
    let (mut scenario, mut hover) = scenarios(
        vehicle,
        &certified.limits,
        &mapped.gains,
        reference,
        settings,
    )
    .map_err(|_| 10.0 * PENALTY)?;
    let firmware = firmware_bounds(&scenario).map_err(|_| 10.0 * PENALTY)?;
    let thrust = thrust_of(
        vehicle,
        &certified,
        &firmware,
        ctx.margin,
        settings.controller.thrust,
    )
    .map_err(|_| 10.0 * PENALTY)?;
    // The floor is within T_min by construction, so the scenarios stay valid.
    scenario.controller = thrust.controller();
    hover.controller = thrust.controller();
    let evaluation = evaluate(
        &scenario,
        &hover,
        (vehicle.motor_time_constant_s, ctx.integral),
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
fn firmware_bounds(scenario: &crate::fly::scenario::Scenario) -> Result<Bounds<f32>> {
    use controller_core::Trajectory as _;
    let c = controller_core::certify(
        &scenario.vehicle::<f32>(),
        &scenario.limits::<f32>(),
        &scenario.gains::<f32>(),
        &scenario.trajectory::<f32>().constants(),
        controller_core::FilterStart::Zero,
    )
    .map_err(|e| anyhow::anyhow!("{}", crate::fly::scenario::describe(&e)))?;
    Ok(c.bounds)
}

/// The thrust of a certified candidate: vertical priority's floor is the lowest at which the
/// box the firmware's gate measures (Theorem 1's `T_max`, Theorem 2's torque bounds, each the
/// larger of the f64 certificate's and the firmware's f32 one, `firmware`; the design's own box
/// when the paper's does not fit) leaves the margin free.
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
    let paper_box = b
        .torque_max
        .zip_map(&firmware.torque_max, |x, y| x.max(f64::from(y)));
    let gate_box = if certified.paper_fits_with_margin {
        paper_box
    } else {
        certified.torque_box
    };
    let mut thrust =
        ThrustDesign::new(kind, &b, &mixer, &gate_box, margin).map_err(anyhow::Error::msg)?;
    // The f32 end only bounds the floor's bisection; the interval reported is the certificate's.
    thrust.interval_N[1] = certified.certificate.bounds.thrust_max;
    Ok(thrust)
}

/// Runs `design`. Errors: unreadable or invalid inputs, an impossible vehicle (with the
/// reason), a reference no scaling makes certifiable, or an output that cannot be written.
pub fn run_design(o: &DesignOptions) -> Result<DesignOutcome> {
    let started = Instant::now();
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
    let vehicle = DesignVehicle::load(&o.vehicle)?;
    let set = refuse_impossible(&vehicle)?;
    let (requested, period) = load_reference(o.reference.as_ref())?;
    let integral = o.integral.as_ref();
    if let Some(spec) = integral {
        refuse_uncoverable(&vehicle, &set, spec)?;
    }
    let binding = binding_condition(
        &vehicle,
        &set,
        (o.margin, o.law, o.bounds),
        integral,
        &requested,
    );
    let (reference, scale) = match &binding {
        None => (requested.clone(), 1.0),
        Some(why) => {
            eprintln!(
                "design: the requested reference cannot be certified on {}: {why}",
                vehicle.name
            );
            let s = largest_certifiable_scale(&requested, |r| {
                binding_condition(&vehicle, &set, (o.margin, o.law, o.bounds), integral, r)
                    .is_none()
            })
            .with_context(|| {
                format!(
                    "{}: no design can be certified for {} even with the reference slowed down \
                         (frequencies x 2^-30): {why}",
                    vehicle.origin, vehicle.name
                )
            })?;
            eprintln!("design: designing for the same reference slowed down by {s:.4} (frequencies x {s:.4})");
            (requested.scaled(s), s)
        }
    };
    let constants = reference.constants();
    let ctx = Context {
        vehicle: &vehicle.body,
        constants: &constants,
        rotors: &set,
        margin: o.margin,
        bounds: o.bounds,
        integral,
        speed_limit: o.speed_limit,
    };
    ThrustDesign::check_flown(o.thrust).map_err(anyhow::Error::msg)?;
    let settings = FlightSettings {
        duration_s: o.duration_s,
        controller_period_s: period,
        controller: ControllerConfig {
            thrust: o.thrust,
            ..ControllerConfig::default()
        },
    };
    let cost = |x: &[f64]| match score(
        &vehicle,
        &ctx,
        &reference,
        (settings, SEARCH_BOXES),
        x,
        false,
    ) {
        Ok(s) => s.evaluation.cost,
        Err(c) => c,
    };
    let guess = Choices::initial_guess(o.law).to_unit();
    let optimum = minimise(&cost, &guess, o.evaluations, o.seed)?;
    // The final design's tight bounds with the default budget: never looser than the search's.
    let final_boxes = crate::bounds::tight::TightOptions::default().max_boxes;
    let best = score(
        &vehicle,
        &ctx,
        &reference,
        (settings, final_boxes),
        &optimum.x,
        true,
    )
    .map_err(|_| anyhow::anyhow!("the best design found could not be certified and flown (bug)"))?;
    if !best.evaluation.feasible && o.fallback == Fallback::VelocityLimited {
        let why = format!(
            "with the paper's position feedback on {} s runs no design met the convergence \
             constraints (the best: worst settling from 180 degrees {}, {:.1} m lost upside down)",
            o.duration_s,
            best.evaluation
                .worst_settling_180_s
                .map_or("not settled".to_owned(), |t| format!("{t:.1} s")),
            best.evaluation.altitude_loss_upside_down_m
        );
        eprintln!(
            "design: {why}; designing again with the velocity-limited position feedback \
             ({FALLBACK_SPEED_LIMIT_M_S} m/s) on {FALLBACK_DURATION_S} s runs"
        );
        return run_design(&DesignOptions {
            speed_limit: Some(FALLBACK_SPEED_LIMIT_M_S),
            duration_s: FALLBACK_DURATION_S,
            fallback: Fallback::Taken {
                why,
                seconds: started.elapsed().as_secs_f64(),
            },
            ..o.clone()
        });
    }
    let (scenario, _) = scenarios(
        &vehicle,
        &best.certified.limits,
        &best.mapped.gains,
        &reference,
        FlightSettings {
            controller: best.thrust.controller(),
            ..settings
        },
    )?;
    let lag_max = largest_converging_lag(&scenario, vehicle.motor_time_constant_s);
    let earlier_s = match &o.fallback {
        Fallback::Taken { seconds, .. } => *seconds,
        _ => 0.0,
    };
    let report = Report::new(
        &vehicle,
        o,
        (&requested, &reference, scale, binding.as_deref()),
        Choices::from_unit(&optimum.x),
        &best,
        lag_max,
        optimum.evaluations,
        earlier_s + started.elapsed().as_secs_f64(),
    );
    let files = write_outputs(&o.out, &report, &vehicle, &best, &reference, period)?;
    Ok(DesignOutcome { report, files })
}

/// The gains of a report, for tests and callers.
pub fn gains_of(s: &Scored) -> Gains<f64> {
    s.mapped.gains
}

#[cfg(test)]
mod firmware_gate_tests {
    use firmware::mixer::Mixer;

    use super::firmware_bounds;
    use crate::fly::scenario::Scenario;

    /// Given the committed x500 design (integral action on, vertical priority's floor), when its
    /// box is rebuilt as the firmware's boot gate builds it (f32 certificate, `[T_floor, T_max]`),
    /// then it still leaves the design's 5 % margin of every rotor's range free; and the f32
    /// bounds are the wider ones, which is why the floor is bisected on them.
    #[test]
    fn the_x500_designs_floor_passes_the_firmwares_gate() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/designs/x500/scenario.toml");
        let s = Scenario::load(std::path::Path::new(path)).unwrap();
        assert!(s.gains.integral.is_some());
        let f32_bounds = firmware_bounds(&s).unwrap();
        let f64_bounds = crate::fly::sim::certificate(&s).unwrap().bounds;
        for i in 0..3 {
            assert!(f64::from(f32_bounds.torque_max[i]) > f64_bounds.torque_max[i]);
        }
        let vehicle =
            crate::model::vehicle::load(&crate::model::vehicle::preset_path("x500")).unwrap();
        let mixer = Mixer::new(&crate::model::vehicle::airframe(&vehicle).rotors).unwrap();
        let floor = s.controller.thrust_floor_N as f32;
        let margin = mixer.box_margin(floor, f32_bounds.thrust_max, &f32_bounds.torque_max);
        assert!(margin >= 0.05, "{margin}");
    }
}
