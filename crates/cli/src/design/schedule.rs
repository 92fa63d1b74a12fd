//! `pendulab design gain-schedule` (arm only): the gain-scheduled LQ integral servo of book
//! part 2 §1.5 (example 1.7) on the lab's arm by the SOS program
//! `pendulab_lmi::synthesis::gain_scheduled_lq`, `K(ρ) = −L(ρ) X(ρ)⁻¹`, `ρ = 1 − cos θ₁`;
//! the file's `x_coefficients`/`l_coefficients`, and the schedule printed: `K(ρ)` at five
//! angles and the frozen closed loops at the range's ends.

use super::inputs::list;
use super::methods::weights;
use super::{Designed, ScheduleArgs};
use crate::lqr::fmt_row;
use anyhow::{Context, Result, bail};
use pendulab_control::spec::DesignInput;
use pendulab_lmi::SolveOptions;
use pendulab_lmi::synthesis::{
    GainScheduleSpec, LpvPlant, LqWeights, ScheduledGain, gain_scheduled_lq,
};
use pendulab_lti::{Complex64, Continuous, Mat, StateSpace};
use pendulab_plants::ArmPendulum;
use pendulab_plants::spec::{PlantParameters, PlantSpec};
use serde::Serialize;

/// The margin `ε` of the SOS program's strict inequalities (the M-file's `ep = 1e-6`).
const SOS_MARGIN: f64 = 1e-6;

/// What `gain_schedule` designs, besides its printed schedule: the schedule, the frozen model
/// `(Ã(0), B̃(0))` of the upright, `K(0)` and its closed-loop poles, `Q`'s diagonal and `Θ0`.
struct GsDesign {
    sched: ScheduledGain,
    a0: Mat,
    b0: Mat,
    k0: Mat,
    poles0: Vec<Complex64>,
    q: Vec<f64>,
    theta10_max_deg: f64,
}

/// The schedule as printed: `K(ρ)` at a few angles, the frozen closed loops at the range's
/// ends, the cost bounds.
#[derive(Serialize)]
pub(super) struct ScheduleJson {
    /// The scheduling variable.
    variable: &'static str,
    /// The design range of `ρ`.
    rho_range: [f64; 2],
    /// The design range of `|θ₁|` \[deg\].
    theta1_range_deg: [f64; 2],
    /// The rate bound `|ρ̇| ≤ ν` \[1/s\].
    rho_dot_max: f64,
    /// The minimised cost bound `γ*`.
    gamma_star: f64,
    /// The cost bound of the schedule written (`≤ (1 + δ) γ*`).
    gamma: f64,
    /// `K(ρ)` at five angles from 0 to `Θ`.
    gains: Vec<GainAt>,
    /// The closed-loop poles of the frozen models at `ρ = 0` and `ρ = ρ̄`.
    vertices: Vec<VertexPoles>,
}

#[derive(Serialize)]
struct GainAt {
    theta1_deg: f64,
    rho: f64,
    /// pendulab/MATLAB convention `u = −K(ρ) [x; w]`.
    k: Vec<f64>,
    /// The book's convention `u = +K_book [x; w]`, `K_book = L(ρ) X(ρ)⁻¹ = −K(ρ)`.
    k_book: Vec<f64>,
}

#[derive(Serialize)]
struct VertexPoles {
    rho: f64,
    closed_loop_poles: Vec<[f64; 2]>,
}

/// `gain-schedule`: the book's SOS gain-scheduled LQ servo on the lab's arm (module
/// documentation); errors name the option, the cart, or the failed solve.
fn gain_schedule(plant: &PlantSpec, sa: &ScheduleArgs) -> Result<(GsDesign, ScheduleJson)> {
    let PlantParameters::Arm(p) = plant.parameters() else {
        bail!(
            "design gain-schedule: the lab's plant is the cart pendulum, and this design is the arm's \
             (book part 2 §1.5: ρ = 1 − cos θ1 schedules the arm's linearisation; the cart's does not \
             depend on its position). Use `design servo` or `design lmi-servo` for the cart"
        );
    };
    let q = weights(&sa.q, sa.r, 5)?;
    let angle = |flag: &str, v: f64| -> Result<f64> {
        if !(v.is_finite() && v > 0.0 && v < 90.0) {
            bail!(
                "{flag} {v}: the design range 0 ≤ |θ1| ≤ {v}° is empty or reaches 90° (where cos θ1 = 0); give 0 < {flag} < 90"
            );
        }
        Ok(v)
    };
    let th_max = angle("--theta1-max-deg", sa.theta1_max_deg)?;
    let th0_max = angle("--theta10-max-deg", sa.theta10_max_deg.unwrap_or(th_max))?;
    if !(sa.rho_dot_max.is_finite() && sa.rho_dot_max >= 0.0) {
        bail!(
            "--rho-dot-max {}: must be a finite number ≥ 0",
            sa.rho_dot_max
        );
    }
    if !(sa.gamma_relax.is_finite() && sa.gamma_relax >= 0.0) {
        bail!(
            "--gamma-relax {}: must be a finite number ≥ 0",
            sa.gamma_relax
        );
    }
    if !sa.reference.is_finite() || !sa.step_time.is_finite() || sa.step_time < 0.0 {
        bail!(
            "--reference {}, --step-time {}: must be finite, the step time ≥ 0",
            sa.reference,
            sa.step_time
        );
    }
    if sa.reference.abs().to_degrees() > th_max {
        bail!(
            "--reference {} rad ({:.2}°) is outside the design range |θ1| ≤ {th_max}° (--theta1-max-deg): the schedule is not certified there",
            sa.reference,
            sa.reference.to_degrees()
        );
    }
    let lpv = ArmPendulum::new(*p).context("the lab's arm")?.lpv();
    // [x; w], w = ∫(r − θ1) dt: Ã(ρ) = [[A(ρ), 0], [−C, 0]], B̃(ρ) = [B(ρ); 0]; the −C row
    // belongs to the constant term, the ρ-coefficient is padded with zeros.
    let (a0, b0) = pendulab_lti::design::integral_augmentation(&StateSpace::continuous(
        lpv.a0.clone(),
        lpv.b0.clone(),
        Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
        Mat::zeros(1, 1),
    )?)?;
    let mut a1 = Mat::zeros(5, 5);
    a1.view_mut((0, 0), (4, 4)).copy_from(&lpv.a1);
    let mut b1 = Mat::zeros(5, 1);
    b1.view_mut((0, 0), (4, 1)).copy_from(&lpv.b1);
    let rho_bar = 1.0 - th_max.to_radians().cos();
    let spec = GainScheduleSpec {
        rho_range: (0.0, rho_bar),
        rho0_range: (0.0, 1.0 - th0_max.to_radians().cos()),
        rho_dot_bound: sa.rho_dot_max,
        lq: LqWeights {
            q: Mat::from_diagonal(&nalgebra::DVector::from_vec(q.clone())),
            r: Mat::from_element(1, 1, sa.r),
        },
        margin: SOS_MARGIN,
        gamma_relax: sa.gamma_relax,
        balance: true,
    };
    let lpv_aug = LpvPlant {
        a0: a0.clone(),
        a1: a1.clone(),
        b0: b0.clone(),
        b1: b1.clone(),
    };
    let d = gain_scheduled_lq(&lpv_aug, &spec, &SolveOptions::default())
        .context("the gain-scheduled SOS design")?;
    let Some(gamma_star) = d.gamma_star else {
        bail!(
            "gain-schedule: the γ minimisation was not solved (status {:?}): no schedule for these weights and ranges; nothing written",
            d.status
        );
    };
    let Some(sched) = d.schedule else {
        bail!(
            "gain-schedule: the re-solve with γ ≤ (1 + {}) γ* did not pass its rechecks (status {:?}); nothing written",
            sa.gamma_relax,
            d.status
        );
    };
    let gains = (0..5)
        .map(|j| {
            let th = th_max * f64::from(j) / 4.0;
            let rho = 1.0 - th.to_radians().cos();
            let k: Vec<f64> = sched.gain(rho)?.row(0).iter().copied().collect();
            Ok(GainAt {
                theta1_deg: th,
                rho,
                k_book: k.iter().map(|x| -x).collect(),
                k,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let mut vertices = Vec::new();
    let mut poles0 = Vec::new();
    for rho in [0.0, rho_bar] {
        let (a, b) = (&a0 + &a1 * rho, &b0 + &b1 * rho);
        let poles = pendulab_lti::linalg::eigenvalues(&(&a - &b * &sched.gain(rho)?))?;
        if let Some(bad) = poles.iter().find(|z| z.re >= 0.0) {
            bail!(
                "gain-schedule: the frozen closed loop at ρ = {rho} has the pole {bad} outside the open left half-plane; nothing written"
            );
        }
        vertices.push(VertexPoles {
            rho,
            closed_loop_poles: poles.iter().map(|z| [z.re, z.im]).collect(),
        });
        if rho == 0.0 {
            poles0 = poles;
        }
    }
    let out = ScheduleJson {
        variable: "rho = 1 - cos(theta1)",
        rho_range: [0.0, rho_bar],
        theta1_range_deg: [0.0, th_max],
        rho_dot_max: sa.rho_dot_max,
        gamma_star,
        gamma: sched.gamma,
        gains,
        vertices,
    };
    let k0 = sched.gain(0.0)?;
    Ok((
        GsDesign {
            sched,
            a0,
            b0,
            k0,
            poles0,
            q,
            theta10_max_deg: th0_max,
        },
        out,
    ))
}

/// `gain-schedule`: the design as a [`Designed`], its `K`, poles and loop those at `ρ = 0`
/// (the upright), the schedule attached.
pub(super) fn gain_schedule_method(
    plant: &PlantSpec,
    ss: &StateSpace<Continuous>,
    sa: &ScheduleArgs,
) -> Result<Designed> {
    let (d, designed) = gain_schedule(plant, sa)?;
    let rows = |m: &Mat| -> String {
        let r: Vec<String> = (0..m.nrows())
            .map(|i| format!("[{}]", list(&m.row(i).iter().copied().collect::<Vec<_>>())))
            .collect();
        format!("[{}]", r.join(", "))
    };
    let xs: Vec<String> = d.sched.x_coefficients.iter().map(rows).collect();
    let ls: Vec<String> = d
        .sched
        .l_coefficients
        .iter()
        .map(|l| format!("[{}]", list(&l.row(0).iter().copied().collect::<Vec<_>>())))
        .collect();
    let loop_ss = StateSpace::new(
        d.a0.clone(),
        d.b0.clone(),
        d.k0.clone(),
        Mat::zeros(1, 1),
        ss.domain(),
    )?;
    let note = "# K(ρ) = −L(ρ) X(ρ)⁻¹ (library sign, u = −K(ρ) [x; w]), ρ = 1 − cos θ1, w = ∫(r − θ1) dt;\n\
         # the book's K = L X⁻¹ is −K(ρ). Guaranteed for ρ and dρ/dt in the design ranges of the record.\n";
    let table = format!(
        "kind = \"gain-scheduled\"\nschedule = \"one-minus-cos-q0\"\nx_coefficients = [{}]\nl_coefficients = [{}]\nreference = [{:?}]\nstep_time = {:?}\n",
        xs.join(", "),
        ls.join(", "),
        sa.reference,
        sa.step_time
    );
    let k: Vec<f64> = d.k0.row(0).iter().copied().collect();
    let words = format!(
        "Q = diag([{}]), R = {}, on [x; w], w = ∫(r − θ1) dt, |θ1| ≤ {}°, |θ1(0)| ≤ {}°, |dρ/dt| ≤ {}, γ* = {:.4}, γ = {:.4} ≤ (1 + {}) γ*",
        list(&d.q),
        sa.r,
        sa.theta1_max_deg,
        d.theta10_max_deg,
        sa.rho_dot_max,
        designed.gamma_star,
        designed.gamma,
        sa.gamma_relax
    );
    let record = vec![
        ("q".to_string(), DesignInput::List(d.q.clone())),
        ("r".to_string(), DesignInput::Number(sa.r)),
        (
            "rho_range".to_string(),
            DesignInput::List(vec![designed.rho_range[0], designed.rho_range[1]]),
        ),
        (
            "rho0_range".to_string(),
            DesignInput::List(vec![0.0, 1.0 - d.theta10_max_deg.to_radians().cos()]),
        ),
        (
            "rho_dot_max".to_string(),
            DesignInput::Number(sa.rho_dot_max),
        ),
        (
            "gamma_relax".to_string(),
            DesignInput::Number(sa.gamma_relax),
        ),
        ("margin".to_string(), DesignInput::Number(SOS_MARGIN)),
        ("reference".to_string(), DesignInput::Number(sa.reference)),
        ("step_time".to_string(), DesignInput::Number(sa.step_time)),
    ];
    Ok(Designed {
        table,
        k,
        poles: d.poles0.clone(),
        loop_ss: Some(loop_ss),
        inputs: words,
        note,
        record,
        schedule: Some(designed),
    })
}

/// Prints the schedule: its ranges and bounds, `K(ρ)` at the five angles in both sign
/// conventions, and the frozen closed loops' poles at the range's ends.
pub(super) fn print_schedule(s: &ScheduleJson) {
    println!(
        "schedule K(ρ), ρ = 1 − cos θ1, designed for ρ ∈ [{:.6}, {:.6}] (|θ1| ≤ {}°), |dρ/dt| ≤ {}; γ* = {:.4}, γ = {:.4}",
        s.rho_range[0], s.rho_range[1], s.theta1_range_deg[1], s.rho_dot_max, s.gamma_star, s.gamma
    );
    println!("(the gain and poles above are those at ρ = 0)");
    for g in &s.gains {
        println!("  θ1 = {:6.2}°, ρ = {:.6}", g.theta1_deg, g.rho);
        println!("    K      (u = −K(ρ) [x; w]):      {}", fmt_row(&g.k));
        println!("    K_book (u = +K_book [x; w]):    {}", fmt_row(&g.k_book));
    }
    println!("closed-loop poles of the frozen models at the range's ends [1/s]:");
    for v in &s.vertices {
        let p: Vec<String> = v
            .closed_loop_poles
            .iter()
            .map(|[re, im]| format!("{re:.4}{im:+.4}j"))
            .collect();
        println!("  ρ = {:.6}: {}", v.rho, p.join(", "));
    }
}
