//! The decision variables: nine numbers in `[0, 1]`, each mapped onto one physical choice, so
//! every point of the unit box is a certifiable design by construction.
//!
//! | # | variable | maps to |
//! |---|----------|---------|
//! | 0 | `k_f` | log scale on `[0.1, 6]` 1/s |
//! | 1 | `k_s / k_f` | log scale on `[1.5, 12]` (so `k_s > k_f`) |
//! | 2 | `M_p / M_p,max(k_f, k_s)` | `[0.05, 0.95]` ([`super::authority::saturation_max`]) |
//! | 3 | `ι / ι_max(M_p, k_f, k_s)` | `[0.2, 0.95]` ([`super::authority::iota_max`]) |
//! | 4 | share of `ι` taken by the MRP term `(1 + (1+δ)²) M_ϑ/4` | `[0.2, 0.9]`; `M_ω` is the rest |
//! | 5 | attitude natural frequency `ω_a` | log scale on `[0.5, 60]` rad/s |
//! | 6 | attitude damping `ζ_a` | `[0.2, 1.5]` |
//! | 7 | position natural frequency `ω_p` | log scale on `[0.5, 4]` rad/s |
//! | 8 | position damping `ζ_p` | `[0.6, 1.5]` |
//!
//! With `--law tilt-priority` ([`AttitudeLaw::TiltPriority`], `docs/tilt-priority.md`) three
//! more ([`TiltChoices`]) choose how the per-axis levels `ι_i` are spent; `ι` above is then roll's and pitch's
//! level `ι₁ = ι₂`, the rotor fit's `ι_max` taken along the direction `(1, 1, ρ)`:
//!
//! | # | variable | maps to |
//! |---|----------|---------|
//! | 9 | yaw share `ρ = ι₃/ι₁` | log scale on `[0.03, 1]` |
//! | 10 | share of `ι₃` taken by the radial MRP term | `[0.2, 0.9]`; the rest of `ι₃` is split equally between `g₁ = g₂` and `M_ω,3` |
//! | 11 | share of `ι₁ − (1+(1+δ)²)M_ϑ/4` taken by the trace term `½(g₁ + g₃)` | `[0.2, 0.9]`; `M_ω,1 = M_ω,2` is the rest |
//! | 12 | turn-over share `M_t / ι₁` (docs/turn-over.md; [`Layout::turn_over`], the refinement's) | `[0, 0.5]`; its per-axis bounds on top of the levels, in the rotor fit and Theorem 2 |
//!
//! `g₃` is capped so that tilt priority's hysteresis-band condition holds with 10 % to spare,
//! and kept `≥ g₁` (the body z axis turns first); per-axis damping
//! `k_ω,i = 2 ζ_a √(κ_i J_ii)` with the stiffness `κ_i = k_ϑ/16 + ½(g_j + g_k)` at zero error.
//!
//! Attitude gains from the linearisation about zero error: the MRP is `ϑ ≈ θ/4` (θ the error
//! angle about one axis) and the torque law is `τ ≈ −(k_ϑ/4) ϑ − k_ω ω = −(k_ϑ/16) θ − k_ω ω`
//! (Section V, `(1 + |ϑ|²)/4 → 1/4`), so `J θ̈ = −(k_ϑ/16) θ − k_ω θ̇` gives
//! `k_ϑ = 16 J ω_a²`, `k_ω = 2 ζ_a ω_a J`, with `J` the *smallest* inertia diagonal entry: `ω_a`
//! is the natural frequency of the fastest axis, the one the motor lag threatens first (the
//! other axes are slower by `sqrt(J_min/J_ii)`). Table I (`k_ϑ = 100`, `k_ω = 0.1`,
//! `J_11 = 2.24e-3`) is `ω_a = 52.8` rad/s, `ζ_a = 0.42`.
//!
//! Position gains: in the z-coordinates of Section IV the loop is the double integrator
//! `z̈₁ = ubar_p = −σ_p(k_p z₁ + k_v ż₁)`, so `k_p = ω_p²`, `k_v = 2 ζ_p ω_p` (Table I: `ω_p = 3`,
//! `ζ_p = 1`).

use controller_core::torque_set::AttitudeJoint;
use controller_core::{
    Gains, TorqueSet, TrajectoryConstants, Vehicle, VelocityLimit, VerticalBraking,
};
use nalgebra::Vector3;

use super::authority::{
    envelope_with, iota_max, iota_max_along, iota_max_by, mrp_factor, probe_gains,
    saturation_max_with, shadow_iota_max, theorem2_iota_max_axes, PositionLaw, RotorFit, RotorSet,
    ALPHA, DELTA,
};
use super::binding::IotaCap;

pub(crate) mod interval;
mod local;
mod tilt;
mod vertical;

use interval::{unit_in, value_in, Interval};

use local::local_gains;
pub use local::{energy_out, LocalChoices, F32_SLACK};
use local::{LOCAL_INTEGRAL_NAME, LOCAL_VERTICAL_NAME, LOCAL_VERTICAL_RANGE};
use tilt::{tilt_gains, turn_over_shares};
pub use tilt::{TiltChoices, TURN_OVER_ONSET};
pub use vertical::VerticalChoices;

/// Number of decision variables of the paper's attitude law.
pub const DIMENSION: usize = 9;
/// Number of decision variables with tilt priority (three more).
pub const TILT_DIMENSION: usize = DIMENSION + 3;
/// The index of tilt priority's turn-over share (module table), when [`Layout::turn_over`].
pub const TURN_OVER: usize = TILT_DIMENSION;
/// Number of decision variables the envelope design's local regime adds, after the vertical
/// channel's ([`LocalChoices`]).
pub const LOCAL_DIMENSION: usize = 6;
/// Number of decision variables the vertical channel apart adds, after the attitude law's
/// ([`VerticalChoices`]).
pub const VERTICAL_DIMENSION: usize = 4;

/// The attitude feedback a design searches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum AttitudeLaw {
    /// The paper's law (Section V): one feedback torque level `ι` on every axis.
    #[default]
    Paper,
    /// Tilt priority (`docs/tilt-priority.md`): per-axis levels `ι_i`, a small yaw level and
    /// the body z axis turned first.
    TiltPriority,
}

impl AttitudeLaw {
    /// Its name on the command line and in `design.json`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::TiltPriority => "tilt-priority",
        }
    }

    /// Number of decision variables.
    pub fn dimension(self) -> usize {
        match self {
            Self::Paper => DIMENSION,
            Self::TiltPriority => TILT_DIMENSION,
        }
    }
}

/// Which variables a point of the unit box holds: the attitude law's, then the vertical
/// channel's (docs/vertical-channel.md), then the local regime's (docs/envelope-design.md), each
/// when the design searches it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Layout {
    /// The attitude feedback searched.
    pub law: AttitudeLaw,
    /// Whether the envelope design's local regime is searched too.
    pub local: bool,
    /// Whether the vertical channel's own levels are searched too.
    pub vertical: bool,
    /// Whether a local regime that fits at no filter ratio with its chosen envelope is narrowed
    /// (`LocalChoices::narrow`): the refinement's, after the search (`crate::design::refine`).
    pub narrow_local: bool,
    /// Whether the local regime's own vertical filters are searched too (one more local
    /// variable, `LocalChoices::vertical_kf_ratio`; with `vertical`): the refinement's.
    pub local_vertical: bool,
    /// Whether tilt priority's turn-over share is searched too (variable [`TURN_OVER`], right
    /// after the law's; with [`AttitudeLaw::TiltPriority`]): the turn-over refinement's
    /// (`crate::design::refine::turn_over`). Without it the term is off.
    pub turn_over: bool,
    /// Whether the integral action and its observer are sized at a frequency of their own, one
    /// more local variable after the others (`LocalChoices::integral_frequency_rad_s`; with
    /// `local`): the local loop's polish (`crate::design::refine::local_loop`). Without it they
    /// are sized at the loop's `ω_p,L`.
    pub local_integral: bool,
}

impl Layout {
    /// Number of decision variables.
    pub fn dimension(self) -> usize {
        self.attitude_dimension()
            + if self.vertical { VERTICAL_DIMENSION } else { 0 }
            + self.local_dimension()
    }

    /// Number of the attitude law's decision variables, the first of a point: the law's, and
    /// the turn-over share with [`Layout::turn_over`] and tilt priority.
    pub fn attitude_dimension(self) -> usize {
        self.law.dimension() + usize::from(self.turn_over && self.law == AttitudeLaw::TiltPriority)
    }

    /// Number of the local regime's decision variables, the last of a point: none without it,
    /// [`LOCAL_DIMENSION`], one more with its own vertical filters, one more with the integral
    /// held apart ([`Layout::local_integral`]).
    pub fn local_dimension(self) -> usize {
        match (self.local, self.local_vertical && self.vertical) {
            (false, _) => 0,
            (true, vertical) => {
                LOCAL_DIMENSION + usize::from(vertical) + usize::from(self.local_integral)
            }
        }
    }
}

/// The interval of each variable: `(low, high, logarithmic)`.
const RANGES: [Interval; TILT_DIMENSION + 1] = [
    (0.1, 6.0, true),
    (1.5, 12.0, true),
    (0.05, 0.95, false),
    (0.2, 0.95, false),
    (0.2, 0.9, false),
    (0.5, 60.0, true),
    (0.2, 1.5, false),
    (0.5, 4.0, true),
    (0.6, 1.5, false),
    (0.03, 1.0, true),
    (0.2, 0.9, false),
    (0.2, 0.9, false),
    (0.0, 0.5, false),
];

/// The names of [`RANGES`]' variables, as reports print them (module table).
const NAMES: [&str; TILT_DIMENSION + 1] = [
    "k_f [1/s]",
    "k_s / k_f",
    "M_p / M_p,max",
    "iota / iota_max",
    "MRP share of iota",
    "attitude natural frequency [rad/s]",
    "attitude damping",
    "position natural frequency [rad/s]",
    "position damping",
    "yaw share iota_3 / iota_1",
    "radial share of iota_3",
    "trace share of iota_1",
    "turn-over share M_t / iota_1",
];

/// The index of the MRP share of `ι` (module table), which tilt priority does not read.
const MRP_SHARE: usize = 4;

/// A decision variable that the design found at an end of its search range.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RangeEnd {
    /// Its name (module table).
    pub variable: &'static str,
    /// Its value (units in the name, else dimensionless).
    pub value: f64,
    /// Its search range `[low, high]`.
    pub range: [f64; 2],
}

impl Choices {
    /// The variables within `within` (a fraction of the unit interval, e.g. 0.01) of an end of
    /// their search range, in the module table's order: where a wider range might find a better
    /// design, or where the design takes all of a certified level it may (`M_p / M_p,max`,
    /// `ι / ι_max` at 0.95). Tilt priority's gains do not read the MRP share (variable 4; its
    /// own three spend `ι`), so it is never reported with it. No errors.
    pub fn range_ends(&self, within: f64) -> Vec<RangeEnd> {
        let tilt = self.tilt.map_or(0, |t| {
            TILT_DIMENSION - DIMENSION + usize::from(t.turn_over_share.is_some())
        });
        let named = NAMES.iter().zip(RANGES).take(DIMENSION + tilt);
        let vertical = self.vertical.iter().flat_map(|_| {
            vertical::VERTICAL_NAMES
                .iter()
                .zip(vertical::VERTICAL_RANGES)
        });
        let local = self.local.iter().flat_map(|l| {
            let vertical = l
                .vertical_kf_ratio
                .map(|_| (&LOCAL_VERTICAL_NAME, LOCAL_VERTICAL_RANGE));
            let integral = l
                .integral_frequency_rad_s
                .map(|_| (&LOCAL_INTEGRAL_NAME, local::LOCAL_RANGES[2]));
            local::LOCAL_NAMES
                .iter()
                .zip(local::LOCAL_RANGES)
                .chain(vertical)
                .chain(integral)
        });
        named
            .chain(vertical)
            .chain(local)
            .zip(self.to_unit())
            .enumerate()
            .filter(|&(i, (_, x))| {
                (x <= within || x >= 1.0 - within) && !(i == MRP_SHARE && self.tilt.is_some())
            })
            .map(|(_, v)| v)
            .map(|((name, range), x)| RangeEnd {
                variable: name,
                value: value_in(range, x),
                range: [range.0, range.1],
            })
            .collect()
    }
}

fn to_value(i: usize, x: f64) -> f64 {
    value_in(RANGES[i], x)
}

fn to_unit(i: usize, v: f64) -> f64 {
    unit_in(RANGES[i], v)
}

/// The physical choices of one design (before they become gains).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Choices {
    /// `k_f` [1/s].
    pub kf: f64,
    /// `k_s` [1/s].
    pub ks: f64,
    /// `M_p / M_p,max`.
    pub saturation_fraction: f64,
    /// `ι / ι_max`.
    pub iota_fraction: f64,
    /// Share of `ι` in the MRP term.
    pub mrp_share: f64,
    /// Attitude natural frequency [rad/s] (smallest-inertia axis).
    pub attitude_frequency_rad_s: f64,
    /// Attitude damping ratio.
    pub attitude_damping: f64,
    /// Position natural frequency [rad/s].
    pub position_frequency_rad_s: f64,
    /// Position damping ratio.
    pub position_damping: f64,
    /// How tilt priority spends the per-axis levels; `None`: the paper's law.
    pub tilt: Option<TiltChoices>,
    /// The vertical channel's levels; `None`: `M_p` on every axis.
    pub vertical: Option<VerticalChoices>,
    /// The envelope design's local regime; `None`: one set of position gains.
    pub local: Option<LocalChoices>,
}

impl Choices {
    /// From a point of the unit box (clamped into it) laid out as `layout`: 9 coordinates for
    /// the paper's law, 12 for tilt priority (13 with its turn-over share), then the vertical
    /// channel's and the local regime's.
    pub fn from_unit(x: &[f64], layout: Layout) -> Self {
        let v = |i: usize| to_value(i, x.get(i).copied().unwrap_or(0.5));
        let kf = v(0);
        let tilt = (layout.law == AttitudeLaw::TiltPriority).then(|| TiltChoices {
            yaw_share: v(9),
            yaw_radial_share: v(10),
            roll_trace_share: v(11),
            turn_over_share: (layout.attitude_dimension() > TILT_DIMENSION).then(|| v(TURN_OVER)),
        });
        let base = layout.attitude_dimension();
        let vertical = layout
            .vertical
            .then(|| VerticalChoices::from_unit(x.get(base..).unwrap_or(&[])));
        let base = base
            + if layout.vertical {
                VERTICAL_DIMENSION
            } else {
                0
            };
        let local = layout.local.then(|| {
            LocalChoices::from_unit(
                x.get(base..).unwrap_or(&[]),
                layout.narrow_local,
                (
                    layout.local_vertical && layout.vertical,
                    layout.local_integral,
                ),
            )
        });
        Self {
            kf,
            ks: kf * v(1),
            saturation_fraction: v(2),
            iota_fraction: v(3),
            mrp_share: v(4),
            attitude_frequency_rad_s: v(5),
            attitude_damping: v(6),
            position_frequency_rad_s: v(7),
            position_damping: v(8),
            tilt,
            vertical,
            local,
        }
    }

    /// The point of the unit box (inverse of [`Choices::from_unit`], clamped).
    pub fn to_unit(&self) -> Vec<f64> {
        let tilt = self
            .tilt
            .map(|t| [t.yaw_share, t.yaw_radial_share, t.roll_trace_share]);
        let turn_over = self.tilt.and_then(|t| t.turn_over_share);
        [
            self.kf,
            self.ks / self.kf,
            self.saturation_fraction,
            self.iota_fraction,
            self.mrp_share,
            self.attitude_frequency_rad_s,
            self.attitude_damping,
            self.position_frequency_rad_s,
            self.position_damping,
        ]
        .iter()
        .chain(tilt.iter().flatten())
        .chain(turn_over.iter())
        .enumerate()
        .map(|(i, &v)| to_unit(i, v))
        .chain(self.vertical.iter().flat_map(|v| v.to_unit()))
        .chain(self.local.iter().flat_map(|l| l.to_unit()))
        .collect()
    }

    /// The initial guess: the most certified torque authority (`ι` at 90 % of `ι_max`) with a
    /// moderate position saturation, slow filters and moderate, well-damped loops; for tilt
    /// priority, [`TiltChoices::initial_guess`]; with the local regime,
    /// [`LocalChoices::initial_guess`].
    pub fn initial_guess(layout: Layout) -> Self {
        let law = layout.law;
        Self {
            kf: 0.6,
            ks: 1.5,
            saturation_fraction: 0.5,
            iota_fraction: 0.9,
            mrp_share: 0.8,
            attitude_frequency_rad_s: 10.0,
            attitude_damping: 0.8,
            position_frequency_rad_s: 1.0,
            position_damping: 1.0,
            tilt: (law == AttitudeLaw::TiltPriority).then(|| TiltChoices {
                turn_over_share: layout.turn_over.then_some(0.0),
                ..TiltChoices::initial_guess()
            }),
            vertical: layout.vertical.then(VerticalChoices::initial_guess),
            local: layout.local.then(|| LocalChoices {
                vertical_kf_ratio: (layout.local_dimension() > LOCAL_DIMENSION).then_some(1.0),
                ..LocalChoices::initial_guess()
            }),
        }
    }
}

/// What the context of a design needs to turn choices into gains.
#[derive(Clone, Copy, Debug)]
pub struct Context<'a> {
    /// The vehicle's rigid body.
    pub vehicle: &'a Vehicle<f64>,
    /// The reference's Assumption 1 constants.
    pub constants: &'a TrajectoryConstants<f64>,
    /// The rotor set.
    pub rotors: &'a RotorSet,
    /// Box-fit margin (fraction of the rotor range).
    pub margin: f64,
    /// How the certified set must sit in the rotors' set: the whole thrust interval at every
    /// torque, or airmode's shadow and aligned fits (docs/airmode.md).
    pub fit: RotorFit,
    /// The bounds that certify the torque condition and the rotor fit.
    pub bounds: super::tight::BoundsKind,
    /// The position law's options that enter the bounds: the bounded integral action (`Some`:
    /// sized by this spec, every bound the extended one, [`super::integral`]) and the shape of
    /// `σ_p` (docs/position-saturation.md).
    pub position: PositionLaw<'a>,
    /// `Some(V)`: the velocity-limited position feedback with speed limit `V` [m/s] and braking
    /// [`BRAKING_SHARE`] `× M_p` (and of `M_up`, `M_down` vertically with the vertical channel
    /// apart; `--speed-limit`, docs/velocity-limit.md).
    pub speed_limit: Option<f64>,
}

/// Braking acceleration of the velocity-limited feedback, as a share of `M_p`: the profile
/// asks for 70 % of the level, so the rest of it covers the filters' lag and disturbances.
pub const BRAKING_SHARE: f64 = 0.7;

/// The gains of `choices`, with `M_p,max` and `ι_max` they were scaled from.
#[derive(Clone, Copy, Debug)]
pub struct Mapped {
    /// Table I gains.
    pub gains: Gains<f64>,
    /// `M_p,max(k_f, k_s)` [m/s²].
    pub saturation_max: f64,
    /// `ι_max(M_p, k_f, k_s)` [N m] (roll's, with tilt priority).
    pub iota_max: f64,
    /// What sets `ι_max`: the rotor fit's level and Theorem 2's per axis.
    pub iota_cap: IotaCap,
}

/// The position law of `c` in `ctx`: `ctx`'s, with `c`'s vertical channel ratios.
pub fn position_law<'a>(ctx: &Context<'a>, c: &Choices) -> PositionLaw<'a> {
    PositionLaw {
        vertical: c
            .vertical
            .map(|v| (v.up_ratio, v.down_ratio, v.kf_ratio, v.ks_ratio)),
        ..ctx.position
    }
}

/// The joint bound's grid in the turn-over refinement's `ι_max` bisection: a quarter of the
/// certificate's [`controller_core::torque_set::attitude_joint::JOINT_SLABS`] (which it
/// divides), so each of its boxes holds sixteen of the certificate's and its bound is never the
/// smaller, at about a quarter of the cost (the quadtree skips most boxes on either grid; `cargo bench -p host-sim --bench control
/// -- attitude_joint`).
const SEARCH_JOINT_SLABS: usize = 32;

/// Maps `choices` to gains. `None` when no positive `ι` exists for `(k_f, k_s)` (the reference
/// is not certifiable on this vehicle), or when with the integral action no `k_i` makes the
/// linearised loop stable ([`super::integral::IntegralSpec::gains`]).
pub fn map(ctx: &Context<'_>, c: &Choices) -> Option<Mapped> {
    let law = position_law(ctx, c);
    let mp_max = saturation_max_with(
        ctx.bounds,
        ctx.vehicle,
        ctx.constants,
        (ctx.rotors, ctx.margin, ctx.fit),
        (c.kf, c.ks),
        law,
    )?;
    let mp = mp_max * c.saturation_fraction;
    let env = envelope_with(
        ctx.bounds,
        ctx.vehicle,
        ctx.constants,
        (mp, c.kf, c.ks),
        law,
    )?;
    let j = ctx.vehicle.inertia.min();
    let w = c.attitude_frequency_rad_s;
    let k_mrp = 16.0 * j * w * w;
    // The paper's feedback is a ball of radius ι (closed form); tilt priority's the set of its
    // gains for ι (ball, disks and box), found from the box's level by bisection.
    let i_max = match (c.tilt, ctx.fit) {
        (None, RotorFit::Set) => iota_max(ctx.rotors, &env, ctx.margin),
        (None, RotorFit::Airmode) => shadow_iota_max(ctx.rotors, &env, ctx.margin),
        (Some(t), fit) => {
            let d = Vector3::new(1.0, 1.0, t.yaw_share) + turn_over_shares(t.turn_over());
            // A level known to fit: the box's on the thrust interval, or with airmode the
            // ball's through the shadow, shrunk so that the ball holds the box `ι d`.
            let lower = match fit {
                RotorFit::Set => iota_max_along(ctx.rotors, &env, ctx.margin, &d),
                RotorFit::Airmode => shadow_iota_max(ctx.rotors, &env, ctx.margin) / d.norm(),
            };
            iota_max_by(ctx.rotors, &env, (ctx.margin, fit), lower, |iota| {
                let (tilt, mrp_saturation) =
                    tilt_gains(&t, iota, k_mrp, &ctx.vehicle.inertia, c.attitude_damping);
                let mut set = TorqueSet::tilt_priority(
                    Vector3::zeros(),
                    0.0,
                    0.0,
                    mrp_factor() * mrp_saturation,
                    tilt.trace_weights,
                    tilt.omega_levels + tilt.turn_over_bounds(DELTA),
                );
                // Where the turn-over term is searched, its level is paid for by the certified
                // joint bound of the attitude terms (docs/torque-set.md), on a coarser grid:
                // looser, never below the certificate's, so what fits here fits there.
                if t.turn_over_share.is_some() {
                    set.attitude_joint =
                        AttitudeJoint::of(&tilt, mrp_saturation, k_mrp, DELTA, SEARCH_JOINT_SLABS);
                }
                set
            })
        }
    };
    // Theorem 2's per-axis conditions, with the feedforward they are judged with (Lemma 1's
    // norms, or the tight bounds'), cap the level too (the set's tighter norms no longer imply
    // them).
    let shares = c.tilt.map_or(Vector3::repeat(1.0), |t| {
        Vector3::new(1.0, 1.0, t.yaw_share) + turn_over_shares(t.turn_over())
    });
    let iota_cap = IotaCap {
        rotor_fit_Nm: i_max,
        theorem2_Nm: theorem2_iota_max_axes(ctx.rotors, &env, ctx.fit, &shares).into(),
    };
    let i_max = iota_cap.theorem2_Nm.iter().fold(i_max, |a, &b| a.min(b));
    if i_max <= 0.0 {
        return None;
    }
    let iota = c.iota_fraction * i_max;
    let wp = c.position_frequency_rad_s;
    let mut g = probe_gains(mp, c.kf, c.ks, law);
    g.position.kp = wp * wp;
    g.position.kv = 2.0 * c.position_damping * wp;
    g.attitude.k_mrp = k_mrp;
    g.attitude.k_omega = 2.0 * c.attitude_damping * w * j;
    g.attitude.mrp_saturation = c.mrp_share * iota / mrp_factor();
    g.attitude.omega_saturation = (1.0 - c.mrp_share) * iota;
    if let Some(t) = &c.tilt {
        let (tilt, mrp_saturation) = tilt_gains(
            t,
            iota,
            g.attitude.k_mrp,
            &ctx.vehicle.inertia,
            c.attitude_damping,
        );
        g.attitude.mrp_saturation = mrp_saturation;
        // Unused by tilt priority's torque; kept valid (`> 0`) for `certify`'s checks.
        g.attitude.omega_saturation = tilt.omega_levels.x;
        g.attitude.k_omega = tilt.omega_gains.x;
        g.tilt_priority = Some(tilt);
    }
    // With the vertical channel apart, the vertical profile brakes at the same share of each
    // of its levels (the descent at `M_up`'s, the climb at `M_down`'s).
    g.velocity_limit = ctx.speed_limit.map(|speed| VelocityLimit {
        speed,
        braking: BRAKING_SHARE * mp,
        vertical: g.position.vertical.map(|v| VerticalBraking {
            up: BRAKING_SHARE * v.up,
            down: BRAKING_SHARE * v.down,
        }),
    });
    g.hysteresis = DELTA;
    g.reset_threshold = ALPHA;
    // The envelope design's local regime, with the probe's integral terms (sized by the global
    // filters, as the final ones).
    g.local = c.local.and_then(|l| local_gains(ctx, &g, &l));
    if let Some(spec) = law.integral {
        // Stable with the position gains the loop settles with: the local ones when there are;
        // sized at the local loop's frequency unless the polish holds it apart.
        let settled = g.local.map_or(g.position, |l| l.position(&g.position));
        let frequency = c
            .local
            .and_then(|l| l.integral_frequency_rad_s)
            .unwrap_or_else(|| settled.kp.sqrt());
        g.integral = Some(spec.gains_at(frequency, &settled, (c.kf, c.ks))?);
    }
    Some(Mapped {
        gains: g,
        saturation_max: mp_max,
        iota_max: i_max,
        iota_cap,
    })
}

#[cfg(test)]
pub(crate) mod tests;
