//! Scratch: a design's upside-down loss, half turns, step, roll and covered disturbance with the
//! turn-over term set from the command line: `turn_over_probe SCENARIO [LEVEL ONSET]`.
use host_sim::design::evaluate::{disturbed_hover, half_turns, nominal_tasks, upside_down};
use host_sim::design::integral::IntegralSpec;
use host_sim::model::scenario::Scenario;
use host_sim::studies::ablation::no_dive::hover_at_start;

fn main() -> anyhow::Result<()> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let path = a
        .first()
        .ok_or_else(|| anyhow::anyhow!("usage: turn_over_probe SCENARIO [LEVEL_NM ONSET]"))?;
    let mut s = Scenario::load(std::path::Path::new(path))?;
    if a.len() >= 3 {
        let t = s
            .gains
            .tilt_priority
            .as_mut()
            .ok_or_else(|| anyhow::anyhow!("{path}: no [gains.tilt_priority]"))?;
        t.turn_over_level_Nm = Some(a[1].parse()?);
        t.turn_over_onset = Some(a[2].parse()?);
    }
    let hover = hover_at_start(&s);
    let u = upside_down(&hover, false)?;
    println!(
        "upside down: lost {:.2} m, settled {:?}, turn over {:?}",
        u.altitude_loss_m, u.settling_time_s, u.turn_over
    );
    let n = nominal_tasks(&hover)?;
    println!(
        "step {:?} roll {:?}",
        n.step_settling_time_s, n.tilt_settling_time_s
    );
    let spec =
        IntegralSpec::covering(s.vehicle.gravity_m_s2, 0.1, 0.05).map_err(anyhow::Error::msg)?;
    let d = disturbed_hover(&hover, &spec, false)?;
    println!(
        "disturbed: lost {:.3} m settled {:?}",
        d.altitude_loss_m, d.settling_time_s
    );
    let e = host_sim::design::evaluate::evaluate(
        &s,
        &hover,
        (
            s.rotors.as_ref().map_or(0.02, |r| r.motor_time_constant_s),
            Some(&spec),
        ),
        false,
    )?;
    println!(
        "evaluate: feasible {} cost {:.3} failures {}",
        e.feasible, e.cost, e.failures
    );
    for t in e
        .nominal
        .iter()
        .chain(&e.doubled_lag)
        .chain(&e.doubled_lag_turned)
        .chain(&e.doubled_lag_random)
    {
        if !t.converged {
            println!(
                "  not converged: {} settling {:?} tail {:.2} deg",
                t.start, t.settling_time_s, t.tail_attitude_error_max_deg
            );
        }
    }
    let h = half_turns(&s, false)?;
    let worst = h
        .iter()
        .map(|t| t.settling_time_s.unwrap_or(f64::INFINITY))
        .fold(0.0, f64::max);
    println!(
        "half turns worst {worst:.2} s, converged {}/7",
        h.iter().filter(|t| t.converged).count()
    );
    Ok(())
}
