//! `host-sim design`: certified, optimised gains for a vehicle file.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use controller_core::{Lemma1Form, PositionSaturation};
use host_sim::design::{
    authority::RotorFit,
    integral::IntegralSpec,
    options::{
        Fallback, HeadingSearch, LawSearch, DEFAULT_DURATION_S, DEFAULT_EVALUATIONS,
        DEFAULT_SPEED_LIMIT_M_S,
    },
    run_design,
    tight::BoundsKind,
    variables::AttitudeLaw,
    DesignOptions,
};
use host_sim::model::scenario::ThrustKind;

/// The thrusts the firmware flies (so the ones `design` offers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignThrust {
    /// `T = m|u|`: the paper's law.
    Norm,
    /// The no-dive thrust with a certified floor.
    VerticalPriority,
}

/// The attitude feedbacks `design` searches (the library's [`AttitudeLaw`], named on the
/// command line).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignLaw {
    /// Both, each on the whole budget; the better design is written (twice the wall time).
    Both,
    /// The paper's law (Section V): one feedback torque level on every axis.
    Paper,
    /// Tilt priority (docs/tilt-priority.md): per-axis levels, yaw's small.
    TiltPriority,
}

/// The desired-frame headings `design` searches (the library's [`HeadingSearch`], named on the
/// command line; docs/heading-compensator.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignHeading {
    /// Both, each on the whole budget with its fallbacks; the better design is written (twice
    /// the wall time).
    Both,
    /// The paper's desired frame: the reference's heading as it is.
    Paper,
    /// The compensated heading (L = 0.3 rad/s, k_psi = 1/s): its rate cancels the
    /// tilt-induced yaw of the desired frame.
    Compensated,
}

/// The bounds that certify a design (the library's [`BoundsKind`], named on the command line).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignBounds {
    /// Lemma 1 and Theorem 2 as the paper writes them.
    Paper,
    /// The tight a-priori bounds.
    Tight,
}

/// The shapes of the position feedback's saturation `design` offers (the library's
/// `PositionSaturation`, named on the command line).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignPositionSaturation {
    /// The paper's `M_p tanh(y_i/M_p)` per component: `|ubar_p| < √3 M_p`.
    Componentwise,
    /// `M_p y / sqrt(M_p² + |y|²)`: `|ubar_p| < M_p` (docs/position-saturation.md).
    Norm,
}

/// The chains bounding `|ω̇_d|` `design` offers (the library's `Lemma1Form`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignLemma1 {
    /// Lemma 1 as the paper states it.
    Paper,
    /// Only the parts of `ρ̈`, `ϋ` that `ω̇_d` reads (docs/tangential-lemma1.md).
    Tangential,
    /// The tangential chain, and Theorem 2's per-axis conditions on the desired frame's norms
    /// of `ω_d`, `ω̇_d`, the ones the certified torque set takes (docs/torque-set.md).
    DesiredFrame,
}

/// Whether the design flies airmode (the library's [`RotorFit`], named on the command line).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DesignAirmode {
    /// Airmode: the thrust moves to where the rotors realise the torque; the torque set need only
    /// fit the rotors at some thrust, the feedforward at zero attitude error over the whole
    /// thrust interval (docs/airmode.md).
    On,
    /// The certified thrust interval times the torque set fits the rotors (docs/torque-set.md).
    Off,
}

/// Options of `host-sim design`.
#[derive(Debug, Args, Clone)]
pub struct DesignArgs {
    /// Vehicle file (`host-sim/vehicles/*.toml` format).
    #[arg(long, value_name = "FILE")]
    pub vehicle: PathBuf,
    /// Scenario file whose `[trajectory]`, `[initial]` and controller period are the requested
    /// reference (default: the paper's helix).
    #[arg(long, value_name = "FILE")]
    pub reference: Option<PathBuf>,
    /// Seed of the optimiser (the design is reproducible from it).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Box-fit margin: fraction of each rotor's thrust range kept free at both ends.
    #[arg(long, default_value_t = 0.05)]
    pub margin: f64,
    /// Optimiser budget (designs scored by simulation).
    #[arg(long, default_value_t = DEFAULT_EVALUATIONS)]
    pub evaluations: usize,
    /// Length of the scoring runs and of the written scenario (s): a run must settle 5 s before
    /// its end. Slow certified designs (small authority) need longer than the paper's 30 s.
    /// Default: 30 s, and when no design converges there (and `--speed-limit` is not given
    /// either), `design` designs again with the velocity-limited feedback at 20 m/s on 300 s runs
    /// and says so.
    #[arg(long)]
    pub duration_s: Option<f64>,
    /// Attitude feedback to search: `both` (each on the whole budget, the better design is
    /// written), `paper` (one feedback torque level on every axis) or `tilt-priority` (per-axis
    /// levels, yaw's small; docs/tilt-priority.md).
    #[arg(long, value_enum, default_value_t = DesignLaw::Both)]
    pub law: DesignLaw,
    /// Bounds that certify Theorem 2's torque condition and the rotor fit: `paper` (Lemma 1 and
    /// Theorem 2 as written; the firmware re-checks them on board) or `tight` (the tight
    /// a-priori bounds, docs/tight-bounds.md; no firmware file unless the paper's certificate
    /// and rotor fit, which the firmware re-checks, pass too).
    #[arg(long, value_enum, default_value_t = DesignBounds::Paper)]
    pub bounds: DesignBounds,
    /// Design without the bounded integral action (the paper's law alone). By default the
    /// design carries it (docs/integral-action.md), sized to cover `--integral-mass-error` and
    /// `--integral-force-fraction`; every bound is then the extended one, and the flight file
    /// switches it on.
    #[arg(long)]
    pub no_integral: bool,
    /// Largest plant mass error the integral action covers, fraction of the vehicle's mass
    /// (a payload, a sagging battery, a thrust coefficient known to 10 %).
    #[arg(
        long,
        value_name = "FRACTION",
        default_value_t = 0.1,
        conflicts_with = "no_integral"
    )]
    pub integral_mass_error: f64,
    /// Largest constant force the integral action covers (any direction), fraction of the
    /// plant's weight (a steady wind, a tether).
    #[arg(
        long,
        value_name = "FRACTION",
        default_value_t = 0.05,
        conflicts_with = "no_integral"
    )]
    pub integral_force_fraction: f64,
    /// Thrust flown and written: `vertical-priority` (the no-dive thrust, docs/no-dive-thrust.md,
    /// with the lowest floor at which the certified box `[T_floor, T_max] x torques` still fits
    /// the rotors with the margin; the flight file carries it as `[controller]`) or `norm` (the
    /// paper's `T = m|u|`, Theorem 1's `[T_min, T_max]`).
    #[arg(long, value_enum, default_value_t = DesignThrust::VerticalPriority)]
    pub thrust: DesignThrust,
    /// Shape of the position feedback's saturation: `componentwise` (the paper's, each component
    /// below `M_p`) or `norm` (`|ubar_p| < M_p`, so Theorem 1 and Lemma 1 lose the paper's √3:
    /// docs/position-saturation.md; the default, as on every preset).
    #[arg(long, value_enum, default_value_t = DesignPositionSaturation::Norm)]
    pub position_saturation: DesignPositionSaturation,
    /// The chain the certificate bounds `|ω̇_d|` with: `desired-frame` (the tangential chain,
    /// with Theorem 2's per-axis conditions on the desired frame's norms, which the certified
    /// torque set takes: docs/torque-set.md), `tangential` (only the parts of `ρ̈` and `ϋ` that
    /// `ω̇_d` reads; a proven, smaller bound: docs/tangential-lemma1.md) or `paper` (Lemma 1 as
    /// stated). The law flown is the same; the flight file carries the choice and the firmware's
    /// gate certifies with it.
    #[arg(long, value_enum, default_value_t = DesignLemma1::DesiredFrame)]
    pub lemma1: DesignLemma1,
    /// Speed limit [m/s] of the velocity-limited position feedback the design flies
    /// (docs/velocity-limit.md), braking at 0.7 of `M_p` (and of each vertical level): the same
    /// law near the reference, a braking profile instead of the paper's overshoot far from it;
    /// the certificate is unchanged. The default since fast gains near the reference no longer
    /// cost the starts far from it (docs/design.md).
    #[arg(long, value_name = "M_S", default_value_t = DEFAULT_SPEED_LIMIT_M_S, conflicts_with = "no_speed_limit")]
    pub speed_limit: f64,
    /// Fly the paper's position feedback (one saturation of `k_p z₁ + k_v z₂`) instead of the
    /// velocity-limited one.
    #[arg(long)]
    pub no_speed_limit: bool,
    /// Airmode (docs/airmode.md): `on` moves the thrust, by as little as possible, to where the
    /// rotors realise the law's torque, so the certified torque set need only fit the rotors at
    /// some thrust (the shadow fit) and the feedforward at zero attitude error over the thrust
    /// interval; the flight file carries it and the firmware's gate checks both fits. `off`: the
    /// thrust interval times the torque set fits the rotors.
    #[arg(long, value_enum, default_value_t = DesignAirmode::On)]
    pub airmode: DesignAirmode,
    /// The envelope design (docs/envelope-design.md): `on` searches, beside the global gains,
    /// faster local position gains flown while the attitude energy is below a level the search
    /// also picks (an invariant set of the law), certified for the torques they can ask there;
    /// `off`: one set of position gains.
    #[arg(long, value_enum, default_value_t = DesignAirmode::On)]
    pub envelope: DesignAirmode,
    /// The vertical channel apart (docs/vertical-channel.md): `on` searches the vertical
    /// feedback's own upward (braking) and downward levels beside the horizontal `M_p`; `off`:
    /// `M_p` on every axis.
    #[arg(long, value_enum, default_value_t = DesignAirmode::On)]
    pub vertical: DesignAirmode,
    /// The desired frame's heading (docs/heading-compensator.md): `both` (each on the whole
    /// budget, the better design is written), `paper` (the reference's heading) or
    /// `compensated` (a heading whose rate cancels the tilt-induced yaw, `L` = 0.3 rad/s,
    /// `k_ψ` = 1/s, so the desired frame's yaw no longer pays for the tilt; the flight file
    /// carries it).
    #[arg(long, value_enum, default_value_t = DesignHeading::Both)]
    pub heading: DesignHeading,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/design")]
    pub out: PathBuf,
}

/// Runs the design and prints where its files went.
pub fn run(args: &DesignArgs) -> Result<()> {
    let integral = if !args.no_integral {
        let gravity = host_sim::design::vehicle::DesignVehicle::load(&args.vehicle)?
            .body
            .gravity;
        Some(
            IntegralSpec::covering(
                gravity,
                args.integral_mass_error,
                args.integral_force_fraction,
            )
            .map_err(anyhow::Error::msg)?,
        )
    } else {
        None
    };
    let outcome = run_design(&DesignOptions {
        vehicle: args.vehicle.clone(),
        reference: args.reference.clone(),
        seed: args.seed,
        margin: args.margin,
        fit: match args.airmode {
            DesignAirmode::On => RotorFit::Airmode,
            DesignAirmode::Off => RotorFit::Set,
        },
        evaluations: args.evaluations,
        duration_s: args.duration_s.unwrap_or(DEFAULT_DURATION_S),
        law: match args.law {
            DesignLaw::Both => LawSearch::Both,
            DesignLaw::Paper => LawSearch::One(AttitudeLaw::Paper),
            DesignLaw::TiltPriority => LawSearch::One(AttitudeLaw::TiltPriority),
        },
        envelope: args.envelope == DesignAirmode::On,
        vertical: args.vertical == DesignAirmode::On,
        heading: match args.heading {
            DesignHeading::Both => HeadingSearch::Both,
            DesignHeading::Paper => HeadingSearch::Paper,
            DesignHeading::Compensated => HeadingSearch::Compensated,
        },
        bounds: match args.bounds {
            DesignBounds::Paper => BoundsKind::Paper,
            DesignBounds::Tight => BoundsKind::Tight,
        },
        integral,
        thrust: match args.thrust {
            DesignThrust::Norm => ThrustKind::Norm,
            DesignThrust::VerticalPriority => ThrustKind::VerticalPriority,
        },
        position_saturation: match args.position_saturation {
            DesignPositionSaturation::Componentwise => PositionSaturation::Componentwise,
            DesignPositionSaturation::Norm => PositionSaturation::Norm,
        },
        lemma1: match args.lemma1 {
            DesignLemma1::Paper => Lemma1Form::Paper,
            DesignLemma1::Tangential => Lemma1Form::Tangential,
            DesignLemma1::DesiredFrame => Lemma1Form::DesiredFrame,
        },
        speed_limit: (!args.no_speed_limit).then_some(args.speed_limit),
        fallback: if args.duration_s.is_none() {
            Fallback::VelocityLimited
        } else {
            Fallback::Off
        },
        heading_held: None,
        out: args.out.clone(),
    })?;
    let r = &outcome.report;
    println!(
        "design for {}: certificate all_hold = {}, rotor_fit fits = {} (margin {:.2} %), worst settling from 180 deg {}, \
         altitude lost upside down {:.3} m, {} evaluations in {:.1} s{}",
        r.vehicle,
        r.certificate.all_hold,
        r.rotor_fit.fits,
        100.0 * r.rotor_fit.margin,
        r.objective
            .worst_settling_180_s
            .map_or("not settled".to_owned(), |s| format!("{s:.2} s")),
        r.objective.altitude_loss_upside_down_m,
        r.evaluations,
        r.wall_time_s,
        if r.reference.scaled {
            format!("; REFERENCE SLOWED DOWN x {:.4}", r.reference.scale)
        } else {
            String::new()
        }
    );
    if !r.objective.constraints_met {
        println!(
            "  NO DESIGN WITHIN THE BUDGET MET THE CONVERGENCE CONSTRAINTS (see design.md); the certificate holds"
        );
    }
    for f in &outcome.files {
        println!("  {}", f.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::super::{Cli, Command};

    fn parse(args: &[&str]) -> Result<super::DesignArgs, clap::Error> {
        let cli = Cli::try_parse_from(
            ["host-sim", "design", "--vehicle", "v.toml"]
                .iter()
                .chain(args),
        )?;
        match cli.command {
            Some(Command::Design(d)) => Ok(d),
            other => panic!("not a design command: {other:?}"),
        }
    }

    /// Given no integral flag, when parsed, then the design carries the integral action covering
    /// 10 % of mass and 5 % of the weight; `--no-integral` turns it off and refuses a coverage.
    #[test]
    fn the_integral_action_is_on_by_default() {
        let d = parse(&[]).unwrap();
        assert!(!d.no_integral);
        assert_eq!(
            (d.integral_mass_error, d.integral_force_fraction),
            (0.1, 0.05)
        );
        assert!(parse(&["--no-integral"]).unwrap().no_integral);
        let e = parse(&["--no-integral", "--integral-mass-error", "0.2"]).unwrap_err();
        assert_eq!(e.kind(), clap::error::ErrorKind::ArgumentConflict);
    }

    /// Given no shape or law flag, when parsed, then the design searches the norm shape (whose
    /// convergence is proven, docs/position-saturation.md) and both attitude laws;
    /// `componentwise` selects the paper's shape, `--law paper` one law, anything else is
    /// refused.
    #[test]
    fn the_norm_shape_and_both_laws_are_the_defaults() {
        use super::{DesignLaw, DesignPositionSaturation as Shape};
        let d = parse(&[]).unwrap();
        assert_eq!(d.position_saturation, Shape::Norm);
        assert_eq!(d.law, DesignLaw::Both);
        let paper = parse(&["--position-saturation", "componentwise", "--law", "paper"]).unwrap();
        assert_eq!(paper.position_saturation, Shape::Componentwise);
        assert_eq!(paper.law, DesignLaw::Paper);
        let e = parse(&["--position-saturation", "radial"]).unwrap_err();
        assert_eq!(e.kind(), clap::error::ErrorKind::InvalidValue);
    }
}
