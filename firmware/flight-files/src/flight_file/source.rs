//! The flight file's values as Rust source for `OUT_DIR/flight.rs`: literals that round like the
//! file's decimals, and the heading, trajectory and thrust choices as constructor calls. Every
//! refusal names the file, the key and the reason.

use super::{ControllerTable, DEFAULT_THRUST_RAMP};
use crate::flight_tables::{HeadingTable, TrajectoryTable};

/// The `crate::config::ThrustChoice` expression of `[controller]` (absent: `Norm`). The floor's
/// bound by Theorem 1's `T_min` needs the certificate and is the gate's, at boot.
pub(super) fn thrust_source(file: &str, c: Option<&ControllerTable>) -> String {
    let Some(c) = c else {
        return "crate::config::ThrustChoice::Norm".to_string();
    };
    match c.thrust.as_deref().unwrap_or("norm") {
        "norm" => {
            if c.thrust_ramp.is_some() || c.thrust_floor_N.is_some() {
                fail(
                    file,
                    "controller",
                    "thrust_ramp and thrust_floor_N are only used with thrust = \"vertical-priority\"".to_string(),
                );
            }
            "crate::config::ThrustChoice::Norm".to_string()
        }
        "vertical-priority" => {
            let ramp = c.thrust_ramp.unwrap_or(DEFAULT_THRUST_RAMP);
            if !(ramp > 0.0 && ramp <= 1.0) {
                fail(
                    file,
                    "controller.thrust_ramp",
                    format!("{ramp} is not in (0, 1]"),
                );
            }
            let floor = c.thrust_floor_N.unwrap_or(0.0);
            if !(floor.is_finite() && floor >= 0.0) {
                fail(
                    file,
                    "controller.thrust_floor_N",
                    format!("{floor} is not a finite thrust >= 0 [N]"),
                );
            }
            format!(
                "crate::config::ThrustChoice::VerticalPriority {{ ramp: {}, floor: {} }}",
                lit(ramp),
                lit(floor)
            )
        }
        other => fail(
            file,
            "controller.thrust",
            format!("{other:?} is not \"norm\" or \"vertical-priority\" (the firmware's thrusts)"),
        ),
    }
}

/// `[controller] airmode` (absent: off). The margin airmode keeps free is `[design] margin`
/// (`margin`, a fraction of the rotor range): a scenario's `airmode_margin` is taken only with
/// `airmode = true` and equal to it, so that no key says another margin than the one flown.
pub(super) fn airmode_source(file: &str, c: Option<&ControllerTable>, margin: f64) -> bool {
    let Some(c) = c else {
        return false;
    };
    let airmode = c.airmode.unwrap_or(false);
    match c.airmode_margin {
        Some(_) if !airmode => fail(
            file,
            "controller.airmode_margin",
            "only used with airmode = true".to_string(),
        ),
        Some(m) if m != margin => fail(
            file,
            "controller.airmode_margin",
            format!(
                "{m} differs from [design] margin = {margin}: airmode keeps [design] margin \
                 free (leave airmode_margin out)"
            ),
        ),
        _ => airmode,
    }
}

/// `[controller] airmode_low_margin`: the margin airmode keeps free above the rotors' least
/// thrust, in `[AIRMODE_LEAST_LOW_MARGIN, margin]` (`margin` = `[design] margin`, what the
/// gate's fits are checked with at both ends; absent: `margin`). Only with `airmode = true`;
/// anything else stops the build naming the key.
pub(super) fn airmode_low_margin_source(
    file: &str,
    c: Option<&ControllerTable>,
    margin: f64,
) -> f64 {
    let Some(low) = c.and_then(|c| c.airmode_low_margin) else {
        return margin;
    };
    if !c.and_then(|c| c.airmode).unwrap_or(false) {
        fail(
            file,
            "controller.airmode_low_margin",
            "only used with airmode = true",
        );
    }
    if !(low.is_finite() && (super::AIRMODE_LEAST_LOW_MARGIN..=margin).contains(&low)) {
        fail(
            file,
            "controller.airmode_low_margin",
            format!(
                "{low} is not in [{}, [design] margin = {margin}]",
                super::AIRMODE_LEAST_LOW_MARGIN
            ),
        );
    }
    low
}

pub(super) fn fail(file: &str, key: &str, reason: impl std::fmt::Display) -> ! {
    panic!("flight file {file}: {key}: {reason}")
}

/// The `f32` the firmware flies (`x as f32`, as host-sim converts the same file), printed as
/// the shortest decimal that gives that `f32` back.
pub(super) fn lit(x: f64) -> String {
    format!("{:?}f32", x as f32)
}

pub(super) fn vec3(v: [f64; 3]) -> String {
    format!(
        "nalgebra::Vector3::new({}, {}, {})",
        lit(v[0]),
        lit(v[1]),
        lit(v[2])
    )
}

pub(super) fn finite(file: &str, key: &str, values: &[f64]) {
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        fail(file, key, format!("{v} is not finite"));
    }
}

pub(super) fn heading_source(file: &str, h: &HeadingTable) -> String {
    match *h {
        HeadingTable::Constant { yaw_rad } => {
            finite(file, "trajectory.heading.yaw_rad", &[yaw_rad]);
            format!(
                "controller_core::HeadingProfile::Constant {{ yaw: {} }}",
                lit(yaw_rad)
            )
        }
        HeadingTable::Sinusoidal {
            amplitude_rad,
            frequency_rad_s,
            offset_rad,
        } => {
            finite(
                file,
                "trajectory.heading",
                &[amplitude_rad, frequency_rad_s, offset_rad],
            );
            format!(
                "controller_core::HeadingProfile::Sinusoidal {{ amplitude: {}, frequency: {}, \
                 offset: {} }}",
                lit(amplitude_rad),
                lit(frequency_rad_s),
                lit(offset_rad)
            )
        }
    }
}

pub(super) fn trajectory_source(file: &str, t: &TrajectoryTable) -> String {
    match t {
        TrajectoryTable::Hover { point_m, heading } => {
            finite(file, "trajectory.point_m", point_m);
            format!(
                "controller_core::ReferenceTrajectory::Hover {{ point: {}, heading: {} }}",
                vec3(*point_m),
                heading_source(file, heading)
            )
        }
        TrajectoryTable::Helix {
            center_m,
            radius_m,
            vertical_amplitude_m,
            frequency_rad_s,
            heading,
        } => {
            finite(file, "trajectory.center_m", center_m);
            finite(
                file,
                "trajectory",
                &[*radius_m, *vertical_amplitude_m, *frequency_rad_s],
            );
            format!(
                "controller_core::ReferenceTrajectory::Helix {{ center: {}, radius: {}, \
                 vertical_amplitude: {}, frequency: {}, heading: {} }}",
                vec3(*center_m),
                lit(*radius_m),
                lit(*vertical_amplitude_m),
                lit(*frequency_rad_s),
                heading_source(file, heading)
            )
        }
        TrajectoryTable::FigureEight {
            center_m,
            x_amplitude_m,
            y_amplitude_m,
            frequency_rad_s,
            heading,
        } => {
            finite(file, "trajectory.center_m", center_m);
            finite(
                file,
                "trajectory",
                &[*x_amplitude_m, *y_amplitude_m, *frequency_rad_s],
            );
            format!(
                "controller_core::ReferenceTrajectory::FigureEight {{ center: {}, \
                 x_amplitude: {}, y_amplitude: {}, frequency: {}, heading: {} }}",
                vec3(*center_m),
                lit(*x_amplitude_m),
                lit(*y_amplitude_m),
                lit(*frequency_rad_s),
                heading_source(file, heading)
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> ControllerTable {
        toml::from_str(text).expect("a [controller] table")
    }

    /// Given `[controller]` without `thrust`, when it is read, then the thrust is the paper's
    /// norm; airmode is off unless `airmode = true`, and off without the table.
    #[test]
    fn airmode_alone_keeps_the_norm_thrust() {
        let c = table("airmode = true");
        assert_eq!(
            thrust_source("f.toml", Some(&c)),
            "crate::config::ThrustChoice::Norm"
        );
        assert!(airmode_source("f.toml", Some(&c), 0.05));
        assert!(!airmode_source(
            "f.toml",
            Some(&table("airmode = false")),
            0.05
        ));
        assert!(!airmode_source(
            "f.toml",
            Some(&table("thrust = \"norm\"")),
            0.05
        ));
        assert!(!airmode_source("f.toml", None, 0.05));
    }

    /// Given a scenario's `airmode_margin` equal to `[design] margin`, when it is read, then
    /// airmode is on (a design's `[controller]` table reads as in its scenario).
    #[test]
    fn airmode_margin_equal_to_the_design_margin_is_taken() {
        let c = table("thrust = \"vertical-priority\"\nairmode = true\nairmode_margin = 0.07");
        assert!(airmode_source("f.toml", Some(&c), 0.07));
    }

    /// Given an `airmode_margin` other than `[design] margin`, when it is read, then the build
    /// stops naming the key and both margins.
    #[test]
    #[should_panic(
        expected = "controller.airmode_margin: 0.07 differs from [design] margin = 0.05"
    )]
    fn airmode_margin_other_than_the_design_margin_is_refused() {
        let c = table("airmode = true\nairmode_margin = 0.07");
        airmode_source("f.toml", Some(&c), 0.05);
    }

    /// Given an `airmode_margin` without airmode, when it is read, then the build stops.
    #[test]
    #[should_panic(expected = "controller.airmode_margin: only used with airmode = true")]
    fn airmode_margin_without_airmode_is_refused() {
        airmode_source("f.toml", Some(&table("airmode_margin = 0.05")), 0.05);
    }

    /// Given an `airmode_low_margin` in `[0.001, [design] margin]` with airmode, when it is read,
    /// then it is the margin flown above the rotors' least thrust; absent, the design margin.
    #[test]
    fn airmode_low_margin_within_the_design_margin_is_taken() {
        let c = table("airmode = true\nairmode_low_margin = 0.001");
        assert_eq!(airmode_low_margin_source("f.toml", Some(&c), 0.05), 0.001);
        let c = table("airmode = true");
        assert_eq!(airmode_low_margin_source("f.toml", Some(&c), 0.05), 0.05);
        assert_eq!(airmode_low_margin_source("f.toml", None, 0.05), 0.05);
    }

    /// Given an `airmode_low_margin` above `[design] margin`, when it is read, then the build
    /// stops naming the key and both ends of the range.
    #[test]
    #[should_panic(
        expected = "controller.airmode_low_margin: 0.06 is not in [0.001, [design] margin = 0.05]"
    )]
    fn airmode_low_margin_above_the_design_margin_is_refused() {
        let c = table("airmode = true\nairmode_low_margin = 0.06");
        airmode_low_margin_source("f.toml", Some(&c), 0.05);
    }

    /// Given an `airmode_low_margin` of 0 (a rotor exactly at its least thrust, which the f32
    /// mixer's rounding clips), when it is read, then the build stops.
    #[test]
    #[should_panic(
        expected = "controller.airmode_low_margin: 0 is not in [0.001, [design] margin = 0.05]"
    )]
    fn airmode_low_margin_of_zero_is_refused() {
        let c = table("airmode = true\nairmode_low_margin = 0.0");
        airmode_low_margin_source("f.toml", Some(&c), 0.05);
    }

    /// Given an `airmode_low_margin` without airmode, when it is read, then the build stops.
    #[test]
    #[should_panic(expected = "controller.airmode_low_margin: only used with airmode = true")]
    fn airmode_low_margin_without_airmode_is_refused() {
        airmode_low_margin_source("f.toml", Some(&table("airmode_low_margin = 0.0")), 0.05);
    }

    /// Unknown `[controller]` keys stay refused.
    #[test]
    fn unknown_controller_keys_are_refused() {
        let e = toml::from_str::<ControllerTable>("airmode = true\nairmod = true").unwrap_err();
        assert!(e.to_string().contains("airmod"), "{e}");
    }
}
