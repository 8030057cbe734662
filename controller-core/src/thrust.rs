//! Collective thrust from the control vector `u`: the paper's `T = m|u|` or a no-dive thrust.
//!
//! The paper applies `T = m|u|` (Section IV), which Theorem 1 keeps in `[T_min, T_max]` with
//! `T_min = m(g − M_p − K_a3) > 0` *whatever the attitude*: while the vehicle is upside down the
//! rotors push it towards the ground at `|u| ≳ g` on top of gravity until the attitude loop has
//! turned it over. The no-dive modes ([`ThrustMode`]) use the measured body z axis
//! `b = R e₃` (inertial) to cut the thrust while `b` points the wrong way:
//!
//! - [`ThrustMode::BodyAxisProjection`]: `T = max(m uᵀb, T_floor)`, the projection of `m u` on
//!   the body z axis as geometric controllers apply it (Lee, Leok, McClamroch 2010), the
//!   least-squares thrust for `u` along `b`; `= m|u| cos θ̃` with `θ̃ = ∠(b, u)`.
//! - [`ThrustMode::AlignmentPower`]: `T = max(m|u| max(cos θ̃, 0)^k, T_floor)`, a smooth factor
//!   of the thrust-direction error (`k = 1`: the projection).
//! - [`ThrustMode::VerticalPriority`]: with `b₃ = e₃ᵀb`, `T = min(m u₃/b₃, T_cap·min(1, b₃/b₀))`
//!   while `b₃ > 0`, else 0, then raised to `T_floor` if below it: the vertical thrust `u` asks
//!   for while the body z axis is above the horizon (tilt compensation, as PX4's multicopter
//!   position control applies it), capped at `T_cap` (Theorem 1's `T_max`) and ramped to 0 as
//!   `b` reaches the horizon, so `T` is continuous in `R` and `u`. The floor keeps the rotors
//!   above what the certified torque box needs at its lower end. The first two *lower* the vertical thrust while the vehicle is
//!   tilted (by `cos θ̃` or a power of it) and so lose altitude while it turns back; this one
//!   holds it, which is what makes the flip cheap (`docs/no-dive-thrust.md` has the figures).
//!
//! Every mode equals `m|u|` when `b = ρ = u/|u|` (`m u₃/ρ₃ = m|u|`, `m uᵀρ = m|u|`), so as the
//! attitude error vanishes the applied thrust becomes the paper's. The torque law, `R_d`,
//! `ω_d`, `ω̇_d` and the filters do not depend on the applied thrust, so Lemma 1 and Theorem 2
//! hold unchanged.
//!
//! A-priori intervals ([`ThrustMode::interval`]): `m uᵀb ≤ m|u| ≤ T_max` (Theorem 1), so the
//! projection and the power law stay in `[T_floor, T_max]` (a floor at most `T_min` never
//! raises the thrust above the paper's); vertical priority stays in `[T_floor, T_cap]` by its
//! cap and floor.

use nalgebra::Vector3;

use crate::bounds::Bounds;
use crate::parameter_error::ParameterError;
use crate::scalar::{norm, to_f64, Scalar};
use crate::vehicle::Vehicle;

/// How the collective thrust is computed from the control vector `u` [m/s²] (inertial) and
/// the measured body z axis (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ThrustMode<T: Scalar> {
    /// `T = m|u|`: the paper's law (Section IV, Theorem 1). The default.
    #[default]
    Norm,
    /// `T = max(m uᵀ R e₃, T_floor)`: the projection of `m u` on the measured body z axis,
    /// clipped below at `floor` (no-dive thrust).
    BodyAxisProjection {
        /// `T_floor` \[N\], `0 ≤ T_floor ≤ T_min` (see [`ThrustMode::validate`] and
        /// [`ThrustMode::interval`]); 0 = the rotors idle while the body z axis points more
        /// than 90° away from `u`.
        floor: T,
    },
    /// `T = max(m|u| · max(cos θ̃, 0)^k, T_floor)` with `cos θ̃ = uᵀRe₃/|u|`: a smooth factor of
    /// the thrust-direction error; `k = 1` is the projection, `k < 1` keeps more thrust while
    /// the body z axis is tilted less than 90° from `u`, `k > 1` less.
    AlignmentPower {
        /// The exponent `k > 0` (dimensionless).
        exponent: T,
        /// `T_floor` \[N\], as for [`ThrustMode::BodyAxisProjection`].
        floor: T,
    },
    /// `T = min(m u₃ / b₃, T_cap · min(1, b₃ / b₀))` for `b₃ = e₃ᵀRe₃ > 0`, else 0: the
    /// vertical component of the thrust is the one `u` asks for (tilt compensation, as PX4
    /// does) while the body z axis is above the horizon, capped at `T_cap` and ramped to 0 as
    /// the body z axis reaches the horizon (continuous in `R`); 0 while it is below.
    VerticalPriority {
        /// `T_cap` \[N\]: Theorem 1's `T_max`, so the thrust stays in `[T_floor, T_max]`.
        cap: T,
        /// `b₀ ∈ (0, 1]`: the ramp's width in `e₃ᵀRe₃` (dimensionless).
        ramp: T,
        /// `T_floor` \[N\], `0 ≤ T_floor ≤ T_min` as for [`ThrustMode::BodyAxisProjection`]; 0 =
        /// the rotors idle while the body z axis is below the horizon. A floor the rotors can
        /// hold the certified torques at is what puts this mode inside a certified `(T, τ)` box.
        floor: T,
    },
}

impl<T: Scalar> ThrustMode<T> {
    /// The body-axis projection with no floor (`T = m·max(uᵀ R e₃, 0)`).
    pub fn body_axis_projection() -> Self {
        Self::BodyAxisProjection { floor: T::zero() }
    }

    /// The collective thrust \[N\] for the control vector `u` [m/s²] (inertial), the vehicle
    /// mass `mass` \[kg\] and the measured body z axis `body_z = R e₃` (unit, inertial; `R`
    /// body to inertial). [`ThrustMode::Norm`] ignores `body_z` and computes `m|u|` exactly as
    /// the paper's law always has.
    #[inline(always)]
    pub fn thrust(&self, mass: T, u: &Vector3<T>, body_z: &Vector3<T>) -> T {
        match *self {
            Self::Norm => mass * norm(u),
            Self::BodyAxisProjection { floor } => (mass * u.dot(body_z)).max(floor),
            Self::AlignmentPower { exponent, floor } => {
                let n = norm(u);
                let cos = (u.dot(body_z) / n).max(T::zero());
                (mass * n * cos.powf(exponent)).max(floor)
            }
            Self::VerticalPriority { cap, ramp, floor } => {
                let b3 = body_z.z;
                let t = if b3 > T::zero() {
                    (mass * u.z / b3).min(cap * (b3 / ramp).min(T::one()))
                } else {
                    T::zero()
                };
                // Not `max`: with no floor the thrust stays the value computed, bit for bit.
                if t < floor {
                    floor
                } else {
                    t
                }
            }
        }
    }

    /// Checks the mode for `vehicle` and the saturation level `M_p` [m/s²]: a floor must be
    /// finite, `≥ 0` and `< m(g − M_p)` (`T_min` of Theorem 1 for a reference with `K_a3 = 0`,
    /// the largest `T_min` can be; [`ThrustMode::interval`] checks against the actual `T_min`);
    /// a vertical-priority cap finite and `> 0`, its ramp in `(0, 1]`. The power law's exponent
    /// is the caller's to check (`> 0`).
    /// Errors: [`ParameterError::OutOfRange`] naming `"thrust_floor"` (its low end 0 is
    /// allowed) or `"thrust_ramp"`; [`ParameterError::NotPositive`] naming `"thrust_cap"`.
    pub fn validate(&self, vehicle: &Vehicle<T>, saturation: T) -> Result<(), ParameterError> {
        match *self {
            Self::Norm => Ok(()),
            Self::VerticalPriority { cap, ramp, floor } => {
                if !(cap.is_finite() && cap > T::zero()) {
                    return Err(ParameterError::NotPositive {
                        name: "thrust_cap",
                        value: to_f64(cap),
                    });
                }
                if !(ramp > T::zero() && ramp <= T::one()) {
                    return Err(ParameterError::OutOfRange {
                        name: "thrust_ramp",
                        value: to_f64(ramp),
                        low: 0.0,
                        high: 1.0,
                    });
                }
                validate_floor(floor, vehicle, saturation)
            }
            Self::BodyAxisProjection { floor } | Self::AlignmentPower { floor, .. } => {
                validate_floor(floor, vehicle, saturation)
            }
        }
    }

    /// The a-priori interval `[low, high]` \[N\] of the thrust this mode applies, from the
    /// paper's bounds: `[T_min, T_max]` for [`ThrustMode::Norm`] (Theorem 1, eq:BoundsT);
    /// `[T_floor, T_max]` for the projection and the power law (because
    /// `m uᵀRe₃ ≤ m|u| ≤ T_max`, and the floor is at most `T_min`); `[T_floor, T_cap]` for
    /// vertical priority (by its cap, which must be at most `T_max`, and its floor).
    ///
    /// Errors: [`ParameterError::OutOfRange`] naming `"thrust_floor"` if the floor is not in
    /// `[0, T_min]` (a larger floor would raise the thrust above the paper's), or
    /// `"thrust_cap"` if the cap is above `T_max`.
    pub fn interval(&self, bounds: &Bounds<T>) -> Result<(T, T), ParameterError> {
        match *self {
            Self::Norm => Ok((bounds.thrust_min, bounds.thrust_max)),
            Self::VerticalPriority { cap, floor, .. } => {
                if cap > bounds.thrust_max {
                    return Err(ParameterError::OutOfRange {
                        name: "thrust_cap",
                        value: to_f64(cap),
                        low: 0.0,
                        high: to_f64(bounds.thrust_max),
                    });
                }
                Ok((floor_in_interval(floor, bounds)?, cap))
            }
            Self::BodyAxisProjection { floor } | Self::AlignmentPower { floor, .. } => {
                Ok((floor_in_interval(floor, bounds)?, bounds.thrust_max))
            }
        }
    }
}

/// A floor must be finite, `≥ 0` and `< m(g − M_p)` (`saturation` = `M_p`, plus `M_i,z` with the
/// integral action). Errors: [`ParameterError::OutOfRange`] naming `"thrust_floor"`.
fn validate_floor<T: Scalar>(
    floor: T,
    vehicle: &Vehicle<T>,
    saturation: T,
) -> Result<(), ParameterError> {
    let high = vehicle.mass * (vehicle.gravity - saturation);
    if floor.is_finite() && floor >= T::zero() && floor < high {
        Ok(())
    } else {
        Err(ParameterError::OutOfRange {
            name: "thrust_floor",
            value: to_f64(floor),
            low: 0.0,
            high: to_f64(high),
        })
    }
}

/// The floor itself when it lies in `[0, T_min]` (Theorem 1's), the low end of the mode's
/// interval. Errors: [`ParameterError::OutOfRange`] naming `"thrust_floor"`.
fn floor_in_interval<T: Scalar>(floor: T, bounds: &Bounds<T>) -> Result<T, ParameterError> {
    if floor.is_finite() && floor >= T::zero() && floor <= bounds.thrust_min {
        Ok(floor)
    } else {
        Err(ParameterError::OutOfRange {
            name: "thrust_floor",
            value: to_f64(floor),
            low: 0.0,
            high: to_f64(bounds.thrust_min),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounds::{certify, FilterStart};
    use crate::gains::Gains;
    use crate::reference::{ReferenceTrajectory, Trajectory};
    use crate::vehicle::Limits;
    use nalgebra::{Rotation3, Unit};
    use proptest::prelude::*;

    fn unit(v: [f64; 3]) -> Vector3<f64> {
        Vector3::from(v).normalize()
    }

    #[test]
    fn norm_is_the_papers_thrust_bit_for_bit() {
        let u = Vector3::new(0.3f32, -1.7, 9.2);
        let m = 0.46f32;
        let t = ThrustMode::Norm.thrust(m, &u, &Vector3::new(0.0, 0.0, -1.0));
        assert_eq!(t.to_bits(), (m * norm(&u)).to_bits());
    }

    proptest! {
        /// The projection is `m|u| cos θ̃` clipped at the floor, with θ̃ the angle between the
        /// body z axis and u computed independently (from the rotation that takes e₃ to body z).
        #[test]
        fn projection_is_m_norm_u_cos_angle(
            u in prop::array::uniform3(-20.0f64..20.0),
            axis in prop::array::uniform3(-1.0f64..1.0),
            angle in 0.0f64..std::f64::consts::PI,
            floor in 0.0f64..3.0,
        ) {
            let u = Vector3::from(u);
            prop_assume!(u.norm() > 1e-3 && Vector3::from(axis).norm() > 1e-3);
            let r = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::from(axis)), angle);
            let body_z = r * Vector3::z();
            let cos = body_z.angle(&u).cos();
            let t = ThrustMode::BodyAxisProjection { floor }.thrust(0.46, &u, &body_z);
            let expected = (0.46 * u.norm() * cos).max(floor);
            prop_assert!((t - expected).abs() <= 1e-12 * (1.0 + expected.abs()), "{t} {expected}");
            // Never more than the paper's thrust once the floor is at most it.
            prop_assert!(t <= (0.46 * u.norm()).max(floor) * (1.0 + 1e-15));
        }
    }

    #[test]
    fn upside_down_gives_the_floor_and_aligned_gives_the_norm() {
        let u = Vector3::new(0.5, -0.2, 9.81);
        let m = 0.46;
        let p = ThrustMode::BodyAxisProjection { floor: 0.25 };
        assert_eq!(p.thrust(m, &u, &unit([0.1, 0.0, -1.0])), 0.25);
        let aligned = p.thrust(m, &u, &u.normalize());
        assert!((aligned - m * u.norm()).abs() < 1e-12);
        assert_eq!(
            ThrustMode::body_axis_projection().thrust(m, &u, &unit([0.0, 1.0, -0.01])),
            0.0
        );
    }

    /// Vertical priority: on the thrust direction it is the paper's `m|u|`; tilted above the
    /// horizon its vertical component is `m u₃` until the cap; below the horizon 0; continuous
    /// across the horizon (the ramp); never above the cap.
    #[test]
    fn vertical_priority_matches_the_vertical_demand() {
        let (m, cap, ramp) = (0.46f64, 6.1875f64, 0.2f64);
        let mode = ThrustMode::VerticalPriority {
            cap,
            ramp,
            floor: 0.0,
        };
        let u = Vector3::new(1.0f64, -2.0, 9.0);
        let aligned = mode.thrust(m, &u, &u.normalize());
        assert!((aligned - m * u.norm()).abs() < 1e-12 * aligned);
        let tilted = unit([0.5, 0.0, 1.0]);
        let t = mode.thrust(m, &u, &tilted);
        assert!((t * tilted.z - m * u.z).abs() < 1e-12, "vertical part {t}");
        assert_eq!(mode.thrust(m, &u, &unit([1.0, 0.0, -0.01])), 0.0);
        let near = mode.thrust(m, &u, &unit([1.0, 0.0, 1e-6]));
        assert!(near < 1e-4, "continuous at the horizon: {near}");
        for z in [0.05, 0.1, 0.3, 0.6, 1.0] {
            let b = unit([1.0, 0.3, z]);
            let t = mode.thrust(m, &u, &b);
            assert!(t >= 0.0 && t <= cap, "{t}");
        }
    }

    #[test]
    fn interval_is_floor_to_theorem1_max() {
        let c = certify(
            &Vehicle::paper(),
            &Limits::paper(),
            &Gains::paper(),
            &ReferenceTrajectory::paper_helix().constants(),
            FilterStart::Zero,
        )
        .unwrap();
        let b = &c.bounds;
        assert_eq!(
            ThrustMode::Norm.interval(b),
            Ok((b.thrust_min, b.thrust_max))
        );
        assert_eq!(
            ThrustMode::body_axis_projection().interval(b),
            Ok((0.0, b.thrust_max))
        );
        let e = ThrustMode::BodyAxisProjection {
            floor: b.thrust_min * 1.01,
        }
        .interval(b)
        .unwrap_err();
        assert!(
            matches!(
                e,
                ParameterError::OutOfRange {
                    name: "thrust_floor",
                    ..
                }
            ),
            "{e:?}"
        );
        let vp = ThrustMode::VerticalPriority {
            cap: b.thrust_max,
            ramp: 0.2,
            floor: 0.0,
        };
        assert_eq!(vp.interval(b), Ok((0.0, b.thrust_max)));
        let vp_with = |cap: f64, floor: f64| ThrustMode::VerticalPriority {
            cap,
            ramp: 0.2,
            floor,
        };
        let floor = 0.5 * b.thrust_min;
        assert_eq!(
            vp_with(b.thrust_max, floor).interval(b),
            Ok((floor, b.thrust_max))
        );
        assert!(vp_with(b.thrust_max * 1.01, 0.0).interval(b).is_err());
        let floor_too_high = vp_with(b.thrust_max, b.thrust_min * 1.01);
        assert!(matches!(
            floor_too_high.interval(b),
            Err(ParameterError::OutOfRange {
                name: "thrust_floor",
                ..
            })
        ));
    }

    /// Vertical priority with a floor: below the horizon and along the ramp the thrust is the
    /// floor wherever the floorless mode gives less, and exactly the floorless thrust elsewhere.
    #[test]
    fn vertical_priority_floor_only_raises_what_is_below_it() {
        let (m, cap, ramp, floor) = (0.46f64, 6.1875f64, 0.2f64, 1.5f64);
        let bare = ThrustMode::VerticalPriority {
            cap,
            ramp,
            floor: 0.0,
        };
        let floored = ThrustMode::VerticalPriority { cap, ramp, floor };
        let u = Vector3::new(1.0f64, -2.0, 9.0);
        for z in [-1.0, -0.3, 0.0, 0.01, 0.05, 0.1, 0.3, 0.6, 1.0] {
            let b = unit([1.0, 0.3, z]);
            let (t0, t) = (bare.thrust(m, &u, &b), floored.thrust(m, &u, &b));
            if t0 < floor {
                assert_eq!(t, floor, "z {z}");
            } else {
                assert_eq!(t.to_bits(), t0.to_bits(), "z {z}");
            }
        }
        assert_eq!(floored.thrust(m, &u, &unit([0.0, 0.0, -1.0])), floor);
        let v = Vehicle::<f64>::paper();
        assert!(floored.validate(&v, 2.0).is_ok());
        let e = ThrustMode::VerticalPriority {
            cap,
            ramp,
            floor: -0.1,
        }
        .validate(&v, 2.0)
        .unwrap_err();
        assert!(matches!(
            e,
            ParameterError::OutOfRange {
                name: "thrust_floor",
                ..
            }
        ));
    }

    #[test]
    fn validate_refuses_bad_floors_by_name() {
        let v = Vehicle::<f64>::paper();
        for floor in [-0.1, f64::NAN, 0.46 * (9.81 - 2.0)] {
            let e = ThrustMode::BodyAxisProjection { floor }
                .validate(&v, 2.0)
                .unwrap_err();
            assert!(
                matches!(
                    e,
                    ParameterError::OutOfRange {
                        name: "thrust_floor",
                        ..
                    }
                ),
                "{e:?}"
            );
        }
        assert!(ThrustMode::body_axis_projection().validate(&v, 2.0).is_ok());
        assert!(ThrustMode::Norm.validate(&v, 2.0).is_ok());
    }
}
