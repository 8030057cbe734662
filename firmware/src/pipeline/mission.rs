//! The reference mode machine: idle on the ground, takeoff, hover, helix, land. A pure type
//! ([`ModeMachine`]): the pipeline feeds it the flight state and the estimate and applies what
//! it answers (targets, mode changes); the certificate gate between a request and the mode
//! change stays with the pipeline ([`super::commands`]).
//!
//! Transitions: arming → idle (latching the ground height); idle or hover → takeoff (takeoff
//! command); takeoff → hover once within reach of the target ([`ModeMachine::tick`]); flying →
//! land (land command), → hover (setpoint, not while landing); armed → helix (helix command);
//! disarming (landed, kill, failsafe end) → idle. The failsafe keeps the mode (it is a flight
//! state, not a reference mode).
//!
//! Heights are measured from the ground height latched at arming (`ground_z`, NWU z \[m\]).

use nalgebra::Vector3;

use crate::config::ReferenceConfig;
use crate::safety::FlightState;

/// What the reference is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Armed on the ground at idle throttle, or disarmed.
    Idle,
    /// Hovering at / moving to a setpoint.
    Hover,
    /// Taking off to a height.
    Takeoff,
    /// Landing.
    Land,
    /// The paper's helix.
    Helix,
    /// An uploaded mission ([`crate::mission`]).
    Mission,
}

impl Mode {
    /// Name for logs.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Idle => "idle",
            Self::Hover => "hover",
            Self::Takeoff => "takeoff",
            Self::Land => "land",
            Self::Helix => "helix",
            Self::Mission => "mission",
        }
    }
}

/// The mode machine's state: the mode and the ground height latched at arming.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeMachine {
    mode: Mode,
    ground_z: f32,
}

impl Default for ModeMachine {
    fn default() -> Self {
        Self::new()
    }
}

impl ModeMachine {
    /// Idle, ground at `z = 0`.
    pub const fn new() -> Self {
        Self {
            mode: Mode::Idle,
            ground_z: 0.0,
        }
    }

    /// The mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Ground height \[m\] (NWU z of the arming point).
    pub fn ground_z(&self) -> f32 {
        self.ground_z
    }

    /// Whether the controller flies: armed and not idle on the ground.
    pub fn flying(&self, state: FlightState) -> bool {
        state == FlightState::Armed && self.mode != Mode::Idle
    }

    /// Switches to `mode`; returns it if it is a change (for the mode-change event).
    pub fn enter(&mut self, mode: Mode) -> Option<Mode> {
        if self.mode != mode {
            self.mode = mode;
            Some(mode)
        } else {
            None
        }
    }

    /// Armed at ground height `ground_z` \[m\] (NWU z): idle; later heights count from there.
    /// Returns the mode if it changed.
    pub fn armed(&mut self, ground_z: f32) -> Option<Mode> {
        self.ground_z = ground_z;
        self.enter(Mode::Idle)
    }

    /// Takeoff target (NWU \[m\]): straight above `position` (the estimate, `None` without one)
    /// at `height` \[m\] (the configured default if `None`) above the ground. Refused (reason)
    /// unless armed and idle or hovering, with an estimate and a height in
    /// `(0, takeoff_height_max)`, checked in that order.
    pub fn takeoff_target(
        &self,
        cfg: &ReferenceConfig,
        state: FlightState,
        position: Option<Vector3<f32>>,
        height: Option<f32>,
    ) -> Result<Vector3<f32>, &'static str> {
        if state != FlightState::Armed {
            return Err("not armed");
        }
        if !matches!(self.mode, Mode::Idle | Mode::Hover) {
            return Err("busy");
        }
        let p = position.ok_or("no estimate")?;
        let h = height.unwrap_or(cfg.takeoff_height);
        if !(h.is_finite() && h > 0.0 && h < cfg.takeoff_height_max) {
            return Err("bad takeoff height");
        }
        Ok(Vector3::new(p.x, p.y, self.ground_z + h))
    }

    /// Land target (NWU \[m\]): straight below `position` (the estimate, `None` without one),
    /// `land_undershoot` below the ground so that the vehicle settles on it. Refused (reason)
    /// unless flying, with an estimate.
    pub fn land_target(
        &self,
        cfg: &ReferenceConfig,
        state: FlightState,
        position: Option<Vector3<f32>>,
    ) -> Result<Vector3<f32>, &'static str> {
        if !self.flying(state) {
            return Err("not flying");
        }
        let p = position.ok_or("no estimate")?;
        Ok(Vector3::new(p.x, p.y, self.ground_z - cfg.land_undershoot))
    }

    /// Whether a hover setpoint may be flown now: only when flying and not landing (a landing
    /// is finished, or aborted with a takeoff after it lands).
    pub fn setpoint_allowed(&self, state: FlightState) -> Result<(), &'static str> {
        if !self.flying(state) {
            return Err("not flying (take off first)");
        }
        if self.mode == Mode::Land {
            return Err("landing");
        }
        Ok(())
    }

    /// One tick of the controller: a takeoff ends (hover) once the estimated `position` is
    /// within `takeoff_reached_distance` of the setpoint filter's `target` (NWU \[m\]). Returns
    /// the new mode if it changed.
    #[inline]
    pub fn tick(
        &mut self,
        cfg: &ReferenceConfig,
        position: &Vector3<f32>,
        target: &Vector3<f32>,
    ) -> Option<Mode> {
        if self.mode == Mode::Takeoff && (position - target).norm() < cfg.takeoff_reached_distance {
            return self.enter(Mode::Hover);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::FlightConfig;

    const ARMED: FlightState = FlightState::Armed;

    fn cfg() -> ReferenceConfig {
        FlightConfig::paper().reference
    }

    /// Armed at ground height 2 m, idle.
    fn armed_at_2m() -> ModeMachine {
        let mut m = ModeMachine::new();
        assert_eq!(m.armed(2.0), None, "armed from idle: no change");
        m
    }

    #[test]
    fn given_disarmed_when_takeoff_or_land_requested_then_refused() {
        let m = ModeMachine::new();
        let p = Some(Vector3::new(1.0, 2.0, 0.0));
        for state in [FlightState::Disarmed, FlightState::Failsafe] {
            assert_eq!(m.takeoff_target(&cfg(), state, p, None), Err("not armed"));
            assert_eq!(m.land_target(&cfg(), state, p), Err("not flying"));
            assert_eq!(
                m.setpoint_allowed(state),
                Err("not flying (take off first)")
            );
        }
    }

    #[test]
    fn given_armed_idle_when_takeoff_then_target_above_arming_ground() {
        let m = armed_at_2m();
        // The estimate drifted up 0.3 m since arming: the height counts from the ground.
        let p = Some(Vector3::new(1.0, -1.0, 2.3));
        let default = m.takeoff_target(&cfg(), ARMED, p, None).unwrap();
        assert_eq!(default, Vector3::new(1.0, -1.0, 2.0 + cfg().takeoff_height));
        let asked = m.takeoff_target(&cfg(), ARMED, p, Some(0.5)).unwrap();
        assert_eq!(asked, Vector3::new(1.0, -1.0, 2.5));
    }

    #[test]
    fn given_armed_idle_when_takeoff_height_is_out_of_range_then_refused() {
        let m = armed_at_2m();
        let p = Some(Vector3::zeros());
        let max = cfg().takeoff_height_max;
        for h in [0.0, -1.0, max, f32::NAN, f32::INFINITY] {
            assert_eq!(
                m.takeoff_target(&cfg(), ARMED, p, Some(h)),
                Err("bad takeoff height"),
                "{h}"
            );
        }
        // Just inside the range is accepted.
        assert!(m
            .takeoff_target(&cfg(), ARMED, p, Some(max * 0.999))
            .is_ok());
        // The estimate is checked before the height.
        assert_eq!(
            m.takeoff_target(&cfg(), ARMED, None, Some(f32::NAN)),
            Err("no estimate")
        );
    }

    #[test]
    fn given_a_mission_running_when_takeoff_requested_then_busy() {
        for mode in [Mode::Takeoff, Mode::Land, Mode::Helix] {
            let mut m = armed_at_2m();
            assert_eq!(m.enter(mode), Some(mode));
            assert_eq!(
                m.takeoff_target(&cfg(), ARMED, Some(Vector3::zeros()), None),
                Err("busy"),
                "{mode:?}"
            );
        }
        // Hovering may take off again (to another height).
        let mut m = armed_at_2m();
        m.enter(Mode::Hover);
        assert!(m
            .takeoff_target(&cfg(), ARMED, Some(Vector3::zeros()), None)
            .is_ok());
    }

    #[test]
    fn given_taking_off_when_position_reaches_target_then_hover_at_exactly_the_threshold() {
        let c = cfg();
        let mut m = armed_at_2m();
        m.enter(Mode::Takeoff);
        // Target at the origin, so that the distance is exactly `d` (no rounding in p − t).
        let target = Vector3::zeros();
        let d = c.takeoff_reached_distance;
        // At exactly the distance: not yet (strictly within).
        assert_eq!(m.tick(&c, &Vector3::new(0.0, 0.0, -d), &target), None);
        assert_eq!(m.mode(), Mode::Takeoff);
        // Just inside: hover, reported once.
        let inside = Vector3::new(0.0, 0.0, -0.99 * d);
        assert_eq!(m.tick(&c, &inside, &target), Some(Mode::Hover));
        assert_eq!(m.mode(), Mode::Hover);
        assert_eq!(m.tick(&c, &inside, &target), None);
    }

    #[test]
    fn given_not_taking_off_when_position_reaches_target_then_mode_unchanged() {
        let c = cfg();
        for mode in [Mode::Idle, Mode::Hover, Mode::Land, Mode::Helix] {
            let mut m = armed_at_2m();
            m.enter(mode);
            let p = Vector3::new(0.0, 0.0, 3.0);
            assert_eq!(m.tick(&c, &p, &p), None);
            assert_eq!(m.mode(), mode);
        }
    }

    #[test]
    fn given_flying_when_land_then_target_undershoots_the_arming_ground() {
        let c = cfg();
        let mut m = armed_at_2m();
        // Idle on the ground is not flying.
        assert_eq!(
            m.land_target(&c, ARMED, Some(Vector3::zeros())),
            Err("not flying")
        );
        m.enter(Mode::Helix);
        assert_eq!(m.land_target(&c, ARMED, None), Err("no estimate"));
        let t = m
            .land_target(&c, ARMED, Some(Vector3::new(4.0, 5.0, 6.0)))
            .unwrap();
        assert_eq!(t, Vector3::new(4.0, 5.0, 2.0 - c.land_undershoot));
    }

    #[test]
    fn given_landing_when_setpoint_then_refused_and_hover_accepts_it() {
        let mut m = armed_at_2m();
        m.enter(Mode::Land);
        assert_eq!(m.setpoint_allowed(ARMED), Err("landing"));
        m.enter(Mode::Hover);
        assert_eq!(m.setpoint_allowed(ARMED), Ok(()));
    }

    #[test]
    fn given_flying_when_rearmed_then_idle_at_the_new_ground() {
        let mut m = armed_at_2m();
        m.enter(Mode::Helix);
        assert!(m.flying(ARMED));
        assert!(!m.flying(FlightState::Failsafe));
        assert_eq!(m.armed(-1.0), Some(Mode::Idle));
        assert!(!m.flying(ARMED));
        assert_eq!(m.ground_z(), -1.0);
    }
}
