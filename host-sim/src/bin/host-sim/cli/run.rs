//! The default job (also `host-sim run`): one scenario, its time series, plots and summary.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::fly::files::console::human_summary;
use host_sim::model::scenario::{describe_edits, KeyEdit, Scenario, PAPER_SCENARIO};

use super::common::{PlantArgs, PrecisionArg, ThrustArgs};

/// Options of a single run.
#[derive(Debug, Args, Clone, Default)]
pub struct RunArgs {
    /// Scenario file (TOML). Default: the embedded paper scenario (see `print-scenario`).
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Output directory. Default: `./out/<scenario name>` ("paper" for the embedded scenario,
    /// the file stem otherwise). Created if missing; files in it are overwritten.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Controller precision, overriding the scenario's `simulation.precision`.
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// Clip thrust and torque to the physical limits before applying them to the plant,
    /// overriding the scenario's `simulation.clip_to_limits`.
    #[arg(long)]
    pub clip: bool,
    /// Write only summary.json and the CSV (skip the PNG plots).
    #[arg(long)]
    pub no_plots: bool,
    /// Plant and vehicle.
    #[command(flatten)]
    pub plant: PlantArgs,
    /// Thrust law.
    #[command(flatten)]
    pub thrust: ThrustArgs,
    /// Edit a key of the scenario (the embedded paper's or `--scenario`'s) before flying it,
    /// `TABLE.KEY=VALUE` (repeatable; e.g. `--set gains.M_p=2 --set initial.euler_deg=[170,0,0]`):
    /// the file is not changed.
    #[arg(long = "set", value_name = "TABLE.KEY=VALUE")]
    pub set: Vec<KeyEdit>,
}

/// Runs one scenario: prints its summary and writes its time series, plots and summary.
///
/// Errors: the scenario cannot be read or is invalid; its certificate cannot be computed; a
/// sample is refused; a file cannot be written.
pub fn run(args: &RunArgs) -> Result<()> {
    let (mut scenario, name, title) = match &args.scenario {
        None => (
            Scenario::parse_with_edits(PAPER_SCENARIO, "<embedded paper scenario>", &args.set)?,
            "paper".to_string(),
            "the paper's Section VI scenario (embedded)".to_string(),
        ),
        Some(path) => {
            let stem = path
                .file_stem()
                .map_or_else(|| "scenario".into(), |s| s.to_string_lossy().into_owned());
            (
                Scenario::load_with_edits(path, &args.set)?,
                stem,
                path.display().to_string(),
            )
        }
    };
    let title = if args.set.is_empty() {
        title
    } else {
        format!("{title} with {}", describe_edits(&args.set))
    };
    if let Some(p) = args.precision {
        scenario.simulation.precision = p.into();
    }
    scenario.simulation.clip_to_limits |= args.clip;
    let scenario = scenario.with_plant_overrides(
        args.plant.vehicle.as_deref(),
        args.plant.plant.map(Into::into),
        args.plant.motor_time_constant_s,
    )?;
    let scenario = args.thrust.apply(scenario);
    scenario
        .validate()
        .map_err(|e| anyhow::anyhow!("scenario {title}: {e}"))?;
    let out: PathBuf = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&name));

    let setup = host_sim::fly::setup::FlightSetup::new(&scenario)?;
    let certificate = &setup.certificate;
    if let Err(v) = certificate.require_feasible() {
        eprintln!(
            "host-sim: WARNING: the a-priori guarantees do not all apply to this scenario: {v}.\n\
             host-sim: WARNING: the conditions are sufficient, not necessary; the run proceeds. \
             Violated conditions are listed in the summary."
        );
        let report =
            host_sim::bounds::certificate::tight_report(certificate, &setup.tight).conditions;
        for c in report.iter().filter(|c| !c.holds_paper) {
            eprintln!(
                "host-sim: {}: {} (tight bound {:.4} vs tau_max {:.4}; docs/tight-bounds.md).",
                c.name,
                c.verdict(),
                c.rhs_tight,
                c.lhs
            );
        }
    }
    let (summary, records) = host_sim::fly::sim::run_set_up(&scenario, &setup)?;
    let s = &scenario.simulation;
    let header = format!(
        "Scenario: {title}; controller precision {:?}, {} s at {:.0} Hz, {}plant RK4 step {} s{}{}{}",
        s.precision,
        s.duration_s,
        1.0 / s.controller_period_s,
        if s.plant.is_ideal() {
            String::new()
        } else {
            format!("{} plant, ", s.plant.name())
        },
        s.plant_step_s,
        if s.clip_to_limits {
            ", commands clipped to the limits"
        } else {
            ""
        },
        if scenario.perturbations.is_nominal() {
            String::new()
        } else {
            format!(", [perturbations] applied (seed {})", s.seed)
        },
        if scenario.controller.is_paper() {
            String::new()
        } else {
            format!(", thrust = {}", scenario.controller.thrust.name())
        }
    );
    print!("{}", human_summary(&header, &summary));
    if let Some(m) = &summary.mixer {
        println!(
            "Mixer: gave something up in {} of {} samples (at most {:.3} N of thrust, {:.4} N m \
             of torque in one sample)",
            m.samples_given_up, m.samples, m.thrust_given_up_max_N, m.torque_given_up_max_Nm
        );
    }
    let files = if args.no_plots {
        std::fs::create_dir_all(&out)?;
        let csv = out.join("timeseries.csv");
        let json = out.join("summary.json");
        host_sim::fly::files::write_csv(&csv, &records)?;
        host_sim::fly::files::write_summary(&json, &summary)?;
        vec![csv, json]
    } else {
        host_sim::fly::files::write_all(&out, &scenario, &summary, &records)?
    };
    println!("Wrote {} files to {}:", files.len(), out.display());
    for f in &files {
        println!("  {}", f.display());
    }
    Ok(())
}
