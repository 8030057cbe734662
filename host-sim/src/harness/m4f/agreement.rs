//! The agreement of the ARM outputs with the same computation on the host.

use anyhow::{anyhow, ensure, Result};
use firmware::config::FlightConfig;
use firmware::step_inputs::{self, Record};
use serde::Serialize;

use super::regions::{tag, ArmRun, Kind, Region};

/// Relative tolerance between the ARM and the host outputs.
pub const RELATIVE_TOLERANCE: f64 = 1e-5;
/// The same records computed natively (see [`step_inputs::run_sequence`]). Errors: a host
/// flight step left the flight path.
pub fn host_records() -> Result<Vec<Record>> {
    let mut records = Vec::new();
    let ok = step_inputs::run_sequence(|r| records.push(r));
    ensure!(
        ok,
        "on the host, some flight steps did not run the flight path"
    );
    Ok(records)
}

/// Absolute floors of the comparison, for outputs that can be close to zero (torques): the
/// tolerance `1e-5` applied to the magnitude of the terms the value is a sum of, instead of to
/// the value itself. Two computations that agree to `1e-5` relative in every term agree to
/// `1e-5 Σ|terms|` in the sum; when the terms cancel, the value alone says nothing.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Floors {
    /// Controller torque, per axis [N m]: `1e-5 ×` Theorem 2's a-priori bound on `|τ_i|` (the
    /// certificate of the paper set-up, a sum of bounds of the law's terms).
    pub controller_torque: [f64; 3],
    /// Mixer torque, per axis, per unit of `Σ_k |B_ik| f_k` [N m / N m]: the achieved torque is
    /// `Σ_k B_ik f_k` over the rotor thrusts `f_k` (recovered from the step's throttles).
    pub mixer_torque_relative: f64,
}

impl Floors {
    /// The floors of the paper set-up.
    pub fn paper() -> Result<Self> {
        let p = firmware::pipeline::FlightPipeline::new(&FlightConfig::paper())
            .map_err(|e| anyhow!("paper pipeline refused: {e:?}"))?;
        let b = p.boot_report().certificate.bounds.torque_max;
        Ok(Self {
            controller_torque: [b.x, b.y, b.z].map(|x| RELATIVE_TOLERANCE * f64::from(x)),
            mixer_torque_relative: RELATIVE_TOLERANCE,
        })
    }
}

/// The outcome of the ARM-vs-host comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Agreement {
    /// Values compared.
    pub compared: usize,
    /// Largest `|a − b| / max(|a|, |b|)` over all values (0 when both are 0).
    pub max_relative_difference: f64,
    /// Where it was (`"F 12 throttle[2]"`).
    pub worst: String,
    /// Largest relative difference among the full steps (arming tick included).
    pub max_relative_difference_full: f64,
    /// Largest relative difference among the controller steps.
    pub max_relative_difference_controller: f64,
    /// Largest relative difference among the values within the relative tolerance (that is,
    /// leaving out those that needed their floor: cancellations).
    pub max_relative_difference_within_tolerance: f64,
    /// Values that passed only thanks to their absolute floor.
    pub passed_by_floor: usize,
    /// Those values (first 20): where, both values, the difference and the floor.
    pub floor_cases: Vec<String>,
    /// Values outside the tolerance (empty when everything agrees).
    pub failures: Vec<String>,
    /// Values whose bits are identical.
    pub bit_identical: usize,
}

const FULL_NAMES: [&str; 8] = [
    "throttle[0]",
    "throttle[1]",
    "throttle[2]",
    "throttle[3]",
    "mixer thrust",
    "mixer torque x",
    "mixer torque y",
    "mixer torque z",
];
const CONTROLLER_NAMES: [&str; 4] = ["thrust", "torque x", "torque y", "torque z"];

/// Compares the ARM regions with the host records, value by value:
/// `|a − b| ≤ 1e-5 · max(|a|, |b|)`, or below the value's absolute floor ([`Floors`]).
/// Errors: the two sequences do not line up (different kinds or indices).
pub fn compare(arm: &ArmRun, host: &[Record], floors: &Floors) -> Result<Agreement> {
    let measured: Vec<&Region> = arm
        .regions
        .iter()
        .filter(|r| r.kind != Kind::Empty)
        .collect();
    ensure!(
        measured.len() == host.len(),
        "{} regions on ARM, {} records on the host",
        measured.len(),
        host.len()
    );
    let rotors = FlightConfig::paper().rotors;
    let b = firmware::mixer::Mixer::new(&rotors)
        .map_err(|e| anyhow!("paper mixer refused: {e:?}"))?
        .effectiveness()
        .cast::<f64>();
    let mut a = Agreement {
        compared: 0,
        max_relative_difference: 0.0,
        worst: String::new(),
        max_relative_difference_full: 0.0,
        max_relative_difference_controller: 0.0,
        max_relative_difference_within_tolerance: 0.0,
        passed_by_floor: 0,
        floor_cases: Vec::new(),
        failures: Vec::new(),
        bit_identical: 0,
    };
    for (r, h) in measured.iter().zip(host) {
        let (kind, index, values, names): (Kind, u32, Vec<f32>, &[&str]) = match h {
            Record::Arm(i, o) => (Kind::Arm, *i, o.to_vec(), &FULL_NAMES),
            Record::Full(i, o) => (Kind::Full, *i, o.to_vec(), &FULL_NAMES),
            Record::Controller(i, o) => (Kind::Controller, *i, o.to_vec(), &CONTROLLER_NAMES),
        };
        ensure!(
            r.kind == kind && r.index == index,
            "sequence mismatch: ARM {:?} {} vs host {kind:?} {index}",
            r.kind,
            r.index
        );
        // Per-value floors.
        let mut floor = vec![0.0f64; values.len()];
        match kind {
            Kind::Controller => floor[1..4].copy_from_slice(&floors.controller_torque),
            Kind::Arm | Kind::Full => {
                let f: Vec<f64> = r.outputs[..4]
                    .iter()
                    .map(|&u| {
                        if u > 0.0 {
                            f64::from(rotors.thrust_from_throttle(u))
                        } else {
                            0.0
                        }
                    })
                    .collect();
                for axis in 0..3 {
                    let scale: f64 = (0..4).map(|k| b[(axis + 1, k)].abs() * f[k]).sum();
                    floor[5 + axis] = floors.mixer_torque_relative * scale;
                }
            }
            Kind::Empty => {}
        }
        for (i, (&x, &y)) in r.outputs.iter().zip(&values).enumerate() {
            a.compared += 1;
            let name = || format!("{} {} {}", tag(kind), index, names[i]);
            if x.to_bits() == y.to_bits() {
                a.bit_identical += 1;
                continue;
            }
            let (x, y) = (f64::from(x), f64::from(y));
            let diff = (x - y).abs();
            let scale = x.abs().max(y.abs());
            let rel = if scale > 0.0 { diff / scale } else { 0.0 };
            if rel.is_nan() || rel > a.max_relative_difference {
                a.max_relative_difference = rel;
                a.worst = name();
            }
            let per_kind = if kind == Kind::Controller {
                &mut a.max_relative_difference_controller
            } else {
                &mut a.max_relative_difference_full
            };
            *per_kind = per_kind.max(rel);
            if diff <= RELATIVE_TOLERANCE * scale {
                a.max_relative_difference_within_tolerance =
                    a.max_relative_difference_within_tolerance.max(rel);
                continue;
            }
            if diff <= floor[i] {
                a.passed_by_floor += 1;
                if a.floor_cases.len() < 20 {
                    a.floor_cases.push(format!(
                        "{}: ARM {x:e} vs host {y:e} (|diff| {diff:.3e}, floor {:.3e})",
                        name(),
                        floor[i]
                    ));
                }
                continue;
            }
            a.failures.push(format!(
                "{}: ARM {x:e} vs host {y:e} (|diff| {diff:.3e}, relative {rel:.3e}, floor {:.3e})",
                name(),
                floor[i]
            ));
        }
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The host records compare equal to themselves, and a perturbed value is caught.
    #[test]
    fn comparison() {
        let host = host_records().unwrap();
        let regions = std::iter::once(Region {
            kind: Kind::Empty,
            index: 0,
            raw_instructions: 5,
            outputs: vec![],
        })
        .chain(host.iter().map(|r| {
            match r {
                Record::Arm(i, o) => (Kind::Arm, *i, o.to_vec()),
                Record::Full(i, o) => (Kind::Full, *i, o.to_vec()),
                Record::Controller(i, o) => (Kind::Controller, *i, o.to_vec()),
            }
            .into()
        }))
        .collect();
        let mut arm = ArmRun {
            regions,
            overhead: 5,
            total_instructions: 0,
        };
        let floors = Floors::paper().unwrap();
        let a = compare(&arm, &host, &floors).unwrap();
        assert!(a.failures.is_empty());
        assert_eq!(a.bit_identical, a.compared);
        let x = &mut arm.regions[2].outputs[4];
        *x *= 1.0 + 2e-5;
        let a = compare(&arm, &host, &floors).unwrap();
        assert_eq!(a.failures.len(), 1, "{:?}", a.failures);
    }
}
