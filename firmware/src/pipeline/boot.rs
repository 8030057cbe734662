//! Boot: the set-up's checks (the demo mission's certificate, the hover controller, the
//! a-priori box against the rotors and the gate) and the pipeline built from a configuration.
//! Every accepted parameter change runs the same checks ([`certify_setup`]).

use controller_core::{
    certify, Certificate, Controller, FilterStart, ParameterError, TrajectoryConstants,
};
use heapless::Deque;
use nalgebra::{UnitQuaternion, Vector3};

use super::events::Counters;
use super::landed::LandedDetector;
use super::mission::ModeMachine;
use super::param_queue::ParamQueue;
use super::schedule::Schedule;
use super::{gate, mahony_dt_cap, storage, FlightPipeline, GateFailure, MotorOutput};
use crate::config::FlightConfig;
use crate::estimator::{Estimator, EstimatorConfig};
use crate::flight_reference::{FlightReference, SupTable};
use crate::imu_attitude::Mahony;
use crate::link::{Decoder, SigningConfig};
use crate::mixer::{BoxFit, Mixer, MixerError};
use crate::safety::Supervisor;

/// Why the pipeline cannot be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BootError {
    /// A vehicle, limit, gain or reference parameter is refused (see
    /// [`crate::report::refusal`] to flatten it for logs).
    Parameter(ParameterError),
    /// The rotor geometry or range is unusable.
    Mixer(MixerError),
    /// The HIL motor order ([`FlightConfig::hil_motor_order`]) needs one rotor per quadrant.
    MotorOrder(crate::motor_order::NotAQuadX),
}

/// What the board logs at boot: the certificate of the demo mission (the configured trajectory,
/// filters starting at zero), whether its a-priori `(T, τ)` box fits inside the rotors and by
/// how much, and the gate's verdict (arming needs it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BootReport {
    /// The a-priori bound certificate for the demo mission.
    pub certificate: Certificate<f32>,
    /// The certified box `[T_lo, T_hi] × Π[−τ_i, τ_i]` against the rotors (`[T_lo, T_hi]` the
    /// configured thrust's interval, [`crate::config::ThrustChoice::interval`]).
    pub a_priori_fit: BoxFit,
    /// The smallest headroom of the gate's rotor fits, a fraction of the rotor range (the
    /// certified set's, [`crate::mixer::Mixer::set_margin`], without airmode or a local regime;
    /// [`gate::fit_margin`]; negative: one does not fit; NaN: the thrust interval is refused).
    pub fit_margin: f32,
    /// Each rotor fit the gate checks, with its margin, in the gate's order
    /// ([`gate::rotor_fits`]); `None` when the thrust interval is refused (the gate says why).
    pub fits: Option<gate::RotorFits>,
    /// The margin the configuration requires ([`FlightConfig::box_margin`]).
    pub required_margin: f32,
    /// The gate on this set-up: `Ok(margin)` when every condition holds and every rotor fit
    /// leaves the required margin (`margin` the smallest, [`BootReport::fit_margin`]), else the
    /// first failure. Arming is refused on `Err` unless [`FlightConfig::allow_uncertified`].
    pub gate: Result<f32, GateFailure>,
    /// Whether airmode flies ([`FlightConfig::airmode`]).
    pub airmode: bool,
    /// With airmode, the headroom it keeps above the rotors' least thrust
    /// ([`FlightConfig::airmode_low_margin`]; the top keeps [`BootReport::required_margin`]).
    pub airmode_low_margin: f32,
    /// With airmode: the headroom of the feedforward at zero attitude error over Theorem 1's
    /// interval, a fraction of the rotor range ([`gate::aligned_margin`]; at least
    /// [`BootReport::required_margin`]: airmode's convergence is proven, else shown by
    /// simulation only); `None` without airmode.
    pub aligned_margin: Option<f32>,
    /// Total rotor thrust capacity `4 f_max` \[N\] (vs the configured `T_max`).
    pub thrust_capacity: f32,
    /// The thrust the set-up flies (its interval is the box's thrust side).
    pub thrust: crate::config::ThrustChoice,
}

/// The boot checks of set-up `cfg` on the rotors of `mixer`: the certificate of its demo mission
/// (filters starting at zero), the hover controller (constants zero) and the gate with
/// `cfg.box_margin`. Boot and every parameter change run this one function. Errors: a
/// parameter controller-core refuses.
pub(super) fn certify_setup(
    cfg: &FlightConfig,
    mixer: &Mixer,
) -> Result<BootReport, ParameterError> {
    let reference = FlightReference::new(
        cfg.reference.smoothing_rate,
        Vector3::zeros(),
        0.0,
        SupTable::PRECOMPUTED,
        cfg.mission,
    );
    let certificate = certify(
        &cfg.vehicle,
        &cfg.limits,
        &cfg.gains,
        &reference.helix_constants(),
        FilterStart::Zero,
    )?;
    // The controller must accept a hover (constants zero) too.
    Controller::new(cfg.vehicle, cfg.gains, &TrajectoryConstants::zero())?;
    let b = &certificate.bounds;
    // A refused floor shows as the gate's failure; the fit is then reported for T_min's box.
    let (lo, hi) =
        gate::thrust_interval(&certificate, &cfg.thrust).unwrap_or((b.thrust_min, b.thrust_max));
    Ok(BootReport {
        certificate,
        a_priori_fit: mixer.box_fit(lo, hi, &b.torque_max),
        fit_margin: gate::fit_margin(&certificate, cfg, mixer),
        fits: gate::rotor_fits(&certificate, cfg, mixer).ok(),
        required_margin: cfg.box_margin,
        gate: gate::check(&certificate, cfg, mixer),
        airmode: cfg.airmode,
        airmode_low_margin: cfg.airmode_low_margin,
        aligned_margin: gate::aligned_margin(&certificate, cfg, mixer),
        thrust_capacity: 4.0 * cfg.rotors.thrust_max,
        thrust: cfg.thrust,
    })
}

impl FlightPipeline {
    /// Builds the pipeline: certifies the demo mission, builds the mixer and checks the a-priori
    /// box against the rotors. Errors: [`BootError`].
    pub fn new(config: &FlightConfig) -> Result<Self, BootError> {
        let cfg = *config;
        let mixer = Mixer::new(&cfg.rotors).map_err(BootError::Mixer)?;
        let motor_slots = cfg
            .hil_motor_order
            .slots(&cfg.rotors.rotors)
            .map_err(BootError::MotorOrder)?;
        // Checked in every build (a flight build refuses what its PIL twin would), used with HIL.
        #[cfg(not(feature = "hil"))]
        let _ = motor_slots;
        let table = SupTable::PRECOMPUTED;
        let reference = FlightReference::new(
            cfg.reference.smoothing_rate,
            Vector3::zeros(),
            0.0,
            table,
            cfg.mission,
        );
        let report = certify_setup(&cfg, &mixer).map_err(BootError::Parameter)?;
        let estimator = Estimator::new(EstimatorConfig {
            latency_us: cfg.mocap_latency_us,
            calibration_samples: cfg.gyro_calibration_samples,
            position_sigma: cfg.mocap_position_sigma,
            accel_psd: cfg.velocity_filter_accel_psd,
            gravity: cfg.vehicle.gravity,
        });
        Ok(Self {
            cfg,
            built: cfg,
            mixer,
            report,
            table,
            estimator,
            mahony: Mahony::new(
                cfg.mahony_gains[0],
                cfg.mahony_gains[1],
                cfg.vehicle.gravity,
            ),
            decoder: Decoder::with_address(
                cfg.system_id,
                cfg.component_id,
                cfg.signing_key.map(|key| SigningConfig {
                    key,
                    link_id: 0,
                    accept_unsigned_sensors: cfg.accept_unsigned_sensors,
                }),
            )
            .with_trust(cfg.link_trust),
            supervisor: Supervisor::new(cfg.safety),
            controller: None,
            reference,
            mission: ModeMachine::new(),
            last_tick_us: None,
            pending_non_finite: false,
            landed: LandedDetector::new(cfg.landed, &cfg.vehicle, cfg.control_rate),
            last_mix: None,
            last_output: MotorOutput::STOPPED,
            failsafe_thrust: 0.0,
            events: Deque::new(),
            acks: Deque::new(),
            texts: Deque::new(),
            params: ParamQueue::new(),
            sequence: 0,
            schedule: Schedule::new(&cfg.telemetry),
            timesync: Deque::new(),
            home: Vector3::zeros(),
            load_permille: 0,
            counters: Counters::default(),
            status_position: [0.0; 3],
            status_velocity: [0.0; 3],
            status_attitude: UnitQuaternion::identity(),
            status_rates: [0.0; 3],
            status_reference: [0.0; 3],
            #[cfg(feature = "hil")]
            motor_slots,
            status_reference_motion: ([0.0; 3], [0.0; 3], [1.0, 0.0], [0.0; 2]),
            status_error: 0.0,
            status_pose_age: u64::MAX,
            was_calibrating: true,
            storage: storage::StorageHold::default(),
            mahony_dt_cap: mahony_dt_cap(&cfg),
            #[cfg(feature = "hil")]
            hil_time_us: None,
            #[cfg(feature = "hil")]
            hil_pending: None,
            mission_items: heapless::Vec::new(),
            mission_transfer: crate::mission::Transfer::new(),
            mission_current: 0,
            mission_run: None,
            mission_replies: Deque::new(),
            long_texts: Deque::new(),
            global_origin: None,
        })
    }

    /// The certificate and the mixer fit of the set-up flown now, for the defmt banner: boot's,
    /// or the latest accepted parameter change's.
    pub fn boot_report(&self) -> BootReport {
        self.report
    }
}
