//! What the bench measures: regions between the markers, and one run's regions.

use serde::Serialize;

/// What a measured region is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Kind {
    /// Nothing between the brackets: their own overhead.
    Empty,
    /// The arming tick's full step (IMU, pose + arm + mission-start commands, tick).
    Arm,
    /// A flight tick's full step.
    Full,
    /// A controller-core step alone.
    Controller,
}

/// One region measured on the MCU.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// What it is.
    pub kind: Kind,
    /// Tick (arming), flight tick `1..=FLIGHT_TICKS` (full, controller) or index (empty).
    pub index: u32,
    /// Instructions counted between the brackets, overhead included.
    pub raw_instructions: u64,
    /// Outputs (see [`firmware::step_inputs::FullOutputs`],
    /// [`firmware::step_inputs::ControllerOutputs`]).
    pub outputs: Vec<f32>,
}

/// Everything one QEMU run of the bench gave.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmRun {
    /// The regions, in execution order.
    pub regions: Vec<Region>,
    /// The brackets' overhead \[instructions\] (the empty regions' count; they must agree).
    pub overhead: u64,
    /// Instructions executed by the whole program.
    pub total_instructions: u64,
}

impl ArmRun {
    /// Instruction counts of the regions of `kind`, overhead removed.
    pub fn instructions(&self, kind: Kind) -> Vec<u64> {
        self.regions
            .iter()
            .filter(|r| r.kind == kind)
            .map(|r| r.raw_instructions.saturating_sub(self.overhead))
            .collect()
    }
}

impl From<(Kind, u32, Vec<f32>)> for Region {
    fn from((kind, index, outputs): (Kind, u32, Vec<f32>)) -> Self {
        Self {
            kind,
            index,
            raw_instructions: 0,
            outputs,
        }
    }
}

/// The one-letter tag of `kind` in the bench's output and in value names.
pub fn tag(kind: Kind) -> &'static str {
    match kind {
        Kind::Empty => "Z",
        Kind::Arm => "A",
        Kind::Full => "F",
        Kind::Controller => "C",
    }
}
