use super::*;

#[test]
fn embedded_scenario_parses() {
    let s = Scenario::paper();
    assert_eq!(s.simulation.duration_s, 30.0);
    assert_eq!(s.initial.euler_deg, [-179.0, 0.0, 100.0]);
}

/// `[gains.integral]`: absent is off (the paper's law); present it reaches the gains; an
/// unknown key or a bad value is refused with its key.
#[test]
fn integral_table_is_parsed_and_checked() {
    assert_eq!(Scenario::paper().gains::<f64>().integral, None);
    let table = "alpha = 0.25\n\n[gains.integral]\nk_i = 5.0\nM_i_m_s2 = [0.1, 0.2, 2.2]\n\
                 rate_m_s3 = [2.0, 2.0, 10.0]\nk_eta = 1.0\n";
    let text = PAPER_SCENARIO.replacen("alpha = 0.25", table, 1);
    let g = Scenario::parse(&text, "i.toml").unwrap().gains::<f64>();
    let i = g.integral.unwrap();
    assert_eq!((i.gain, i.bandwidth), (5.0, 1.0));
    assert_eq!(i.level, Vector3::new(0.1, 0.2, 2.2));
    assert_eq!(i.rate, Vector3::new(2.0, 2.0, 10.0));
    let e = Scenario::parse(&text.replace("k_eta", "k_etta"), "i.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("k_etta"), "{e}");
    let e = Scenario::parse(&text.replace("0.2, 2.2", "-0.2, 2.2"), "i.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("gains.integral.M_i_m_s2"), "{e}");
}

/// `[gains.integral.feedforward_scale]` reaches the gains; a level outside `(0, 1)` or an
/// unknown key is refused with its key.
#[test]
fn feedforward_scale_table_is_parsed_and_checked() {
    let text = include_str!("../../../scenarios/mass-error.toml");
    let s = Scenario::parse(text, "mass-error.toml").unwrap();
    let f = s
        .gains::<f64>()
        .integral
        .unwrap()
        .feedforward_scale
        .unwrap();
    assert_eq!((f.level, f.rate, f.tracking_limit), (0.22, 0.05, 0.05));
    let e = Scenario::parse(&text.replace("level = 0.22", "level = 1.5"), "m.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("gains.integral.feedforward_scale.level"), "{e}");
    let e = Scenario::parse(&text.replace("gain_1_s = 4.0", "gain = 4.0"), "m.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("gain"), "{e}");
}

#[test]
fn unknown_key_is_named() {
    let text = PAPER_SCENARIO.replace("mass_kg", "mass_kgs");
    let e = Scenario::parse(&text, "x.toml").unwrap_err().to_string();
    assert!(e.contains("x.toml") && e.contains("mass_kgs"), "{e}");
}

#[test]
fn bad_value_is_named_with_key() {
    let text = PAPER_SCENARIO.replace("kv = 6.0", "kv = -6.0");
    let e = Scenario::parse(&text, "y.toml").unwrap_err().to_string();
    assert!(
        e.contains("y.toml") && e.contains("gains.kv") && e.contains("-6"),
        "{e}"
    );
    let text = PAPER_SCENARIO.replace("alpha = 0.25", "alpha = 1.5");
    let e = Scenario::parse(&text, "z.toml").unwrap_err().to_string();
    assert!(e.contains("gains.alpha"), "{e}");
}

/// Given `[gains.heading_compensator]`, when it parses, then the gains carry it; a level that is
/// not positive is refused naming its key and value, an unknown key by name.
#[test]
fn heading_compensator_table_is_read_and_checked() {
    let table = |level: &str, key: &str| {
        format!("{PAPER_SCENARIO}\n[gains.heading_compensator]\n{key} = {level}\ngain_1_s = 2.0\n")
    };
    let s = Scenario::parse(&table("0.3", "level_rad_s"), "h.toml").unwrap();
    let h = s
        .gains::<f64>()
        .heading_compensator
        .expect("the compensator is on");
    assert_eq!((h.level, h.gain), (0.3, 2.0));
    assert!(Scenario::paper()
        .gains::<f64>()
        .heading_compensator
        .is_none());
    let e = Scenario::parse(&table("0.0", "level_rad_s"), "h.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gains.heading_compensator.level_rad_s") && e.contains("got 0"),
        "{e}"
    );
    let e = Scenario::parse(&table("0.3", "level"), "h.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("level"), "{e}");
}

/// Given the vertical channel apart and `[gains.local]` with `[gains.local.vertical]`, when it
/// parses, then the local gains carry the vertical filters and, where the table gives none, the
/// global vertical levels; given levels are read as given; local vertical filters slower than
/// the global ones, and a level that is not positive, are refused naming their key and value.
#[test]
fn local_vertical_filters_are_read_and_checked() {
    let table = |kf: &str| {
        format!(
            "{PAPER_SCENARIO}\n[gains.vertical]\nup_m_s2 = 4.0\ndown_m_s2 = 1.0\nkf = 1.5\nks = 2.5\n\
             \n[gains.local]\nkp = 9.0\nkv = 6.0\nkf = 4.0\nks = 30.0\nM_p_m_s2 = 1.5\n\
             energy_in_J = 0.01\nenergy_out_J = 0.02\n\n[gains.local.vertical]\nkf = {kf}\nks = 20.0\n"
        )
    };
    let s = Scenario::parse(&table("6.0"), "l.toml").unwrap();
    let l = s.gains::<f64>().local.expect("the local regime is on");
    let f = l.vertical.expect("its own vertical filters");
    assert_eq!((f.kf, f.ks, f.up, f.down), (6.0, 20.0, 4.0, 1.0));
    let levels = format!("{}up_m_s2 = 1.5\ndown_m_s2 = 0.5\n", table("6.0"));
    let s = Scenario::parse(&levels, "l.toml").unwrap();
    let f = s.gains::<f64>().local.and_then(|l| l.vertical).unwrap();
    assert_eq!((f.kf, f.ks, f.up, f.down), (6.0, 20.0, 1.5, 0.5));
    let e = Scenario::parse(&format!("{}up_m_s2 = -0.5\n", table("6.0")), "l.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gains.local.vertical.up_m_s2") && e.contains("-0.5"),
        "{e}"
    );
    let e = Scenario::parse(&table("1.25"), "l.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gains.local.vertical.kf") && e.contains("1.25"),
        "{e}"
    );
}

/// Given `[gains.local]` with `braking_m_s2` and `[gains.local.attitude]` (with its own tilt
/// priority), when it parses, then the local gains carry that braking and that law; a local
/// law's gain that is not positive and a braking above `M_p_m_s2` are refused naming their key.
#[test]
fn local_attitude_and_braking_are_read_and_checked() {
    let table = |braking: &str, g3: &str| {
        format!(
            "{PAPER_SCENARIO}\n[gains.velocity_limit]\nspeed_m_s = 5.0\nbraking_m_s2 = 1.4\n\
             \n[gains.local]\nkp = 9.0\nkv = 6.0\nkf = 4.0\nks = 30.0\nM_p_m_s2 = 3.0\n\
             energy_in_J = 0.01\nenergy_out_J = 0.02\nbraking_m_s2 = {braking}\n\
             \n[gains.local.attitude]\nk_theta = 40.0\nk_omega = 0.2\nM_theta = 0.3\n\
             M_omega = 0.1\n\n[gains.local.attitude.tilt_priority]\n\
             trace_weights_Nm = [0.01, 0.01, {g3}]\nomega_gains_Nm_s = [0.1, 0.1, 0.05]\n\
             omega_levels_Nm = [0.3, 0.3, 0.02]\n"
        )
    };
    let s = Scenario::parse(&table("2.1", "0.5"), "a.toml").unwrap();
    let l = s.gains::<f64>().local.expect("the local regime is on");
    assert_eq!(l.braking, Some(2.1));
    let a = l.attitude.expect("its own attitude law");
    assert_eq!((a.attitude.k_mrp, a.attitude.mrp_saturation), (40.0, 0.3));
    let t = a.tilt_priority.expect("its own tilt priority");
    assert_eq!((t.trace_weights.z, t.omega_levels.x), (0.5, 0.3));
    let e = Scenario::parse(&table("2.1", "-0.5"), "a.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gains.local.attitude.tilt_priority.trace_weights_Nm") && e.contains("-0.5"),
        "{e}"
    );
    let e = Scenario::parse(&table("3.5", "0.5"), "a.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gains.local.braking_m_s2") && e.contains("3.5"),
        "{e}"
    );
}

#[test]
fn wrong_type_is_named() {
    let text = PAPER_SCENARIO.replace("duration_s = 30.0", "duration_s = \"long\"");
    let e = Scenario::parse(&text, "w.toml").unwrap_err().to_string();
    assert!(e.contains("w.toml") && e.contains("duration_s"), "{e}");
}

#[test]
fn perturbations_table_is_optional_and_checked() {
    assert!(Scenario::paper().perturbations.is_nominal());
    let text = format!("{PAPER_SCENARIO}\n[perturbations]\ngyro_noise_std_rad_s = 0.01\n");
    let s = Scenario::parse(&text, "p.toml").unwrap();
    assert_eq!(s.perturbations.gyro_noise_std_rad_s, 0.01);
    let text = format!("{PAPER_SCENARIO}\n[perturbations]\ngyro_noise = 0.01\n");
    let e = Scenario::parse(&text, "q.toml").unwrap_err().to_string();
    assert!(e.contains("q.toml") && e.contains("gyro_noise"), "{e}");
    let text = format!("{PAPER_SCENARIO}\n[perturbations]\nposition_noise_std_m = -1.0\n");
    let e = Scenario::parse(&text, "r.toml").unwrap_err().to_string();
    assert!(e.contains("perturbations.position_noise_std_m"), "{e}");
}

/// `paper-no-dive.toml` is the paper's scenario with only `[controller]` changed.
#[test]
fn euler_convention_is_zyx() {
    let mut s = Scenario::paper();
    s.initial.euler_deg = [90.0, 0.0, 90.0];
    let r = s.initial_attitude().to_rotation_matrix();
    // Rz(90) Rx(90) maps body y to inertial z... check body z → inertial x.
    let bz = r * Vector3::z();
    assert!((bz - Vector3::x()).norm() < 1e-12, "{bz}");
}
