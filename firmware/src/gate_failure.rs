//! Why a set-up is not certified, in one value that the boot gate, the parameter checks and the
//! events share.

/// The first reason a set-up is not certified: a violated certificate condition with both
/// sides (`lhs > rhs` should hold), the thrust floor, or a rotor fit
/// ([`ROTOR_FIT`](crate::pipeline::ROTOR_FIT) and the other `rotor_fit.*`,
/// [`crate::pipeline::gate`]) with its margin and the required one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateFailure {
    /// Condition name (controller-core's, e.g. `"theorem2.torque_max_yaw"`, or a rotor fit's,
    /// e.g. [`ROTOR_FIT`](crate::pipeline::ROTOR_FIT)).
    pub condition: &'static str,
    /// Left-hand side (for a rotor fit: the margin found, a fraction of the rotor range).
    pub lhs: f32,
    /// Right-hand side (for a rotor fit: the margin required, a fraction of the rotor range).
    pub rhs: f32,
}
