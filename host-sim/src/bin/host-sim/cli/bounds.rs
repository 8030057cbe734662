//! `host-sim bounds`: the paper's, the tight and the witnessed bounds of one set-up.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::bounds::table::{
    bounds_table, markdown, write_table, BoundsOptions, BOUNDS_MAX_BOXES,
};

/// Options of `host-sim bounds`.
#[derive(Debug, Args, Clone)]
pub struct BoundsArgs {
    /// Scenario file (default: the embedded paper scenario): its vehicle, gains and trajectory
    /// set the confining set.
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Seed of the witness search (admissible states where the law comes close to the bound).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Skip the witness search (about two seconds).
    #[arg(long)]
    pub no_witness: bool,
    /// Box budget of each branch-and-bound search of the tight bounds (a larger budget is as
    /// sound and at least as tight; main runs use 150 000).
    #[arg(long, default_value_t = BOUNDS_MAX_BOXES)]
    pub boxes: usize,
    /// Box budget of each of the two searches that keep the filters' correlations (for
    /// |(omega_d_dot_1, omega_d_dot_2)| and |omega_d_dot|; their bounds are kept where smaller);
    /// 0 skips them. Slow and memory-hungry: with 64000000 the paper's set-up takes 32 min on two
    /// cores and 12.5 GB, and beats the default search (docs/tight-bounds.md).
    #[arg(long, default_value_t = 0)]
    pub coupled_boxes: usize,
    /// Also write bounds.json and bounds.md here.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Prints the table (Markdown) and writes the files if asked.
pub fn run(args: &BoundsArgs) -> Result<()> {
    let table = bounds_table(&BoundsOptions {
        scenario: args.scenario.clone(),
        witness_seed: (!args.no_witness).then_some(args.seed),
        max_boxes: args.boxes,
        coupled_boxes: args.coupled_boxes,
    })?;
    print!("{}", markdown(&table));
    if let Some(dir) = &args.out {
        for f in write_table(dir, &table)? {
            println!("wrote {}", f.display());
        }
    }
    Ok(())
}
