//! Emulator physics throughput: steps per second of the emulated cart rig between the D/A
//! and the encoders ([`pendulab_rig::emulator::RigPlant`]: amplifier, one RK4 step of the
//! nonlinear plant, the two encoders), without the network or the real-time clock. Balanced
//! by a fixed LQR-like gain on the counts so the state stays bounded; prints one figure per
//! round: `cargo run --release -p pendulab-rig --example emulator_steps`.

use pendulab_rig::emulator::{EmulatorConfig, PlantKind, RigPlant};
use std::time::Instant;

fn main() -> Result<(), pendulab_rig::RigError> {
    let cfg = EmulatorConfig::new(PlantKind::Cart, [0.0, 0.05, 0.0, 0.0]);
    let spec = PlantKind::Cart.spec();
    let steps = [spec.encoders[0].step, spec.encoders[1].step];
    // u = −K x on the positions from the counts and the true velocities (a stabilising
    // gain of the book cart, cdip_lqr_sim's order of magnitude).
    let k = [-3.16, -13.5, -4.48, -2.26];
    let n = 2_000_000u64;
    for round in 0..5 {
        let mut rig = RigPlant::new(&cfg)?;
        let t0 = Instant::now();
        let mut check = 0i64;
        for _ in 0..n {
            let c = rig.counts(0);
            let x = rig.state();
            let q = [
                f64::from(c[0]) * steps[0],
                f64::from(c[1]) * steps[1] + std::f64::consts::PI,
            ];
            let u = -(k[0] * q[0] + k[1] * q[1] + k[2] * x[2] + k[3] * x[3]);
            let (v, _) = rig.amplify(u);
            rig.step(v);
            check = check.wrapping_add(i64::from(c[1]));
        }
        let dt = t0.elapsed().as_secs_f64();
        println!(
            "round {round}: {:.3e} steps/s (final θ {:.2e} rad, check {check})",
            n as f64 / dt,
            rig.state()[1]
        );
    }
    Ok(())
}
