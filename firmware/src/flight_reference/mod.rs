//! References flown on board: smoothed hover setpoints (also used by takeoff and land) and the
//! demo mission (the flight file's trajectory, e.g. a helix), each with guaranteed Assumption 1 constants.
//!
//! **Setpoint filter.** Each position axis and the yaw angle go through four identical first
//! order lags `ẋ₁ = λ(r − x₁)`, `ẋᵢ = λ(xᵢ₋₁ − xᵢ)`, output `p = x₄`: a critically damped
//! `λ⁴/(s + λ)⁴`, so `p⁽¹⁾…p⁽⁴⁾` exist and are bounded (Assumption 1). With `eᵢ = xᵢ − r`,
//! `p' = λ(e₃ − e₄)`, `p'' = λ²(e₂ − 2e₃ + e₄)`, `p''' = λ³(e₁ − 3e₂ + 3e₃ − e₄)`,
//! `p'''' = λ⁴(−4e₁ + 6e₂ − 4e₃ + e₄)`, and `e(t)` evolves in closed form
//! (`eᵢ(τ) = Σ_{j≤i} τ^{i−j}/(i−j)! e^{−τ} eⱼ(0)`, `τ = λt`), which is also how the filter is
//! stepped (exactly, for any interval).
//!
//! **Constants.** For all future times and no new setpoint,
//! `|p⁽ᵏ⁾(t)| ≤ λᵏ Σⱼ S_kj |eⱼ|` with `S_kj = sup_τ |φ_kj(τ)|`, `φ_kj` the k-th output's
//! response to `eⱼ(0) = 1`. [`SupTable`] computes `S` by dense sampling plus a Lipschitz margin
//! (a guaranteed upper bound up to rounding; the tail beyond `τ = 60` is below 1e-20). A new
//! setpoint shifts every `eⱼ` by the step, and the constants are recomputed from the shifted
//! state: valid from that moment on whatever the filter was doing. `K_a12, K_a3` use the
//! horizontal and vertical parts of `eⱼ`; `K_ν̇ = sup|ψ̇|`, `K_ν̈ ≤ sup|ψ̈| + sup|ψ̇|²`.

use crate::estimator::micros_f32;
use controller_core::{ReferenceSample, ReferenceTrajectory, Trajectory, TrajectoryConstants};
use nalgebra::{Vector2, Vector3};

/// Output coefficients `c_k` (k = 1..4) on `(e₁, e₂, e₃, e₄)`.
const OUT: [[f64; 4]; 4] = [
    [0.0, 0.0, 1.0, -1.0],
    [0.0, 1.0, -2.0, 1.0],
    [1.0, -3.0, 3.0, -1.0],
    [-4.0, 6.0, -4.0, 1.0],
];
const FACT: [f64; 4] = [1.0, 1.0, 2.0, 6.0];

/// Guaranteed upper bounds of the filter's free responses: `s[k][j] = sup_{τ≥0} |φ_kj(τ)|`
/// (derivative k + 1 = 1..4, state j), and `common[k] = sup |Σ_j φ_kj|`, the response to the
/// same deviation in every state (a step from rest), which is much tighter than `Σ_j s[k][j]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SupTable {
    /// `sup |φ_kj|`.
    pub s: [[f32; 4]; 4],
    /// `sup |Σ_j φ_kj|`.
    pub common: [f32; 4],
}

/// Polynomial coefficients (in τ) of `φ_kj(τ) e^{τ}`.
fn poly(k: usize, j: usize) -> [f64; 4] {
    let mut a = [0.0; 4];
    for i in j..4 {
        a[i - j] += OUT[k][i] / FACT[i - j];
    }
    a
}

/// A guaranteed upper bound of `sup_{τ≥0} |a(τ)| e^{−τ}` for a cubic `a`: samples
/// `τ ∈ [0, 60]` every `h = 2e-3` and adds `h/2 · L`, with `L = Σ_m |d_m| (m/e)ᵐ` bounding the
/// derivative (`sup τᵐ e^{−τ} = (m/e)ᵐ`). The tail beyond 60 is below 1e-20.
fn sup_bound(a: [f64; 4]) -> f32 {
    let h = 2e-3f64;
    let decay = libm::exp(-h);
    let sup_pow = [
        1.0,
        libm::exp(-1.0),
        4.0 * libm::exp(-2.0),
        27.0 * libm::exp(-3.0),
    ];
    let d = [a[1] - a[0], 2.0 * a[2] - a[1], 3.0 * a[3] - a[2], -a[3]];
    let lip: f64 = d.iter().zip(sup_pow).map(|(c, s)| c.abs() * s).sum();
    let mut e = 1.0f64;
    let mut best = 0.0f64;
    for n in 0..=30_000 {
        let t = n as f64 * h;
        let v = ((a[3] * t + a[2]) * t + a[1]) * t + a[0];
        best = best.max((v * e).abs());
        e *= decay;
    }
    (best + 0.5 * h * lip) as f32 * (1.0 + 1e-6)
}

impl SupTable {
    /// [`SupTable::compute`]'s result rounded up to five significant digits, so the MCU does
    /// not spend ~0.5 M double-precision operations at boot. A test recomputes it and checks
    /// that every entry is an upper bound within 1e-4 of the computed one.
    pub const PRECOMPUTED: Self = Self {
        s: [
            [0.13174, 0.23259, 1.0024, 1.0011],
            [0.17133, 1.0044, 2.0034, 1.0011],
            [1.0076, 3.0078, 3.0044, 1.0011],
            [4.0153, 6.0122, 4.0054, 1.0011],
        ],
        common: [0.22454, 0.13174, 0.17133, 1.0076],
    };

    /// Computes the table (about 0.5 M multiply-adds).
    pub fn compute() -> Self {
        let mut s = [[0.0f32; 4]; 4];
        let mut common = [0.0f32; 4];
        for (k, (row, c)) in s.iter_mut().zip(common.iter_mut()).enumerate() {
            let mut sum = [0.0f64; 4];
            for (j, out) in row.iter_mut().enumerate() {
                let a = poly(k, j);
                *out = sup_bound(a);
                for (x, y) in sum.iter_mut().zip(a) {
                    *x += y;
                }
            }
            *c = sup_bound(sum);
        }
        Self { s, common }
    }

    /// Bound on the future `|derivative k + 1|` (before the factor `λ^{k+1}`) for deviations
    /// with norms given by `norm`: the smallest of three valid bounds, splitting
    /// `e_j = a + (e_j − a)` with `a ∈ {0, e₁, e₄}`.
    fn bound(&self, k: usize, e: &[Vector3<f32>; 4], norm: &dyn Fn(&Vector3<f32>) -> f32) -> f32 {
        let split = |a: &Vector3<f32>| -> f32 {
            self.common[k] * norm(a)
                + (0..4)
                    .map(|j| self.s[k][j] * norm(&(e[j] - a)))
                    .sum::<f32>()
        };
        split(&Vector3::zeros()).min(split(&e[0])).min(split(&e[3]))
    }
}

/// `us` microseconds in seconds, in `f32` arithmetic only (no software `f64` on the MCU):
/// whole seconds by an integer division, the remaining microseconds by an exact `f32`
/// division (`µs < 10⁶`, both exact in `f32`), then one addition. Within 1 ulp of the exact
/// quotient; it equals the former `(us as f64 * 1e-6) as f32` for all but 0.045 % of the
/// 2³² inputs below 71.6 min, where it is 1 ulp away (about 2 µs at 30 s; checked exhaustively
/// once, and on a sample by the tests). Beyond 2³² µs it falls back to that `f64` formula.
#[inline]
pub fn elapsed_s(us: u64) -> f32 {
    match u32::try_from(us) {
        Ok(us) => (us / 1_000_000) as f32 + (us % 1_000_000) as f32 / 1e6,
        Err(_) => elapsed_s_wide(us),
    }
}

#[cold]
#[inline(never)]
fn elapsed_s_wide(us: u64) -> f32 {
    (us as f64 * 1e-6) as f32
}

/// One filtered channel group: position (3 axes) and yaw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetpointFilter {
    rate: f32,
    target: Vector3<f32>,
    e: [Vector3<f32>; 4],
    yaw_target: f32,
    yaw_e: [f32; 4],
    table: SupTable,
    step: StepCoefficients,
}

/// The closed form's coefficients for the last `τ = λ dt`, kept because the control period,
/// and so `τ`, is the same tick after tick: libm's `expf` is the costly part of a step. A cache,
/// not part of the filter's value: it compares equal whatever it holds.
#[derive(Clone, Copy, Debug)]
struct StepCoefficients {
    /// `c` holds the coefficients of `tau` (false: nothing yet).
    valid: bool,
    tau: f32,
    c: [f32; 4],
}

impl StepCoefficients {
    const EMPTY: Self = Self {
        valid: false,
        tau: 0.0,
        c: [0.0; 4],
    };
}

impl PartialEq for StepCoefficients {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

fn wrap_pi(a: f32) -> f32 {
    let two_pi = 2.0 * core::f32::consts::PI;
    let mut x = libm::fmodf(a + core::f32::consts::PI, two_pi);
    if x < 0.0 {
        x += two_pi;
    }
    x - core::f32::consts::PI
}

impl SetpointFilter {
    /// At rest at `position` \[m\] (NWU) with `yaw` \[rad\] (NWU), bandwidth `rate` λ [1/s].
    pub fn new(rate: f32, position: Vector3<f32>, yaw: f32, table: SupTable) -> Self {
        Self {
            rate,
            target: position,
            e: [Vector3::zeros(); 4],
            yaw_target: yaw,
            yaw_e: [0.0; 4],
            table,
            step: StepCoefficients::EMPTY,
        }
    }

    /// The current output position \[m\] and yaw \[rad\].
    pub fn output(&self) -> (Vector3<f32>, f32) {
        (self.target + self.e[3], self.yaw_target + self.yaw_e[3])
    }

    /// The target \[m\] and yaw \[rad\] being approached.
    pub fn target(&self) -> (Vector3<f32>, f32) {
        (self.target, self.yaw_target)
    }

    /// A copy with a new target; yaw goes the short way round.
    pub fn with_target(&self, position: Vector3<f32>, yaw: f32) -> Self {
        let mut f = *self;
        let shift = position - self.target;
        for e in f.e.iter_mut() {
            *e -= shift;
        }
        let (_, yaw_now) = self.output();
        let yaw_new = yaw_now + wrap_pi(yaw - yaw_now);
        let yaw_shift = yaw_new - self.yaw_target;
        for e in f.yaw_e.iter_mut() {
            *e -= yaw_shift;
        }
        f.target = position;
        f.yaw_target = yaw_new;
        f
    }

    /// Advances the filter by `dt` \[s\] exactly (the closed-form solution).
    pub fn advance(&mut self, dt: f32) {
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        let tau = self.rate * dt;
        // (The same bits as computing them again: the same `τ`, bit for bit.)
        let c = if self.step.valid && self.step.tau.to_bits() == tau.to_bits() {
            self.step.c
        } else {
            let d = libm::expf(-tau);
            let c = [d, tau * d, tau * tau * 0.5 * d, tau * tau * tau / 6.0 * d];
            self.step = StepCoefficients {
                valid: true,
                tau,
                c,
            };
            c
        };
        let old = self.e;
        let oy = self.yaw_e;
        for i in 0..4 {
            let mut v = Vector3::zeros();
            let mut y = 0.0;
            for j in 0..=i {
                v += old[j] * c[i - j];
                y += oy[j] * c[i - j];
            }
            self.e[i] = v;
            self.yaw_e[i] = y;
        }
    }

    fn derivative(&self, k: usize) -> (Vector3<f32>, f32) {
        let l = libm::powf(self.rate, (k + 1) as f32);
        let mut v = Vector3::zeros();
        let mut y = 0.0;
        for ((e, ye), c) in self.e.iter().zip(self.yaw_e).zip(OUT[k]) {
            v += e * c as f32;
            y += ye * c as f32;
        }
        (v * l, y * l)
    }

    /// The reference sample now.
    pub fn sample(&self) -> ReferenceSample<f32> {
        let (p, psi) = self.output();
        let (v, psi_d) = self.derivative(0);
        let (a, psi_dd) = self.derivative(1);
        let (j, _) = self.derivative(2);
        let (s, _) = self.derivative(3);
        let nu = Vector2::new(libm::cosf(psi), libm::sinf(psi));
        let perp = Vector2::new(-nu.y, nu.x);
        ReferenceSample {
            position: p,
            velocity: v,
            acceleration: a,
            jerk: j,
            snap: s,
            heading: nu,
            heading_rate: perp * psi_d,
            heading_acceleration: perp * psi_dd - nu * (psi_d * psi_d),
        }
    }

    /// Assumption 1 constants valid from now on (no new target).
    pub fn constants(&self) -> TrajectoryConstants<f32> {
        let t = &self.table;
        let pow = |k: usize| libm::powf(self.rate, (k + 1) as f32);
        let yaw_e = self.yaw_e.map(|y| Vector3::new(y, 0.0, 0.0));
        let abs_x = |v: &Vector3<f32>| libm::fabsf(v.x);
        let w1 = t.bound(0, &yaw_e, &abs_x) * pow(0);
        let w2 = t.bound(1, &yaw_e, &abs_x) * pow(1);
        TrajectoryConstants {
            horizontal_acceleration: t.bound(1, &self.e, &|v| v.xy().norm()) * pow(1),
            vertical_acceleration: t.bound(1, &self.e, &|v| libm::fabsf(v.z)) * pow(1),
            jerk: t.bound(2, &self.e, &|v| v.norm()) * pow(2),
            snap: t.bound(3, &self.e, &|v| v.norm()) * pow(3),
            heading_rate: w1,
            heading_acceleration: w2 + w1 * w1,
        }
    }
}

/// What is being flown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceMode {
    /// The setpoint filter (hover, takeoff, land).
    Setpoint,
    /// The demo mission (the configured trajectory), started at `start_us`.
    Helix {
        /// Start time \[µs\].
        start_us: u64,
    },
    /// An uploaded mission: the pipeline samples its path (`crate::mission`), not this type.
    Waypoints,
}

/// The on-board reference: a setpoint filter or the demo mission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightReference {
    filter: SetpointFilter,
    mode: ReferenceMode,
    helix: ReferenceTrajectory<f32>,
    last_us: Option<u64>,
}

impl FlightReference {
    /// At rest at `position` \[m\] NWU, `yaw` \[rad\], smoothing rate λ [1/s]; `mission` is
    /// the demo trajectory flown by [`FlightReference::start_helix`] (the flight file's
    /// `[trajectory]`, [`crate::config::FlightConfig::mission`]).
    pub fn new(
        rate: f32,
        position: Vector3<f32>,
        yaw: f32,
        table: SupTable,
        mission: ReferenceTrajectory<f32>,
    ) -> Self {
        Self {
            filter: SetpointFilter::new(rate, position, yaw, table),
            mode: ReferenceMode::Setpoint,
            helix: mission,
            last_us: None,
        }
    }

    /// The mode.
    pub fn mode(&self) -> ReferenceMode {
        self.mode
    }

    /// The setpoint filter.
    pub fn filter(&self) -> &SetpointFilter {
        &self.filter
    }

    /// Constants of the reference as it stands (from now on).
    pub fn constants(&self) -> TrajectoryConstants<f32> {
        match self.mode {
            ReferenceMode::Setpoint | ReferenceMode::Waypoints => self.filter.constants(),
            ReferenceMode::Helix { .. } => self.helix.constants(),
        }
    }

    /// The constants a new setpoint would have, given the current output (when flying the
    /// helix, the filter restarts at rest at the helix's current point: see
    /// [`FlightReference::set_target`]).
    pub fn proposed(&self, now_us: u64, position: Vector3<f32>, yaw: f32) -> SetpointFilter {
        let base = match self.mode {
            ReferenceMode::Setpoint | ReferenceMode::Waypoints => self.filter,
            ReferenceMode::Helix { .. } => {
                let s = self.sample_at(now_us);
                SetpointFilter::new(self.filter.rate, s.position, s.yaw(), self.filter.table)
            }
        };
        base.with_target(position, yaw)
    }

    /// Flies `filter` (from [`FlightReference::proposed`]) from now on.
    pub fn set_target(&mut self, filter: SetpointFilter) {
        self.filter = filter;
        self.mode = ReferenceMode::Setpoint;
    }

    /// The demo mission's constants (closed form, controller-core).
    pub fn helix_constants(&self) -> TrajectoryConstants<f32> {
        self.helix.constants()
    }

    /// Hands the reference over to an uploaded mission's path (sampled by the pipeline).
    pub fn fly_waypoints(&mut self) {
        self.mode = ReferenceMode::Waypoints;
    }

    /// The setpoint filter at rest at `position` \[m\] NWU with `yaw` \[rad\], flown from now
    /// on (an uploaded mission hands back where its reference is).
    pub fn hold_at(&mut self, position: Vector3<f32>, yaw: f32) {
        self.filter = SetpointFilter::new(self.filter.rate, position, yaw, self.filter.table);
        self.mode = ReferenceMode::Setpoint;
    }

    /// Starts the demo mission at `now_us`.
    pub fn start_helix(&mut self, now_us: u64) {
        self.mode = ReferenceMode::Helix { start_us: now_us };
    }

    fn sample_at(&self, now_us: u64) -> ReferenceSample<f32> {
        match self.mode {
            ReferenceMode::Setpoint | ReferenceMode::Waypoints => self.filter.sample(),
            ReferenceMode::Helix { start_us } => self
                .helix
                .sample(elapsed_s(now_us.saturating_sub(start_us))),
        }
    }

    /// Advances to `now_us` and returns the reference sample there.
    pub fn sample(&mut self, now_us: u64) -> ReferenceSample<f32> {
        if let Some(t) = self.last_us {
            if now_us > t {
                self.filter.advance(micros_f32(now_us - t) * 1e-6);
            }
        }
        self.last_us = Some(now_us);
        self.sample_at(now_us)
    }
}

#[cfg(test)]
mod tests;
