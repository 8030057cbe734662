//! The reference a design is certified for, and its scaled family.
//!
//! The requested reference is a scenario file's `[trajectory]` and `[initial]` (default: the
//! paper's helix). Its *family* keeps the shape and scales time: the helix / figure-eight
//! frequency and the heading sinusoid's frequency are multiplied by `s ∈ (0, 1]`, which scales
//! every Assumption 1 constant down (`K_a ∝ s²`, `K_j ∝ s³`, `K_s ∝ s⁴`, `K_ν̇ ∝ s`,
//! `K_ν̈ ∝ s²`). A hover has nothing to scale.

use controller_core::{Trajectory, TrajectoryConstants};
use serde::Serialize;

use crate::model::scenario::{HeadingConfig, InitialConfig, TrajectoryConfig};

/// A reference: trajectory and initial state (scenario syntax).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reference {
    /// `[trajectory]`.
    pub trajectory: TrajectoryConfig,
    /// `[initial]`.
    pub initial: InitialConfig,
}

impl Reference {
    /// The Assumption 1 constants of the trajectory.
    pub fn constants(&self) -> TrajectoryConstants<f64> {
        self.scenario_trajectory().constants()
    }

    fn scenario_trajectory(&self) -> controller_core::ReferenceTrajectory<f64> {
        let mut s = crate::model::scenario::Scenario::paper();
        s.trajectory = self.trajectory.clone();
        s.trajectory::<f64>()
    }

    /// The reference position and heading at `t = 0` (`p_d(0)` \[m\], `ψ_d(0)` \[rad\]).
    pub fn start(&self) -> ([f64; 3], f64) {
        let r = self.scenario_trajectory().sample(0.0);
        (r.position.into(), r.heading.y.atan2(r.heading.x))
    }

    /// The same shape with time scaled by `s` (frequencies times `s`).
    pub fn scaled(&self, s: f64) -> Self {
        let mut trajectory = self.trajectory.clone();
        let heading = match &mut trajectory {
            TrajectoryConfig::Hover { heading, .. } => heading,
            TrajectoryConfig::Helix {
                frequency_rad_s,
                heading,
                ..
            }
            | TrajectoryConfig::FigureEight {
                frequency_rad_s,
                heading,
                ..
            } => {
                *frequency_rad_s *= s;
                heading
            }
        };
        if let HeadingConfig::Sinusoidal {
            frequency_rad_s, ..
        } = heading
        {
            *frequency_rad_s *= s;
        }
        Self {
            trajectory,
            initial: self.initial.clone(),
        }
    }

    /// The same path with the heading held at `ψ_d(0)` \[rad\]: `design`'s first fallback when
    /// no design converges with the requested heading's swing (its rate multiplies the tilt rate
    /// in `ω̇_d`, docs/design.md). `None` when the heading is already constant: nothing to hold.
    pub fn heading_held(&self) -> Option<Self> {
        let (_, yaw) = self.start();
        let mut trajectory = self.trajectory.clone();
        let heading = match &mut trajectory {
            TrajectoryConfig::Hover { heading, .. }
            | TrajectoryConfig::Helix { heading, .. }
            | TrajectoryConfig::FigureEight { heading, .. } => heading,
        };
        if matches!(heading, HeadingConfig::Constant { .. }) {
            return None;
        }
        *heading = HeadingConfig::Constant { yaw_rad: yaw };
        Some(Self {
            trajectory,
            initial: self.initial.clone(),
        })
    }

    /// A hover at `p_d(0)` with the heading `ψ_d(0)`: the reference of the upside-down test.
    pub fn hover_at_start(&self) -> TrajectoryConfig {
        let (p, yaw) = self.start();
        TrajectoryConfig::Hover {
            point_m: p,
            heading: HeadingConfig::Constant { yaw_rad: yaw },
        }
    }
}

/// Largest `s ∈ (0, 1]` for which `certifiable(reference.scaled(s))` holds (bisection, 30
/// steps; `certifiable` must be monotone in `s`, as it is when the constants shrink with `s`).
/// `None` when not even `s = 2⁻³⁰` is certifiable.
pub fn largest_certifiable_scale(
    reference: &Reference,
    certifiable: impl Fn(&Reference) -> bool,
) -> Option<f64> {
    if certifiable(reference) {
        return Some(1.0);
    }
    let tiny = 2f64.powi(-30);
    if !certifiable(&reference.scaled(tiny)) {
        return None;
    }
    Some(super::bisect::bisect(tiny, 1.0, 30, |s| {
        certifiable(&reference.scaled(s))
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scenario::Scenario;

    /// The paper's helix and initial state, the default requested reference.
    fn paper() -> Reference {
        let s = Scenario::paper();
        Reference {
            trajectory: s.trajectory,
            initial: s.initial,
        }
    }

    /// Scaling time by `s` scales the constants by the powers of `s` the derivatives carry.
    #[test]
    fn scaling_scales_the_constants() {
        let r = paper();
        let (a, b) = (r.constants(), r.scaled(0.5).constants());
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(1e-12);
        assert!(close(
            b.horizontal_acceleration,
            a.horizontal_acceleration * 0.25
        ));
        assert!(close(b.jerk, a.jerk * 0.125));
        assert!(close(b.snap, a.snap * 0.0625));
        assert!(close(b.heading_rate, a.heading_rate * 0.5));
    }

    /// Holding the heading keeps the path (its start and every position constant) and its
    /// start heading, and leaves no heading rate; a constant heading has nothing to hold.
    #[test]
    fn holding_the_heading_keeps_the_path() {
        let r = paper();
        let held = r.heading_held().expect("the paper's heading swings");
        let (a, b) = (r.constants(), held.constants());
        assert!(
            a.heading_rate > 0.1 && a.heading_acceleration > 0.01,
            "{a:?}"
        );
        assert_eq!((b.heading_rate, b.heading_acceleration), (0.0, 0.0));
        assert_eq!(b.horizontal_acceleration, a.horizontal_acceleration);
        assert_eq!(b.vertical_acceleration, a.vertical_acceleration);
        assert_eq!(b.jerk, a.jerk);
        assert_eq!(b.snap, a.snap);
        assert_eq!(held.start(), r.start());
        assert_eq!(held.initial, r.initial);
        assert!(held.heading_held().is_none());
    }

    #[test]
    fn bisection_finds_the_threshold() {
        let r = paper();
        let limit = r.constants().heading_rate * 0.3;
        let scale = largest_certifiable_scale(&r, |x| x.constants().heading_rate <= limit).unwrap();
        assert!((scale - 0.3).abs() < 1e-6, "{scale}");
    }
}
