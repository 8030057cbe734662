//! Why a set-up is not certified, in one value that the boot gate, the parameter checks and the
//! events share.

/// The first reason a set-up is not certified: a violated certificate condition with both
/// sides (`lhs > rhs` should hold), or [`BOX_FIT`](crate::pipeline::BOX_FIT) with the box's margin and the required one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateFailure {
    /// Condition name (controller-core's, e.g. `"theorem2.torque_max_yaw"`, or [`BOX_FIT`](crate::pipeline::BOX_FIT)).
    pub condition: &'static str,
    /// Left-hand side (for [`BOX_FIT`](crate::pipeline::BOX_FIT): the margin found).
    pub lhs: f32,
    /// Right-hand side (for [`BOX_FIT`](crate::pipeline::BOX_FIT): the margin required).
    pub rhs: f32,
}
