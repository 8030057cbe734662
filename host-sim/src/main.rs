fn main() -> anyhow::Result<()> {
    let s = host_sim::scenario::Scenario::paper();
    for p in [
        host_sim::scenario::Precision::F64,
        host_sim::scenario::Precision::F32,
    ] {
        let mut s = s.clone();
        s.simulation.precision = p;
        let t0 = std::time::Instant::now();
        let (summary, recs) = host_sim::sim::run(&s)?;
        println!("{:?}", t0.elapsed());
        println!("{}", serde_json::to_string_pretty(&summary)?);
        for r in recs.iter().step_by(100) {
            println!(
                "{:.2} pe={:.3e} me={:.3e} T={:.3} tau=({:.3},{:.3},{:.3}) flips={} resets={}",
                r.t_s,
                r.position_error_m,
                r.mrp_error,
                r.thrust_N,
                r.torque_x_Nm,
                r.torque_y_Nm,
                r.torque_z_Nm,
                r.m_flips,
                r.q_hat_resets
            );
        }
    }
    Ok(())
}
