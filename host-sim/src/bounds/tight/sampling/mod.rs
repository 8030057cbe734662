//! Admissible states of the law's inputs and the law's actual values at them.
//!
//! The confining set (one definition for the tight bounds and for these samples), per inertial
//! component `i` with `M = M_p`:
//! - filter states `x_f = (u_f, u_s)` reachable by eq:FilterDynamics from the start set
//!   (`0`, or any point of `[−M, M]²`) under an input `|ubar_i(t)| ≤ M`. Here a state is made
//!   reachable by construction: [`FilterHistory`] is a piecewise-constant input of
//!   [`SEGMENTS`] levels in `[−M, M]` held for non-negative durations, integrated exactly by
//!   `PositionGains::propagator`. With one real-eigenvalue pair the extreme points of the
//!   reachable set are reached by bang-bang inputs with one switch (after a long hold), which
//!   this family contains;
//! - the current `ubar_i ∈ [−M, M]`, independent of `x_f` (`p̃`, `ṽ` are free); with the norm
//!   shape of `σ_p` (docs/position-saturation.md) this cube contains the ball the law reaches;
//! - reference: `|(p̈_d1, p̈_d2)| ≤ K_a12`, `|p̈_d3| ≤ K_a3`, `|p_d⁽³⁾| ≤ K_j`, `|p_d⁽⁴⁾| ≤ K_s`,
//!   `ν_d = (cos ψ, sin ψ)`, `ν̇_d = ψ̇ ν⊥`, `ν̈_d = ψ̈ ν⊥ − ψ̇² ν` with `|ν̇_d| ≤ K_ν̇`,
//!   `|ν̈_d| ≤ K_ν̈`;
//! - attitude: `|ϑ̃| ≤ 1 + δ`, `R̃ = rotation_from_mrp(ϑ̃)`, `ω̃` any;
//! - with the integral action on (extension, docs/integral-action.md): per component the
//!   estimate `|η_i| ≤ M_i,i`, its filtered value `|η_f,i| ≤ M_i,i` and the clamped rate
//!   `|η̇_i| ≤ R_i,i`, each anywhere in its interval (the clamps allow every combination), which
//!   `IntegralGains::output` turns into the terms added to `u`, `u̇`, `ü`.
//!
//! [`AdmissibleState::evaluate`] runs the actual controller-core law on a state
//! (`PositionGains::evaluate`, `desired_attitude`, `AttitudeGains::evaluate`), never a
//! re-implementation. [`AdmissibleState::from_parameters`] maps any vector of
//! [`PARAMETER_COUNT`] reals onto an admissible state (clamping each part to its set), which
//! is what the witness search ([`super::witness`]) moves in; [`sample`] draws states densely,
//! with much weight on the boundaries of the sets (where the suprema are).

use controller_core::desired_attitude::{desired_attitude, DesiredAttitudeError};
use controller_core::integral::IntegralState;
use controller_core::mrp::rotation_from_mrp;
use controller_core::position::{FilterState, PositionGains};
use controller_core::{FilterStart, PositionSaturation};
use nalgebra::{Vector2, Vector3};

use super::setup::Setup;

mod draw;
pub use draw::{sample, sample_parameters, sample_parameters_for};

/// Number of constant-input segments of one component's filter input history.
pub const SEGMENTS: usize = 4;

/// Parameters of one component's filter history: start (2), levels, durations.
const FILTER_PARAMETERS: usize = 2 + 2 * SEGMENTS;

/// Length of the parameter vector of [`AdmissibleState::from_parameters`] without the integral
/// action: three filter histories, `ubar` (3), `p̈_d` (3), `p_d⁽³⁾` (3), `p_d⁽⁴⁾` (3),
/// `ψ, ψ̇, ψ̈` (3), `ϑ̃` (3), `ω̃` (3). With it, [`INTEGRAL_PARAMETERS`] more follow.
pub const PARAMETER_COUNT: usize = 3 * FILTER_PARAMETERS + 21;

/// Parameters of the integral action's state: `η` (3), `η_f` (3), `η̇` (3).
pub const INTEGRAL_PARAMETERS: usize = 9;

/// The saturation `ubar = −M tanh(s/M)` is exactly `±M` in f64 once `|s| ≥ 20 M`
/// (`1 − tanh 20 ≈ 8·10⁻¹⁸` is below half an ulp of 1).
const SATURATED_ARGUMENT: f64 = 20.0;

/// `ω̃` ranges over the box `|ω̃_i| ≤ OMEGA_ERROR_SCALE · M_ω / k_ω` in the parameter map: there
/// `|s_ω(k_ω ω̃)|` reaches `M_ω` within `2·10⁻⁴` along an axis (every `ω̃` is admissible; the
/// box only gives the search a scale).
const OMEGA_ERROR_SCALE: f64 = 50.0;

/// One inertial component's filter input history: `ubar_i` held at `levels[k]` for
/// `durations[k]`, oldest first, from `start = (u_f(0), u_s(0))`; the current state is where it
/// ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterHistory {
    /// `(u_f(0), u_s(0))` [m/s²]: `0` for `FilterStart::Zero`, in `[−M_p, M_p]²` otherwise.
    pub start: [f64; 2],
    /// Input level of each segment [m/s²], in `[−M_p, M_p]`.
    pub levels: [f64; SEGMENTS],
    /// Length of each segment \[s\], `≥ 0`.
    pub durations: [f64; SEGMENTS],
}

impl FilterHistory {
    /// The filter state `(u_f, u_s)` [m/s²] at the end of the history, by the exact solution of
    /// eq:FilterDynamics (`PositionGains::propagator`).
    pub fn end_state(&self, gains: &PositionGains<f64>) -> [f64; 2] {
        let mut state = FilterState {
            u_f: Vector3::new(self.start[0], 0.0, 0.0),
            u_s: Vector3::new(self.start[1], 0.0, 0.0),
        };
        for (level, duration) in self.levels.iter().zip(&self.durations) {
            state = gains
                .propagator(*duration)
                .apply(&state, &Vector3::new(*level, 0.0, 0.0));
        }
        [state.u_f.x, state.u_s.x]
    }
}

/// A point of the confining set: everything the law's `ω_d`, `ω̇_d` and `τ` depend on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdmissibleState {
    /// Filter input history per inertial component (x, y, z).
    pub filters: [FilterHistory; 3],
    /// Current saturated feedback `ubar_p` [m/s²], each component in `[−M_p, M_p]`.
    pub ubar: Vector3<f64>,
    /// Reference acceleration `p̈_d` [m/s²].
    pub acceleration: Vector3<f64>,
    /// Reference jerk `p_d⁽³⁾` [m/s³].
    pub jerk: Vector3<f64>,
    /// Reference snap `p_d⁽⁴⁾` [m/s⁴].
    pub snap: Vector3<f64>,
    /// Desired yaw `ψ` \[rad\]: `ν_d = (cos ψ, sin ψ)`.
    pub yaw: f64,
    /// `ψ̇` [rad/s].
    pub yaw_rate: f64,
    /// `ψ̈` [rad/s²].
    pub yaw_acceleration: f64,
    /// MRP attitude error `ϑ̃`, `|ϑ̃| ≤ 1 + δ`.
    pub mrp_error: Vector3<f64>,
    /// Angular velocity error `ω̃ = ω − R̃ᵀω_d` [rad/s], body frame.
    pub omega_error: Vector3<f64>,
    /// The integral action's `(η, η_f)` [m/s²] (zero with it off), inertial.
    pub integral: IntegralState<f64>,
    /// The integral action's clamped rate `η̇` [m/s³] (zero with it off), inertial.
    pub integral_rate: Vector3<f64>,
}

/// The law's values at one admissible state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawValues {
    /// `ω_d` [rad/s], desired body frame.
    pub angular_velocity: Vector3<f64>,
    /// `ω̇_d` [rad/s²], desired body frame.
    pub angular_acceleration: Vector3<f64>,
    /// `τ` [N m], body frame.
    pub torque: Vector3<f64>,
    /// `u` [m/s²], inertial (for reports: `|u|` sets the thrust).
    pub u: Vector3<f64>,
    /// The law's `ubar_p` [m/s²] (equals the state's `ubar` up to rounding).
    pub ubar: Vector3<f64>,
}

impl LawValues {
    /// `|ω_d|` [rad/s].
    pub fn angular_velocity_norm(&self) -> f64 {
        self.angular_velocity.norm()
    }

    /// `|ω̇_d|` [rad/s²].
    pub fn angular_acceleration_norm(&self) -> f64 {
        self.angular_acceleration.norm()
    }

    /// `H₁₂ = |(ω̇_d1, ω̇_d2)|` [rad/s²]: the roll/pitch part of `ω̇_d`.
    pub fn horizontal_acceleration(&self) -> f64 {
        self.angular_acceleration.xy().norm()
    }

    /// `H₃ = |ω̇_d3|` [rad/s²]: the yaw part of `ω̇_d`.
    pub fn yaw_acceleration(&self) -> f64 {
        self.angular_acceleration.z.abs()
    }
}

/// Limits of the heading derivatives: `|ψ̇| ≤ min(K_ν̇, √K_ν̈)` (since `|ν̈_d| ≥ ψ̇²`), and
/// `|ψ̈| ≤ sqrt(K_ν̈² − ψ̇⁴)` so that `|ν̈_d|² = ψ̈² + ψ̇⁴ ≤ K_ν̈²`.
fn yaw_rate_limit(setup: &Setup) -> f64 {
    let k = &setup.constants;
    k.heading_rate.min(k.heading_acceleration.sqrt())
}

fn yaw_acceleration_limit(setup: &Setup, yaw_rate: f64) -> f64 {
    let k = setup.constants.heading_acceleration;
    (k * k - yaw_rate.powi(4)).max(0.0).sqrt()
}

/// Longest segment of a filter history \[s\]: 30 time constants of the slower filter, after
/// which the state equals the held level to f64 precision (`e⁻³⁰ ≈ 10⁻¹³`).
fn longest_segment(setup: &Setup) -> f64 {
    let p = &setup.gains.position;
    30.0 / p.kf.min(p.ks)
}

/// `v / k`, or 0 when the set is the point 0.
fn ratio(v: f64, k: f64) -> f64 {
    if k > 0.0 {
        v / k
    } else {
        0.0
    }
}

/// `v` scaled into the unit ball if outside it.
fn into_unit_ball<const N: usize>(v: [f64; N]) -> [f64; N] {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n > 1.0 {
        v.map(|x| x / n)
    } else {
        v
    }
}

/// Reads parameters in order.
struct Reader<'a> {
    x: &'a [f64],
    at: usize,
}

impl Reader<'_> {
    fn next(&mut self) -> f64 {
        let v = self.x.get(self.at).copied().unwrap_or(0.0);
        self.at += 1;
        if v.is_finite() {
            v
        } else {
            0.0
        }
    }
    fn unit(&mut self) -> f64 {
        self.next().clamp(-1.0, 1.0)
    }
    fn ball<const N: usize>(&mut self) -> [f64; N] {
        into_unit_ball(core::array::from_fn(|_| self.next()))
    }
}

impl AdmissibleState {
    /// The admissible state of a parameter vector: each part of `x` is clamped (boxes) or
    /// scaled radially (balls) into its set, in units of the set's size (`M_p`, `K_a12`, ...;
    /// durations as `T_seg x²`, `x ∈ [0, 1]`). Missing or non-finite entries read as 0. The map
    /// is onto the parameterised family, and `from_parameters(setup, &s.parameters(setup))`
    /// gives `s` back up to rounding.
    pub fn from_parameters(setup: &Setup, x: &[f64]) -> Self {
        let mp = setup.gains.position.saturation;
        let k = &setup.constants;
        let t_seg = longest_segment(setup);
        let mut r = Reader { x, at: 0 };
        let filters = core::array::from_fn(|_| {
            let start = [r.unit() * mp, r.unit() * mp];
            let levels = core::array::from_fn(|_| r.unit() * mp);
            let durations = core::array::from_fn(|_| {
                let d = r.next().clamp(0.0, 1.0);
                t_seg * d * d
            });
            FilterHistory {
                start: match setup.filter_start {
                    FilterStart::Zero => [0.0; 2],
                    FilterStart::InSaturationBox => start,
                },
                levels,
                durations,
            }
        });
        let ubar = Vector3::from_fn(|_, _| r.unit() * mp);
        let [ax, ay] = r.ball::<2>();
        let acceleration = Vector3::new(
            ax * k.horizontal_acceleration,
            ay * k.horizontal_acceleration,
            r.unit() * k.vertical_acceleration,
        );
        let jerk = Vector3::from(r.ball::<3>()) * k.jerk;
        let snap = Vector3::from(r.ball::<3>()) * k.snap;
        let yaw = r.unit() * core::f64::consts::PI;
        let yaw_rate = r.unit() * yaw_rate_limit(setup);
        let yaw_acceleration = r.unit() * yaw_acceleration_limit(setup, yaw_rate);
        let mrp_error = Vector3::from(r.ball::<3>()) * (1.0 + setup.gains.hysteresis);
        let a = &setup.gains.attitude;
        let omega_scale = OMEGA_ERROR_SCALE * a.omega_saturation / a.k_omega;
        let omega_error = Vector3::from_fn(|_, _| r.unit() * omega_scale);
        let (integral, integral_rate) = match &setup.gains.integral {
            None => (IntegralState::zero(), Vector3::zeros()),
            Some(i) => {
                // The states reachable from arming: |η − η_f| ≤ b/k_η per axis
                // (controller_core::integral's reachable-set bound).
                let estimate = Vector3::from_fn(|c, _| r.unit() * i.level[c]);
                let gap = i.filtered_rate_bound() / i.bandwidth;
                let filtered = Vector3::from_fn(|c, _| {
                    (estimate[c] - r.unit() * gap[c]).clamp(-i.level[c], i.level[c])
                });
                let rate = Vector3::from_fn(|c, _| r.unit() * i.rate[c]);
                (IntegralState { estimate, filtered }, rate)
            }
        };
        Self {
            filters,
            ubar,
            acceleration,
            jerk,
            snap,
            yaw,
            yaw_rate,
            yaw_acceleration,
            mrp_error,
            omega_error,
            integral,
            integral_rate,
        }
    }

    /// The parameter vector of this state (inverse of [`Self::from_parameters`]); an `ω̃`
    /// outside the parameter box is clamped to it.
    pub fn parameters(&self, setup: &Setup) -> Vec<f64> {
        let mp = setup.gains.position.saturation;
        let k = &setup.constants;
        let t_seg = longest_segment(setup);
        let mut x = Vec::with_capacity(PARAMETER_COUNT);
        for f in &self.filters {
            x.extend(f.start.iter().map(|v| ratio(*v, mp)));
            x.extend(f.levels.iter().map(|v| ratio(*v, mp)));
            x.extend(f.durations.iter().map(|d| ratio(*d, t_seg).max(0.0).sqrt()));
        }
        x.extend(self.ubar.iter().map(|v| ratio(*v, mp)));
        x.push(ratio(self.acceleration.x, k.horizontal_acceleration));
        x.push(ratio(self.acceleration.y, k.horizontal_acceleration));
        x.push(ratio(self.acceleration.z, k.vertical_acceleration));
        x.extend(self.jerk.iter().map(|v| ratio(*v, k.jerk)));
        x.extend(self.snap.iter().map(|v| ratio(*v, k.snap)));
        // ψ modulo 2π into [−π, π].
        let yaw = self.yaw.sin().atan2(self.yaw.cos());
        x.push(yaw / core::f64::consts::PI);
        x.push(ratio(self.yaw_rate, yaw_rate_limit(setup)));
        x.push(ratio(
            self.yaw_acceleration,
            yaw_acceleration_limit(setup, self.yaw_rate),
        ));
        let alpha = 1.0 + setup.gains.hysteresis;
        x.extend(self.mrp_error.iter().map(|v| v / alpha));
        let a = &setup.gains.attitude;
        let omega_scale = OMEGA_ERROR_SCALE * a.omega_saturation / a.k_omega;
        x.extend(
            self.omega_error
                .iter()
                .map(|v| ratio(*v, omega_scale).clamp(-1.0, 1.0)),
        );
        if let Some(i) = &setup.gains.integral {
            let s = &self.integral;
            x.extend((0..3).map(|c| ratio(s.estimate[c], i.level[c])));
            x.extend((0..3).map(|c| ratio(s.filtered[c], i.level[c])));
            x.extend((0..3).map(|c| ratio(self.integral_rate[c], i.rate[c])));
        }
        x
    }

    /// The filter states `(u_f, u_s)` [m/s²] at the end of the three input histories.
    pub fn filter_state(&self, setup: &Setup) -> FilterState<f64> {
        let ends = self.filters.map(|f| f.end_state(&setup.gains.position));
        FilterState {
            u_f: Vector3::from_fn(|i, _| ends[i][0]),
            u_s: Vector3::from_fn(|i, _| ends[i][1]),
        }
    }

    /// Checks every constraint of the confining set (module documentation) on the stored
    /// values, independently of the parameter map, with a relative slack of `10⁻¹²` for
    /// rounding.
    ///
    /// Errors: the first violated constraint, with its numbers.
    pub fn check(&self, setup: &Setup) -> Result<(), String> {
        const SLACK: f64 = 1e-12;
        let within = |what: &str, v: f64, limit: f64| {
            if v.is_finite() && v <= limit * (1.0 + SLACK) + SLACK {
                Ok(())
            } else {
                Err(format!("{what} = {v} exceeds {limit}"))
            }
        };
        let mp = setup.gains.position.saturation;
        let k = &setup.constants;
        for (i, f) in self.filters.iter().enumerate() {
            match setup.filter_start {
                FilterStart::Zero if f.start != [0.0; 2] => {
                    return Err(format!("filter {i}: start {:?} is not 0", f.start));
                }
                _ => {}
            }
            for s in f.start.iter().chain(&f.levels) {
                within(&format!("filter {i}: |start or level|"), s.abs(), mp)?;
            }
            if let Some(d) = f.durations.iter().find(|d| !(d.is_finite() && **d >= 0.0)) {
                return Err(format!("filter {i}: duration {d} is not >= 0"));
            }
        }
        within("|ubar_i|", self.ubar.amax(), mp)?;
        within(
            "|(p̈_d1, p̈_d2)|",
            self.acceleration.xy().norm(),
            k.horizontal_acceleration,
        )?;
        within("|p̈_d3|", self.acceleration.z.abs(), k.vertical_acceleration)?;
        within("|p_d⁽³⁾|", self.jerk.norm(), k.jerk)?;
        within("|p_d⁽⁴⁾|", self.snap.norm(), k.snap)?;
        let (nu, nu_dot, nu_ddot) = self.heading();
        within("|ν_d| − 1", (nu.norm() - 1.0).abs(), 0.0)?;
        within("|ν̇_d|", nu_dot.norm(), k.heading_rate)?;
        within("|ν̈_d|", nu_ddot.norm(), k.heading_acceleration)?;
        within("|ϑ̃|", self.mrp_error.norm(), 1.0 + setup.gains.hysteresis)?;
        if !self.omega_error.iter().all(|v| v.is_finite()) {
            return Err("ω̃ is not finite".into());
        }
        let s = &self.integral;
        match &setup.gains.integral {
            None => {
                let all = [s.estimate, s.filtered, self.integral_rate];
                if all.iter().any(|v| *v != Vector3::zeros()) {
                    return Err("integral state is not zero with the integral action off".into());
                }
            }
            Some(i) => {
                for c in 0..3 {
                    within("|η_i|", s.estimate[c].abs(), i.level[c])?;
                    within("|η_f,i|", s.filtered[c].abs(), i.level[c])?;
                    within("|η̇_i|", self.integral_rate[c].abs(), i.rate[c])?;
                }
            }
        }
        Ok(())
    }

    /// `(ν_d, ν̇_d, ν̈_d)` of the heading: `ν = (cos ψ, sin ψ)`, `ν̇ = ψ̇ ν⊥`,
    /// `ν̈ = ψ̈ ν⊥ − ψ̇² ν`, `ν⊥ = (−sin ψ, cos ψ)`.
    pub fn heading(&self) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let (s, c) = self.yaw.sin_cos();
        let nu = Vector2::new(c, s);
        let perp = Vector2::new(-s, c);
        (
            nu,
            perp * self.yaw_rate,
            perp * self.yaw_acceleration - nu * (self.yaw_rate * self.yaw_rate),
        )
    }

    /// The actual law at this state: `PositionGains::evaluate` (with `ṽ = 0` and the `p̃` at
    /// which `ubar_p = −σ_p(k_p z₁ + k_v z₂)` equals [`Self::ubar`]), then
    /// `desired_attitude`, then `AttitudeGains::evaluate` with `R̃ = rotation_from_mrp(ϑ̃)` and
    /// `ω = ω̃ + R̃ᵀω_d`.
    ///
    /// Errors: [`DesiredAttitudeError`] if `u` is not upward (impossible for an admissible
    /// state when `M_p < g − K_a3`, which `certify` requires).
    pub fn evaluate(&self, setup: &Setup) -> Result<LawValues, DesiredAttitudeError> {
        // Componentwise whatever the set-up's shape: `ubar` is a point of the cube, which holds
        // the norm shape's ball, and only its value enters the law (docs/position-saturation.md).
        let p = &PositionGains {
            saturation_shape: PositionSaturation::Componentwise,
            vertical: None,
            ..setup.gains.position
        };
        let filter = self.filter_state(setup);
        let zero = Vector3::zeros();
        // ṽ = 0: z₂ = u_f/k_f + u_s/k_s, z₁ = p̃ + u_f/(k_f k_s); pick p̃ so that
        // k_p z₁ + k_v z₂ = s with −M tanh(s/M) = ubar.
        let (_, z2) = p.z_coordinates(&zero, &zero, &filter);
        let argument = self.ubar.map(|ub| {
            let r = ub / p.saturation;
            let t = if r.abs() >= 1.0 {
                r.signum() * SATURATED_ARGUMENT
            } else {
                r.atanh().clamp(-SATURATED_ARGUMENT, SATURATED_ARGUMENT)
            };
            -p.saturation * t
        });
        let position_error = (argument - z2 * p.kv) / p.kp - filter.u_f * (1.0 / (p.kf * p.ks));
        // The paper's shape: only the value of ubar_p matters here, and the velocity-limited
        // feedback reaches the same values (docs/velocity-limit.md).
        let mut out = p.evaluate(
            None,
            &position_error,
            &zero,
            &filter,
            &self.acceleration,
            &self.jerk,
            &self.snap,
            setup.vehicle.gravity,
        );
        // As Controller::step does: η_f and its closed-form derivatives added after the paper's
        // sums.
        if let Some(i) = &setup.gains.integral {
            let eta = i.output(&self.integral, &self.integral_rate);
            out.u += eta.filtered;
            out.u_dot += eta.filtered_dot;
            out.u_ddot += eta.filtered_ddot;
        }
        let (nu, nu_dot, nu_ddot) = self.heading();
        let d = desired_attitude(&out.u, &out.u_dot, &out.u_ddot, &nu, &nu_dot, &nu_ddot)?;
        let rotation = rotation_from_mrp(&self.mrp_error);
        let omega = self.omega_error + rotation.transpose() * d.angular_velocity;
        let torque = setup.gains.attitude_torque(
            &self.mrp_error,
            &omega,
            &rotation,
            &d.angular_velocity,
            &d.angular_acceleration,
            &setup.vehicle.inertia,
        );
        Ok(LawValues {
            angular_velocity: d.angular_velocity,
            angular_acceleration: d.angular_acceleration,
            torque: torque.torque,
            u: out.u,
            ubar: out.ubar_p,
        })
    }
}

#[cfg(test)]
mod tests;
