//! What a design run takes and scores: its options, the long-run fallback and one scored
//! candidate.

use super::certificate::Certified;
use super::evaluate::Evaluation;
use super::integral::IntegralSpec;
use super::thrust::ThrustDesign;
use super::tight::BoundsKind;
use super::variables::{AttitudeLaw, Mapped};
use crate::model::scenario::ThrustKind;
use controller_core::{Gains, Lemma1Form, PositionSaturation};
use std::path::PathBuf;

/// Default length of each scoring run and of the written scenario \[s\]: the paper's 30 s (the
/// last 5 s are the limit-cycle window; campaigns judge convergence 5 s before the end).
pub const DEFAULT_DURATION_S: f64 = 30.0;

/// Shortest `--duration-s` \[s\]: twice the limit-cycle window.
pub const MIN_DURATION_S: f64 = 2.0 * super::evaluate::TAIL_S;

/// Speed limit [m/s] of the velocity-limited position feedback `design` flies by default
/// (`--speed-limit`, docs/velocity-limit.md), and of the fallback design
/// ([`Fallback::VelocityLimited`]) when the first attempt flew the paper's feedback.
pub const DEFAULT_SPEED_LIMIT_M_S: f64 = 20.0;

/// Run length \[s\] of the fallback design ([`Fallback::VelocityLimited`]).
pub const FALLBACK_DURATION_S: f64 = 300.0;

/// What `design` does when no design within the budget meets the convergence constraints.
#[derive(Clone, Debug, PartialEq)]
pub enum Fallback {
    /// Nothing: the best design is written and reported as not converging.
    Off,
    /// Design again: first, when the requested heading swings, for the same path with the
    /// heading held at `ψ_d(0)` on the same runs with the better law (its swing's rate
    /// multiplies the tilt rate in `ω̇_d`, which small yaw authority pays for at any attitude
    /// error); if that does not converge either, with the velocity-limited position feedback
    /// (the first attempt's speed limit, or [`DEFAULT_SPEED_LIMIT_M_S`] if it flew the paper's
    /// feedback; docs/velocity-limit.md) for the requested reference on runs of
    /// [`FALLBACK_DURATION_S`], and write that design (the CLI's default when `--duration-s` is
    /// not given): a certified design with a small `M_p` needs minutes to brake a long fall and
    /// climb back.
    VelocityLimited,
    /// This design is that second attempt: why the first was set aside, and its wall time \[s\].
    Taken {
        /// The first attempt's outcome, for the report.
        why: String,
        /// The first attempt's wall time \[s\].
        seconds: f64,
    },
}

/// The compensated heading `design` flies (`--heading compensated`, or `both`, the default):
/// `L` = 0.3 rad/s, `k_ψ` = 1/s (docs/heading-compensator.md; not searched).
pub const DESIGN_HEADING_COMPENSATOR: controller_core::HeadingCompensatorGains<f64> =
    controller_core::HeadingCompensatorGains {
        level: 0.3,
        gain: 1.0,
    };

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
    /// How the certified set must sit in the rotors' set: the whole thrust interval at every
    /// torque, or airmode's shadow and aligned fits (`--airmode`, docs/airmode.md).
    pub fit: super::authority::RotorFit,
    /// Evaluation budget of the optimiser.
    pub evaluations: usize,
    /// Length of the scoring runs and of the written scenario \[s\] (at least
    /// [`MIN_DURATION_S`]): the horizon a run must settle in, 5 s before its end. A vehicle whose
    /// certified authority is small needs longer than the paper's 30 s.
    pub duration_s: f64,
    /// The attitude feedbacks searched: both (each on the full budget, the better design is
    /// written) or one.
    pub law: LawSearch,
    /// Whether the envelope design's local regime is searched too (`--envelope`,
    /// docs/envelope-design.md): faster position gains while the attitude energy is small.
    pub envelope: bool,
    /// Whether the vertical channel's own levels are searched too (`--vertical`,
    /// docs/vertical-channel.md): a braking level upwards apart from the downward one.
    pub vertical: bool,
    /// Whether the designs fly the compensated heading ([`DESIGN_HEADING_COMPENSATOR`],
    /// `--heading`, docs/heading-compensator.md): both searched (the better design is written)
    /// or one.
    pub heading: HeadingSearch,
    /// The bounds that certify Theorem 2's torque condition and the rotor fit.
    pub bounds: BoundsKind,
    /// `Some`: the design carries the bounded integral action sized to cover this disturbance,
    /// certified with the extended bounds (the default, [`super::integral`]; `None` with `--no-integral`).
    pub integral: Option<IntegralSpec>,
    /// The thrust flown and written: the paper's `norm`, or `vertical-priority` with the lowest
    /// floor the certified box allows ([`super::thrust`]).
    pub thrust: ThrustKind,
    /// The shape of the position feedback's saturation `σ_p` searched and written
    /// (`--position-saturation`, docs/position-saturation.md).
    pub position_saturation: PositionSaturation,
    /// The chain the certificate bounds `|ω̇_d|` with (`--lemma1`, docs/tangential-lemma1.md):
    /// by default the desired frame's form (the tangential chain, Theorem 2's per-axis
    /// conditions on the desired frame's norms, docs/torque-set.md); the law is the same.
    pub lemma1: Lemma1Form,
    /// `Some(V)`: the design flies the velocity-limited position feedback with speed limit `V`
    /// [m/s] (`--speed-limit`, docs/velocity-limit.md); `None`: the paper's.
    pub speed_limit: Option<f64>,
    /// What to do when no design meets the convergence constraints.
    pub fallback: Fallback,
    /// `Some(why)`: this attempt is the fallback's first step, the requested path with the
    /// heading held at `ψ_d(0)` ([`super::reference::Reference::heading_held`]); `why` is the
    /// first attempt's outcome, for the report. `None`: the requested reference.
    pub heading_held: Option<String>,
    /// Output directory.
    pub out: PathBuf,
}

/// Which attitude feedbacks `design` searches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LawSearch {
    /// Both the paper's law and tilt priority, each with the whole evaluation budget; the
    /// design that meets the convergence constraints with the lower objective is written (which
    /// wins depends on the vehicle: tilt priority where yaw's authority is a small part of
    /// roll's, docs/tilt-priority.md). Twice the wall time of one.
    #[default]
    Both,
    /// This one only.
    One(AttitudeLaw),
}

impl LawSearch {
    /// The laws searched, in order.
    pub fn laws(self) -> Vec<AttitudeLaw> {
        match self {
            Self::Both => vec![AttitudeLaw::Paper, AttitudeLaw::TiltPriority],
            Self::One(l) => vec![l],
        }
    }
}

/// Which desired-frame headings `design` searches (docs/heading-compensator.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HeadingSearch {
    /// The paper's heading and the compensated one, each designed on the whole budget with
    /// every fallback; the design that meets the convergence constraints on the shorter runs
    /// with the lower objective is written (which wins depends on the vehicle: the compensated
    /// heading where the tilt-induced yaw fills the yaw authority, the x500). Twice the wall
    /// time of one.
    #[default]
    Both,
    /// The paper's desired frame (eq:DesiredRotationMatrix with the reference's heading).
    Paper,
    /// The compensated heading [`DESIGN_HEADING_COMPENSATOR`].
    Compensated,
}

impl HeadingSearch {
    /// Whether each design searched flies the compensated heading, in order.
    pub fn modes(self) -> Vec<bool> {
        match self {
            Self::Both => vec![false, true],
            Self::Paper => vec![false],
            Self::Compensated => vec![true],
        }
    }

    /// The compensator a single attempt flies: `Some` for [`Self::Compensated`] only
    /// (`run_design` resolves [`Self::Both`] into one attempt per mode before designing).
    pub fn compensator(self) -> Option<controller_core::HeadingCompensatorGains<f64>> {
        (self == Self::Compensated).then_some(DESIGN_HEADING_COMPENSATOR)
    }

    /// The single search flying the compensated heading when `compensated`, else the paper's.
    pub fn one(compensated: bool) -> Self {
        if compensated {
            Self::Compensated
        } else {
            Self::Paper
        }
    }
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

/// The gains of a report, for tests and callers.
pub fn gains_of(s: &Scored) -> Gains<f64> {
    s.mapped.gains
}
