//! The checks of every value of a vehicle file: finite, signs, ranges, four rotors, two spinning
//! each way, an invertible mixer, a thrust range above the weight.

use std::format;
use std::string::{String, ToString};

use super::{DragTable, RotorsTable, Spin, VehicleFileError, VehicleTable, ROTOR_COUNT};

pub(super) fn error(
    file: &str,
    key: impl Into<String>,
    reason: impl Into<String>,
) -> VehicleFileError {
    VehicleFileError {
        file: file.to_string(),
        key: key.into(),
        reason: reason.into(),
    }
}

/// A value that must be finite and `> 0` (`positive`) or `≥ 0` (not), in f32 too.
fn check_sign(file: &str, key: &str, v: f64, positive: bool) -> Result<(), VehicleFileError> {
    if !v.is_finite() {
        return Err(error(file, key, format!("must be finite, got {v}")));
    }
    if v < 0.0 {
        return Err(error(file, key, format!("must not be negative, got {v}")));
    }
    if positive && v == 0.0 {
        return Err(error(file, key, "must be > 0, got 0"));
    }
    // The firmware flies f32: the value must survive the conversion.
    let single = v as f32;
    if single.is_infinite() || (positive && single == 0.0) {
        return Err(error(
            file,
            key,
            format!("out of the firmware's f32 range, got {v}"),
        ));
    }
    Ok(())
}

/// [`check_sign`] on each element, naming it `key[i]`.
fn check_signs(file: &str, key: &str, v: &[f64], positive: bool) -> Result<(), VehicleFileError> {
    v.iter()
        .enumerate()
        .try_for_each(|(i, &x)| check_sign(file, &format!("{key}[{i}]"), x, positive))
}

/// A value that must be finite and in `[lo, hi]` (`hi` excluded when `hi_open`).
fn check_range(
    file: &str,
    key: &str,
    v: f64,
    lo: f64,
    hi: f64,
    hi_open: bool,
) -> Result<(), VehicleFileError> {
    let above = if hi_open { v >= hi } else { v > hi };
    if !v.is_finite() {
        Err(error(file, key, format!("must be finite, got {v}")))
    } else if v < lo || above {
        let close = if hi_open { ")" } else { "]" };
        Err(error(
            file,
            key,
            format!("must be in [{lo}, {hi}{close}, got {v}"),
        ))
    } else {
        Ok(())
    }
}

/// Rank test of the 4×4 effectiveness matrix `B` (rows T, τx, τy, τz per newton of each rotor,
/// as the firmware's mixer builds it), each row scaled to its largest entry so the tolerance
/// does not depend on the vehicle's size: `true` when `B` is invertible.
fn geometry_invertible(positions: &[[f64; 2]], spin: &[Spin], yaw_ratio: f64) -> bool {
    let mut b = [[0.0f64; ROTOR_COUNT]; ROTOR_COUNT];
    for (k, (p, s)) in positions.iter().zip(spin).enumerate() {
        b[0][k] = 1.0;
        b[1][k] = p[1];
        b[2][k] = -p[0];
        b[3][k] = -f64::from(s.sign()) * yaw_ratio;
    }
    for row in &mut b {
        let scale = row.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return false;
        }
        row.iter_mut().for_each(|x| *x /= scale);
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..ROTOR_COUNT {
        let pivot = (col..ROTOR_COUNT)
            .max_by(|&i, &j| b[i][col].abs().total_cmp(&b[j][col].abs()))
            .unwrap_or(col);
        if b[pivot][col].abs() < 1e-9 {
            return false;
        }
        b.swap(col, pivot);
        let (done, rest) = b.split_at_mut(col + 1);
        let top = done[col];
        for row in rest {
            let f = row[col] / top[col];
            row.iter_mut().zip(top).for_each(|(x, t)| *x -= f * t);
        }
    }
    true
}

impl VehicleTable {
    /// Checks the rigid body (and, when `identity`, that name and source are given and not
    /// empty and `real_propeller` is stated, as a vehicle file must). Errors name `file`, the
    /// key and the reason.
    pub fn validate(&self, file: &str, identity: bool) -> Result<(), VehicleFileError> {
        if identity {
            for (key, v) in [
                ("vehicle.name", &self.name),
                ("vehicle.source", &self.source),
            ] {
                match v {
                    None => return Err(error(file, key, "missing")),
                    Some(s) if s.trim().is_empty() => {
                        return Err(error(file, key, "must not be empty"))
                    }
                    Some(_) => {}
                }
            }
            if self.real_propeller.is_none() {
                return Err(error(file, "vehicle.real_propeller", "missing"));
            }
        }
        check_sign(file, "vehicle.mass_kg", self.mass_kg, true)?;
        check_signs(file, "vehicle.inertia_kg_m2", &self.inertia_kg_m2, true)?;
        check_sign(file, "vehicle.gravity_m_s2", self.gravity_m_s2, true)
    }
}

impl RotorsTable {
    /// Checks the rotors on their own (counts, spins, signs, ranges, an invertible mixer) and
    /// against the rigid body (`4 thrust_max_N > m g`, or the vehicle cannot hover). Errors
    /// name `file`, the key and the reason.
    pub fn validate(&self, file: &str, vehicle: &VehicleTable) -> Result<(), VehicleFileError> {
        if self.positions_m.len() != ROTOR_COUNT {
            return Err(error(
                file,
                "rotors.positions_m",
                format!(
                    "{} rotors given; exactly {ROTOR_COUNT} (a quadrotor) are supported",
                    self.positions_m.len()
                ),
            ));
        }
        for (i, p) in self.positions_m.iter().enumerate() {
            if !p.iter().all(|x| x.is_finite()) {
                return Err(error(
                    file,
                    format!("rotors.positions_m[{i}]"),
                    format!("must be finite, got {p:?}"),
                ));
            }
            // The firmware flies f32: the position and its distance from the centre of mass
            // (the arm length) must survive the conversion.
            if !(p[0].hypot(p[1]) as f32).is_finite() {
                return Err(error(
                    file,
                    format!("rotors.positions_m[{i}]"),
                    format!("out of the firmware's f32 range, got {p:?}"),
                ));
            }
        }
        if self.spin.len() != ROTOR_COUNT {
            return Err(error(
                file,
                "rotors.spin",
                format!(
                    "{} spins given; one per rotor ({ROTOR_COUNT}) is needed",
                    self.spin.len()
                ),
            ));
        }
        let ccw = self.spin.iter().filter(|s| **s == Spin::Ccw).count();
        if ccw != ROTOR_COUNT / 2 {
            return Err(error(
                file,
                "rotors.spin",
                format!(
                    "must be two \"cw\" and two \"ccw\" (the yaw torques must cancel at \
                     hover), got {ccw} ccw"
                ),
            ));
        }
        check_sign(file, "rotors.thrust_min_N", self.thrust_min_N, false)?;
        check_sign(file, "rotors.thrust_max_N", self.thrust_max_N, true)?;
        if self.thrust_max_N <= self.thrust_min_N {
            return Err(error(
                file,
                "rotors.thrust_max_N",
                format!(
                    "thrust range empty: thrust_max_N = {} N is not above thrust_min_N = {} N",
                    self.thrust_max_N, self.thrust_min_N
                ),
            ));
        }
        check_sign(
            file,
            "rotors.yaw_torque_per_thrust_m",
            self.yaw_torque_per_thrust_m,
            true,
        )?;
        check_sign(
            file,
            "rotors.motor_time_constant_s",
            self.motor_time_constant_s,
            true,
        )?;
        check_range(
            file,
            "rotors.thrust_curve_factor",
            self.thrust_curve_factor,
            0.0,
            1.0,
            false,
        )?;
        check_range(
            file,
            "rotors.throttle_idle",
            self.throttle_idle,
            0.0,
            1.0,
            true,
        )?;
        if !geometry_invertible(&self.positions_m, &self.spin, self.yaw_torque_per_thrust_m) {
            return Err(error(
                file,
                "rotors.positions_m",
                "singular geometry: these positions and spins cannot produce thrust, roll, \
                 pitch and yaw independently (the mixer cannot be inverted)",
            ));
        }
        let weight = vehicle.mass_kg * vehicle.gravity_m_s2;
        let most = ROTOR_COUNT as f64 * self.thrust_max_N;
        if most <= weight {
            return Err(error(
                file,
                "rotors.thrust_max_N",
                format!(
                    "cannot hover: {ROTOR_COUNT} x thrust_max_N = {most} N is not above the \
                     weight m g = {weight} N"
                ),
            ));
        }
        Ok(())
    }
}

impl DragTable {
    /// Checks the coefficients: finite and not negative.
    pub fn validate(&self, file: &str) -> Result<(), VehicleFileError> {
        check_signs(
            file,
            "drag.body_drag_N_s2_m2",
            &self.body_drag_N_s2_m2,
            false,
        )
    }
}
