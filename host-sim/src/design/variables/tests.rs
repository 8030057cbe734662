use super::*;
use controller_core::PositionSaturation;

#[test]
fn unit_box_round_trips() {
    let layout = Layout {
        law: AttitudeLaw::TiltPriority,
        local: true,
        vertical: true,
        narrow_local: false,
        local_vertical: false,
        turn_over: false,
        local_integral: false,
    };
    let c = Choices::initial_guess(layout);
    let back = Choices::from_unit(&c.to_unit(), layout);
    for (a, b) in c.to_unit().iter().zip(back.to_unit()) {
        assert!((a - b).abs() < 1e-12);
    }
    assert!((back.ks - c.ks).abs() < 1e-9 && (back.kf - c.kf).abs() < 1e-9);
    assert_eq!(
        c.to_unit().len(),
        TILT_DIMENSION + VERTICAL_DIMENSION + LOCAL_DIMENSION
    );
    assert!(back.local.is_some() && back.vertical.is_some());
    let paper_layout = Layout::default();
    let paper = Choices::initial_guess(paper_layout);
    assert_eq!(paper.to_unit().len(), DIMENSION);
    let back = Choices::from_unit(&paper.to_unit(), paper_layout);
    assert!(back.tilt.is_none() && back.local.is_none() && back.vertical.is_none());
}

/// A uniform point of the unit box of `layout`.
fn random_point(rng: &mut impl rand::Rng, layout: Layout) -> Vec<f64> {
    use rand::RngExt;
    (0..layout.dimension())
        .map(|_| rng.random_range(0.0..=1.0))
        .collect()
}

/// The Crazyflie preset, its rotor set and the paper helix's constants.
fn crazyflie_on_the_paper_helix() -> (
    crate::design::vehicle::DesignVehicle,
    RotorSet,
    TrajectoryConstants<f64>,
) {
    preset_on_the_paper_helix("crazyflie-2.1")
}

/// The preset `name`, its rotor set and the paper helix's constants.
pub(crate) fn preset_on_the_paper_helix(
    name: &str,
) -> (
    crate::design::vehicle::DesignVehicle,
    RotorSet,
    TrajectoryConstants<f64>,
) {
    use controller_core::Trajectory;
    let v = crate::design::vehicle::DesignVehicle::load(&crate::model::vehicle::preset_path(name))
        .unwrap();
    let set = RotorSet::new(&v.rotors).unwrap();
    let constants = crate::model::scenario::Scenario::paper()
        .trajectory::<f64>()
        .constants();
    (v, set, constants)
}

/// A context on `v`'s body, `constants` and `set` with the 5 % margin, `fit`, the paper's
/// bounds, no integral action, `shape` and `lemma1`, and no speed limit.
pub(crate) fn context<'a>(
    (v, constants, set): (
        &'a crate::design::vehicle::DesignVehicle,
        &'a TrajectoryConstants<f64>,
        &'a RotorSet,
    ),
    fit: crate::design::authority::RotorFit,
    shape: PositionSaturation,
    lemma1: controller_core::Lemma1Form,
) -> Context<'a> {
    Context {
        vehicle: &v.body,
        constants,
        rotors: set,
        margin: 0.05,
        fit,
        bounds: Default::default(),
        position: PositionLaw {
            integral: None,
            shape,
            lemma1,
            vertical: None,
            heading: None,
        },
        speed_limit: None,
    }
}

/// Certified by construction: points all over the unit box map to gains that pass
/// `certify` and the rotor fit with the margin, for both fits (the set over the thrust
/// interval, and airmode's shadow: every torque realised at some thrust).
#[test]
fn every_point_of_the_box_is_certified() {
    use crate::design::authority::RotorFit;
    use crate::design::certificate::certify_design_with;
    let (v, set, constants) = crazyflie_on_the_paper_helix();
    let mut rng = crate::runs::sampler::seeded_rng(11);
    let shapes = [PositionSaturation::Componentwise, PositionSaturation::Norm];
    for ((law, shape), fit) in [AttitudeLaw::Paper, AttitudeLaw::TiltPriority]
        .into_iter()
        .flat_map(|l| shapes.map(|s| (l, s)))
        .flat_map(|ls| [RotorFit::Set, RotorFit::Airmode].map(|f| (ls, f)))
    {
        let ctx = context(
            (&v, &constants, &set),
            fit,
            shape,
            controller_core::Lemma1Form::Tangential,
        );
        // Tilt priority with its turn-over share searched (`Layout::turn_over`): the term's
        // bounds on top of the levels stay certified too.
        let layout = Layout {
            law,
            turn_over: law == AttitudeLaw::TiltPriority,
            local_integral: false,
            ..Layout::default()
        };
        for _ in 0..50 {
            let x = random_point(&mut rng, layout);
            let choices = Choices::from_unit(&x, layout);
            let m = map(&ctx, &choices).expect("the paper helix is usable on the Crazyflie");
            assert_eq!(
                m.gains.tilt_priority.is_some(),
                law == AttitudeLaw::TiltPriority
            );
            assert_eq!(m.gains.position.saturation_shape, shape);
            let c = certify_design_with(&v.body, &v.rotors, &m.gains, &constants, 0.05, None, fit)
                .unwrap();
            assert!(
                c.ok() && c.paper_certified(),
                "{law:?} {fit:?} {x:?}: {:?} margin {}",
                c.certificate.require_feasible(),
                c.margin
            );
            assert!(c.margin >= 0.05 - 1e-6, "{}", c.margin);
            if let Some(t) = choices.tilt {
                // The levels are spent as chosen: yaw's is ρ times roll's, roll's the
                // chosen fraction of ι_max along (1, 1, ρ), the turn-over term's bounds on top.
                let tilt = m.gains.tilt_priority.unwrap();
                let level = tilt.turn_over.map_or(0.0, |o| o.level);
                let chosen = t.turn_over() * choices.iota_fraction * m.iota_max;
                assert!(
                    (level - chosen).abs() <= 1e-12 * chosen,
                    "{level} vs {chosen}"
                );
                let levels =
                    c.certificate.bounds.feedback_torque_axes - tilt.turn_over_bounds(super::DELTA);
                let iota = choices.iota_fraction * m.iota_max;
                assert!(
                    (levels.x - iota).abs() <= 1e-9 * iota,
                    "{levels:?} vs {iota}"
                );
                assert!(
                    (levels.z - t.yaw_share * iota).abs() <= 1e-9 * iota,
                    "{levels:?}"
                );
                let g = m.gains.tilt_priority.unwrap().trace_weights;
                assert!(g.z >= g.x && g.x == g.y, "{g:?}");
            }
        }
    }
}

/// Certified by construction with the tight bounds too: random points of the unit box, both
/// laws, mapped with the tight feedforward, pass `certify_design_with` with the tight bounds
/// (Theorem 2's torque conditions judged with their per-axis bounds, the set with their norms
/// fitted with the margin).
#[test]
fn every_point_is_certified_with_the_tight_bounds() {
    use crate::design::certificate::certify_design_with;
    use crate::design::tight::{tight_torque, BoundsKind, SEARCH_BOXES};
    let (v, set, constants) = crazyflie_on_the_paper_helix();
    let ctx = Context {
        vehicle: &v.body,
        constants: &constants,
        rotors: &set,
        margin: 0.05,
        fit: Default::default(),
        bounds: BoundsKind::Tight,
        position: PositionLaw::paper(),
        speed_limit: None,
    };
    let mut rng = crate::runs::sampler::seeded_rng(12);
    for law in [AttitudeLaw::Paper, AttitudeLaw::TiltPriority] {
        for _ in 0..6 {
            let layout = Layout {
                law,
                turn_over: law == AttitudeLaw::TiltPriority,
                local_integral: false,
                ..Layout::default()
            };
            let x = random_point(&mut rng, layout);
            let m = map(&ctx, &Choices::from_unit(&x, layout)).expect("usable on the Crazyflie");
            let tight = tight_torque(&v.body, &m.gains, &constants, SEARCH_BOXES).unwrap();
            let c = certify_design_with(
                &v.body,
                &v.rotors,
                &m.gains,
                &constants,
                0.05,
                Some(tight),
                Default::default(),
            )
            .unwrap();
            assert!(c.ok(), "{law:?} {x:?}: {:?} margin {}", c.tight, c.margin);
            assert!(c.margin >= 0.05 - 1e-6, "{}", c.margin);
        }
    }
}

/// Given a point with every coordinate inside its range, when one coordinate is moved to an end
/// of its range, then exactly that variable is reported at the end, named in the layout's
/// order, with the end's value (except the MRP share, which tilt priority does not read; the
/// turn-over share, searched here, is reported); and the interior point reports none. With the
/// paper's law the MRP share is reported.
#[test]
fn range_ends_name_the_variable_at_the_end() {
    use rand::RngExt;
    let layout = Layout {
        law: AttitudeLaw::TiltPriority,
        local: true,
        vertical: true,
        narrow_local: false,
        local_vertical: false,
        turn_over: true,
        local_integral: false,
    };
    let mut rng = crate::runs::sampler::seeded_rng(3);
    let names: Vec<&str> = NAMES
        .iter()
        .chain(&vertical::VERTICAL_NAMES)
        .chain(&local::LOCAL_NAMES)
        .copied()
        .collect();
    assert_eq!(names.len(), layout.dimension());
    for _ in 0..20 {
        let interior: Vec<f64> = (0..layout.dimension())
            .map(|_| rng.random_range(0.05..0.95))
            .collect();
        assert!(Choices::from_unit(&interior, layout)
            .range_ends(0.01)
            .is_empty());
        for (i, name) in names.iter().enumerate() {
            for end in [0.0, 1.0] {
                let mut x = interior.clone();
                x[i] = end;
                let ends = Choices::from_unit(&x, layout).range_ends(0.01);
                if i == MRP_SHARE {
                    // Tilt priority does not read it.
                    assert!(ends.is_empty(), "{ends:?}");
                    continue;
                }
                assert_eq!(ends.len(), 1, "{name}: {ends:?}");
                let e = &ends[0];
                assert_eq!(e.variable, *name);
                let expected = e.range[end as usize];
                assert!(
                    (e.value - expected).abs() <= 1e-9 * expected.abs(),
                    "{name}: {} vs {expected}",
                    e.value
                );
            }
        }
    }
    let mut x = vec![0.5; DIMENSION];
    x[MRP_SHARE] = 1.0;
    let ends = Choices::from_unit(&x, Layout::default()).range_ends(0.01);
    assert_eq!(ends.len(), 1);
    assert_eq!(ends[0].variable, NAMES[MRP_SHARE]);
}
