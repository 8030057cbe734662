//! The fixture pipeline: the flight pipeline and the controller as the firmware builds them,
//! one full step and one controller step (never inlined, so every caller measures the same
//! code), their compared outputs, and the whole sequence run on this machine.

use controller_core::{
    ControlOutput, Controller, ReferenceTrajectory, StepError, Trajectory, VehicleState,
};
use nalgebra::Vector3;

use super::truth::{helix_reference, truth};
use super::{
    ControllerInputs, ControllerOutputs, FullOutputs, Phase, StepInputs, StepSequence, ARM_TICK,
    ARM_US, CONTROLLER_DT, TICK_US,
};
use crate::config::FlightConfig;
use crate::pipeline::{FlightPipeline, MotorOutput};
use crate::safety::FlightState;

/// The flight pipeline of the paper vehicle, as the firmware boots it, allowed to arm although
/// the paper's set-up is not certified (its Theorem 2 yaw condition fails and its box does not
/// fit): the bench measures the paper's control step, not the gate.
/// Panics if `FlightConfig::paper()` is refused (it is not; a test checks).
pub fn new_pipeline() -> FlightPipeline {
    let config = FlightConfig {
        allow_uncertified: true,
        ..FlightConfig::paper()
    };
    match FlightPipeline::new(&config) {
        Ok(p) => p,
        Err(_) => panic!("FlightConfig::paper() refused"),
    }
}

/// One full control step as the firmware's control task runs it: the tick's IMU samples, its
/// link bytes, then `control_tick`. Never inlined, so that every caller (MCU bench, host bench,
/// host comparison) runs the same code between its measurement brackets.
#[inline(never)]
pub fn full_step(pipeline: &mut FlightPipeline, inputs: &StepInputs) -> MotorOutput {
    for s in inputs.imu.iter() {
        pipeline.on_imu(s);
    }
    pipeline.on_link_bytes(&inputs.link[..inputs.link_len], inputs.now_us);
    pipeline.control_tick(inputs.now_us)
}

/// The compared figures of a full step (see [`FullOutputs`]), read after it.
pub fn full_outputs(pipeline: &FlightPipeline, out: &MotorOutput) -> FullOutputs {
    let (thrust, torque) = pipeline.last_mix().map_or((0.0, Vector3::zeros()), |m| {
        (m.achieved_thrust, m.achieved_torque)
    });
    [
        out.throttle[0],
        out.throttle[1],
        out.throttle[2],
        out.throttle[3],
        thrust,
        torque.x,
        torque.y,
        torque.z,
    ]
}

/// True when the last step ran the real flight path: armed, flying the helix, the controller
/// and the mixer ran (not an idle or failsafe early return).
pub fn on_flight_path(pipeline: &FlightPipeline) -> bool {
    let s = pipeline.status();
    s.state == FlightState::Armed
        && s.mode == crate::pipeline::Mode::Helix
        && pipeline.last_mix().is_some()
        && s.counters.non_finite == 0
}

/// The inputs of the `k`-th controller step (`k = 1..=FLIGHT_TICKS`): the scripted state
/// (exact, no estimator) and the helix reference at flight time `k · 10 ms`.
pub fn controller_inputs(k: u32) -> ControllerInputs {
    let x = truth(ARM_US + u64::from(k) * TICK_US);
    ControllerInputs {
        state: VehicleState {
            position: x.position,
            velocity: x.velocity,
            attitude: x.attitude,
            angular_velocity: x.angular_velocity,
        },
        reference: helix_reference(k as f32 * CONTROLLER_DT),
        dt: CONTROLLER_DT,
    }
}

/// The paper's controller (vehicle, Table I gains) for the helix, filters at zero.
/// Panics if the paper parameters are refused (they are not; a test checks).
pub fn new_controller() -> Controller<f32> {
    let c = FlightConfig::paper();
    let k = ReferenceTrajectory::<f32>::paper_helix().constants();
    match Controller::new(c.vehicle, c.gains, &k) {
        Ok(ctl) => ctl,
        Err(_) => panic!("paper controller refused"),
    }
}

/// One controller step (`Controller::step`), never inlined (see [`full_step`]).
/// Errors: [`StepError`] as `Controller::step`.
#[inline(never)]
pub fn controller_step(
    controller: &mut Controller<f32>,
    inputs: &ControllerInputs,
) -> Result<ControlOutput<f32>, StepError> {
    controller.step(&inputs.state, &inputs.reference, inputs.dt)
}

/// The compared figures of a controller step (see [`ControllerOutputs`]); NaN for an error.
pub fn controller_outputs(out: &Result<ControlOutput<f32>, StepError>) -> ControllerOutputs {
    match out {
        Ok(o) => [o.thrust, o.torque.x, o.torque.y, o.torque.z],
        Err(_) => [f32::NAN; 4],
    }
}

/// One comparable record of the sequence, as the MCU bench prints it and the host recomputes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Record {
    /// The arming tick (tick number, outputs).
    Arm(u32, FullOutputs),
    /// A flight tick's full step (flight tick `1..=FLIGHT_TICKS`, outputs).
    Full(u32, FullOutputs),
    /// A controller step (flight tick, outputs).
    Controller(u32, ControllerOutputs),
}

/// Runs the whole sequence on this machine, calling `record` for every arming, full and
/// controller step, in the order the MCU bench brackets them (per flight tick: the full step,
/// then the controller step). Returns false if some flight step left the flight path
/// (see [`on_flight_path`]).
pub fn run_sequence(mut record: impl FnMut(Record)) -> bool {
    let mut pipeline = new_pipeline();
    let mut controller = new_controller();
    let mut ok = true;
    for inputs in StepSequence::new() {
        let out = full_step(&mut pipeline, &inputs);
        match inputs.phase {
            Phase::Setup => {}
            Phase::Arm => record(Record::Arm(inputs.tick, full_outputs(&pipeline, &out))),
            Phase::Flight => {
                let k = inputs.tick - ARM_TICK;
                ok &= on_flight_path(&pipeline);
                record(Record::Full(k, full_outputs(&pipeline, &out)));
                let c = controller_inputs(k);
                let r = controller_step(&mut controller, &c);
                record(Record::Controller(k, controller_outputs(&r)));
            }
        }
    }
    ok
}

#[cfg(test)]
mod tests {
    use super::super::FLIGHT_TICKS;
    use super::*;

    /// The sequence calibrates, arms upside down into the helix, and every flight tick runs the
    /// controller and the mixer; every controller step succeeds; outputs are finite.
    #[test]
    fn sequence_exercises_the_flight_path() {
        let mut flights = 0;
        let mut controllers = 0;
        let ok = run_sequence(|r| match r {
            Record::Arm(_, o) => assert!(o.iter().all(|x| x.is_finite())),
            Record::Full(_, o) => {
                flights += 1;
                assert!(o.iter().all(|x| x.is_finite()));
                assert!(o[4] > 0.0, "thrust {o:?}");
            }
            Record::Controller(_, o) => {
                controllers += 1;
                assert!(o.iter().all(|x| x.is_finite()), "{o:?}");
            }
        });
        assert!(ok);
        assert_eq!(flights, FLIGHT_TICKS);
        assert_eq!(controllers, FLIGHT_TICKS);
    }
}
