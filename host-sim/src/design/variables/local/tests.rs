use super::*;
use crate::design::variables::tests::{context, preset_on_the_paper_helix};
use crate::design::variables::{map, AttitudeLaw, Choices, Layout};

/// Choices with the filter ratio `kf_ratio` and the envelope `tilt_out_deg`, the rest the
/// initial guess's.
fn asking(kf_ratio: f64, tilt_out_deg: f64) -> LocalChoices {
    LocalChoices {
        kf_ratio,
        tilt_out_deg,
        ..LocalChoices::initial_guess()
    }
}

/// Given a fit that holds while `ratio · θ_out ≤ 24` (monotone in both, as the local torque
/// set's fit is), when the chosen filters fit at the narrowest envelope, then the envelope is
/// the widest that fits them; when they do not, the filters are the fastest that fit at the
/// narrowest envelope; when even `k_f,L = k_f` does not, there is none.
#[test]
fn narrowing_keeps_the_filters_and_finds_the_widest_envelope() {
    let fits = |ratio: f64, tilt: f64| ratio * tilt <= 24.0;
    let (ratio, tilt) = narrowed(&asking(4.0, 30.0), fits).unwrap();
    assert_eq!(ratio, 4.0);
    assert!(tilt <= 6.0 && 6.0 - tilt < 1e-9, "{tilt}");

    let (ratio, tilt) = narrowed(&asking(20.0, 30.0), fits).unwrap();
    assert_eq!(tilt, NARROWEST_TILT_OUT_DEG);
    let fastest = 24.0 / NARROWEST_TILT_OUT_DEG;
    assert!(ratio <= fastest && fastest - ratio < 1e-9, "{ratio}");

    assert_eq!(narrowed(&asking(20.0, 30.0), |r, t| r * t <= 1.0), None);
}

/// Given the x500 (yaw torque 0.016 m per newton against a 0.174 m roll arm) on the paper's
/// helix with airmode's fit, with the paper's desired frame and with the compensated heading,
/// when random points of the box ask for local regimes, then every one the design maps passes
/// the certificate with the local regime's conditions and the fit with the margin, some of them
/// only after their envelope was narrowed, and none is lost that fitted as chosen.
#[test]
fn narrowed_local_regimes_are_certified() {
    narrowed_local_regimes_certified_with(None, false);
    narrowed_local_regimes_certified_with(
        Some(crate::design::options::DESIGN_HEADING_COMPENSATOR),
        false,
    );
}

/// Given the same with the vertical channel apart and the local regime's own vertical filters
/// searched (the refinement's layout, compensated heading), every mapped design is certified
/// too, and some fly local vertical filters faster than the global ones, with the global
/// `k_s,z / k_f,z`.
#[test]
fn local_vertical_filters_are_certified() {
    narrowed_local_regimes_certified_with(
        Some(crate::design::options::DESIGN_HEADING_COMPENSATOR),
        true,
    );
}

/// The check of [`narrowed_local_regimes_are_certified`] with the heading compensator
/// `heading` (every mapped design must carry it), and with the vertical channel apart and the
/// local vertical filters searched when `vertical`.
fn narrowed_local_regimes_certified_with(
    heading: Option<controller_core::HeadingCompensatorGains<f64>>,
    vertical: bool,
) {
    use crate::design::authority::RotorFit;
    use crate::design::certificate::certify_design_with;
    use controller_core::{Lemma1Form, PositionSaturation};
    use rand::RngExt;
    let (v, set, constants) = preset_on_the_paper_helix("x500");
    // The helix's path with its heading held, as the x500's design certifies it.
    let constants = controller_core::TrajectoryConstants {
        heading_rate: 0.0,
        heading_acceleration: 0.0,
        ..constants
    };
    let mut ctx = context(
        (&v, &constants, &set),
        RotorFit::Airmode,
        PositionSaturation::Norm,
        Lemma1Form::DesiredFrame,
    );
    ctx.position.heading = heading;
    let layout = Layout {
        law: AttitudeLaw::TiltPriority,
        local: true,
        vertical,
        narrow_local: true,
        local_vertical: vertical,
        turn_over: false,
        local_integral: false,
    };
    let mut rng = crate::runs::sampler::seeded_rng(21);
    let (mut with_local, mut narrowed_count, mut carrying) = (0, 0, 0);
    let mut own_vertical = 0;
    for _ in 0..40 {
        let x: Vec<f64> = (0..layout.dimension())
            .map(|_| rng.random_range(0.0..=1.0))
            .collect();
        let choices = Choices::from_unit(&x, layout);
        let Some(m) = map(&ctx, &choices) else {
            continue;
        };
        let Some(l) = m.gains.local else {
            continue;
        };
        with_local += 1;
        carrying += usize::from(m.gains.heading_compensator == heading);
        if let (Some(f), Some(global)) = (l.vertical, m.gains.position.vertical) {
            assert!(vertical && f.kf > global.kf, "{f:?} {global:?}");
            assert!((f.ks / f.kf - global.ks / global.kf).abs() < 1e-12);
            own_vertical += 1;
        }
        let chosen = choices.local.unwrap();
        let chosen_energy = energy_out(&m.gains, &chosen);
        if l.energy_out < chosen_energy * (1.0 - 1e-12) {
            narrowed_count += 1;
            // Narrowed only where nothing fitted at the chosen envelope.
            let g = Gains {
                local: None,
                ..m.gains
            };
            let at_chosen = |ratio: f64| {
                local_fits(
                    &ctx,
                    &g,
                    LocalGains {
                        kf: g.position.kf * ratio,
                        ks: g.position.kf * ratio * chosen.ks_ratio,
                        energy_in: 0.5 * chosen_energy,
                        energy_out: chosen_energy,
                        ..l
                    },
                )
            };
            assert!(!at_chosen(1.0), "{chosen:?}");
        }
        let c = certify_design_with(
            &v.body,
            &v.rotors,
            &m.gains,
            &constants,
            0.05,
            None,
            RotorFit::Airmode,
        )
        .unwrap();
        assert!(
            c.ok() && c.certificate.local.is_some(),
            "{x:?}: {:?} margin {}",
            c.certificate.require_feasible(),
            c.margin
        );
    }
    assert!(
        narrowed_count > 0 && with_local > narrowed_count,
        "{heading:?}: {with_local} {narrowed_count}"
    );
    assert_eq!(
        carrying, with_local,
        "every mapped design carries the compensator asked for"
    );
    assert_eq!(own_vertical > 0, vertical, "{own_vertical} of {with_local}");
}
