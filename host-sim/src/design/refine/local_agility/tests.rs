//! The agility refinement's map: it starts at the design's own local regime, asks for the
//! stiffness it names, and keeps the design when nothing scores lower.

use super::*;
use crate::model::scenario::Scenario;

/// The x500 preset's design (a local regime, tilt priority, the vertical channel apart) with
/// its local regime flying the global attitude law, as the search leaves it before the
/// refinement (the committed design's local law is the refinement's own result).
fn x500() -> (Gains<f64>, Vector3<f64>) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/designs/x500/scenario.toml");
    let s = Scenario::load(std::path::Path::new(path)).expect("the x500 design loads");
    let mut g = s.gains::<f64>();
    if let Some(l) = g.local.as_mut() {
        l.attitude = None;
    }
    (g, s.vehicle::<f64>().inertia)
}

/// Given the x500 design, when its start point is mapped back, then the local regime flies
/// what the design flies: the same filters, level, loop, braking, envelope and vertical
/// channel, a local law whose stiffness terms equal the global law's at random errors (at rest),
/// and roll damping at the global law's damping ratio brought into the searched range (the
/// x500's 0.30 is below it: the start is clamped there, and the refinement is kept only if it
/// scores below the design itself).
#[test]
fn the_start_point_is_the_designs_own_local_regime() {
    let (g, j) = x500();
    let l0 = g.local.expect("a local regime");
    let x = start(&g, &j).expect("a start point");
    let mapped = agility_gains(&g, &j, &x)
        .expect("gains")
        .local
        .expect("local");
    let close = |a: f64, b: f64| approx::relative_eq!(a, b, max_relative = 1e-9);
    assert!(close(mapped.kf, l0.kf) && close(mapped.ks, l0.ks));
    assert!(close(mapped.kp, l0.kp) && close(mapped.kv, l0.kv));
    assert!(close(mapped.saturation, l0.saturation));
    assert!(close(mapped.energy_out, l0.energy_out) && close(mapped.energy_in, l0.energy_in));
    let limit = g.velocity_limit.expect("a velocity limit");
    assert!(close(
        mapped.velocity_limit(&g.position, &limit).braking,
        l0.velocity_limit(&g.position, &limit).braking
    ));
    let (v, v0) = (
        mapped.vertical.expect("vertical"),
        l0.vertical.expect("vertical"),
    );
    assert!(close(v.kf, v0.kf) && close(v.ks, v0.ks) && close(v.up, v0.up));
    let law = mapped.attitude.expect("a local law");
    let mut rng = crate::runs::sampler::seeded_rng(7);
    use rand::RngExt;
    for _ in 0..200 {
        let mrp = Vector3::from_fn(|_, _| rng.random_range(-0.3..0.3));
        let w = Vector3::zeros();
        let r = controller_core::mrp::rotation_from_mrp(&mrp);
        let zero = Vector3::zeros();
        let local = controller_core::gains::torque_law(
            &law.attitude,
            law.tilt_priority.as_ref(),
            &mrp,
            &w,
            &r,
            &zero,
            &zero,
            &j,
        );
        let global = g.attitude_torque(&mrp, &w, &r, &zero, &zero, &j);
        assert!(
            (local.torque - global.torque).norm() <= 1e-9 * (1.0 + global.torque.norm()),
            "{local:?} vs {global:?}"
        );
    }
    let stiffness = roll_stiffness(&g.attitude, &trace_of(&g));
    let ratio = |gain: f64| gain / (2.0 * (stiffness * j.x).sqrt());
    let global_ratio = ratio(roll_damping(&g).0);
    let (low, high, _) = AGILITY_RANGES[8];
    let own = law.tilt_priority.expect("tilt priority").omega_gains.x;
    assert!(close(ratio(own), global_ratio.clamp(low, high)), "{own}");
}

/// Given a point asking for twice the roll frequency near the reference, then the local law's
/// roll stiffness (measured from its torque at a small roll error) is four times the global
/// law's, and its damping ratio is the one asked.
#[test]
fn the_local_law_has_the_stiffness_and_damping_asked() {
    let (g, j) = x500();
    let mut x = start(&g, &j).expect("a start point");
    x[6] = unit_in(AGILITY_RANGES[6], 2.0);
    x[7] = 1.0; // the largest M_ϑ,L: the radial term stays linear at the small error below
    x[8] = unit_in(AGILITY_RANGES[8], 0.7);
    let local = agility_gains(&g, &j, &x)
        .expect("gains")
        .local
        .expect("local");
    let law = local.attitude.expect("a local law");
    let stiffness_of =
        |attitude: &AttitudeGains<f64>, tilt: Option<&controller_core::TiltPriorityGains<f64>>| {
            let phi: f64 = 1e-5;
            let mrp = Vector3::new((phi / 4.0).tan(), 0.0, 0.0);
            let r = controller_core::mrp::rotation_from_mrp(&mrp);
            let zero = Vector3::zeros();
            let t = controller_core::gains::torque_law(
                attitude, tilt, &mrp, &zero, &r, &zero, &zero, &j,
            );
            -t.torque.x / phi
        };
    let global = stiffness_of(&g.attitude, g.tilt_priority.as_ref());
    let own = stiffness_of(&law.attitude, law.tilt_priority.as_ref());
    assert!((own / global - 4.0).abs() < 1e-3, "{own} vs 4 x {global}");
    let gain = law.tilt_priority.expect("tilt priority").omega_gains.x;
    let zeta = gain / (2.0 * (own * j.x).sqrt());
    assert!((zeta - 0.7).abs() < 1e-3, "damping ratio {zeta}");
}

/// Given a cost that no candidate beats, then the refinement keeps the design; given one that
/// rewards a stiffer local law, then it returns gains with one, which the design's certificate
/// still accepts for the x500 design's own vehicle.
#[test]
fn the_refinement_keeps_the_design_unless_it_scores_lower() {
    let (g, j) = x500();
    let (kept, r) = refine_local_agility(&|_: &Gains<f64>| 10.0, &g, &j, 5.0, 1).expect("runs");
    let r = r.expect("a refinement");
    assert!(kept.is_none() && !r.kept && r.refined >= 10.0);
    let stiffer = |gains: &Gains<f64>| {
        let k = gains
            .local
            .and_then(|l| l.attitude)
            .map_or(0.0, |a| a.attitude.k_mrp);
        100.0 / (1.0 + k)
    };
    let before = stiffer(&g);
    let (kept, r) = refine_local_agility(&stiffer, &g, &j, before, 1).expect("runs");
    let r = r.expect("a refinement");
    let gains = kept.expect("a stiffer law is kept");
    assert!(r.kept && r.refined < before);
    assert!(
        gains
            .local
            .and_then(|l| l.attitude)
            .expect("a law")
            .attitude
            .k_mrp
            > g.attitude.k_mrp
    );
    assert!(gains.validate().is_ok());
}
