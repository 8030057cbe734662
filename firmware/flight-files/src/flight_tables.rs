//! The `[limits]`, `[gains]` and `[trajectory]` tables (TOML) of host-sim's scenario files and
//! of the firmware build's flight file: actuator limits, the Table I gains and the reference
//! trajectory with its heading profile, with units in the key names (format:
//! `docs/firmware-board.md`, "Flight files").
//!
//! Unknown keys are refused (`deny_unknown_fields`); the values are checked by their users
//! (host-sim's `Scenario::validate`, the build's flight file checks).
//!
//! Used by host-sim's scenario files, by the firmware library (`firmware::flight_tables`, with
//! its `vehicle-file` feature) and by the firmware's build script through
//! [`crate::flight_file`], which turns the build's flight file into Rust source.

use serde::{Deserialize, Serialize};

/// `[limits]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct LimitsTable {
    /// Maximum thrust \[N\].
    pub thrust_max_N: f64,
    /// Per-axis maximum torque [N m], body frame.
    pub torque_max_Nm: [f64; 3],
}

/// `[gains]`, Table I names.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct GainsTable {
    /// `k_p` [1/s²].
    pub kp: f64,
    /// `k_v` [1/s].
    pub kv: f64,
    /// `k_f` [1/s].
    pub kf: f64,
    /// `k_s` [1/s].
    pub ks: f64,
    /// `k_ϑ`.
    pub k_theta: f64,
    /// `k_ω`.
    pub k_omega: f64,
    /// `M_p` [m/s²].
    pub M_p: f64,
    /// `M_ϑ` [N m].
    pub M_theta: f64,
    /// `M_ω` [N m].
    pub M_omega: f64,
    /// Hysteresis `δ`.
    pub delta: f64,
    /// Reset threshold `α`.
    pub alpha: f64,
    /// Shape of the position feedback's saturation `σ_p`: `"componentwise"` (absent: the
    /// paper's) or `"norm"` (extension, docs/position-saturation.md).
    #[serde(
        default,
        skip_serializing_if = "PositionSaturationTable::is_componentwise"
    )]
    pub position_saturation: PositionSaturationTable,
    /// The chain the certificate bounds `|ω̇_d|` with: `"paper"` (absent: Lemma 1 as the paper
    /// states it) or `"tangential"` (extension, docs/tangential-lemma1.md). The law is the same.
    #[serde(default, skip_serializing_if = "Lemma1Table::is_paper")]
    pub lemma1: Lemma1Table,
    /// `[gains.integral]`: the bounded integral action (absent = off, the paper's law;
    /// extension, docs/integral-action.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integral: Option<IntegralTable>,
    /// `[gains.tilt_priority]` (and `[gains.local.attitude.tilt_priority]`): per-axis attitude feedback with tilt priority (absent = off, the
    /// paper's radial feedback; extension, docs/tilt-priority.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_priority: Option<TiltPriorityTable>,
    /// `[gains.velocity_limit]`: the velocity-limited position feedback (absent = off, the
    /// paper's `−σ_p(k_p z₁ + k_v z₂)`; extension, docs/velocity-limit.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_limit: Option<VelocityLimitTable>,
    /// `[gains.vertical]`: the vertical channel's own saturation levels (absent = off, `M_p` on
    /// every axis; extension, docs/vertical-channel.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical: Option<VerticalTable>,
    /// `[gains.local]`: the envelope design's local regime (absent = off, one set of position
    /// gains; extension, docs/envelope-design.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub local: Option<LocalTable>,
    /// `[gains.heading_compensator]`: the desired frame built from a compensated heading
    /// (extension, controller-core's `heading_compensator`); absent: from the reference heading.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_compensator: Option<HeadingCompensatorTable>,
}

/// `[gains.vertical]`: the vertical channel of the position feedback apart from the horizontal
/// one (extension, docs/vertical-channel.md, controller-core's `vertical_channel`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct VerticalTable {
    /// `M_up` [m/s²]: the largest upward `ubar_p,z` (braking a fall).
    pub up_m_s2: f64,
    /// `M_down` [m/s²]: the largest downward `ubar_p,z` (Theorem 1's thrust floor takes only this).
    pub down_m_s2: f64,
    /// `k_f,z` [1/s]: the vertical output filter's bandwidth.
    pub kf: f64,
    /// `k_s,z` [1/s]: the vertical inner filter's bandwidth.
    pub ks: f64,
}

/// `[gains.local]`: the envelope design's local position gains, flown while the attitude energy
/// is inside `energy_out_J` once it has fallen to `energy_in_J` (extension,
/// docs/envelope-design.md, controller-core's `local_regime`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct LocalTable {
    /// `k_p` [1/s²] of the local regime.
    pub kp: f64,
    /// `k_v` [1/s] of the local regime.
    pub kv: f64,
    /// `k_f` [1/s] of the local regime, at least `[gains] kf`.
    pub kf: f64,
    /// `k_s` [1/s] of the local regime.
    pub ks: f64,
    /// `M_p,L` [m/s²]: the local regime's saturation level (above `[gains] M_p` too: the
    /// certificate then checks Theorem 1 for it, `local_regime.*`).
    pub M_p_m_s2: f64,
    /// `E_in` \[J\]: the local gains take over once the attitude energy is at most this.
    pub energy_in_J: f64,
    /// `E_out` \[J\], above `E_in`: the global gains take back over above this.
    pub energy_out_J: f64,
    /// `[gains.local.vertical]`: the local regime's own vertical channel, with `[gains.vertical]`
    /// (absent = the global vertical channel in both regimes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical: Option<LocalVerticalTable>,
    /// `braking_m_s2`: the local regime's horizontal braking acceleration [m/s²], below
    /// `M_p_m_s2`, with `[gains.velocity_limit]` (absent: the global braking at the local
    /// level's share, never above it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub braking_m_s2: Option<f64>,
    /// `[gains.local.attitude]`: the local regime's own attitude law (absent: the global law in
    /// both regimes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attitude: Option<LocalAttitudeTable>,
}

/// `[gains.local.attitude]`: the attitude law the local regime flies (controller-core's
/// `LocalAttitude`): the `[gains]` attitude keys, and optionally its own tilt priority.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct LocalAttitudeTable {
    /// `k_ϑ` [N m] of the local law.
    pub k_theta: f64,
    /// `k_ω` [N m s/rad] of the local law (unused with its tilt priority).
    pub k_omega: f64,
    /// `M_ϑ` [N m] of the local law.
    pub M_theta: f64,
    /// `M_ω` [N m] of the local law (unused with its tilt priority).
    pub M_omega: f64,
    /// `[gains.local.attitude.tilt_priority]`: the local law's tilt priority (absent: the
    /// paper's radial feedback with the gains above).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_priority: Option<TiltPriorityTable>,
}

/// `[gains.local.vertical]`: the local regime's vertical filter bandwidths and, optionally, its
/// vertical levels (absent: `[gains.vertical]`'s; controller-core's `VerticalChannel`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct LocalVerticalTable {
    /// `k_f,z,L` [1/s]: the vertical output filter's bandwidth, at least `[gains.vertical] kf`.
    pub kf: f64,
    /// `k_s,z,L` [1/s]: the vertical inner filter's bandwidth.
    pub ks: f64,
    /// `M_up,L` [m/s²]: the largest upward `ubar_p,z` while the local regime flies (absent:
    /// `[gains.vertical] up_m_s2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up_m_s2: Option<f64>,
    /// `M_down,L` [m/s²]: the largest downward `ubar_p,z` while the local regime flies (absent:
    /// `[gains.vertical] down_m_s2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub down_m_s2: Option<f64>,
}

impl LocalVerticalTable {
    /// `(M_up,L, M_down,L)` [m/s²]: this table's levels, each `global`'s (`[gains.vertical]`)
    /// where absent; 0 where absent without `[gains.vertical]`, which `certify` refuses (a local
    /// vertical channel needs the global one).
    pub fn levels(&self, global: Option<&VerticalTable>) -> (f64, f64) {
        let (up, down) = global.map_or((0.0, 0.0), |c| (c.up_m_s2, c.down_m_s2));
        (self.up_m_s2.unwrap_or(up), self.down_m_s2.unwrap_or(down))
    }
}

/// `[gains.heading_compensator]`: the heading state whose rate cancels the desired frame's
/// tilt-induced yaw, so that the frame's yaw rate is `c = ψ̇_d + L tanh(k_ψ sin(ψ_d − ψ_c)/L)`
/// alone (extension, controller-core's `heading_compensator`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HeadingCompensatorTable {
    /// `L` [rad/s]: the level of the heading correction, `> 0`.
    pub level_rad_s: f64,
    /// `k_ψ` [1/s]: the heading correction's gain at zero heading error, `> 0`.
    pub gain_1_s: f64,
}

/// `[gains] position_saturation`: the shape of the position feedback's saturation `σ_p`
/// (controller-core's `PositionSaturation`).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PositionSaturationTable {
    /// `M_p tanh(y_i/M_p)` per inertial component (Definition 1, Section VI).
    #[default]
    Componentwise,
    /// `M_p y / sqrt(M_p² + |y|²)` (extension, docs/position-saturation.md).
    Norm,
}

impl PositionSaturationTable {
    /// Whether this is the paper's shape (then the key is left out when written).
    pub fn is_componentwise(&self) -> bool {
        *self == Self::Componentwise
    }
}

/// `[gains] lemma1`: the chain the certificate bounds `|ω̇_d|` with (controller-core's
/// `Lemma1Form`).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Lemma1Table {
    /// Lemma 1 as the paper states it.
    #[default]
    Paper,
    /// Only the parts of `ρ̈`, `ϋ` that `ω̇_d` reads (extension, docs/tangential-lemma1.md).
    Tangential,
    /// The tangential chain, with Theorem 2's per-axis conditions judged on the desired frame's
    /// norms of `ω_d`, `ω̇_d` (extension, docs/torque-set.md).
    DesiredFrame,
}

impl Lemma1Table {
    /// Whether this is the paper's chain (then the key is left out when written).
    pub fn is_paper(&self) -> bool {
        *self == Self::Paper
    }
}

/// `[gains.velocity_limit]`: the braking profile of the velocity-limited position feedback
/// (extension, docs/velocity-limit.md, controller-core's `velocity_limit`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct VelocityLimitTable {
    /// `V` [m/s]: speed limit of the desired velocity, per inertial axis (z-coordinates).
    pub speed_m_s: f64,
    /// `a` [m/s²]: braking acceleration of the profile, `0 < a < M_p`.
    pub braking_m_s2: f64,
    /// `a_up` [m/s²]: with `[gains.vertical]`, the vertical profile's braking above the
    /// reference, `0 < a_up < M_up`; required with it, refused without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub braking_up_m_s2: Option<f64>,
    /// `a_down` [m/s²]: with `[gains.vertical]`, the vertical profile's braking below the
    /// reference, `0 < a_down < M_down`; required with it, refused without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub braking_down_m_s2: Option<f64>,
}

impl VelocityLimitTable {
    /// The vertical braking `(a_up, a_down)` [m/s²]: `None` when neither key is given; a key
    /// given alone reads the other as 0, which controller-core's validation refuses by name.
    pub fn vertical_braking(&self) -> Option<(f64, f64)> {
        match (self.braking_up_m_s2, self.braking_down_m_s2) {
            (None, None) => None,
            (up, down) => Some((up.unwrap_or(0.0), down.unwrap_or(0.0))),
        }
    }
}

/// `[gains.tilt_priority]`: per-axis attitude feedback with tilt priority (extension,
/// docs/tilt-priority.md, controller-core's `tilt_priority`). `k_theta`, `M_theta` of `[gains]`
/// give its radial MRP term; these replace `k_omega`, `M_omega`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct TiltPriorityTable {
    /// `(g_1, g_2, g_3)` [N m], body axes: weights of the trace potential `½ tr(G(I − R̃))`.
    pub trace_weights_Nm: [f64; 3],
    /// `k_ω,i` [N m s/rad], body axes: per-axis damping gains.
    pub omega_gains_Nm_s: [f64; 3],
    /// `M_ω,i` [N m], body axes: per-axis damping levels.
    pub omega_levels_Nm: [f64; 3],
    /// `M_t` [N m]: the turn-over term's torque about a horizontal half turn's axis
    /// (docs/turn-over.md); absent with `turn_over_onset`: off.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_over_level_Nm: Option<f64>,
    /// `ρ₀` (dimensionless, in (0, 1)): the turn-over term's onset, the horizontal MRP norm below
    /// which it is zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_over_onset: Option<f64>,
}

impl TiltPriorityTable {
    /// The turn-over term `(M_t, ρ₀)`: `None` when neither key is given; a key given alone reads
    /// the other as 0, which controller-core's validation refuses by name.
    pub fn turn_over(&self) -> Option<(f64, f64)> {
        match (self.turn_over_level_Nm, self.turn_over_onset) {
            (None, None) => None,
            (level, onset) => Some((level.unwrap_or(0.0), onset.unwrap_or(0.0))),
        }
    }
}

/// `[gains.integral]`: the bounded integral action (extension, docs/integral-action.md).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct IntegralTable {
    /// `k_i` [1/s³]: integral gain on `z₁`.
    pub k_i: f64,
    /// `M_i` [m/s²] per inertial axis: saturation level of the estimate.
    pub M_i_m_s2: [f64; 3],
    /// `R_i` [m/s³] per inertial axis: rate limit of the estimate.
    pub rate_m_s3: [f64; 3],
    /// `k_η` [1/s]: bandwidth of the estimate's output filter.
    pub k_eta: f64,
    /// `[gains.integral.observer]`: the velocity disturbance observer that anchors the estimate
    /// (absent: the integral of `z₁` alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observer: Option<ObserverTable>,
    /// `[gains.integral.feedforward_scale]`: the bounded estimate of the feedforward's scale (a
    /// mass or thrust-coefficient error; absent: the paper's feedforward `p̈_d`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feedforward_scale: Option<FeedforwardScaleTable>,
}

/// `[gains.integral.feedforward_scale]`: the feedforward scale `μ` (extension,
/// docs/integral-action.md, controller-core's `feedforward_scale`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FeedforwardScaleTable {
    /// `λ` [1/s]: adaptation gain along the reference's acceleration.
    pub gain_1_s: f64,
    /// `a₀` [m/s²]: floor of the normalisation by `|p̈_d|²`.
    pub excitation_m_s2: f64,
    /// `μ̄` (dimensionless, in (0, 1)): the largest mass or thrust-coefficient error covered.
    pub level: f64,
    /// `R_μ` [1/s]: rate limit of the estimate.
    pub rate_1_s: f64,
    /// `z̄_μ` \[m\]: the estimate adapts only while every `|z₁,i|` is at most this.
    pub tracking_limit_m: f64,
}

/// `[gains.integral.observer]`: the velocity disturbance observer (extension,
/// docs/integral-action.md, controller-core's `disturbance_observer`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObserverTable {
    /// `L_v` [1/s]: gain of the velocity innovation in the observer's velocity.
    pub velocity_gain_1_s: f64,
    /// `L_d` [1/s²]: gain of the velocity innovation in the estimate's rate.
    pub disturbance_gain_1_s2: f64,
    /// `z̄` \[m\]: per-axis clamp of `z₁` before `k_i`.
    pub error_limit_m: f64,
}

/// `[trajectory]`, tagged by `kind`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TrajectoryTable {
    /// Hold a point.
    Hover {
        /// Point \[m\], inertial.
        point_m: [f64; 3],
        /// Heading profile (default: yaw 0).
        #[serde(default)]
        heading: HeadingTable,
    },
    /// `center + (r cos f t, r sin f t, h cos f t)`.
    Helix {
        /// Center \[m\].
        center_m: [f64; 3],
        /// Radius \[m\].
        radius_m: f64,
        /// Vertical amplitude \[m\].
        vertical_amplitude_m: f64,
        /// Angular frequency [rad/s].
        frequency_rad_s: f64,
        /// Heading profile.
        #[serde(default)]
        heading: HeadingTable,
    },
    /// `center + (a sin f t, (b/2) sin 2 f t, 0)`.
    FigureEight {
        /// Center \[m\].
        center_m: [f64; 3],
        /// `a` \[m\].
        x_amplitude_m: f64,
        /// `b` \[m\].
        y_amplitude_m: f64,
        /// Angular frequency [rad/s].
        frequency_rad_s: f64,
        /// Heading profile.
        #[serde(default)]
        heading: HeadingTable,
    },
}

/// `[trajectory.heading]`, tagged by `kind`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum HeadingTable {
    /// Constant yaw.
    Constant {
        /// Yaw \[rad\].
        yaw_rad: f64,
    },
    /// `offset + amplitude sin(frequency t)`.
    Sinusoidal {
        /// Amplitude \[rad\].
        amplitude_rad: f64,
        /// Angular frequency [rad/s].
        frequency_rad_s: f64,
        /// Offset \[rad\].
        #[serde(default)]
        offset_rad: f64,
    },
}

impl Default for HeadingTable {
    /// Yaw 0 (a `[trajectory]` without `[trajectory.heading]`).
    fn default() -> Self {
        Self::Constant { yaw_rad: 0.0 }
    }
}
