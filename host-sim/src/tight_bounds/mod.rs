//! Tight a-priori bounds on `|ω_d|`, `|ω̇_d|` and the per-axis torque, and the admissible states
//! that show how close they are: [`setup`] holds one set-up (vehicle, gains, trajectory
//! constants, where the filters start), [`sampling`] draws random admissible states of the
//! closed loop's law inputs (filter states reachable by eq:FilterDynamics, saturated feedback,
//! reference derivatives inside Assumption 1's sets, MRP and angular velocity errors) and
//! evaluates the actual controller-core law at them, and [`witness`] searches those states for
//! the largest value of each bounded quantity.

pub mod sampling;
pub mod setup;
pub mod witness;
