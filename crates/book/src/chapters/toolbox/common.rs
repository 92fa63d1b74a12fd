//! Shared set-up of the chapter 5–8 and toolbox examples: error mapping, rig presets, gain
//! conventions and figure/animation writing.

use crate::error::BookError;
use crate::output::ExampleOutput;
use crate::registry::RunContext;
use pendulab_lti::{Complex64, Mat, Trajectory};
use pendulab_plants::RigSpec;
use pendulab_plot::{Animation, AnimationOptions, ArmGeometry, CartGeometry, Figure};
use pendulab_sim::rig::RigChains;
use pendulab_sim::{Actuator, SensorChain};

/// A [`BookError::Computation`] for example `id`.
pub(crate) fn fail(id: &str, e: impl std::fmt::Display) -> BookError {
    BookError::Computation {
        id: id.to_string(),
        message: e.to_string(),
    }
}

/// `diag(d)`.
pub(crate) fn diag(d: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(d))
}

/// Row `0` of `k` in the book's convention `u = +K_book x` (`K_book = −K`).
pub(crate) fn book_row(k: &Mat) -> Vec<f64> {
    (0..k.ncols()).map(|j| -k[(0, j)]).collect()
}

/// Column `j` of a sample matrix (rows = samples).
pub(crate) fn column(x: &Mat, j: usize) -> Vec<f64> {
    (0..x.nrows()).map(|i| x[(i, j)]).collect()
}

/// Complex numbers from `(re, im)` pairs.
pub(crate) fn complex(p: &[(f64, f64)]) -> Vec<Complex64> {
    p.iter().map(|&(r, i)| Complex64::new(r, i)).collect()
}

/// Sorted the workspace's way (real part descending, then imaginary part descending).
pub(crate) fn sorted(mut p: Vec<Complex64>) -> Vec<Complex64> {
    pendulab_lti::linalg::sort_eigenvalues(&mut p);
    p
}

/// The book's rig preset "with quantizer" of a rig description: encoders on the positions,
/// pseudo-differentiated velocities `1/(0.02 s + 1)·s`, ±5 V and a 16-bit D/A.
///
/// # Errors
/// The preset's construction errors (none for the built-in rigs).
pub(crate) fn quantized_rig(id: &str, rig: &RigSpec) -> Result<RigChains, BookError> {
    let enc: Vec<(usize, f64)> = rig.encoders.iter().map(|e| (e.state, e.step)).collect();
    RigChains::with_quantizer(
        rig.nx,
        &enc,
        &velocities(rig),
        rig.input_limit,
        rig.dac.bits,
    )
    .map_err(|e| fail(id, e))
}

/// The nonlinear plant "plain" with the book's default measurement (examples.md preamble):
/// exact positions, velocities by derivative + `1/(0.02 s + 1)`, ideal actuator.
///
/// # Errors
/// The sensor's construction errors (none for the built-in rigs).
pub(crate) fn filtered_rig(id: &str, rig: &RigSpec) -> Result<RigChains, BookError> {
    Ok(RigChains {
        sensor: SensorChain::state_layout(rig.nx, &[], &velocities(rig))
            .map_err(|e| fail(id, e))?,
        actuator: Actuator::ideal(),
    })
}

fn velocities(rig: &RigSpec) -> Vec<(usize, usize, f64)> {
    rig.velocity_estimators
        .iter()
        .map(|v| (v.position_state, v.velocity_state, v.time_constant))
        .collect()
}

/// Saves `fig` as `<out>/<id>_<what>.svg/.png` when the context has an output directory.
///
/// # Errors
/// [`BookError::Figure`] naming the path.
pub(crate) fn save_figure(
    ctx: &RunContext,
    id: &str,
    what: &str,
    fig: &Figure,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    let Some(dir) = &ctx.out_dir else {
        return Ok(());
    };
    let stem = format!("{id}_{what}");
    let saved = fig.save(dir, &stem).map_err(|e| BookError::Figure {
        id: id.to_string(),
        path: dir.join(&stem).display().to_string(),
        message: e.to_string(),
    })?;
    out.figures.push(saved.svg);
    out.figures.push(saved.png);
    Ok(())
}

/// Which rig an animation draws.
pub(crate) enum Rig {
    /// The cart-type pendulum: state columns `z` = 0, `θ` = 1.
    Cart,
    /// The arm-type pendulum: state columns `θ₁` = 0, `θ₂` = 1.
    Arm,
}

/// Saves an animation of a run as `<out>/<id>_<what>.gif` and `.svg` (SMIL) when the
/// context has an output directory.
///
/// # Errors
/// [`BookError::Figure`] naming the path.
pub(crate) fn save_animation(
    ctx: &RunContext,
    id: &str,
    what: &str,
    rig: Rig,
    traj: &Trajectory,
    title: &str,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    let Some(dir) = &ctx.out_dir else {
        return Ok(());
    };
    let stem = dir.join(format!("{id}_{what}"));
    let figure_err = |path: &std::path::Path, e: pendulab_plot::PlotError| BookError::Figure {
        id: id.to_string(),
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let t = traj.t();
    let (a, b) = (traj.x_signal(0), traj.x_signal(1));
    let anim = match rig {
        Rig::Cart => Animation::cart(t, a, b, CartGeometry::default()),
        Rig::Arm => Animation::arm(t, a, b, ArmGeometry::default()),
    }
    .map_err(|e| figure_err(&stem, e))?
    .options(AnimationOptions {
        max_frames: 120,
        ..Default::default()
    })
    .title(title);
    let gif = stem.with_extension("gif");
    anim.save_gif(&gif).map_err(|e| figure_err(&gif, e))?;
    let svg = stem.with_extension("svg");
    anim.save_svg(&svg).map_err(|e| figure_err(&svg, e))?;
    out.figures.push(gif);
    out.figures.push(svg);
    Ok(())
}

/// Largest |v_k| over the samples with `t_k ≥ from`.
pub(crate) fn max_abs_after(t: &[f64], v: &[f64], from: f64) -> f64 {
    t.iter()
        .zip(v)
        .filter(|(ti, _)| **ti >= from - 1e-12)
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max)
}

/// Smallest value of `v`.
pub(crate) fn min_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Largest value of `v`.
pub(crate) fn max_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}
