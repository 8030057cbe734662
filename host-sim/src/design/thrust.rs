//! `design --thrust vertical-priority`: the no-dive thrust inside the certified set.
//!
//! The paper's `T = m|u|` stays in Theorem 1's `[T_min, T_max]` whatever the attitude, so an
//! upside-down vehicle is driven towards the ground at about `T_min/m + g` while it turns over.
//! Vertical priority ([`controller_core::ThrustMode::VerticalPriority`], docs/no-dive-thrust.md)
//! cuts the thrust while the body z axis points down, but not below a floor `T_floor`: the
//! certified set is then `[T_floor, T_max] × S` (`S` the torque set), and the rotors must
//! realise every torque of `S` at the floor too. The design takes the lowest floor for which
//! that set still leaves the margin of every rotor's range free, measured with the firmware's
//! own [`Mixer::set_margin`] (the function its boot gate uses), so the firmware certifies the flight
//! file it writes. The torque levels are chosen first, for `[T_min, T_max]` as without the
//! option; the floor then spends what headroom is left at the bottom of the rotors' range.

use controller_core::{Bounds, TorqueSet};
use firmware::mixer::Mixer;
use serde::Serialize;

use crate::model::scenario::{ControllerConfig, ThrustKind};

/// Bisection steps on the floor: `T_min / 2^40`, far below an f32's resolution of it.
const BISECTION_STEPS: usize = 40;

/// Headroom the floor leaves above the requested margin \[fraction of the rotor range\]: the
/// firmware recomputes the certificate in f32 from the flight file, and at a floor exactly on
/// the margin its rounding can flip the gate's verdict (measured on the x500: a margin of
/// 0.049999993 against 0.05). A ten-thousandth of the range costs nothing measurable.
pub const GATE_SLACK: f64 = 1e-4;

/// The lowest thrust floor \[N\] in `[0, t_min]` at which the set `[floor, t_max] × torques`
/// (body axes) leaves at least `margin` (fraction of the rotor range) of every rotor's range
/// free on `mixer`; `None` when even `t_min` does not (the certified set does not fit). The
/// headroom only grows with the floor (the set's lower end rises), so the bisection keeps the
/// certified end.
pub fn lowest_floor(
    mixer: &Mixer,
    (t_min, t_max): (f32, f32),
    torques: &TorqueSet<f32>,
    margin: f32,
) -> Option<f32> {
    let fits = |floor: f32| mixer.set_margin(floor, t_max, torques) >= margin;
    if !fits(t_min) {
        return None;
    }
    if fits(0.0) {
        return Some(0.0);
    }
    Some(super::bisect::bisect(t_min, 0.0, BISECTION_STEPS, fits))
}

/// The thrust a design flies and writes (`design.json` `thrust`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct ThrustDesign {
    /// `"norm"` (the paper's `T = m|u|`) or `"vertical-priority"`.
    pub mode: &'static str,
    /// Vertical priority's floor \[N\] (0 for `norm`).
    pub floor_N: f64,
    /// The certified thrust interval \[N\]: Theorem 1's `[T_min, T_max]`, or `[T_floor, T_max]`.
    pub interval_N: [f64; 2],
    /// Vertical priority's ramp `b₀` (dimensionless; 0 for `norm`).
    pub ramp: f64,
    /// `Some(margin)`: airmode, keeping `margin` (fraction) of each rotor's range free
    /// (docs/airmode.md); the floor is then 0, since airmode raises the thrust wherever the torque
    /// needs it, and the interval is airmode's.
    pub airmode_margin: Option<f64>,
    /// With airmode, `Some(low)`: the smaller margin (fraction) airmode keeps free above the
    /// rotors' least thrust (`[controller] airmode_low_margin`); `None`: `airmode_margin` at both
    /// ends. The fits are checked with `airmode_margin` at both ends either way.
    pub airmode_low_margin: Option<f64>,
    /// With airmode and vertical priority, the design's objective flown with 0.1 % above
    /// the rotors' least thrust, and whether it met every constraint (`design` keeps that way
    /// when it does and scores lower); `None` when not tried.
    pub airmode_idle_trial: Option<(f64, bool)>,
}

impl ThrustDesign {
    /// The design's thrust for `kind` with the certificate's `bounds` and the torque set
    /// `torques` the firmware's gate measures, on the vehicle's `mixer` with `margin` (plus
    /// [`GATE_SLACK`] for vertical priority's floor).
    /// Errors: a thrust the firmware does not fly (only `norm` and `vertical-priority`), or no
    /// floor fits (the certified set does not fit even at `T_min`; not expected for a certified design).
    pub fn new(
        kind: ThrustKind,
        bounds: &Bounds<f64>,
        mixer: &Mixer,
        torques: &TorqueSet<f32>,
        margin: f64,
    ) -> Result<Self, String> {
        let (t_min, t_max) = (bounds.thrust_min, bounds.thrust_max);
        match kind {
            ThrustKind::Norm => Ok(Self {
                mode: kind.name(),
                floor_N: 0.0,
                interval_N: [t_min, t_max],
                ramp: 0.0,
                airmode_margin: None,
                airmode_low_margin: None,
                airmode_idle_trial: None,
            }),
            ThrustKind::VerticalPriority => {
                let floor = lowest_floor(
                    mixer,
                    (t_min as f32, t_max as f32),
                    torques,
                    (margin + GATE_SLACK) as f32,
                )
                .ok_or_else(|| {
                    format!("no thrust floor fits the rotors with margin {margin}: the certified set does not fit even at T_min = {t_min} N")
                })?;
                // The floor must stay within T_min in the scalar the scenario stores.
                let floor = f64::from(floor).min(t_min);
                Ok(Self {
                    mode: kind.name(),
                    floor_N: floor,
                    interval_N: [floor, t_max],
                    ramp: ControllerConfig::default().thrust_ramp,
                    airmode_margin: None,
                    airmode_low_margin: None,
                    airmode_idle_trial: None,
                })
            }
            other => Err(not_flown(other)),
        }
    }

    /// The thrust of a design that flies airmode (docs/airmode.md) with `kind` on `rotors`,
    /// keeping `margin` (fraction of the range) free below their top and `low_margin` (`None`:
    /// `margin`) above their bottom: vertical priority with no floor (airmode raises the thrust
    /// wherever the torque needs it), and the interval airmode keeps the thrust in for the
    /// certificate's `bounds` on that range. Errors: a thrust the firmware does not fly.
    pub fn airmode(
        kind: ThrustKind,
        bounds: &Bounds<f64>,
        rotors: &super::authority::RotorSet,
        (margin, low_margin): (f64, Option<f64>),
    ) -> Result<Self, String> {
        let envelope = rotors
            .envelope(0.0)
            .shrunk_ends(low_margin.unwrap_or(margin), margin);
        Self::check_flown(kind)?;
        let floor = 0.0;
        let low = if kind == ThrustKind::Norm {
            bounds.thrust_min
        } else {
            floor
        };
        // The interval of the Minkowski sum, without the attitude terms' joint bound: a
        // narrower interval than the joint bound allows, so still airmode's. With the joint
        // bound here and in the search's `ι_max`, the x500's search met no constraint on 30 s
        // runs (docs/design.md, "Scoring an edited design").
        let sum = TorqueSet {
            attitude_joint: None,
            ..bounds.torque_set
        };
        let (a, b) = envelope.airmode_interval(low, bounds.thrust_max, &sum);
        Ok(Self {
            mode: kind.name(),
            floor_N: floor,
            interval_N: [a, b],
            ramp: if kind == ThrustKind::Norm {
                0.0
            } else {
                ControllerConfig::default().thrust_ramp
            },
            airmode_margin: Some(margin),
            airmode_low_margin: low_margin,
            airmode_idle_trial: None,
        })
    }

    /// `Ok` for the thrusts the firmware flies (`norm`, `vertical-priority`), so the ones a
    /// design may write. Errors: the refusal naming the other thrust.
    pub fn check_flown(kind: ThrustKind) -> Result<(), String> {
        match kind {
            ThrustKind::Norm | ThrustKind::VerticalPriority => Ok(()),
            other => Err(not_flown(other)),
        }
    }

    /// The scenario's `[controller]` for this thrust.
    pub fn controller(&self) -> ControllerConfig {
        let airmode = ControllerConfig {
            airmode: self.airmode_margin.is_some(),
            airmode_margin: self
                .airmode_margin
                .unwrap_or(ControllerConfig::default().airmode_margin),
            airmode_low_margin: self.airmode_low_margin,
            ..ControllerConfig::default()
        };
        if self.mode == ThrustKind::VerticalPriority.name() {
            ControllerConfig {
                thrust: ThrustKind::VerticalPriority,
                thrust_floor_N: self.floor_N,
                thrust_ramp: self.ramp,
                ..airmode
            }
        } else {
            airmode
        }
    }
}

fn not_flown(kind: ThrustKind) -> String {
    format!(
        "--thrust: the firmware flies \"norm\" or \"vertical-priority\", not {:?}",
        kind.name()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware::config::FlightConfig;
    use nalgebra::Vector3;

    /// The floor is where the set's headroom crosses the margin: the set fits with the margin
    /// at the floor and not 1 % below it; a margin the set cannot leave even at `T_min` gives
    /// none; with nothing to hold the floor is the rotors' idle.
    #[test]
    fn the_floor_is_where_the_margin_binds() {
        let c = FlightConfig::built();
        let mixer = Mixer::new(&c.rotors).unwrap();
        let (t_min, t_max) = (18.0f32, 24.0f32);
        // The x500's inertia, a small feedforward and a 0.05 N m feedback ball: about 1.1 N of a
        // rotor's range for the torques (the yaw row dominates), so the floor is near 7 N.
        let tau = TorqueSet::new(
            Vector3::new(0.024f32, 0.024, 0.044),
            0.5,
            0.5,
            0.05,
            Vector3::repeat(0.05),
        );
        let floor = lowest_floor(&mixer, (t_min, t_max), &tau, 0.05).unwrap();
        assert!(floor > 0.0 && floor < t_min);
        assert!(mixer.set_margin(floor, t_max, &tau) >= 0.05);
        assert!(mixer.set_margin(0.99 * floor, t_max, &tau) < 0.05);
        assert_eq!(lowest_floor(&mixer, (t_min, t_max), &tau, 0.6), None);
        // With (almost) no torque to hold and no margin, the floor is the rotors' idle: four
        // times each rotor's least thrust.
        let tiny = TorqueSet::new(Vector3::zeros(), 0.0, 0.0, 1e-6f32, Vector3::repeat(1e-6));
        let idle = 4.0 * c.rotors.thrust_min;
        let floor = lowest_floor(&mixer, (t_min, t_max), &tiny, 0.0).unwrap();
        assert!(
            (floor - idle).abs() < 1e-3 * idle,
            "{floor} N against {idle} N"
        );
    }

    /// Only the thrusts the firmware flies may be designed; another is refused by name.
    #[test]
    fn only_the_firmwares_thrusts_are_designed() {
        assert!(ThrustDesign::check_flown(ThrustKind::Norm).is_ok());
        assert!(ThrustDesign::check_flown(ThrustKind::VerticalPriority).is_ok());
        let e = ThrustDesign::check_flown(ThrustKind::BodyAxisProjection).unwrap_err();
        assert!(e.contains("body-axis-projection"), "{e}");
    }
}
