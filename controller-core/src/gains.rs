//! All controller gains (Table I) and the extensions' options, with their validation, and the
//! torque law the gains select.

use nalgebra::{Matrix3, Vector3};

use crate::attitude_control::{AttitudeGains, TorqueOutput};
use crate::heading_compensator::HeadingCompensatorGains;
use crate::integral::IntegralGains;
use crate::lemma1_form::Lemma1Form;
use crate::local_regime::LocalGains;
use crate::parameter_error::{positive, ParameterError};
use crate::position::PositionGains;
use crate::reference::TrajectoryConstants;
use crate::scalar::{lit, to_f64, Scalar};
use crate::tilt_priority::TiltPriorityGains;
use crate::velocity_limit::VelocityLimit;

/// All controller gains (Table I).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gains<T: Scalar> {
    /// Position loop: `k_p, k_v, k_f, k_s, M_p`.
    pub position: PositionGains<T>,
    /// Attitude loop: `k_ϑ, k_ω, M_ϑ, M_ω`.
    pub attitude: AttitudeGains<T>,
    /// Hysteresis margin `δ > 0` of the MRP switch (Appendix).
    pub hysteresis: T,
    /// Memory reset threshold `α ∈ (0, 1)` of the path lifting (Appendix).
    pub reset_threshold: T,
    /// Bounded integral action (extension, docs/integral-action.md): `None` is the paper's law,
    /// bit for bit.
    pub integral: Option<IntegralGains<T>>,
    /// Per-axis attitude feedback with tilt priority (extension, docs/tilt-priority.md): `None`
    /// is the paper's radial feedback, bit for bit.
    pub tilt_priority: Option<TiltPriorityGains<T>>,
    /// Velocity-limited position feedback (extension, docs/velocity-limit.md): `None` is the
    /// paper's `ubar_p = −σ_p(k_p z₁ + k_v z₂)`, bit for bit.
    pub velocity_limit: Option<VelocityLimit<T>>,
    /// The chain [`crate::certify`] bounds `|ω̇_d|` with: the paper's Lemma 1 (bit for bit) or
    /// the tangential form (extension, docs/tangential-lemma1.md). No effect on the law.
    pub lemma1: Lemma1Form,
    /// The envelope design's local regime (extension, docs/envelope-design.md,
    /// [`crate::local_regime`]): faster position gains flown while the attitude energy is inside
    /// a sublevel set; `None` flies `position` always, bit for bit.
    pub local: Option<LocalGains<T>>,
    /// The compensated heading (extension, [`crate::heading_compensator`]): the desired frame is
    /// built from a heading state whose rate cancels the tilt-induced yaw, so that its yaw rate is
    /// the compensator's alone; `None` builds it from the reference heading, bit for bit.
    pub heading_compensator: Option<HeadingCompensatorGains<T>>,
}

impl<T: Scalar> Gains<T> {
    /// Table I: `k_p = 9, k_v = 6, k_f = 2, k_s = 20, k_ϑ = 100, k_ω = 0.1, M_p = 2,
    /// M_ϑ = 0.206, M_ω = 0.045, δ = 0.02, α = 0.25`; no integral action.
    pub fn paper() -> Self {
        Self {
            position: PositionGains {
                kp: lit(9.0),
                kv: lit(6.0),
                kf: lit(2.0),
                ks: lit(20.0),
                saturation: lit(2.0),
                saturation_shape: crate::position_saturation::PositionSaturation::Componentwise,
                vertical: None,
            },
            attitude: AttitudeGains {
                k_mrp: lit(100.0),
                k_omega: lit(0.1),
                mrp_saturation: lit(0.206),
                omega_saturation: lit(0.045),
            },
            hysteresis: lit(0.02),
            reset_threshold: lit(0.25),
            integral: None,
            tilt_priority: None,
            velocity_limit: None,
            lemma1: Lemma1Form::Paper,
            local: None,
            heading_compensator: None,
        }
    }
}

impl<T: Scalar> Gains<T> {
    /// These gains with the attitude law `law` in place of their own (everything else
    /// unchanged): what the local certificate evaluates the energy limits and the feedback of
    /// the local regime's own law with ([`crate::LocalAttitude`]). No errors.
    pub fn with_attitude_law(&self, law: &crate::LocalAttitude<T>) -> Self {
        Self {
            attitude: law.attitude,
            tilt_priority: law.tilt_priority,
            ..*self
        }
    }

    /// The Assumption 1 constants of the reference as the law applies it: `k` itself, or with the
    /// feedforward scale on ([`crate::feedforward_scale`], extension, docs/integral-action.md)
    /// the constants of the scaled feedforward `(1 + μ_f) p̈_d`
    /// ([`crate::feedforward_scale::FeedforwardScaleGains::constants`]). Every bound of
    /// [`crate::certify`] and the controller's reference check use these.
    pub fn law_constants(&self, k: &TrajectoryConstants<T>) -> TrajectoryConstants<T> {
        match &self.integral {
            Some(IntegralGains {
                feedforward_scale: Some(f),
                bandwidth,
                ..
            }) => f.constants(k, *bandwidth),
            _ => *k,
        }
    }

    /// Checks every gain and level `> 0`, `δ > 0` and `0 < α < 1`.
    /// Errors: [`ParameterError::NotPositive`] or [`ParameterError::OutOfRange`].
    /// Source: Section IV (`k_p, k_v, k_f, k_s, M_p > 0`), Section V (`k_ϑ, k_ω, M_ϑ, M_ω > 0`),
    /// Appendix (`δ > 0`, `α ∈ (0, 1)`); with the integral action, [`IntegralGains::validate`]; with
    /// tilt priority, [`TiltPriorityGains::validate`]; with the velocity limit,
    /// [`VelocityLimit::validate`].
    pub fn validate(&self) -> Result<(), ParameterError> {
        if let Some(i) = &self.integral {
            i.validate()?;
        }
        if let Some(t) = &self.tilt_priority {
            t.validate()?;
        }
        if let Some(v) = &self.velocity_limit {
            v.validate(self.position.saturation, self.position.vertical.as_ref())?;
        }
        if let Some(v) = &self.position.vertical {
            v.validate()?;
        }
        if let Some(l) = &self.local {
            l.validate(&self.position)?;
            if let (Some(b), None) = (l.braking, &self.velocity_limit) {
                // Braking belongs to the velocity limit: without it the key would do nothing.
                return Err(ParameterError::OutOfRange {
                    name: "local braking",
                    value: to_f64(b),
                    low: 0.0,
                    high: 0.0,
                });
            }
        }
        if let Some(h) = &self.heading_compensator {
            h.validate()?;
        }
        let p = &self.position;
        let a = &self.attitude;
        for (name, v) in [
            ("k_p", p.kp),
            ("k_v", p.kv),
            ("k_f", p.kf),
            ("k_s", p.ks),
            ("M_p", p.saturation),
            ("k_theta", a.k_mrp),
            ("k_omega", a.k_omega),
            ("M_theta", a.mrp_saturation),
            ("M_omega", a.omega_saturation),
            ("delta", self.hysteresis),
        ] {
            positive(name, v)?;
        }
        let alpha = self.reset_threshold;
        if !(alpha.is_finite() && alpha > T::zero() && alpha < T::one()) {
            return Err(ParameterError::OutOfRange {
                name: "alpha",
                value: to_f64(alpha),
                low: 0.0,
                high: 1.0,
            });
        }
        Ok(())
    }

    /// The torque law the gains select: the paper's ([`AttitudeGains::evaluate`](crate::attitude_control::AttitudeGains::evaluate)) or, with
    /// `self.tilt_priority` set, the per-axis tilt-priority feedback
    /// ([`crate::TiltPriorityGains::evaluate`]). Inputs and output as [`AttitudeGains::evaluate`](crate::attitude_control::AttitudeGains::evaluate).
    /// Source: Section V; extension, docs/tilt-priority.md.
    #[inline]
    pub fn attitude_torque(
        &self,
        mrp_error: &Vector3<T>,
        angular_velocity: &Vector3<T>,
        error_rotation: &Matrix3<T>,
        desired_angular_velocity: &Vector3<T>,
        desired_angular_acceleration: &Vector3<T>,
        inertia: &Vector3<T>,
    ) -> TorqueOutput<T> {
        torque_law(
            &self.attitude,
            self.tilt_priority.as_ref(),
            mrp_error,
            angular_velocity,
            error_rotation,
            desired_angular_velocity,
            desired_angular_acceleration,
            inertia,
        )
    }
}

/// The torque law of `attitude` alone (the paper's, Section V) or with `tilt_priority` (its
/// per-axis variant, docs/tilt-priority.md): what [`Gains::attitude_torque`] flies with the
/// global gains and the envelope design's local regime with its own
/// ([`crate::LocalAttitude`]). Inputs and output as
/// [`AttitudeGains::evaluate`](crate::attitude_control::AttitudeGains::evaluate). No errors.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn torque_law<T: Scalar>(
    attitude: &AttitudeGains<T>,
    tilt_priority: Option<&TiltPriorityGains<T>>,
    mrp_error: &Vector3<T>,
    angular_velocity: &Vector3<T>,
    error_rotation: &Matrix3<T>,
    desired_angular_velocity: &Vector3<T>,
    desired_angular_acceleration: &Vector3<T>,
    inertia: &Vector3<T>,
) -> TorqueOutput<T> {
    match tilt_priority {
        None => attitude.evaluate(
            mrp_error,
            angular_velocity,
            error_rotation,
            desired_angular_velocity,
            desired_angular_acceleration,
            inertia,
        ),
        Some(tilt) => tilt.evaluate(
            attitude,
            mrp_error,
            angular_velocity,
            error_rotation,
            desired_angular_velocity,
            desired_angular_acceleration,
            inertia,
        ),
    }
}
