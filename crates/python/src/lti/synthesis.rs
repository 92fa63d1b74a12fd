//! H∞ and H2 synthesis and the mixed-sensitivity plant: `hinfsyn`, `h2syn`, `augw`
//! (pendulab-lti's `design::hinf_syn`, `hinf_syn_optimal`, `h2_syn`, `augw`).
//!
//! The plant `P` has the inputs `[w; u]` and outputs `[z; y]`; the last `ncon` inputs are the
//! controls and the last `nmeas` outputs the measurements (python-control's and MATLAB's
//! `hinfsyn(P, nmeas, ncon)`). The controller is connected as `u = K y` (positive feedback,
//! the lower LFT), as in python-control.

use super::nogil;
use super::results::{obj, result_class};
use super::system::{StateSpace, Sys, system};
use crate::convert::{count, matrix_to_numpy};
use crate::errors::{Kind, new_err};
use pendulab_lti::design::{self, GammaIteration, StandardPlant};
use pendulab_lti::{Continuous, StateSpace as Ss};
use pyo3::prelude::*;

result_class!(
    HinfsynResult, "HinfsynResult",
    "An H∞ controller; unpacks as python-control's `K, CL, gam` (without its `rcond`).",
    array none,
    unpack {
        k as "K": "The controller K (u = K y), a continuous StateSpace with nmeas inputs and ncon outputs.",
        cl as "CL": "The closed loop from w to z, F_l(P, K).",
        gam as "gam": "The level γ of the controller: ‖CL‖∞ < γ.",
    }
    also {
        x as "X": "The stabilising solution X∞ ⪰ 0 of the control Riccati equation at γ.",
        y as "Y": "The stabilising solution Y∞ ⪰ 0 of the filter Riccati equation at γ.",
        rho as "rho": "ρ(X∞ Y∞) < γ².",
        gamma_infeasible as "gamma_infeasible": "With the γ-iteration: the largest level found infeasible (a lower bound of the optimum); None for a given γ.",
    }
);

result_class!(
    H2synResult, "H2synResult",
    "The H2-optimal controller; unpacks as `K, CL, norm` (python-control's h2syn returns K alone).",
    array none,
    unpack {
        k as "K": "The controller K (u = K y), a continuous StateSpace.",
        cl as "CL": "The closed loop from w to z, F_l(P, K).",
        norm as "norm": "The optimal ‖CL‖₂ from the Riccati formula √(tr(B₁ᵀX₂B₁) + tr(R₁K_xY₂K_xᵀ)).",
    }
    also {
        x as "X": "X₂, the control Riccati solution.",
        y as "Y": "Y₂, the filter Riccati solution.",
        state_gain as "Kx": "The state-feedback gain K_x (u = −K_x x̂).",
        estimator_gain as "L": "The estimator gain L (x̂' = A x̂ + B₂u + L(y − C₂x̂)).",
    }
);

/// The standard plant of `P` with its partition.
fn standard_plant(p: &Bound<'_, PyAny>, nmeas: usize, ncon: usize) -> PyResult<StandardPlant> {
    match system(p)? {
        Sys::Continuous(s) => StandardPlant::new(s, nmeas, ncon).map_err(crate::errors::lti),
        Sys::Discrete(_) => Err(new_err(
            Kind::InvalidArgument,
            "hinfsyn/h2syn need a continuous-time plant (dt = 0)".into(),
            None,
        )),
    }
}

fn wrap(py: Python<'_>, s: Ss<Continuous>) -> PyResult<Py<PyAny>> {
    StateSpace::wrap(py, Sys::Continuous(s))
}

/// `hinfsyn(P, nmeas, ncon, gamma=None, tol=1e-6)`: H∞ output-feedback synthesis by the
/// Riccati equations of Doyle, Glover, Khargonekar & Francis (the central controller; for
/// `D11 ≠ 0` the formulas of Glover & Doyle 1988, as SLICOT's SB10AD).
/// Without `gamma`, the optimal level is found by bisection to the relative tolerance `tol`
/// and the controller at the smallest feasible level found is returned (a controller this
/// close to the optimum is ill-conditioned: ask for a `gamma` a little above `gam` for one
/// to use); with `gamma`, the controller at that level. Returns `HinfsynResult`
/// (`K, CL, gam = hinfsyn(...)`). Any `D11` (a level must exceed the bound
/// max(‖[D1111 D1112]‖, ‖[D1111; D1121]‖) that no controller moves); `D22 ≠ 0` is handled by
/// loop shifting.
///
/// Raises `pendulab.InvalidArgumentError` (variant `SynthesisAssumption`) naming the violated
/// assumption ((A, B2) stabilisable, (C2, A) detectable, D12 full column rank, D21 full row
/// rank, no imaginary-axis zeros of P12 and P21), `pendulab.InfeasibleError` (variant
/// `HinfInfeasible`) naming the failed condition when `gamma` is below the optimum.
#[pyfunction]
#[pyo3(signature = (P, nmeas, ncon, gamma = None, tol = 1e-6))]
#[allow(non_snake_case)]
pub fn hinfsyn(
    py: Python<'_>,
    P: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = count)] nmeas: usize,
    #[pyo3(from_py_with = count)] ncon: usize,
    gamma: Option<f64>,
    tol: f64,
) -> PyResult<HinfsynResult> {
    let plant = standard_plant(P, nmeas, ncon)?;
    let (c, lower) = match gamma {
        Some(g) => (nogil(py, || design::hinf_syn(&plant, g))?, None),
        None => {
            let it = GammaIteration {
                tolerance: tol,
                ..GammaIteration::default()
            };
            let r = nogil(py, || design::hinf_syn_optimal(&plant, &it))?;
            (r.design, Some(r.gamma_infeasible))
        }
    };
    Ok(HinfsynResult {
        k: wrap(py, c.controller)?,
        cl: wrap(py, c.closed_loop)?,
        gam: obj(py, c.gamma)?,
        x: matrix_to_numpy(py, &c.x).into_any().unbind(),
        y: matrix_to_numpy(py, &c.y).into_any().unbind(),
        rho: obj(py, c.spectral_radius)?,
        gamma_infeasible: obj(py, lower)?,
    })
}

/// `h2syn(P, nmeas, ncon)`: the H2-optimal (LQG) output-feedback controller from the two
/// decoupled Riccati equations. Returns `H2synResult` (`K, CL, norm = h2syn(...)`; python-
/// control's `h2syn` returns `K` alone). Requires `D11 = 0` (otherwise ‖CL‖₂ = ∞).
///
/// Raises `pendulab.InvalidArgumentError` (variant `SynthesisAssumption`) as `hinfsyn`.
#[pyfunction]
#[pyo3(signature = (P, nmeas, ncon))]
#[allow(non_snake_case)]
pub fn h2syn(
    py: Python<'_>,
    P: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = count)] nmeas: usize,
    #[pyo3(from_py_with = count)] ncon: usize,
) -> PyResult<H2synResult> {
    let plant = standard_plant(P, nmeas, ncon)?;
    let c = nogil(py, || design::h2_syn(&plant))?;
    Ok(H2synResult {
        k: wrap(py, c.controller)?,
        cl: wrap(py, c.closed_loop)?,
        norm: obj(py, c.norm)?,
        x: matrix_to_numpy(py, &c.x).into_any().unbind(),
        y: matrix_to_numpy(py, &c.y).into_any().unbind(),
        state_gain: matrix_to_numpy(py, &c.state_gain).into_any().unbind(),
        estimator_gain: matrix_to_numpy(py, &c.estimator_gain).into_any().unbind(),
    })
}

/// `augw(G, w1=None, w2=None, w3=None)`: the mixed-sensitivity plant
/// `[[W1, −W1 G], [0, W2], [0, W3 G], [I, −G]]` (python-control's and MATLAB's `augw`), a
/// continuous StateSpace with inputs `[w; u]` and outputs `[z1; z2; z3; y]`; use it with
/// `nmeas = G.noutputs`, `ncon = G.ninputs`. With `u = K y` the closed loop is
/// `[W1 S; W2 K S; W3 T]`. `W1`, `W3` take `G.noutputs` inputs, `W2` `G.ninputs`.
///
/// Raises `pendulab.ShapeError` for a weight of the wrong size.
#[pyfunction]
#[pyo3(signature = (G, w1 = None, w2 = None, w3 = None))]
#[allow(non_snake_case)]
pub fn augw(
    py: Python<'_>,
    G: &Bound<'_, PyAny>,
    w1: Option<&Bound<'_, PyAny>>,
    w2: Option<&Bound<'_, PyAny>>,
    w3: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let continuous = |o: &Bound<'_, PyAny>, what: &str| -> PyResult<Ss<Continuous>> {
        match system(o)? {
            Sys::Continuous(s) => Ok(s),
            Sys::Discrete(_) => Err(new_err(
                Kind::InvalidArgument,
                format!("augw: {what} must be continuous-time (dt = 0)"),
                None,
            )),
        }
    };
    let g = continuous(G, "G")?;
    let (w1, w2, w3) = (
        w1.map(|w| continuous(w, "w1")).transpose()?,
        w2.map(|w| continuous(w, "w2")).transpose()?,
        w3.map(|w| continuous(w, "w3")).transpose()?,
    );
    let p = nogil(py, || {
        design::augw(&g, w1.as_ref(), w2.as_ref(), w3.as_ref())
    })?;
    wrap(py, p.system().clone())
}
