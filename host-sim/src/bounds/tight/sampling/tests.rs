use super::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Parameters round-trip and samples pass the independent admissibility check.
#[test]
fn samples_are_admissible_and_round_trip() {
    let setup = Setup::paper();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..2000 {
        let s = sample(&mut rng, &setup);
        s.check(&setup).unwrap();
        let back = AdmissibleState::from_parameters(&setup, &s.parameters(&setup));
        let (a, b) = (s.evaluate(&setup).unwrap(), back.evaluate(&setup).unwrap());
        assert!((a.torque - b.torque).amax() <= 1e-9 * (1.0 + a.torque.amax()));
        assert!(
            (a.angular_acceleration - b.angular_acceleration).amax()
                <= 1e-9 * (1.0 + a.angular_acceleration.amax())
        );
    }
}

/// The law sees the filter state and the `ubar` the state asks for, also at the corners
/// `±M_p`.
#[test]
fn the_law_sees_the_requested_inputs() {
    let setup = Setup::paper();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut corners = 0;
    for _ in 0..500 {
        let s = sample(&mut rng, &setup);
        let f = s.filter_state(&setup);
        let v = s.evaluate(&setup).unwrap();
        let expected_u = f.u_f + Vector3::z() * setup.vehicle.gravity + s.acceleration;
        assert!((v.u - expected_u).amax() < 1e-12);
        assert!((v.ubar - s.ubar).amax() < 1e-12, "{} vs {}", v.ubar, s.ubar);
        corners += s.ubar.iter().filter(|u| u.abs() == 2.0).count();
    }
    assert!(corners > 500, "ubar is often at ±M_p: {corners} of 1500");
}

/// A long hold at `−M_p` then `+M_p` gives the known closed-form end state (independent
/// of the propagator: `u_s − M = −2M e^{−k_s t}`, `u_f − M = −2M (k_s e^{−k_f t} −
/// k_f e^{−k_s t})/(k_s − k_f)`), and the end state stays in the saturation box.
#[test]
fn a_bang_bang_history_ends_where_the_closed_form_says() {
    let setup = Setup::paper();
    let p = &setup.gains.position;
    let (m, kf, ks) = (p.saturation, p.kf, p.ks);
    for t in [0.0, 0.01, 0.1, 0.3, 1.0, 3.0] {
        let h = FilterHistory {
            start: [0.0; 2],
            levels: [0.0, 0.0, -m, m],
            durations: [0.0, 0.0, longest_segment(&setup), t],
        };
        let [uf, us] = h.end_state(p);
        let es = -2.0 * m * (-ks * t).exp();
        let ef = -2.0 * m * (ks * (-kf * t).exp() - kf * (-ks * t).exp()) / (ks - kf);
        assert!(
            (us - m - es).abs() < 1e-9 && (uf - m - ef).abs() < 1e-9,
            "t = {t}"
        );
        assert!(uf.abs() <= m && us.abs() <= m);
    }
}
