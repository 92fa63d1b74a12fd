//! Shared glue of the part 2 chapters: errors, figure and animation writing, the book's
//! models in the shapes these chapters use, and small signal summaries.

use crate::error::BookError;
use crate::output::ExampleOutput;
use crate::registry::RunContext;
use pendulab_lti::{Complex64, Continuous, Mat, StateSpace};
use pendulab_plants::{ArmEquilibrium, ArmPendulum, ArmPendulumParams, RigSpec};
use pendulab_plot::{Animation, AnimationOptions, ArmGeometry, CartGeometry, Figure};
use pendulab_sim::rig::RigChains;

/// A computation error of example `id`.
pub(in crate::chapters) fn err(id: &str, what: impl std::fmt::Display) -> BookError {
    BookError::Computation {
        id: id.to_string(),
        message: what.to_string(),
    }
}

/// `diag(d)`.
pub(in crate::chapters) fn diag(d: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(d))
}

/// Row `0` of a `1 × n` matrix as a vector.
pub(in crate::chapters) fn row(m: &Mat) -> Vec<f64> {
    m.row(0).iter().copied().collect()
}

/// The book's sign convention `u = +K x` for a library gain (`u = −K x`).
pub(in crate::chapters) fn book_row(k: &Mat) -> Vec<f64> {
    row(k).into_iter().map(|v| -v).collect()
}

/// Largest real part of a set of poles.
pub(in crate::chapters) fn max_re(p: &[Complex64]) -> f64 {
    p.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max)
}

/// Poles sorted by real part then imaginary part (a stable order for reporting).
pub(in crate::chapters) fn sorted(mut p: Vec<Complex64>) -> Vec<Complex64> {
    p.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
    p
}

/// Largest `|v|` over samples with `t ≥ from`.
pub(in crate::chapters) fn max_abs_after(t: &[f64], v: &[f64], from: f64) -> f64 {
    t.iter()
        .zip(v)
        .filter(|(ti, _)| **ti >= from - 1e-12)
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max)
}

/// The rig preset "with quantizer" of a rig (encoders, pseudo-differentiated velocities,
/// ±5 V, 16-bit D/A).
pub(in crate::chapters) fn quantized(id: &str, rig: &RigSpec) -> Result<RigChains, BookError> {
    let enc: Vec<(usize, f64)> = rig.encoders.iter().map(|e| (e.state, e.step)).collect();
    let vel: Vec<(usize, usize, f64)> = rig
        .velocity_estimators
        .iter()
        .map(|v| (v.position_state, v.velocity_state, v.time_constant))
        .collect();
    RigChains::with_quantizer(rig.nx, &enc, &vel, rig.input_limit, rig.dac.bits)
        .map_err(|e| err(id, e))
}

/// The arm pendulum linearised upright at `θ₁ = 0` with drive parameters `a1`, `b1`,
/// augmented with the servo integrator `w = ∫(r − θ₁)`: `Ã = [[A, 0], [−C, 0]]`, `B̃ = [B; 0]`.
pub(in crate::chapters) fn arm_servo_model(
    id: &str,
    a1: f64,
    b1: f64,
) -> Result<(Mat, Mat), BookError> {
    let plant = ArmPendulum::new(ArmPendulumParams {
        a1,
        b1,
        ..ArmPendulumParams::book()
    })
    .map_err(|e| err(id, e))?;
    let lin = plant
        .linearize(ArmEquilibrium::upright(0.0))
        .map_err(|e| err(id, e))?;
    let c = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let sys =
        StateSpace::<Continuous>::continuous(lin.a().clone(), lin.b().clone(), c, Mat::zeros(1, 1))
            .map_err(|e| err(id, e))?;
    pendulab_lti::design::integral_augmentation(&sys).map_err(|e| err(id, e))
}

/// Writes `fig` as `<out>/<id>_<what>.svg/.png` when figures are wanted.
pub(in crate::chapters) fn save(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    what: &str,
    fig: Result<Figure, pendulab_plot::PlotError>,
) -> Result<(), BookError> {
    let Some(dir) = &ctx.out_dir else {
        return Ok(());
    };
    let stem = format!("{id}_{what}");
    let fail = |e: &dyn std::fmt::Display| BookError::Figure {
        id: id.to_string(),
        path: dir.join(format!("{stem}.svg")).display().to_string(),
        message: e.to_string(),
    };
    let fig = fig.map_err(|e| fail(&e))?;
    let saved = fig.save(dir, &stem).map_err(|e| fail(&e))?;
    out.figures.push(saved.svg);
    out.figures.push(saved.png);
    Ok(())
}

/// Writes an animation as `<out>/<id>_<what>.gif` and `.svg` when figures are wanted.
pub(in crate::chapters) fn save_animation(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    what: &str,
    anim: impl FnOnce() -> Result<Animation, pendulab_plot::PlotError>,
) -> Result<(), BookError> {
    let Some(dir) = &ctx.out_dir else {
        return Ok(());
    };
    let gif = dir.join(format!("{id}_{what}.gif"));
    let svg = dir.join(format!("{id}_{what}.svg"));
    let fail = |p: &std::path::Path, e: &dyn std::fmt::Display| BookError::Figure {
        id: id.to_string(),
        path: p.display().to_string(),
        message: e.to_string(),
    };
    let a = anim().map_err(|e| fail(&gif, &e))?.title(id.to_string());
    a.save_gif(&gif).map_err(|e| fail(&gif, &e))?;
    a.save_svg(&svg).map_err(|e| fail(&svg, &e))?;
    out.figures.push(gif);
    out.figures.push(svg);
    Ok(())
}

/// An arm-pendulum animation of a recorded run (`x = [θ₁, θ₂, θ̇₁, θ̇₂]`).
pub(in crate::chapters) fn arm_animation(
    tr: &pendulab_lti::Trajectory,
) -> Result<Animation, pendulab_plot::PlotError> {
    Ok(Animation::arm(
        tr.t(),
        tr.x_signal(0),
        tr.x_signal(1),
        ArmGeometry::default(),
    )?
    .options(AnimationOptions {
        fps: 20.0,
        max_frames: 160,
        ..Default::default()
    }))
}

/// A cart-pendulum animation of a recorded run (`x = [z, θ, ż, θ̇]`).
pub(in crate::chapters) fn cart_animation(
    tr: &pendulab_lti::Trajectory,
) -> Result<Animation, pendulab_plot::PlotError> {
    Ok(Animation::cart(
        tr.t(),
        tr.x_signal(0),
        tr.x_signal(1),
        CartGeometry::default(),
    )?
    .options(AnimationOptions {
        fps: 20.0,
        max_frames: 160,
        ..Default::default()
    }))
}
