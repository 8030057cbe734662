//! `host-sim design`: Table I gains and saturation levels certified for a real vehicle, best
//! on a stated objective measured by simulation.
//!
//! Certified by construction: [`authority`] computes, for `(M_p, k_f, k_s)`, the largest
//! feedback torque level `ι` whose certified `(T, τ)` set fits the rotor set with the margin
//! (closed form); [`variables`] maps nine numbers in `[0, 1]` onto gains inside that envelope;
//! [`certificate`] checks every design with the functions the firmware trusts
//! (`controller_core::bounds::certify`, `Mixer::set_margin`); [`evaluate`] flies it (the seven
//! 180° starts, upside down at hover, the doubled motor time constant); [`optimise`] runs
//! argmin's particle swarm; [`mod@reference`] scales the reference down when it cannot be
//! certified; [`report`] writes `design.json`, `design.md`, the plots, `scenario.toml` and
//! `firmware.toml`. [`vehicle`] reads the vehicle file, [`flight`] builds the scenarios;
//! [`integral`] sizes the bounded integral action of `design` (unless `--no-integral`); [`thrust`] puts the
//! no-dive thrust of `design --thrust vertical-priority` inside the certified box; [`binding`]
//! names what caps the design's levels; [`refine`] refines the envelope design's local regime
//! after the search.

pub mod attitude_terms;
pub mod authority;
pub mod binding;
pub mod bisect;
pub mod certificate;
pub mod evaluate;
pub mod feasibility;
pub mod fit_binding;
pub mod flight;
pub mod integral;
pub mod markdown;
pub mod optimise;
pub mod options;
pub mod outputs;
pub mod reference;
pub mod refine;
pub mod report;
pub mod run;
pub mod score;
pub mod thrust;
pub mod tight;
pub mod turn_over;
pub mod variables;
pub mod vehicle;

pub use options::DesignOptions;
pub use run::{run_design, DesignOutcome};
