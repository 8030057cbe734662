//! Flying the uploaded mission: the start (`MAV_CMD_MISSION_START` or custom mode 5 with a
//! stored mission), the reference along the plan's path on each tick, the items reached, and
//! the end (land, or hover at the last stop).
//!
//! The path's clock runs with the ticks, except that the reference waits at a stop after its
//! hold until the estimate is within the stop's acceptance radius: `MISSION_ITEM_REACHED` is
//! sent then, and `MISSION_CURRENT` names the next item. Waiting changes no certified constant
//! (the reference is at rest at a stop, every derivative zero; [`controller_core::waypoint_path`]).

use controller_core::{ReferenceSample, Trajectory};
use nalgebra::Vector3;

use super::commands::Refusal;
use super::{FlightPipeline, Mode};
use crate::estimator::micros_f32;
use crate::flight_reference::ReferenceMode;
use crate::link::Command;
use crate::mission::{plan, MissionReply, Plan};

/// A mission being flown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MissionRun {
    plan: Plan,
    /// Sequence number of the first item flown (the plan's stop 0).
    first_seq: u16,
    /// Path time \[s\].
    time: f32,
    last_us: u64,
    /// The stop being approached or held.
    next: usize,
    /// Whether stop `next` has been reached.
    reached: bool,
}

/// What the tick found at the end of the path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum MissionEnd {
    /// The mission goes on.
    Flying,
    /// Every stop reached: land (the last item is a land) or hover.
    Done {
        /// Land now.
        land: bool,
    },
}

impl FlightPipeline {
    /// Starts the stored mission from item `mission_current` at `now_us` (armed; on the ground
    /// only if its first item is a takeoff): plans it from where the reference is, passes the
    /// certificate gate and the controller ([`FlightPipeline::accept`]), then flies it.
    pub(super) fn start_mission(&mut self, now_us: u64) -> Result<(), Refusal> {
        if !self.armed() {
            return Err(Self::simple("not armed"));
        }
        let first = usize::from(self.mission_current).min(self.mission_items.len());
        let items = &self.mission_items[first..];
        if items.is_empty() {
            return Err(Self::simple("no mission"));
        }
        if self.mission.mode() == Mode::Idle
            && items[0].command != mavlink::dialects::common::MavCmd::MAV_CMD_NAV_TAKEOFF
        {
            return Err(Self::simple(
                "on the ground: mission must begin with a takeoff",
            ));
        }
        let (start, yaw) = self.mission_start_point(now_us);
        let plan = plan(items, start, yaw, &self.cfg.reference, &self.global_frame())
            .map_err(|e| Self::simple(e.reason))?;
        let k = plan.path.constants();
        self.accept(&k, self.filter_start())?;
        self.mission_run = Some(MissionRun {
            plan,
            first_seq: first as u16,
            time: 0.0,
            last_us: now_us,
            next: 0,
            reached: false,
        });
        self.reference.fly_waypoints();
        self.set_mode(Mode::Mission);
        self.mission_reply(MissionReply::Current { seq: first as u16 });
        Ok(())
    }

    /// The mission's reference at `now_us` for the estimated `position` (NWU \[m\]), advancing
    /// its clock and its items; with what the path's end asks for.
    ///
    /// Out of line: called only while a mission is flown.
    #[inline(never)]
    pub(super) fn mission_sample(
        &mut self,
        now_us: u64,
        position: &Vector3<f32>,
    ) -> (ReferenceSample<f32>, MissionEnd) {
        let Some(run) = self.mission_run.as_mut() else {
            return (
                self.reference.sample(now_us),
                MissionEnd::Done { land: false },
            );
        };
        let dt = micros_f32(now_us.saturating_sub(run.last_us)) * 1e-6;
        run.last_us = now_us;
        run.time += dt;
        let path = &run.plan.path;
        let mut reached = None;
        let mut current = None;
        let mut end = MissionEnd::Flying;
        match (
            path.arrival(run.next),
            path.departure(run.next),
            path.stop(run.next),
        ) {
            (Some(arrival), Some(departure), Some((stop, _))) => {
                let seq = run.first_seq + run.plan.seqs[run.next];
                if !run.reached
                    && run.time >= arrival
                    && (position - stop).norm() <= run.plan.radius[run.next]
                {
                    run.reached = true;
                    reached = Some(seq);
                }
                if !run.reached && run.time > departure {
                    run.time = departure; // wait at rest at the stop
                }
                if run.reached && run.time >= departure {
                    run.next += 1;
                    run.reached = false;
                    if run.next < path.len() {
                        current = Some(seq + 1);
                    }
                }
            }
            _ => {
                end = MissionEnd::Done {
                    land: run.plan.land_at_end,
                }
            }
        }
        let sample = path.sample(run.time);
        if let Some(seq) = reached {
            self.mission_reply(MissionReply::Reached { seq });
            self.event(super::Event::MissionItemReached { seq });
        }
        if let Some(seq) = current {
            self.mission_current = seq;
            self.mission_reply(MissionReply::Current { seq });
        }
        (sample, end)
    }

    /// The mission's end at `now_us`: land there (the land mode's certified descent), or
    /// hover at the last stop; the mission is no longer flown.
    #[inline(never)]
    pub(super) fn end_mission(&mut self, land: bool, last: &ReferenceSample<f32>, now_us: u64) {
        self.mission_run = None;
        self.reference.hold_at(last.position, last.yaw());
        self.set_mode(Mode::Hover);
        if land {
            if let Err(r) = self.run_command(Command::Land, now_us) {
                self.mission_text(format_args!("mission land refused: {}", r.reason()));
            }
        }
    }

    /// Leaves the mission (another reference takes over): the setpoint filter restarts at rest
    /// at the mission's reference now. Nothing when the mission is not what is flown (a run
    /// left behind by a failsafe or a disarm is only dropped: the reference built at arming
    /// stands).
    pub(super) fn leave_mission(&mut self) {
        let Some(run) = self.mission_run.take() else {
            return;
        };
        if self.reference.mode() == ReferenceMode::Waypoints {
            let s = run.plan.path.sample(run.time);
            self.reference.hold_at(s.position, s.yaw());
        }
    }
}
