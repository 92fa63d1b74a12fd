//! Writes one of each figure type and both animations into a directory, and prints the time and
//! size of each: `cargo run --release -p pendulab-plot --example gallery -- [DIR]` (default
//! `target/gallery`).
//!
//! The data are computed here from the book's cart-type pendulum (book table 3.5, `docs/model.md`
//! §1) with a small RK4 loop, so that the pictures look like the book's; the plotting calls are
//! what the book examples and the report use.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pendulab_lti::{Complex64, Trajectory};
use pendulab_plot::{
    Animation, AnimationOptions, ArmGeometry, Axes, Bode, CartGeometry, Channel, Color, Figure,
    GainCurves, IdentFit, Marker, PoleZeroMap, RegionBound, SignalPanel, Surface, TimeResponse,
    region_of_attraction,
};

// Book parameters (table 3.5).
const AC: f64 = 6.25;
const BC: f64 = 4.36;
const MP: f64 = 0.107;
const LP: f64 = 0.230;
const JP: f64 = 1.59e-3;
const MUP: f64 = 2.35e-4;
const G: f64 = 9.81;

fn cart_rhs(x: [f64; 4], v: f64) -> [f64; 4] {
    let j = JP + MP * LP * LP;
    let zdd = -AC * x[2] + BC * v;
    let thdd = (MP * G * LP * x[1].sin() - MUP * x[3] - MP * LP * x[1].cos() * zdd) / j;
    [x[2], x[3], zdd, thdd]
}

/// Simulates the nonlinear cart pendulum at 1 kHz under the control law `u(t, x)` (saturated to
/// ±5 V) and returns the trajectory with x = [z, θ, ż, θ̇] and u = [v].
fn simulate(x0: [f64; 4], t_end: f64, u: impl Fn(f64, &[f64; 4]) -> f64) -> Trajectory {
    let h = 1e-3;
    let n = (t_end / h).round() as usize + 1;
    let mut t = Vec::with_capacity(n);
    let mut xs = Vec::with_capacity(4 * n);
    let mut us = Vec::with_capacity(n);
    let mut x = x0;
    for k in 0..n {
        let tk = k as f64 * h;
        let v = u(tk, &x).clamp(-5.0, 5.0);
        t.push(tk);
        xs.extend_from_slice(&x);
        us.push(v);
        let f = |x: [f64; 4]| cart_rhs(x, v);
        let add = |a: [f64; 4], b: [f64; 4], s: f64| {
            [
                a[0] + s * b[0],
                a[1] + s * b[1],
                a[2] + s * b[2],
                a[3] + s * b[3],
            ]
        };
        let k1 = f(x);
        let k2 = f(add(x, k1, h / 2.0));
        let k3 = f(add(x, k2, h / 2.0));
        let k4 = f(add(x, k3, h));
        for i in 0..4 {
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    Trajectory::from_row_major(t, (4, &xs), (1, &us), (0, &[])).expect("consistent buffers")
}

/// LQ gains of the IP Toolbox sample `cdip_lqr_sim.m`, book convention u = +K x with the book's
/// sign.
const K_Q: [(&str, [f64; 4]); 3] = [
    ("q₂ = 10", [3.16228, 13.47175, 4.48137, 2.26289]),
    ("q₂ = 50", [3.16228, 15.81695, 4.72006, 2.44448]),
    ("q₂ = 100", [3.16228, 18.12126, 4.93879, 2.61065]),
];

fn lqr_law(k: [f64; 4]) -> impl Fn(f64, &[f64; 4]) -> f64 {
    move |_, x| k[0] * x[0] + k[1] * x[1] + k[2] * x[2] + k[3] * x[3]
}

struct Log {
    dir: PathBuf,
    total: f64,
}

impl Log {
    fn fig(&mut self, stem: &str, fig: &Figure) {
        let t0 = Instant::now();
        let saved = fig.save(&self.dir, stem).expect("figure renders");
        let dt = t0.elapsed().as_secs_f64();
        self.total += dt;
        let size = |p: &Path| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0);
        println!(
            "{stem:<28} {:>7.1} ms   svg {:>7} B   png {:>7} B",
            dt * 1e3,
            size(&saved.svg),
            size(&saved.png)
        );
    }
}

fn main() {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target/gallery"));
    std::fs::create_dir_all(&dir).expect("output directory");
    let mut log = Log {
        dir: dir.clone(),
        total: 0.0,
    };

    // 1. Superposition (p1c41_cdip_response): plain series, three line styles.
    {
        let kp = 1.0;
        let (a, b) = (-AC, -BC * kp);
        // ẋ = [[0, 1], [b, a]] x + [0; 1] r, y = BC kP x1; RK4 at 10 ms like t = 0:0.01:10.
        let run = |x0: [f64; 2], r: &dyn Fn(f64) -> f64| -> Vec<f64> {
            let h = 0.01;
            let mut x = x0;
            let mut y = Vec::new();
            for k in 0..=1000 {
                let t = k as f64 * h;
                y.push(BC * kp * x[0]);
                let f = |t: f64, x: [f64; 2]| [x[1], b * x[0] + a * x[1] + r(t)];
                let k1 = f(t, x);
                let k2 = f(
                    t + h / 2.0,
                    [x[0] + h / 2.0 * k1[0], x[1] + h / 2.0 * k1[1]],
                );
                let k3 = f(
                    t + h / 2.0,
                    [x[0] + h / 2.0 * k2[0], x[1] + h / 2.0 * k2[1]],
                );
                let k4 = f(t + h, [x[0] + h * k3[0], x[1] + h * k3[1]]);
                for i in 0..2 {
                    x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
            }
            y
        };
        let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
        let y1 = run([1.0, 1.0], &|_| 0.0);
        let y2 = run([0.0, 0.0], &|t| 2.0 * t.sin());
        let y3 = run([1.0, 1.0], &|t| 2.0 * t.sin());
        let mut ax = Axes::new();
        ax.xlabel("time [s]").ylabel("position [m]");
        ax.plot(&t, &y1).label("y₁(t)").color(Color::RED).dashed();
        ax.plot(&t, &y2).label("y₂(t)").color(Color::GREEN).dotted();
        ax.plot(&t, &y3).label("y₃(t)").color(Color::BLUE);
        log.fig(
            "time_response",
            &Figure::new(ax).title("Zero-input, zero-state and full response"),
        );
    }

    // 2. Several runs of a 1 kHz simulation, stacked panels (cdip_lqr_sim).
    let runs: Vec<(String, Trajectory)> = K_Q
        .iter()
        .map(|(name, k)| {
            (
                name.to_string(),
                simulate([0.0, 15f64.to_radians(), 0.0, 0.0], 4.0, lqr_law(*k)),
            )
        })
        .collect();
    {
        let mut tr = TimeResponse::new().title("Cart-type pendulum, LQR, θ(0) = 15°");
        for (name, r) in &runs {
            tr = tr.run(name.clone(), r);
        }
        let fig = tr
            .panel(SignalPanel::new(Channel::State(0), "z [m]"))
            .panel(SignalPanel::new(Channel::State(1), "θ [deg]").scaled(180.0 / PI))
            .panel(SignalPanel::new(Channel::Input(0), "v [V]").stairs())
            .figure()
            .expect("channels exist");
        log.fig("trajectories", &fig);
    }

    // 3. Bode (p1c213_pidbode): P(s), C(s) = kP (1 + 1/(T_I s) + T_D s), P(s) C(s).
    {
        let (kp, ki, kd) = (10.0, 5.0, 0.8);
        let w: Vec<f64> = (0..=400)
            .map(|k| 10f64.powf(-2.0 + 5.0 * k as f64 / 400.0))
            .collect();
        let p: Vec<Complex64> = w
            .iter()
            .map(|&w| {
                let s = Complex64::new(0.0, w);
                BC / (s * (s + AC))
            })
            .collect();
        let c: Vec<Complex64> = w
            .iter()
            .map(|&w| {
                let s = Complex64::new(0.0, w);
                kp + ki / s + kd * s
            })
            .collect();
        let pc: Vec<Complex64> = p.iter().zip(&c).map(|(a, b)| a * b).collect();
        let fig = Bode::new()
            .response("P(s)", &w, &p)
            .response("C(s)", &w, &c)
            .response("P(s)C(s)", &w, &pc)
            .title("PID control of the cart: Bode diagram")
            .figure();
        log.fig("bode", &fig);
    }

    // 4. Pole map with the D-stability region of p2c122 (Re < −2, Re > −16, sector π/4).
    {
        let poles = [
            Complex64::new(-3.1, 2.4),
            Complex64::new(-3.1, -2.4),
            Complex64::new(-5.6, 0.0),
            Complex64::new(-9.8, 4.1),
            Complex64::new(-9.8, -4.1),
        ];
        let lq = [
            Complex64::new(-1.2, 0.0),
            Complex64::new(-4.0, 5.5),
            Complex64::new(-4.0, -5.5),
            Complex64::new(-22.0, 0.0),
        ];
        let fig = PoleZeroMap::new()
            .region(
                "D-stability region",
                &[
                    RegionBound::DecayRate(2.0),
                    RegionBound::SpeedLimit(16.0),
                    RegionBound::Sector(PI / 4.0),
                ],
            )
            .poles("LMI design", &poles)
            .poles("LQ design", &lq)
            .zeros("zeros", &[Complex64::new(-6.9, 0.0)])
            .title("Closed-loop poles and the design region")
            .figure();
        log.fig("pole_map", &fig);
        let zp: Vec<Complex64> = poles.iter().map(|p| (p * 0.1).exp()).collect();
        let fig = PoleZeroMap::discrete()
            .poles("ZOH, ts = 0.1 s", &zp)
            .title("Discrete-time poles")
            .figure();
        log.fig("pole_map_discrete", &fig);
    }

    // 5. Gain scheduling curves against constant LQ gains (p2c15_ex7 fig. 1.16).
    {
        let th: Vec<f64> = (0..=130).map(|k| k as f64 * 0.5).collect();
        let names = ["K₁₁", "K₁₂", "K₁₃", "K₁₄", "K₂"];
        let lq = [-4.9, 27.7, -2.1, 3.6, 2.0];
        let mut gc = GainCurves::new("θ₁ [deg]", &th).title("Gain-scheduled servo gains K(ρ(θ₁))");
        for (k, n) in names.iter().enumerate() {
            let v: Vec<f64> = th
                .iter()
                .map(|t| {
                    let rho = 1.0 - t.to_radians().cos();
                    lq[k] * (1.0 + (0.8 + 0.3 * k as f64) * rho + 0.6 * rho * rho)
                })
                .collect();
            gc = gc.gain(*n, &v, Some(lq[k]));
        }
        log.fig("gain_curves", &gc.figure().expect("gains"));
    }

    // 6. Identification fit: measured (noisy, quantised) vs model.
    {
        let r = &runs[0].1;
        let t = r.t();
        let model: Vec<f64> = r.x_signal(1).iter().map(|v| v.to_degrees()).collect();
        let mut seed = 12345u64;
        let measured: Vec<f64> = model
            .iter()
            .enumerate()
            .map(|(k, v)| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let noise = ((seed >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.6;
                let step = 360.0 / 14400.0;
                ((v * 1.04 + 0.3 * (k as f64 * 0.004).sin() + noise) / step).round() * step
            })
            .collect();
        let fig = IdentFit::new(t)
            .signal("θ [deg]", &measured, &[("identified model", &model)])
            .title("Pendulum angle: measurement and identified model")
            .figure()
            .expect("fit");
        log.fig("ident_fit", &fig);
    }

    // 7. Region of attraction of the saturated LQR (q₂ = 10) over θ(0) × θ'(0), and the
    //    settling time as a heat map.
    {
        let (nx, ny) = (41, 31);
        let xr = (-60.0, 60.0);
        let yr = (-400.0, 400.0);
        let mut ok = Vec::with_capacity(nx * ny);
        let mut settle = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let th = (xr.0 + (xr.1 - xr.0) * (i as f64 + 0.5) / nx as f64).to_radians();
                let om = (yr.0 + (yr.1 - yr.0) * (j as f64 + 0.5) / ny as f64).to_radians();
                let tr = simulate([0.0, th, 0.0, om], 3.0, lqr_law(K_Q[0].1));
                let thv = tr.x_signal(1);
                let good = thv.iter().all(|v| v.abs() < 1.6) && thv[thv.len() - 1].abs() < 0.02;
                ok.push(good);
                let ts = thv
                    .iter()
                    .rposition(|v| v.abs() > 2f64.to_radians())
                    .map(|k| tr.t()[k])
                    .unwrap_or(0.0);
                settle.push(if good { ts } else { f64::NAN });
            }
        }
        let mut ax = region_of_attraction(xr, yr, nx, ny, &ok, "θ(0) [deg]", "θ'(0) [deg/s]");
        ax.title("Region of attraction, LQR with |v| ≤ 5 V");
        log.fig("region_of_attraction", &Figure::new(ax));
        let mut ax = Axes::new();
        ax.xlabel("θ(0) [deg]")
            .ylabel("θ'(0) [deg/s]")
            .title("Settling time (|θ| < 2°)")
            .grid(false);
        ax.heat_map(xr, yr, nx, ny, &settle, "settling time [s]");
        log.fig("heat_map", &Figure::new(ax));
    }

    // 8. Lyapunov function surface (p1c43_lyapunov_func).
    {
        let s = Surface::from_fn((-5.0, 5.0), (-5.0, 5.0), 21, 21, |a, b| a * a + b * b)
            .labels("x₁", "x₂", "V(x)")
            .title("V(x) = x₁² + x₂²");
        log.fig("surface", &Figure::new(s));
    }

    // 9. Bars and scatter.
    {
        let mut bars = Axes::new();
        let x = [1.0, 2.0, 3.0, 4.0];
        bars.bar(&x, &[0.394, 0.701, 0.755, 0.52])
            .label("|φ| peaks")
            .color(Color::BLUE);
        bars.xlabel("peak number").ylabel("|φ| [rad]").title("Bars");
        let mut sc = Axes::new();
        let zs: Vec<f64> = (0..40)
            .map(|k| (k as f64 * 0.37).sin() * 0.1 + 0.2)
            .collect();
        let ps: Vec<f64> = (0..40)
            .map(|k| (k as f64 * 0.61).cos() * 0.05 + 0.24)
            .collect();
        sc.scatter(&zs, &ps)
            .label("runs")
            .color(Color::PURPLE)
            .marker(Marker::Circle);
        sc.xlabel("z(0) [m]").ylabel("z peak [m]").title("Scatter");
        log.fig("bar_scatter", &Figure::row([bars, sc]));
    }
    println!("figures: {:.1} ms in total", log.total * 1e3);

    // 10. Animations: cart swing-up (energy pumping, then LQR) and the arm pendulum.
    {
        let k = K_Q[0].1;
        // Energy pumping (book part 2 §3.2.3): commanded acceleration −K₁ θ' cos θ scaled
        // by the energy still missing, with a weak pull of the cart to the rail's centre; LQR
        // once the pendulum is within 20° of upright.
        let j = JP + MP * LP * LP;
        let e_top = 2.0 * MP * G * LP;
        let swing = simulate([0.1, PI + 0.001, 0.0, 0.0], 10.0, move |_, x| {
            let th = (x[1] + PI).rem_euclid(2.0 * PI) - PI;
            if th.abs() < 20f64.to_radians() {
                k[0] * x[0] + k[1] * th + k[2] * x[2] + k[3] * x[3]
            } else {
                let e = 0.5 * j * x[3] * x[3] + MP * G * LP * (1.0 + x[1].cos());
                let gain = (8.0 * (e_top - e) / e_top).clamp(-1.0, 1.0);
                let acc = -6.0 * gain * x[3] * x[1].cos() - 20.0 * x[0] - 6.0 * x[2];
                (AC * x[2] + acc) / BC
            }
        });
        let zs = swing.x_signal(0);
        println!(
            "swing-up: z in [{:.3}, {:.3}] m, final θ = {:.3} rad",
            zs.iter().cloned().fold(f64::INFINITY, f64::min),
            zs.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            swing.x_signal(1)[swing.len() - 1]
        );
        let t0 = Instant::now();
        let anim = Animation::cart(
            swing.t(),
            swing.x_signal(0),
            swing.x_signal(1),
            CartGeometry::default(),
        )
        .expect("finite data")
        .title("Cart-type pendulum: swing-up and LQR");
        let gi = anim.save_gif(dir.join("cart.gif")).expect("gif");
        let t_gif = t0.elapsed().as_secs_f64();
        let si = anim.save_svg(dir.join("cart.svg")).expect("svg");
        std::fs::write(
            dir.join("cart_frame.png"),
            anim.frame_png(4.0).expect("png"),
        )
        .expect("write");
        println!(
            "cart.gif: {} frames every {:.2} s, {} B, {:.0} ms; cart.svg: {} B",
            gi.frames,
            gi.frame_interval,
            gi.bytes,
            t_gif * 1e3,
            si.bytes
        );

        let n = 6001;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
        let th1: Vec<f64> = t
            .iter()
            .map(|t| {
                (PI / 3.0)
                    * (1.0 - (-2.0 * t).exp() * (1.0 + 2.0 * t))
                    * if *t < 3.0 {
                        1.0
                    } else {
                        (-(t - 3.0) * 3.0).exp()
                    }
            })
            .collect();
        let th2: Vec<f64> = t
            .iter()
            .zip(&th1)
            .map(|(t, a)| -0.15 * a * (-(t * 1.5)).exp() * (9.0 * t).sin())
            .collect();
        let t0 = Instant::now();
        let anim = Animation::arm(&t, &th1, &th2, ArmGeometry::default())
            .expect("finite data")
            .title("Arm-type pendulum: LQ servo")
            .options(AnimationOptions {
                fps: 20.0,
                ..Default::default()
            });
        let gi = anim.save_gif(dir.join("arm.gif")).expect("gif");
        let t_gif = t0.elapsed().as_secs_f64();
        let si = anim.save_svg(dir.join("arm.svg")).expect("svg");
        std::fs::write(dir.join("arm_frame.png"), anim.frame_png(1.0).expect("png"))
            .expect("write");
        println!(
            "arm.gif: {} frames every {:.2} s, {} B, {:.0} ms; arm.svg: {} B",
            gi.frames,
            gi.frame_interval,
            gi.bytes,
            t_gif * 1e3,
            si.bytes
        );
    }
    println!("written to {}", dir.display());
}
