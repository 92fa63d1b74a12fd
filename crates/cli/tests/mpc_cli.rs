//! `pendulab simulate` with a controller file of `kind = "mpc"` (`docs/mpc.md`): the cart
//! from 10° with the voltage and a track limit active, and the file's errors naming the key.

mod common;
use common::*;

/// A cart controller file of kind `mpc` with the extra `keys`.
fn controller(dir: &Dir, name: &str, keys: &str) -> String {
    dir.file(
        name,
        &format!(
            "plant = \"cart\"\nrate_hz = 1000.0\n\n[controller]\nkind = \"mpc\"\n{keys}\n\n\
             [safety]\nvoltage_limit = 5.0\ntravel_limit = 0.4\nangle_window_deg = 30.0\n"
        ),
    )
}

#[test]
fn simulate_runs_the_mpc_on_the_cart_within_its_voltage_and_track_limits() {
    let dir = Dir::new("mpc-simulate");
    let lab = dir.path("lab");
    json(&pendulab(&[
        "lab", "init", &lab, "--plant", "cart", "--json",
    ]));
    let file = controller(&dir, "cart_mpc.toml", "travel_limit = 0.08");
    // Ideal loop: the track holds to 2 % (the prediction is linear, the plant not). With the
    // rig's sensors the MPC starts each prediction from the pseudo-differentiated (lagging)
    // velocities and the track is overrun by up to 10 %: measured 0.0858 m.
    for (name, track_slack, scenario) in [
        (
            "ideal",
            1.02,
            "initial_state = [0.0, 0.17453292519943295, 0.0, 0.0]\nduration = 5.0\n",
        ),
        // The rig's encoders, pseudo-differentiated velocities and 16-bit D/A.
        (
            "rig",
            1.10,
            "initial_state = [0.0, 0.17453292519943295, 0.0, 0.0]\nduration = 5.0\n\
             [imperfections]\nquantization = true\npseudo_differentiator = true\n\
             saturation = true\ndac = true\n",
        ),
    ] {
        let scen = dir.file(&format!("{name}.toml"), scenario);
        let out = dir.path(name);
        let v = json(&pendulab(&[
            "simulate",
            "--lab",
            &lab,
            "--controller",
            &file,
            "--scenario",
            &scen,
            "--out",
            &out,
            "--json",
        ]));
        assert_eq!(v["samples"], 5001, "{name}");
        assert_eq!(v["left_travel"], false, "{name}");
        let theta = v["final_state"][1].as_f64().unwrap();
        assert!(theta.abs() < 1e-2, "{name}: final θ = {theta}");
        // The command never exceeds 5 V, and reaches it (the limit is active).
        let peak = v["peak_command"].as_f64().unwrap();
        assert!(peak <= 5.0 + 1e-12 && peak > 4.9, "{name}: {peak}");
        // The track limit at every sample, from the written run.
        let csv = std::fs::read_to_string(dir.join(name).join("run.csv")).unwrap();
        let mut lines = csv.lines();
        assert_eq!(lines.next().unwrap(), "t,z,theta,dz,dtheta,v,u_ctrl");
        let max_z = lines
            .map(|l| l.split(',').nth(1).unwrap().parse::<f64>().unwrap().abs())
            .fold(0.0, f64::max);
        assert!(max_z <= 0.08 * track_slack, "{name}: max |z| = {max_z}");
        assert!(max_z > 0.04, "{name}: max |z| = {max_z}");
    }
}

#[test]
fn the_mpc_files_errors_name_the_key() {
    let dir = Dir::new("mpc-errors");
    let lab = dir.path("lab");
    json(&pendulab(&[
        "lab", "init", &lab, "--plant", "cart", "--json",
    ]));
    for (keys, needles) in [
        ("horizon = 0", &["controller.horizon", "0"][..]),
        ("step = 0.0105", &["controller.step", "0.0105"]),
        ("r = -1.0", &["controller.r", "-1"]),
        ("q = [1.0, 1.0]", &["controller.q", "2"]),
        ("travel_limit = 0.0", &["controller.travel_limit"]),
        ("u_max = nan", &["controller.u_max"]),
        ("qf = [1.0, 1.0, 0.0, 0.0]", &["qf", "mpc"]),
    ] {
        let file = controller(&dir, "bad.toml", keys);
        fails_with(
            &pendulab(&["simulate", "--lab", &lab, "--controller", &file]),
            needles,
        );
    }
}
