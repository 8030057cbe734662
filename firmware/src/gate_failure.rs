//! Why a set-up is not certified, in one value that the boot gate, the parameter checks and the
//! events share.

/// The first reason a set-up is not certified: a violated certificate condition with both
/// sides (`lhs > rhs` should hold), or [`ROTOR_FIT`](crate::pipeline::ROTOR_FIT) with the certified set's margin and the required one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateFailure {
    /// Condition name (controller-core's, e.g. `"theorem2.torque_max_yaw"`, or [`ROTOR_FIT`](crate::pipeline::ROTOR_FIT)).
    pub condition: &'static str,
    /// Left-hand side (for [`ROTOR_FIT`](crate::pipeline::ROTOR_FIT): the margin found).
    pub lhs: f32,
    /// Right-hand side (for [`ROTOR_FIT`](crate::pipeline::ROTOR_FIT): the margin required).
    pub rhs: f32,
}
