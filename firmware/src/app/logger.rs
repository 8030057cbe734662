//! The log task (thread mode, lowest priority): pipeline events as they happen, step timing and
//! I/O counters at 1 Hz, a flight summary at 10 Hz, all as defmt.

use core::sync::atomic::Ordering;

use defmt::{error, info, warn};
use embassy_futures::select::{select3, Either3};

use super::queues::{Summary, EVENTS, IO, SUMMARY, TIMING};
use crate::pipeline::{Event, PipelineStatus};
use crate::timing::{self, WindowReport};

/// The log task; `core_hz` \[Hz\] converts the DWT cycle counts of the step to time.
#[embassy_executor::task]
pub async fn logger(core_hz: u32) {
    let mut last: Option<Summary> = None;
    loop {
        match select3(EVENTS.receive(), TIMING.wait(), SUMMARY.wait()).await {
            Either3::First(event) => log_event(&event),
            Either3::Second(w) => {
                log_timing(&w, core_hz);
                if let Some(s) = &last {
                    log_counters(&s.status);
                }
            }
            Either3::Third(s) => {
                log_summary(&s);
                last = Some(s);
            }
        }
    }
}

fn log_timing(w: &WindowReport, core_hz: u32) {
    let us = |c| timing::cycles_to_us(c, core_hz);
    info!(
        "timing: {=u32} steps, mean {=u32} cyc ({=f32} us), max {=u32} cyc ({=f32} us), \
         longest step {=u64} us, overruns {=u32} (total {=u32})",
        w.steps,
        w.mean_cycles,
        us(w.mean_cycles),
        w.max_cycles,
        us(w.max_cycles),
        w.max_step_us,
        w.overruns,
        w.total_overruns
    );
    info!(
        "io: imu reads {=u32} errors {=u32} queue-full {=u32}; link rx {=u32} B dropped \
         {=u32} B errors {=u32}; tx dropped {=u32}; events dropped {=u32}",
        IO.imu_reads.load(Ordering::Relaxed),
        IO.imu_errors.load(Ordering::Relaxed),
        IO.imu_queue_full.load(Ordering::Relaxed),
        IO.link_rx_bytes.load(Ordering::Relaxed),
        IO.link_rx_dropped.load(Ordering::Relaxed),
        IO.link_rx_errors.load(Ordering::Relaxed),
        IO.link_tx_dropped.load(Ordering::Relaxed),
        IO.events_dropped.load(Ordering::Relaxed)
    );
}

fn log_event(event: &Event) {
    match *event {
        Event::Calibrated { bias } => info!(
            "event: gyro calibrated, bias [{=f32}, {=f32}, {=f32}] rad/s",
            bias[0], bias[1], bias[2]
        ),
        Event::StateChanged { from, to, reason } => info!(
            "event: state {=str} -> {=str} ({=str})",
            from.name(),
            to.name(),
            reason
        ),
        Event::ModeChanged { mode } => info!("event: mode {=str}", mode.name()),
        Event::MissionItemReached { seq } => info!("event: mission item {=u16} reached", seq),
        Event::CommandAccepted { command } => info!("event: command {=str} accepted", command),
        Event::CommandRefused { command, reason } => {
            warn!("event: command {=str} refused: {=str}", command, reason)
        }
        Event::ReferenceRefused {
            condition,
            lhs,
            rhs,
        } => warn!(
            "event: reference refused: {=str} (lhs = {=f32}, rhs = {=f32})",
            condition, lhs, rhs
        ),
        Event::Uncertified {
            condition,
            lhs,
            rhs,
        } => error!(
            "event: UNCERTIFIED set-up accepted (uncertified-paper build): {=str} fails \
             (lhs = {=f32}, rhs = {=f32}); the a-priori bounds are NOT guaranteed",
            condition, lhs, rhs
        ),
        Event::ParamChanged { name, value } => {
            info!("event: parameter {=str} = {=f32} (certified)", name, value)
        }
        Event::ParamsReset => info!("event: parameters reset to the flight file"),
        Event::NonFinite { source } => warn!("event: non-finite value in {=str}", source),
    }
}

fn log_summary(s: &Summary) {
    let st = &s.status;
    let pose_age_ms = if st.pose_age_us == u64::MAX {
        -1.0
    } else {
        st.pose_age_us as f32 * 1e-3
    };
    info!(
        "flight t={=u64} ms {=str}/{=str} cal={=bool} conv={=bool} pose_age={=f32} ms \
         p=[{=f32}, {=f32}, {=f32}] p_d=[{=f32}, {=f32}, {=f32}] |e|={=f32} m \
         T={=f32} N tau=[{=f32}, {=f32}, {=f32}] throttle=[{=f32}, {=f32}, {=f32}, {=f32}] \
         eta=[{=f32}, {=f32}, {=f32}] m/s^2 mu={=f32} armed={=bool}",
        s.now_us / 1000,
        st.state.name(),
        st.mode.name(),
        st.calibrating,
        st.converged,
        pose_age_ms,
        st.position[0],
        st.position[1],
        st.position[2],
        st.reference_position[0],
        st.reference_position[1],
        st.reference_position[2],
        st.position_error,
        st.thrust,
        st.torque[0],
        st.torque[1],
        st.torque[2],
        s.output.throttle[0],
        s.output.throttle[1],
        s.output.throttle[2],
        s.output.throttle[3],
        st.integral[0],
        st.integral[1],
        st.integral[2],
        st.feedforward_scale,
        s.output.armed
    );
}

fn log_counters(st: &PipelineStatus) {
    let c = &st.counters;
    info!(
        "link: frames ok {=u32} dropped {=u32} malformed {=u32}, bytes discarded {=u32}; \
         telemetry dropped {=u32}",
        c.link.frames_ok,
        c.link.frames_dropped,
        c.link.frames_malformed,
        c.link.bytes_discarded,
        c.telemetry_dropped
    );
    info!(
        "pipeline: ticks {=u32} imu {=u32} poses {=u32} non-finite {=u32} refused {=u32} \
         mixer-saturated {=u32} events dropped {=u32}",
        c.control_ticks,
        c.imu_samples,
        c.poses_used,
        c.non_finite,
        c.refused_commands,
        c.mixer_saturations,
        c.events_dropped
    );
}
