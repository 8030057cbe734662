//! `[controller]`: the options of the law that depart from the paper (the no-dive thrust,
//! [`controller_core::thrust`]), their validation and the thrust interval they certify.

use controller_core::scalar::{lit, Scalar};
use controller_core::{ThrustMode, Trajectory};
use serde::{Deserialize, Serialize};

use super::{describe, Scenario};

/// `[controller]`: options of the law that depart from the paper (all off by default).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ControllerConfig {
    /// How the collective thrust is computed from `u`: `"norm"` (`T = m|u|`, the paper's; the
    /// default), or a no-dive thrust ([`controller_core::thrust`]): `"body-axis-projection"`
    /// (`T = max(m uᵀRe₃, thrust_floor_N)`), `"alignment-power"`
    /// (`T = max(m|u| max(cos θ̃, 0)^thrust_exponent, thrust_floor_N)`) or `"vertical-priority"`
    /// (see [`ThrustKind::VerticalPriority`]).
    #[serde(default)]
    pub thrust: ThrustKind,
    /// `T_floor` \[N\] of the no-dive thrusts, in `[0, T_min]` (Theorem 1's `T_min`); default 0.
    /// Refused with `thrust = "norm"` unless 0.
    #[serde(default, skip_serializing_if = "is_zero_f64")]
    pub thrust_floor_N: f64,
    /// Exponent `k > 0` of `"alignment-power"`; default 1.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub thrust_exponent: f64,
    /// Ramp width `b₀ ∈ (0, 1]` of `"vertical-priority"` in `e₃ᵀRe₃`; default 0.2.
    #[serde(default = "default_ramp", skip_serializing_if = "is_default_ramp")]
    pub thrust_ramp: f64,
    /// Airmode (docs/airmode.md): the thrust moved, by as little as possible, to where the
    /// rotors realise the law's torque, keeping `airmode_margin` of each rotor's range free
    /// ([`controller_core::RotorEnvelope::airmode_thrust`]). Needs the `[rotors]` table; off by
    /// default.
    #[serde(default, skip_serializing_if = "is_false")]
    pub airmode: bool,
    /// The fraction of each rotor's thrust range airmode keeps free at both ends, in
    /// `[0, 0.5)`; default 0.05 (`design`'s margin).
    #[serde(
        default = "default_airmode_margin",
        skip_serializing_if = "is_default_airmode_margin"
    )]
    pub airmode_margin: f64,
    /// The fraction of each rotor's thrust range airmode keeps free above the rotors' least
    /// thrust, in `[0.001, airmode_margin]` (the least: `flight_files`'
    /// `AIRMODE_LEAST_LOW_MARGIN`); absent: `airmode_margin` (the same at both ends). A
    /// smaller one lets the thrust fall closer to the rotors' idle while the no-dive thrust cuts
    /// it (upside down), and the certified fits still hold (they are checked with the margin at
    /// both ends; docs/airmode.md). Only with `airmode = true`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub airmode_low_margin: Option<f64>,
}

fn is_false(x: &bool) -> bool {
    !*x
}

fn default_airmode_margin() -> f64 {
    0.05
}

fn is_default_airmode_margin(x: &f64) -> bool {
    *x == default_airmode_margin()
}

fn default_ramp() -> f64 {
    0.2
}

fn is_default_ramp(x: &f64) -> bool {
    *x == default_ramp()
}

fn one() -> f64 {
    1.0
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

/// `controller.thrust`: the thrust law's name in scenario files and on the command line.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ThrustKind {
    /// `T = m|u|` (the paper's).
    #[default]
    Norm,
    /// `T = max(m uᵀRe₃, T_floor)`, the no-dive thrust.
    BodyAxisProjection,
    /// `T = max(m|u| max(cos θ̃, 0)^k, T_floor)`.
    AlignmentPower,
    /// `T = min(m u₃/b₃, T_max · min(1, b₃/b₀))` for `b₃ = e₃ᵀRe₃ > 0`, else 0, raised to
    /// `thrust_floor_N` where below it: the vertical thrust `u` asks for while the body z axis
    /// is above the horizon (tilt compensation), capped at Theorem 1's `T_max` and ramped to 0
    /// (or the floor) at the horizon.
    VerticalPriority,
}

impl ThrustKind {
    /// The name used in scenario files and on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Norm => "norm",
            Self::BodyAxisProjection => "body-axis-projection",
            Self::AlignmentPower => "alignment-power",
            Self::VerticalPriority => "vertical-priority",
        }
    }
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            thrust: ThrustKind::Norm,
            thrust_floor_N: 0.0,
            thrust_exponent: 1.0,
            thrust_ramp: default_ramp(),
            airmode: false,
            airmode_margin: default_airmode_margin(),
            airmode_low_margin: None,
        }
    }
}

impl ControllerConfig {
    /// True for the paper's law (the default, left out when a scenario is written).
    pub fn is_paper(&self) -> bool {
        *self == Self::default()
    }

    /// The core's thrust mode in scalar `T`; `thrust_max_n` \[N\] is Theorem 1's `T_max`, the
    /// cap of `"vertical-priority"` (unused by the others).
    pub fn thrust_mode<T: Scalar>(&self, thrust_max_n: f64) -> ThrustMode<T> {
        match self.thrust {
            ThrustKind::Norm => ThrustMode::Norm,
            ThrustKind::BodyAxisProjection => ThrustMode::BodyAxisProjection {
                floor: lit(self.thrust_floor_N),
            },
            ThrustKind::AlignmentPower => ThrustMode::AlignmentPower {
                exponent: lit(self.thrust_exponent),
                floor: lit(self.thrust_floor_N),
            },
            ThrustKind::VerticalPriority => ThrustMode::VerticalPriority {
                cap: lit(thrust_max_n),
                ramp: lit(self.thrust_ramp),
                floor: lit(self.thrust_floor_N),
            },
        }
    }
}

/// Overrides of `[controller]` keys (from the command line); `None` keeps the scenario's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct ControllerOverrides {
    /// `thrust`.
    pub thrust: Option<ThrustKind>,
    /// `thrust_floor_N` \[N\].
    pub thrust_floor_N: Option<f64>,
    /// `thrust_ramp`.
    pub thrust_ramp: Option<f64>,
    /// `thrust_exponent`.
    pub thrust_exponent: Option<f64>,
}

fn is_zero_f64(x: &f64) -> bool {
    *x == 0.0
}

impl Scenario {
    /// `[controller]`: the floor only with a no-dive thrust, and within `[0, m(g − M_p))`
    /// ([`ThrustMode::validate`]; the bound check against Theorem 1's `T_min` needs the
    /// reference and is [`Scenario::thrust_interval`]'s).
    pub(super) fn validate_controller(&self) -> std::result::Result<(), String> {
        let c = &self.controller;
        if !(c.airmode_margin.is_finite() && (0.0..0.5).contains(&c.airmode_margin)) {
            return Err(format!(
                "controller.airmode_margin: must lie in [0, 0.5), got {}",
                c.airmode_margin
            ));
        }
        if let Some(low) = c.airmode_low_margin {
            if !c.airmode {
                return Err("controller.airmode_low_margin: only used with airmode = true".into());
            }
            let least = flight_files::flight_file::AIRMODE_LEAST_LOW_MARGIN;
            if !(low.is_finite() && (least..=c.airmode_margin).contains(&low)) {
                return Err(format!(
                    "controller.airmode_low_margin: must lie in [{least}, airmode_margin = {}], \
                     got {low}",
                    c.airmode_margin
                ));
            }
        }
        if c.airmode && self.rotors.is_none() {
            return Err(
                "controller.airmode: needs the [rotors] table (the rotors' (T, tau) set)".into(),
            );
        }
        if c.thrust == ThrustKind::Norm && c.thrust_floor_N != 0.0 {
            return Err(format!(
                "controller.thrust_floor_N: only used with the no-dive thrusts, \
                 got {} N with thrust = \"norm\"",
                c.thrust_floor_N
            ));
        }
        if c.thrust == ThrustKind::AlignmentPower
            && !(c.thrust_exponent.is_finite() && c.thrust_exponent > 0.0)
        {
            return Err(format!(
                "controller.thrust_exponent: must be finite and > 0, got {}",
                c.thrust_exponent
            ));
        }
        // The cap (Theorem 1's T_max) is checked with the certificate; any positive value here.
        // With the integral action the vertical part of u can drop by M_p + M_i,z.
        let drop = self.gains.M_p + self.gains.integral.as_ref().map_or(0.0, |i| i.M_i_m_s2[2]);
        c.thrust_mode::<f64>(1.0)
            .validate(&self.vehicle(), drop)
            .map_err(|e| describe(&e))
    }

    /// The core's thrust mode of `[controller]` for this scenario, in scalar `T` (the
    /// vertical-priority cap is Theorem 1's `T_max` from the certificate).
    /// Errors: the certificate cannot be computed (named by key).
    pub fn thrust_mode<T: Scalar>(&self) -> std::result::Result<ThrustMode<T>, String> {
        let thrust_max = if self.controller.thrust == ThrustKind::VerticalPriority {
            // Only Theorem 1's `T_max` is read: the torque set's joint bound is not built.
            controller_core::bounds::certify_without_joint_bound(
                &self.vehicle::<f64>(),
                &self.limits::<f64>(),
                &self.gains::<f64>(),
                &self.trajectory::<f64>().constants(),
                controller_core::FilterStart::Zero,
            )
            .map_err(|e| describe(&e))?
            .bounds
            .thrust_max
        } else {
            0.0
        };
        Ok(self.controller.thrust_mode(thrust_max))
    }

    /// The a-priori interval `[low, high]` \[N\] of the thrust the scenario's law applies,
    /// from its certificate's bounds: Theorem 1's `[T_min, T_max]` for `thrust = "norm"`,
    /// `[thrust_floor_N, T_max]` for the no-dive thrust ([`ThrustMode::interval`]), widened
    /// with airmode to where the rotors realise the certified torques
    /// ([`controller_core::RotorEnvelope::airmode_interval`]).
    /// Errors: the floor exceeds `T_min` (named by key), or airmode's rotors are refused.
    pub fn thrust_interval(
        &self,
        certificate: &controller_core::Certificate<f64>,
    ) -> std::result::Result<[f64; 2], String> {
        let bounds = &certificate.bounds;
        let (low, high) = self
            .controller
            .thrust_mode::<f64>(bounds.thrust_max)
            .interval(bounds)
            .map_err(|e| format!("{} (Theorem 1's interval)", describe(&e)))?;
        Ok(match self.airmode_envelope::<f64>()? {
            Some(e) => {
                // Every torque set the law's torque can be in: Theorem 2's, and the local
                // regime's with the envelope design.
                let (mut a, mut b) = e.airmode_interval(low, high, &bounds.torque_set);
                if let Some(l) = &certificate.local {
                    let (c, d) = e.airmode_interval(low, high, &l.torque_set);
                    (a, b) = (a.min(c), b.max(d));
                }
                [a, b]
            }
            None => [low, high],
        })
    }

    /// Airmode's rotor envelope in scalar `T` (the firmware mixer's rows, the range shrunk by
    /// `airmode_margin` below its top and `airmode_low_margin` above its bottom), or `None` when
    /// airmode is off.
    /// Errors: no `[rotors]` table, or the mixer refuses the rotors (named by key).
    pub fn airmode_envelope<T: Scalar>(
        &self,
    ) -> std::result::Result<Option<controller_core::RotorEnvelope<T>>, String> {
        if !self.controller.airmode {
            return Ok(None);
        }
        let rotors = self
            .rotor_config()
            .ok_or("controller.airmode: needs the [rotors] table")?
            .rotors;
        let mixer = firmware::mixer::Mixer::new(&rotors)
            .map_err(|e| format!("[rotors]: the mixer refuses the rotors: {e:?}"))?;
        let m = mixer.mixing();
        let (lo, hi) = mixer.thrust_range();
        let rows = [0, 1, 2, 3].map(|k| [0, 1, 2, 3].map(|j| lit::<T>(f64::from(m[(k, j)]))));
        controller_core::RotorEnvelope::new(rows, lit(f64::from(lo)), lit(f64::from(hi)))
            .map(|e| {
                let c = &self.controller;
                let top = c.airmode_margin;
                Some(e.shrunk_ends(lit(c.airmode_low_margin.unwrap_or(top)), lit(top)))
            })
            .map_err(|e| format!("[rotors]: {}", describe(&e)))
    }
}

#[cfg(test)]
mod tests {
    use super::super::PAPER_SCENARIO;
    use super::*;

    #[test]
    fn paper_no_dive_is_the_paper_with_the_thrust_option() {
        let text = include_str!("../../../scenarios/paper-no-dive.toml");
        let s = Scenario::parse(text, "paper-no-dive.toml").unwrap();
        assert_eq!(s.controller.thrust, ThrustKind::VerticalPriority);
        assert_eq!(
            Scenario {
                controller: ControllerConfig::default(),
                ..s
            },
            Scenario::paper()
        );
    }

    #[test]
    fn controller_keys_are_checked_by_name() {
        let table = |body: &str| format!("{PAPER_SCENARIO}\n[controller]\n{body}\n");
        let e = Scenario::parse(&table("thrust = \"sideways\""), "a.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("a.toml") && e.contains("sideways"), "{e}");
        let e = Scenario::parse(
            &table("thrust = \"body-axis-projection\"\nthrust_floor_N = -1.0"),
            "b.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("controller.thrust_floor_N"), "{e}");
        let e = Scenario::parse(&table("thrust_floor_N = 0.5"), "c.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("controller.thrust_floor_N") && e.contains("norm"),
            "{e}"
        );
        let e = Scenario::parse(
            &table("thrust = \"vertical-priority\"\nthrust_ramp = 0.0"),
            "d.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("controller.thrust_ramp"), "{e}");
        // A floor between T_min (3.51 N) and m(g - M_p) (3.59 N) passes the file check (which
        // knows no reference) but not the interval.
        let s = Scenario::parse(
            &table("thrust = \"body-axis-projection\"\nthrust_floor_N = 3.55"),
            "e.toml",
        )
        .unwrap();
        let cert = crate::fly::sim::certificate(&s).unwrap();
        let e = s.thrust_interval(&cert).unwrap_err();
        assert!(e.contains("controller.thrust_floor_N"), "{e}");
        // The paper's scenario written back has no [controller] table.
        let written = toml::to_string(&Scenario::paper()).unwrap();
        assert!(!written.contains("[controller]"), "{written}");
    }

    /// Given the committed Hummingbird design's scenario (airmode on, `airmode_low_margin =
    /// 0.001`), when the low margin is read, then airmode flies the rotors' range shrunk by it
    /// at the bottom and by `airmode_margin` at the top; a low margin of 0, above
    /// `airmode_margin`, or without airmode is refused naming the key.
    #[test]
    fn airmode_low_margin_is_checked_by_name_and_flown_at_the_bottom_only() {
        let text = include_str!("../../../designs/hummingbird/scenario.toml");
        let s = Scenario::parse(text, "hummingbird.toml").unwrap();
        assert_eq!(s.controller.airmode_low_margin, Some(0.001));
        let (lo, hi) = (0.0, s.rotors.as_ref().unwrap().thrust_max_N);
        let (a, b) = s.airmode_envelope::<f64>().unwrap().unwrap().range;
        let span = hi - lo;
        assert!((a - (lo + 0.001 * span)).abs() < 1e-5 * span, "{a}");
        assert!((b - (hi - 0.05 * span)).abs() < 1e-5 * span, "{b}");
        let with = |line: &str| text.replace("airmode_low_margin = 0.001", line);
        for (line, says) in [
            (
                "airmode_low_margin = 0.0",
                "must lie in [0.001, airmode_margin = 0.05]",
            ),
            ("airmode_low_margin = 0.06", "got 0.06"),
        ] {
            let e = Scenario::parse(&with(line), "f.toml")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("controller.airmode_low_margin") && e.contains(says),
                "{e}"
            );
        }
        let off = with("airmode_low_margin = 0.001").replace("airmode = true", "airmode = false");
        let e = Scenario::parse(&off, "g.toml").unwrap_err().to_string();
        assert!(
            e.contains("controller.airmode_low_margin: only used with airmode = true"),
            "{e}"
        );
    }
}
