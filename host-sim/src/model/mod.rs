//! What is flown: the rigid-body plant of eq:FullDynamics ([`plant`]), the rotor-level plant
//! with the firmware's mixer and motor lag ([`rotor_plant`]), perturbations of a run
//! ([`perturbation`]), vehicle files ([`vehicle`]), scenario files ([`scenario`]: vehicle, gains,
//! trajectory and simulation settings of one flight) and SO(3) helpers ([`so3`]).

pub mod perturbation;
pub mod plant;
pub mod rotor_plant;
pub mod scenario;
pub mod so3;
pub mod vehicle;
