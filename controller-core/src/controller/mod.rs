//! The complete controller: one sample of the saturated hybrid law.
//!
//! `step(state, reference, dt)` runs, in order: the filtered saturated position law
//! (Section IV) → thrust `T = m|u|` (or the no-dive projection, [`ThrustMode`]) and thrust
//! direction → desired attitude `R_d`, `ω_d`, `ω̇_d`
//! (eq:DesiredRotationMatrix, eq:DesiredAngularVelocity, eq:DesiredAngularAcceleration) →
//! attitude error `R̃ = R_dᵀR` lifted to the MRP `ϑ̃` by the hybrid path lifting (Appendix) →
//! saturated MRP torque with feedforward (Section V; or its per-axis tilt-priority variant,
//! [`crate::tilt_priority`]) → exact propagation of the filter states over
//! the sample with `ubar_p` held. The controller samples the state every `dt` and the caller
//! holds `(T, τ)` until the next sample (Section VI uses `dt = 0.01 s`).
//!
//! The step allocates nothing, logs nothing and never returns NaN: non-finite inputs are an
//! error and leave the controller's state untouched.

use nalgebra::Vector3;

use crate::attitude_energy::attitude_energy;
use crate::desired_attitude::{desired_attitude, normalize_with_derivatives, DesiredAttitudeError};
use crate::feedforward_scale::FeedforwardScaleState;
use crate::gains::Gains;
use crate::heading_compensator::{
    advance, compensated_heading, CompensatedHeading, HeadingCompensatorGains,
};
use crate::integral::{modelled_compensation, IntegralGains, IntegralState};
use crate::local_regime::Regime;
use crate::mrp::rotation_from_quaternion;
use crate::parameter_error::ParameterError;
use crate::path_lifting::{JumpCounters, PathLifting};
use crate::position::{FilterPropagator, FilterState};
use crate::reference::{ReferenceSample, TrajectoryConstants};
use crate::rotor_envelope::RotorEnvelope;
use crate::scalar::{finite_probe, to_f64, Scalar};
use crate::thrust::ThrustMode;
use crate::vehicle::Vehicle;

mod step_io;
pub use step_io::{ControlOutput, Diagnostics, StepError, VehicleState};

/// The saturated hybrid position and heading tracking controller.
#[derive(Clone, Copy, Debug)]
pub struct Controller<T: Scalar> {
    vehicle: Vehicle<T>,
    gains: Gains<T>,
    filter: FilterState<T>,
    lifting: PathLifting<T>,
    /// The filter propagation of the last `dt` and regime, reused while neither changes.
    propagator: Option<(Regime, FilterPropagator<T>)>,
    /// The envelope design's regime (always `Global` without [`Gains::local`]).
    regime: Regime,
    thrust_mode: ThrustMode<T>,
    /// Airmode's rotor envelope (`None`: the thrust mode's thrust is applied as computed).
    airmode: Option<RotorEnvelope<T>>,
    /// `(η, η_f)` of the integral action; stays zero when it is off.
    integral: IntegralState<T>,
    /// `(μ, μ_f)` of the feedforward scale; stays zero when it is off.
    feedforward_scale: FeedforwardScaleState<T>,
    /// Failsafe: the estimates are held (still applied) while set.
    integral_frozen: bool,
    /// The disturbance observer's velocity `v̂` [m/s], inertial (`None`: it starts at the next
    /// measured velocity; extension, docs/integral-action.md).
    observed_velocity: Option<Vector3<T>>,
    /// The compensated heading's state `ψ_c` \[rad\] (extension, [`crate::heading_compensator`]):
    /// `None` until the first sample with [`Gains::heading_compensator`], which starts it at `ψ_d`.
    compensated_heading: Option<T>,
}

fn finite3<T: Scalar>(v: &Vector3<T>, field: &'static str) -> Result<(), StepError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(StepError::NonFiniteInput { field })
    }
}

impl<T: Scalar> Controller<T> {
    /// A controller for `vehicle` with `gains`, for references bounded by `constants`.
    ///
    /// Validates: `m, J_ii, g > 0`; every gain and saturation level `> 0`; `δ > 0`;
    /// `0 < α < 1`; the constants finite and `≥ 0`; and `M_p < g − K_a3` (Section IV), without
    /// which the thrust may vanish. Filter states start at `x_f = 0`.
    /// Errors: [`ParameterError`] naming the parameter and its value.
    /// The theorems' feasibility conditions are separate: see [`crate::certify`].
    pub fn new(
        vehicle: Vehicle<T>,
        gains: Gains<T>,
        constants: &TrajectoryConstants<T>,
    ) -> Result<Self, ParameterError> {
        vehicle.validate()?;
        gains.validate()?;
        let mut c = Self {
            vehicle,
            gains,
            filter: FilterState::zero(),
            lifting: PathLifting::new(gains.hysteresis, gains.reset_threshold),
            propagator: None,
            regime: Regime::Global,
            thrust_mode: ThrustMode::Norm,
            airmode: None,
            integral: IntegralState::zero(),
            feedforward_scale: FeedforwardScaleState::zero(),
            integral_frozen: false,
            observed_velocity: None,
            compensated_heading: None,
        };
        c.accept_reference(constants)?;
        Ok(c)
    }

    /// Checks that a new reference with these constants keeps `M_p < g − K_a3`, and with the
    /// integral action `M_p + M_i,z < g − K_a3` (so that `u_z > 0` whatever `η_f` is).
    /// Errors: [`ParameterError::SaturationTooLarge`], [`ParameterError::OutOfRange`] naming
    /// `"M_p + M_i_z"` (bounds `(0, g − K_a3)`), or `BadTrajectoryConstant`.
    pub fn accept_reference(
        &mut self,
        constants: &TrajectoryConstants<T>,
    ) -> Result<(), ParameterError> {
        let ka3 = constants.vertical_acceleration;
        if !(ka3.is_finite() && ka3 >= T::zero()) {
            return Err(ParameterError::BadTrajectoryConstant {
                name: "K_a3",
                value: to_f64(ka3),
            });
        }
        // The vertical feedforward as applied: scaled by up to 1 + μ̄ with the feedforward scale.
        let ka3 = self.gains.law_constants(constants).vertical_acceleration;
        let limit = self.vehicle.gravity - ka3;
        let down = self.gains.position.downward_level();
        if !crate::condition::strictly_less(down, limit) {
            return Err(ParameterError::SaturationTooLarge {
                saturation: to_f64(down),
                limit: to_f64(limit),
            });
        }
        if let Some(i) = &self.gains.integral {
            let total = down + i.level.z;
            if !crate::condition::strictly_less(total, limit) {
                return Err(crate::bounds::integral_margin_error(total, limit));
            }
        }
        Ok(())
    }

    /// The vehicle parameters.
    pub fn vehicle(&self) -> &Vehicle<T> {
        &self.vehicle
    }

    /// The gains.
    pub fn gains(&self) -> &Gains<T> {
        &self.gains
    }

    /// Filter states `(u_f, u_s)` [m/s²].
    pub fn filter_state(&self) -> FilterState<T> {
        self.filter
    }

    /// Sets the filter states; they must lie in `M_p 𝔹⁶_∞` (Lemma 1's premise), or with the norm
    /// shape of `σ_p` each of `u_f`, `u_s` in the ball `M_p 𝔹³` (docs/position-saturation.md).
    /// Errors: [`ParameterError::OutOfRange`] naming `"x_f"` with the largest component (the
    /// larger norm, with the norm shape).
    pub fn set_filter_state(&mut self, filter: FilterState<T>) -> Result<(), ParameterError> {
        let p = &self.gains.position;
        let (m, shape) = (p.saturation, p.saturation_shape);
        let largest = shape.size(&filter.u_f).max(shape.size(&filter.u_s));
        let finite = filter
            .u_f
            .iter()
            .chain(filter.u_s.iter())
            .all(|x| x.is_finite());
        if !(finite && p.contains(&filter.u_f) && p.contains(&filter.u_s)) {
            return Err(ParameterError::OutOfRange {
                name: "x_f",
                value: to_f64(largest),
                low: -to_f64(m),
                high: to_f64(m),
            });
        }
        self.filter = filter;
        Ok(())
    }

    /// The integral action's state `(η, η_f)` [m/s²], inertial (zero when it is off).
    pub fn integral_state(&self) -> IntegralState<T> {
        self.integral
    }

    /// The feedforward scale's state `(μ, μ_f)` (zero when it is off).
    /// Extension, [`crate::feedforward_scale`].
    pub fn feedforward_scale_state(&self) -> FeedforwardScaleState<T> {
        self.feedforward_scale
    }

    /// Resets the integral action's state, and the feedforward scale's, to zero (arming).
    /// Extension, docs/integral-action.md.
    pub fn reset_integral(&mut self) {
        self.integral = IntegralState::zero();
        self.feedforward_scale = FeedforwardScaleState::zero();
        self.observed_velocity = None;
    }

    /// Freezes (`true`) or releases the integral estimate and the feedforward scale: while
    /// frozen they are held, not integrated, and still applied (failsafe). Extension,
    /// docs/integral-action.md.
    pub fn set_integral_frozen(&mut self, frozen: bool) {
        self.integral_frozen = frozen;
    }

    /// Whether the integral estimate is frozen.
    pub fn integral_frozen(&self) -> bool {
        self.integral_frozen
    }

    /// How the thrust is computed from `u` ([`ThrustMode::Norm`], the paper's, unless set).
    pub fn thrust_mode(&self) -> ThrustMode<T> {
        self.thrust_mode
    }

    /// Sets how the thrust is computed from `u` from the next step on (the torque, the desired
    /// attitude and the filters do not depend on it).
    /// Errors: [`ParameterError::OutOfRange`] naming `"thrust_floor"` (see
    /// [`ThrustMode::validate`], with `M_p + M_i,z` in place of `M_p` when the integral action
    /// is on: the vertical part of `u` can drop by that much); the mode is unchanged then.
    pub fn set_thrust_mode(&mut self, mode: ThrustMode<T>) -> Result<(), ParameterError> {
        let drop = match &self.gains.integral {
            None => self.gains.position.downward_level(),
            Some(i) => self.gains.position.downward_level() + i.level.z,
        };
        mode.validate(&self.vehicle, drop)?;
        self.thrust_mode = mode;
        Ok(())
    }

    /// Airmode's rotor envelope, if airmode is on.
    pub fn airmode(&self) -> Option<&RotorEnvelope<T>> {
        self.airmode.as_ref()
    }

    /// Turns airmode on with the rotors' envelope `envelope` (its range shrunk by the margin the
    /// flight keeps free), or off with `None`, from the next step on: the thrust mode's thrust
    /// is then moved, by as little as possible, to where the rotors realise the law's torque
    /// ([`RotorEnvelope::airmode_thrust`]). The torque, the desired attitude and the filters do
    /// not depend on it. No errors: the envelope was checked when it was built.
    /// Extension, docs/airmode.md.
    pub fn set_airmode(&mut self, envelope: Option<RotorEnvelope<T>>) {
        self.airmode = envelope;
    }

    /// The envelope design's regime the next step flies (`Global` without [`Gains::local`];
    /// extension, [`crate::local_regime`]).
    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// Path-lifting jumps since construction.
    pub fn jump_counters(&self) -> JumpCounters {
        self.lifting.counters()
    }

    /// Computes the thrust \[N\] and torque [N m] for the sample, then advances the filters by
    /// `dt` \[s\].
    ///
    /// Inputs: measured state (inertial `p, v`; body-to-inertial attitude; body `ω`), the
    /// reference sample at the same time, and the sampling period `dt`.
    /// Errors: [`StepError`]; on error nothing in the controller changes.
    pub fn step(
        &mut self,
        state: &VehicleState<T>,
        reference: &ReferenceSample<T>,
        dt: T,
    ) -> Result<ControlOutput<T>, StepError> {
        // One probe over all inputs; the field-by-field checks only name the culprit.
        let mut probe = T::zero();
        for v in [&state.position, &state.velocity, &state.angular_velocity] {
            probe = finite_probe(probe, v);
        }
        probe = finite_probe(probe, &state.attitude.coords);
        if !(probe.is_finite() && reference.is_finite()) {
            finite3(&state.position, "state.position")?;
            finite3(&state.velocity, "state.velocity")?;
            finite3(&state.angular_velocity, "state.angular_velocity")?;
            if !state.attitude.coords.iter().all(|x| x.is_finite()) {
                return Err(StepError::NonFiniteInput {
                    field: "state.attitude",
                });
            }
            return Err(StepError::NonFiniteInput { field: "reference" });
        }
        if !(dt.is_finite() && dt > T::zero()) {
            return Err(StepError::BadTimeStep { dt: to_f64(dt) });
        }

        let g = &self.gains;
        // The envelope design's local gains while its regime is on (extension,
        // crate::local_regime); the paper's gains otherwise.
        let (position_gains, velocity_limit) = match (&g.local, self.regime) {
            (Some(l), Regime::Local) => (
                l.position(&g.position),
                g.velocity_limit.map(|v| l.velocity_limit(&g.position, &v)),
            ),
            _ => (g.position, g.velocity_limit),
        };
        let mut position = position_gains.evaluate(
            velocity_limit.as_ref(),
            &(state.position - reference.position),
            &(state.velocity - reference.velocity),
            &self.filter,
            &reference.acceleration,
            &reference.jerk,
            &reference.snap,
            self.vehicle.gravity,
        );
        // The integral action adds η_f and its closed-form derivatives to u, u̇, ü after the
        // paper's sums are formed, so that with it off every value is the paper's, bit for bit.
        let integral = g.integral.as_ref().map(|ig| {
            let raw = match &ig.observer {
                None => position.z1 * (-ig.gain),
                // The innovation v − v̂ against the observer's velocity before this sample.
                Some(o) => {
                    let v_hat = self.observed_velocity.unwrap_or(state.velocity);
                    o.raw_rate(ig.gain, &position.z1, &(state.velocity - v_hat))
                }
            };
            let rate = ig.clamped_rate(&self.integral, &raw, self.integral_frozen);
            let out = ig.output(&self.integral, &rate);
            position.u += out.filtered;
            position.u_dot += out.filtered_dot;
            position.u_ddot += out.filtered_ddot;
            // The feedforward scale takes the part of the estimate that turns with p̈_d.
            let scale = ig.feedforward_scale.as_ref().map(|f| {
                let state = &self.feedforward_scale;
                let moving = self.integral.estimate - self.integral.filtered;
                let rate = f.rate_of(
                    state,
                    &moving,
                    &reference.acceleration,
                    &position.z1,
                    self.integral_frozen,
                );
                let out = f.output(state, rate, ig.bandwidth, reference);
                position.u += out.u;
                position.u_dot += out.u_dot;
                position.u_ddot += out.u_ddot;
                (f, rate)
            });
            (ig, rate, scale)
        });
        // The compensated heading (extension, crate::heading_compensator): the desired frame is
        // built from the state ψ_c, started at ψ_d, whose rate cancels the tilt-induced yaw.
        let compensated = match &g.heading_compensator {
            None => None,
            Some(hc) => Some(self.compensated_heading_of(hc, &position, reference)?),
        };
        let (heading, heading_rate, heading_acceleration) = match &compensated {
            None => (
                reference.heading,
                reference.heading_rate,
                reference.heading_acceleration,
            ),
            Some(c) => (c.heading, c.heading_rate, c.heading_acceleration),
        };
        let desired = desired_attitude(
            &position.u,
            &position.u_dot,
            &position.u_ddot,
            &heading,
            &heading_rate,
            &heading_acceleration,
        )
        .map_err(StepError::DesiredAttitude)?;

        let rotation = rotation_from_quaternion(state.attitude.quaternion());
        let error_rotation = desired.rotation.transpose() * rotation;
        let mut lifting = self.lifting;
        let lifted = lifting.lift(&error_rotation);
        // The local regime's own attitude law where it has one (extension, crate::local_regime);
        // the switch measures that law's energy in both regimes.
        let local_law = g
            .local
            .as_ref()
            .and_then(|l| l.attitude.as_ref())
            .map(|a| (&a.attitude, a.tilt_priority.as_ref()));
        let (energy_attitude, energy_tilt) =
            local_law.unwrap_or((&g.attitude, g.tilt_priority.as_ref()));
        let (attitude, tilt_priority) = match (local_law, self.regime) {
            (Some(law), Regime::Local) => law,
            _ => (&g.attitude, g.tilt_priority.as_ref()),
        };
        let torque = crate::gains::torque_law(
            attitude,
            tilt_priority,
            &lifted.mrp,
            &state.angular_velocity,
            &error_rotation,
            &desired.angular_velocity,
            &desired.angular_acceleration,
            &self.vehicle.inertia,
        );
        let body_z = rotation.column(2).into_owned();
        let mode_thrust = self
            .thrust_mode
            .thrust(self.vehicle.mass, &position.u, &body_z);
        let thrust = match &self.airmode {
            Some(e) => e.airmode_thrust(mode_thrust, &torque.torque),
            None => mode_thrust,
        };
        let propagator = match self.propagator {
            Some((r, p)) if p.dt == dt && r == self.regime => p,
            _ => position_gains.propagator(dt),
        };
        let mut next_filter = propagator.apply(&self.filter, &position.ubar_p);
        // The envelope design's switch on the attitude energy, with the inner filter re-timed so
        // that u̇ (hence ω_d) does not jump into the local regime.
        let energy = g.local.as_ref().map(|_| {
            attitude_energy(
                energy_attitude,
                energy_tilt,
                &self.vehicle.inertia,
                &lifted.mrp,
                &torque.omega_error,
                &error_rotation,
            )
        });
        let next_regime = match (&g.local, energy) {
            (Some(l), Some(e)) => {
                let (regime, filter) = l.switch(&g.position, self.regime, e, &next_filter);
                next_filter = filter;
                regime
            }
            _ => self.regime,
        };
        let next_integral = match integral {
            Some((ig, rate, _)) => ig.advance(&self.integral, &rate, dt),
            None => self.integral,
        };
        let next_feedforward_scale = match integral {
            Some((ig, _, Some((f, rate)))) => {
                f.advance(&self.feedforward_scale, rate, ig.bandwidth, dt)
            }
            _ => self.feedforward_scale,
        };
        // Only the gains and rates live across the attitude's calls, as without the observer,
        // so that the flight build's step (integral off) pays nothing for it.
        let next_observed_velocity = match integral {
            Some((
                IntegralGains {
                    observer: Some(o), ..
                },
                _,
                scale,
            )) => {
                // The observer's model subtracts what both estimates compensate.
                let compensation = match scale {
                    None => self.integral.estimate,
                    Some(_) => modelled_compensation(
                        &self.integral,
                        &self.feedforward_scale,
                        &reference.acceleration,
                    ),
                };
                Some(o.advance(
                    &self.observed_velocity.unwrap_or(state.velocity),
                    &state.velocity,
                    thrust,
                    self.vehicle.mass,
                    &body_z,
                    self.vehicle.gravity,
                    &compensation,
                    dt,
                ))
            }
            _ => None,
        };

        let mut probe = (thrust + next_feedforward_scale.filtered) * T::zero();
        for v in [
            &torque.torque,
            &next_filter.u_f,
            &next_filter.u_s,
            &next_integral.filtered,
        ] {
            probe = finite_probe(probe, v);
        }
        if let Some(v) = &next_observed_velocity {
            probe = finite_probe(probe, v);
        }
        if !probe.is_finite() {
            return Err(StepError::NonFiniteOutput);
        }
        let diagnostics = Diagnostics {
            z1: position.z1,
            z2: position.z2,
            ubar_p: position.ubar_p,
            u_f: self.filter.u_f,
            u_s: self.filter.u_s,
            integral: self.integral.filtered,
            feedforward_scale: self.feedforward_scale.filtered,
            u: position.u,
            thrust_direction: desired.thrust_direction.unit,
            desired_rotation: desired.rotation,
            desired_angular_velocity: desired.angular_velocity,
            desired_angular_acceleration: desired.angular_acceleration,
            mrp_error: lifted.mrp,
            omega_error: torque.omega_error,
            s_mrp: torque.s_mrp,
            s_omega: torque.s_omega,
            feedforward: torque.feedforward,
            airmode_shift: thrust - mode_thrust,
            regime: self.regime,
            attitude_energy: energy.unwrap_or_else(T::zero),
            jumps: lifted.jumps,
            jumps_total: lifting.counters(),
        };
        self.lifting = lifting;
        self.filter = next_filter;
        self.integral = next_integral;
        self.feedforward_scale = next_feedforward_scale;
        if next_observed_velocity.is_some() {
            self.observed_velocity = next_observed_velocity;
        }
        self.propagator = Some((self.regime, propagator));
        self.regime = next_regime;
        if let Some(c) = &compensated {
            self.compensated_heading = Some(advance(c.angle, c.rate, dt));
        }
        Ok(ControlOutput {
            thrust,
            torque: torque.torque,
            diagnostics,
        })
    }

    /// The compensated heading at this sample ([`crate::heading_compensator`]): the thrust
    /// direction of `position`'s `u` with its derivatives and the reference heading as an angle
    /// with its rates (`ψ̇_d = ν_d^⊥ᵀ ν̇_d`, `ψ̈_d = ν_d^⊥ᵀ ν̈_d` for the unit `ν_d`), from the
    /// state `ψ_c` (or `ψ_d` at the first sample). Errors: the desired attitude's, when `u = 0`
    /// or points down (the compensator's rate divides by `ρ₃`).
    fn compensated_heading_of(
        &self,
        gains: &HeadingCompensatorGains<T>,
        position: &crate::position::PositionOutput<T>,
        reference: &ReferenceSample<T>,
    ) -> Result<CompensatedHeading<T>, StepError> {
        let rho = normalize_with_derivatives(&position.u, &position.u_dot, &position.u_ddot)
            .ok_or(StepError::DesiredAttitude(DesiredAttitudeError::ZeroThrust))?;
        if rho.unit.z <= T::zero() {
            return Err(StepError::DesiredAttitude(
                DesiredAttitudeError::ThrustNotUpward,
            ));
        }
        let nu = &reference.heading;
        let across = nalgebra::Vector2::new(-nu.y, nu.x);
        let psi_d = reference.yaw();
        let rates = (
            psi_d,
            across.dot(&reference.heading_rate),
            across.dot(&reference.heading_acceleration),
        );
        let psi_c = self.compensated_heading.unwrap_or(psi_d);
        Ok(compensated_heading(gains, psi_c, &rho, rates))
    }
}
