//! Witnesses and soundness sampling of the a-priori bounds (host_sim::tight_bounds).

use host_sim::tight_bounds::setup::Setup;
use host_sim::tight_bounds::witness::{witnesses, WitnessBudget};

#[test]
fn print_paper_witnesses() {
    let setup = Setup::paper();
    let t = std::time::Instant::now();
    let w = witnesses(&setup, 1, &WitnessBudget::default()).unwrap();
    println!("{:?} evals {}", t.elapsed(), w.evaluations);
    let b = setup.certificate().unwrap().bounds;
    println!(
        "paper: {} {} {:?}",
        b.angular_velocity, b.angular_acceleration, b.torque_max
    );
    for x in &w.all {
        println!(
            "{}: {:.4}  u={:.3?} wd={:.3?} wdd={:.3?} tau={:.4?}",
            x.quantity.name(),
            x.value,
            x.values.u.as_slice(),
            x.values.angular_velocity.as_slice(),
            x.values.angular_acceleration.as_slice(),
            x.values.torque.as_slice()
        );
        println!("   {:?}", x.state);
    }
}
