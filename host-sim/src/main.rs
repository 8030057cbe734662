//! `host-sim`: run the paper scenario (default) or a scenario file; see `host-sim --help`.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use host_sim::cli::{Cli, Command, RunArgs};
use host_sim::report::human_summary;
use host_sim::scenario::{Scenario, PAPER_SCENARIO};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => run(&cli.run),
        Some(Command::Run(args)) => run(&args),
        Some(Command::PrintScenario) => {
            print!("{PAPER_SCENARIO}");
            Ok(())
        }
        Some(Command::Sil(args)) => host_sim::sil::run_cli(&args),
        Some(Command::Pil(args)) => host_sim::pil::run_cli(&args),
        Some(Command::Campaign(args)) => host_sim::experiments::campaign(&args),
        Some(Command::Ablation(args)) => host_sim::ablation::run_cli(&args),
        Some(Command::Compare(args)) => host_sim::compare::run_cli(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("host-sim: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &RunArgs) -> Result<()> {
    let (mut scenario, name, title) = match &args.scenario {
        None => (
            Scenario::paper(),
            "paper".to_string(),
            "the paper's Section VI scenario (embedded)".to_string(),
        ),
        Some(path) => {
            let stem = path
                .file_stem()
                .map_or_else(|| "scenario".into(), |s| s.to_string_lossy().into_owned());
            (Scenario::load(path)?, stem, path.display().to_string())
        }
    };
    if let Some(p) = args.precision {
        scenario.simulation.precision = p;
    }
    scenario.simulation.clip_to_limits |= args.clip;
    let out: PathBuf = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&name));

    let certificate = host_sim::sim::certificate(&scenario)?;
    if let Err(v) = certificate.require_feasible() {
        eprintln!(
            "host-sim: WARNING: the a-priori guarantees do not all apply to this scenario: {v}.\n\
             host-sim: WARNING: the conditions are sufficient, not necessary; the run proceeds. \
             Violated conditions are listed in the summary."
        );
    }
    let (summary, records) = host_sim::sim::run(&scenario)?;
    let s = &scenario.simulation;
    let header = format!(
        "Scenario: {title}; controller precision {:?}, {} s at {:.0} Hz, plant RK4 step {} s{}",
        s.precision,
        s.duration_s,
        1.0 / s.controller_period_s,
        s.plant_step_s,
        if s.clip_to_limits {
            ", commands clipped to the limits"
        } else {
            ""
        }
    );
    print!("{}", human_summary(&header, &summary));
    let files = if args.no_plots {
        std::fs::create_dir_all(&out)?;
        let csv = out.join("timeseries.csv");
        let json = out.join("summary.json");
        host_sim::output::write_csv(&csv, &records)?;
        host_sim::output::write_summary(&json, &summary)?;
        vec![csv, json]
    } else {
        host_sim::output::write_all(&out, &scenario, &summary, &records)?
    };
    println!("Wrote {} files to {}:", files.len(), out.display());
    for f in &files {
        println!("  {}", f.display());
    }
    Ok(())
}
