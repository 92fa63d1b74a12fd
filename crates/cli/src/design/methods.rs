//! The state-feedback methods of `pendulab design` on the lab plant's upright linearisation:
//! `lqr`, `place`, `servo` and `lmi-servo`, `observer`, and the drive's `p` step, each a
//! [`Designed`] (the `[controller]` table, the gain, the closed-loop poles, the loop for the
//! margins and the design record's inputs; module documentation of `design`).

use super::Designed;
use super::inputs::{four_poles, list, numbers, pole_rows, pole_words};
use anyhow::{Context, Result, bail};
use pendulab_control::spec::design::{
    UprightDesign, drive_servo_model, lqr_upright, place_upright, pole_inputs, servo_upright,
    weight_inputs,
};
use pendulab_control::spec::{DesignInput, ObserverSpec, observer_design};
use pendulab_lmi::SolveOptions;
use pendulab_lmi::synthesis::lq_state_feedback;
use pendulab_lti::design::{integral_augmentation, place_observer};
use pendulab_lti::{Complex64, Continuous, Mat, StateSpace};
use pendulab_plants::spec::PlantSpec;

/// `Q`'s diagonal from `--q` (`n` weights ≥ 0) and `R = --r` (> 0); errors name the flag.
pub(super) fn weights(q: &str, r: f64, n: usize) -> Result<Vec<f64>> {
    let qv = numbers("--q", q, n)?;
    if qv.iter().any(|&x| x < 0.0) {
        bail!("--q {q}: the weights must be ≥ 0");
    }
    if !(r.is_finite() && r > 0.0) {
        bail!("--r {r}: must be a finite number > 0");
    }
    Ok(qv)
}

/// The LQ regulator `Q = diag(q)` (four weights ≥ 0), `R = r` (> 0) on `ss`
/// (`pendulab_control::spec::design`), with the weights; errors name the flag or the Riccati
/// equation without a stabilising solution.
fn lqr_design(ss: &StateSpace<Continuous>, q: &str, r: f64) -> Result<(UprightDesign, Vec<f64>)> {
    let qv = weights(q, r, 4)?;
    let l = lqr_upright(ss, &qv, r)
        .with_context(|| format!("lqr with Q = diag({q}), R = {r}: no stabilising solution"))?;
    Ok((l, qv))
}

/// The loop of `u = −K x` broken at the plant input, `L(s) = K (sI − A)⁻¹ B`, as a state space
/// `(A, B, K, 0)` of `ss`'s domain.
pub(super) fn state_feedback_loop(
    ss: &StateSpace<Continuous>,
    gain: Mat,
) -> Result<StateSpace<Continuous>> {
    Ok(StateSpace::new(
        ss.a().clone(),
        ss.b().clone(),
        gain,
        Mat::zeros(1, 1),
        ss.domain(),
    )?)
}

/// The `[controller]` keys of a state feedback `u = −K x`.
pub(super) fn state_feedback_table(k: &[f64]) -> String {
    format!("kind = \"state-feedback\"\nk = [{}]\n", list(k))
}

/// `lqr --q … --r …`: the continuous LQ regulator.
pub(super) fn lqr(ss: &StateSpace<Continuous>, q: &str, r: f64) -> Result<Designed> {
    let (l, qv) = lqr_design(ss, q, r)?;
    let k: Vec<f64> = l.gain.row(0).iter().copied().collect();
    Ok(Designed {
        table: state_feedback_table(&k),
        k,
        poles: l.poles,
        loop_ss: Some(state_feedback_loop(ss, l.gain)?),
        inputs: format!("Q = diag([{}]), R = {r}", list(&qv)),
        note: "",
        record: weight_inputs(&qv, r).into_iter().collect(),
        schedule: None,
    })
}

/// `place --poles …`: pole placement at four poles.
pub(super) fn place(ss: &StateSpace<Continuous>, poles: &str) -> Result<Designed> {
    let p = four_poles("--poles", poles)?;
    let pl = place_upright(ss, &p).with_context(|| format!("place with poles {poles}"))?;
    let k: Vec<f64> = pl.gain.row(0).iter().copied().collect();
    Ok(Designed {
        table: state_feedback_table(&k),
        k,
        poles: pl.poles,
        loop_ss: Some(state_feedback_loop(ss, pl.gain)?),
        inputs: format!("poles = {}", pole_words(&p)),
        note: "",
        record: pole_inputs(&p).into_iter().collect(),
        schedule: None,
    })
}

/// `servo` (Riccati) or, with `lmi`, `lmi-servo` (the LMI guaranteed-cost LQ design, book
/// part 2 §1.2.2): the LQ integral servo of the drive position on `[x; w]`.
pub(super) fn servo(
    ss: &StateSpace<Continuous>,
    sa: &super::ServoArgs,
    lmi: bool,
) -> Result<Designed> {
    let super::ServoArgs {
        q,
        r,
        reference,
        step_time,
    } = sa;
    let qv = weights(q, *r, 5)?;
    if !reference.is_finite() || !step_time.is_finite() || *step_time < 0.0 {
        bail!(
            "--reference {reference}, --step-time {step_time}: must be finite, the step time ≥ 0"
        );
    }
    // The gain on [x; w] (1 × 5, u = −K [x; w]), its closed-loop poles and the
    // augmented model: by the Riccati equation (`servo`), or by the LMI
    // guaranteed-cost LQ design on the same augmented model (`lmi-servo`, book part 2
    // §1.2.2).
    let (gain, cl_poles, aa, ba) = if lmi {
        lmi_servo_gain(ss, &qv, *r)?
    } else {
        let s = servo_upright(ss, &qv, *r).with_context(|| {
            format!(
                "lq servo with Q = diag({}), R = {r}: no stabilising solution",
                list(&qv)
            )
        })?;
        (s.gain, s.poles, s.a, s.b)
    };
    let k: Vec<f64> = gain.row(0).iter().copied().collect();
    let (k1, k2) = (k[..4].to_vec(), k[4]);
    let loop_ss = StateSpace::new(aa, ba, gain, Mat::zeros(1, 1), ss.domain())?;
    Ok(Designed {
        table: format!(
            "kind = \"lq-servo\"\nk1 = [{}]\nk2 = {k2:?}\nreference = [{reference:?}]\nstep_time = {step_time:?}\n",
            list(&k1)
        ),
        k,
        poles: cl_poles,
        loop_ss: Some(loop_ss),
        inputs: format!(
            "Q = diag([{}]), R = {r}, on [x; w], w = ∫(r − q0) dt",
            list(&qv)
        ),
        note: "",
        record: weight_inputs(&qv, *r)
            .into_iter()
            .chain([
                ("reference".to_string(), DesignInput::Number(*reference)),
                ("step_time".to_string(), DesignInput::Number(*step_time)),
            ])
            .collect(),
        schedule: None,
    })
}

/// `lmi-servo`'s gain on `[x; w]`, its closed-loop poles and the augmented `(Ã, B̃)`, by
/// `pendulab_lmi::synthesis::lq_state_feedback`; errors name the weights and the solver's status.
fn lmi_servo_gain(
    ss: &StateSpace<Continuous>,
    qv: &[f64],
    r: f64,
) -> Result<(Mat, Vec<Complex64>, Mat, Mat)> {
    let qm = Mat::from_diagonal(&nalgebra::DVector::from_vec(qv.to_vec()));
    let rm = Mat::from_element(1, 1, r);
    let (aa, ba) = integral_augmentation(&drive_servo_model(ss)?)?;
    let d = lq_state_feedback(&aa, &ba, &qm, &rm, &SolveOptions::default())
        .with_context(|| format!("LMI LQ servo with Q = diag({}), R = {r}", list(qv)))?;
    let Some(f) = d.feedback else {
        bail!(
            "LMI LQ servo with Q = diag({}), R = {r}: the LMIs were not solved (status {:?}); nothing written",
            list(qv),
            d.status
        );
    };
    let poles = f.closed_loop_poles.into_iter().next().unwrap_or_default();
    Ok((f.gain, poles, aa, ba))
}

/// `observer`: `u = −K x̂`, `K` by LQR (`q`, `r`) or placement (`poles`), `x̂` from the
/// full-order observer of `[q₀, q₁]` with `A − LC` at `observer_poles`.
pub(super) fn observer(
    plant: &PlantSpec,
    ss: &StateSpace<Continuous>,
    q: Option<&str>,
    r: Option<f64>,
    poles: Option<&str>,
    observer_poles: &str,
) -> Result<Designed> {
    let (a, b) = (ss.a(), ss.b());
    // K: an LQ regulator or a placement, as `lqr` and `place` design it.
    let (k_mat, k_inputs, k_words) = match (q, r, poles) {
        (Some(q), Some(r), None) => {
            let (l, qv) = lqr_design(ss, q, r)?;
            let inputs: Vec<(String, DesignInput)> = weight_inputs(&qv, r).into_iter().collect();
            let words = format!("K by LQR, Q = diag([{}]), R = {r}", list(&qv));
            (l.gain, inputs, words)
        }
        (None, None, Some(text)) => {
            let p = four_poles("--poles", text)?;
            let g = place_upright(ss, &p)
                .with_context(|| format!("place with poles {text}"))?
                .gain;
            (
                g,
                pole_inputs(&p).into_iter().collect(),
                format!("K placed at {}", pole_words(&p)),
            )
        }
        _ => bail!("observer: give the state feedback as --q with --r, or as --poles"),
    };
    // L: A − LC at the observer poles, C = [I₂ 0] (the encoder positions).
    let op = four_poles("--observer-poles", observer_poles)?;
    let c = Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let l_mat = place_observer(a, &c, &op)
        .with_context(|| format!("observer placement at {observer_poles}"))?
        .gain;
    let k: Vec<f64> = k_mat.row(0).iter().copied().collect();
    let l_rows: Vec<Vec<f64>> = (0..4)
        .map(|i| l_mat.row(i).iter().copied().collect())
        .collect();
    // The 8 closed-loop poles of plant and observer-based controller, as the
    // controller kind computes them.
    let d = observer_design(
        plant.parameters(),
        &ObserverSpec {
            k: Some(k.clone()),
            l: Some(l_rows.clone()),
            ..ObserverSpec::default()
        },
    )
    .context("the observer-based loop")?;
    // The loop broken at the plant input: plant (A, B, C) into the controller
    // (A − BK − LC, L, K): states [x; x̂], L(s) = K x̂ / u.
    let mut al = Mat::zeros(8, 8);
    al.view_mut((0, 0), (4, 4)).copy_from(a);
    al.view_mut((4, 0), (4, 4)).copy_from(&(&l_mat * &c));
    al.view_mut((4, 4), (4, 4))
        .copy_from(&(a - b * &k_mat - &l_mat * &c));
    let mut bl = Mat::zeros(8, 1);
    bl.view_mut((0, 0), (4, 1)).copy_from(b);
    let mut cl = Mat::zeros(1, 8);
    cl.view_mut((0, 4), (1, 4)).copy_from(&k_mat);
    let loop_ss = StateSpace::new(al, bl, cl, Mat::zeros(1, 1), ss.domain())?;
    let mut record = k_inputs;
    record.push((
        "observer_poles".to_string(),
        DesignInput::Rows(pole_rows(&op)),
    ));
    Ok(Designed {
        table: format!(
            "kind = \"observer\"\nk = [{}]\nl = [{}]\n",
            list(&k),
            l_rows
                .iter()
                .map(|r| format!("[{}]", list(r)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        k,
        poles: d.closed_loop_poles,
        loop_ss: Some(loop_ss),
        inputs: format!(
            "{k_words}, observer of [q0, q1] with A − LC at {}",
            pole_words(&op)
        ),
        note: "",
        record,
        schedule: None,
    })
}

/// `p --kp … --target …`: the drive's P-control step `u = −k_P (q₀ − r)` (book part 1 §3.2),
/// its poles those of the drive alone, no margins.
pub(super) fn p_step(ss: &StateSpace<Continuous>, kp: f64, target: f64) -> Result<Designed> {
    let (a, b) = (ss.a(), ss.b());
    if !(kp.is_finite() && kp > 0.0) {
        bail!("--kp {kp}: must be a finite number > 0");
    }
    if !target.is_finite() {
        bail!("--target {target}: must be finite");
    }
    // The drive alone, q0'' = −a q0' + b v under u = −kP q0: s² + a s + b kP.
    let k = vec![kp, 0.0, 0.0, 0.0];
    let drive = Mat::from_row_slice(2, 2, &[0.0, 1.0, -b[(2, 0)] * kp, a[(2, 2)]]);
    let poles = pendulab_lti::linalg::eigenvalues(&drive)?;
    Ok(Designed {
        table: format!(
            "kind = \"state-feedback\"\nk = [{}]\nreference = [{target:?}, 0.0, 0.0, 0.0]\n",
            list(&k)
        ),
        k,
        poles,
        loop_ss: None,
        inputs: format!("kP = {kp}, target = {target}"),
        note: "# The drive's P-control step (book part 1 §3.2) with the pendulum hanging: run it\n\
               # with `pendulab rig run --hanging`, identify with `pendulab identify`.\n",
        record: vec![
            ("kp".to_string(), DesignInput::Number(kp)),
            ("target".to_string(), DesignInput::Number(target)),
        ],
        schedule: None,
    })
}
