//! host-sim: the controller-core law against a desktop rigid-body model.
//!
//! Grouped by role:
//! - [`model`]: what is flown: the rigid-body plant (eq:FullDynamics), the rotor-level plant,
//!   perturbations, vehicle files, scenario files and SO(3) helpers;
//! - [`fly`]: how one flight is flown and what it writes: the closed loop, the controllers (the
//!   paper's law and the baselines), the set-up built once from a scenario, and the main run;
//! - [`bounds`]: the a-priori bounds before flying: the tight bounds, the certificate beside the
//!   paper's, and the `bounds` table;
//! - [`runs`]: the toolkit for many runs: sampled initial conditions, per-run metrics, the
//!   parallel runner, statistics and kept traces;
//! - [`studies`]: what is measured with it: campaigns, ablations (hysteresis, filters, no-dive
//!   thrust, integral action), the baseline comparison and the law-rate study;
//! - [`design`]: gains and levels certified for a real vehicle;
//! - [`harness`]: the firmware itself in the loop (software, processor on QEMU, M4F counts);
//! - [`output`]: what every report shares: one Markdown table, one figure panel of traces, PNG
//!   files (the main run's own files are [`fly::files`]).
//!
//! The command line belongs to the `host-sim` binary (`src/bin/host-sim/`): the library takes
//! plain option structs ([`harness::sil::SilOptions`], [`harness::pil::PilCommandOptions`],
//! [`studies::campaign::CampaignOptions`], [`studies::ablation::AblationOptions`],
//! [`studies::compare::CompareOptions`]) and knows nothing of clap.

#![deny(missing_docs)]

pub mod bounds;
pub mod design;
pub mod fly;
pub mod harness;
pub mod model;
pub mod output;
pub mod runs;
pub mod studies;

// The paths the workspace's cross-crate tests and fuzz targets import (`tests/`, `tests/fuzz/`),
// kept from before the grouping by role.
pub use fly::{controllers, sim};
pub use model::{plant, scenario, so3};
pub use studies::campaign;
