//! Model reduction and the H∞ norm: `stabsep`, `hsvd`, `balreal`, `balred`, `hinfnorm`
//! (pendulab-lti's `reduction` and `norms` modules; MATLAB's names, python-control's `hsvd`
//! and `balred`).
//!
//! Unstable systems follow MATLAB: `G = G_s + G_u` is split by `stabsep` (ordered Schur form
//! and a Sylvester equation), the Hankel singular values of the unstable states are `inf`
//! (listed first), and `balreal`/`balred` keep the unstable part `G_u` unchanged while they
//! balance or reduce `G_s`.

use super::nogil;
use super::results::{obj, result_class};
use super::system::{StateSpace, Sys, system, with_sys};
use crate::convert::{matrix_to_numpy, slice_to_numpy};
use crate::errors::{Kind, new_err};
use pendulab_lti::norms::hinf_norm;
use pendulab_lti::reduction::{
    Balanced, BalredMethod, balreal as lti_balreal, balred as lti_balred,
};
use pendulab_lti::{StateSpace as Ss, TimeDomain};
use pyo3::prelude::*;
use pyo3::types::PyList;

/// Wraps a system of domain `D` as the `Sys` of the same domain as `like`.
fn same_domain<D: TimeDomain>(s: Ss<D>) -> PyResult<Sys> {
    let (a, b, c, d) = (s.a().clone(), s.b().clone(), s.c().clone(), s.d().clone());
    Sys::new(a, b, c, d, s.domain().sample_time())
}

fn wrap<D: TimeDomain>(py: Python<'_>, s: Ss<D>) -> PyResult<Py<PyAny>> {
    StateSpace::wrap(py, same_domain(s)?)
}

result_class!(
    StabsepResult, "StabsepResult",
    "The additive stable/unstable decomposition G = G_s + G_u; unpacks as MATLAB's `GS, GNS = stabsep(G)`.",
    array none,
    unpack {
        stable as "stable": "G_s: the poles with Re λ < 0 (|λ| < 1 in discrete time) and the feedthrough D, a StateSpace.",
        unstable as "unstable": "G_u: the poles with Re λ > 0 (|λ| > 1) and a zero feedthrough (strictly proper), a StateSpace.",
    }
    also {}
);

/// `stabsep(sys)`: the additive decomposition `G = G_s + G_u` (MATLAB `stabsep`): the real
/// Schur form `A = Z T Zᵀ` is reordered with the stable eigenvalues first,
/// `T = [[T₁₁, T₁₂], [0, T₂₂]]`, and `T₁₁ X − X T₂₂ + T₁₂ = 0` decouples the blocks:
/// `G_s = (T₁₁, B₁ − X B₂, C₁, D)`, `G_u = (T₂₂, B₂, C₁ X + C₂, 0)` with `Zᵀ B = [B₁; B₂]`,
/// `C Z = [C₁, C₂]`. Either part may have no states. Returns `StabsepResult`
/// (`stable, unstable`).
///
/// Raises `pendulab.InvalidArgumentError` naming the eigenvalues of `A` on the stability
/// boundary (`|Re λ|` or `||λ| − 1|` at most `100·ε·max(1, ‖A‖_F)`: they belong to neither
/// part); `pendulab.LinAlgError` if the Schur form or its reordering fails.
#[pyfunction]
pub fn stabsep(sys: &Bound<'_, PyAny>) -> PyResult<StabsepResult> {
    let py = sys.py();
    let s = system(sys)?;
    let (gs, gu) = with_sys!(&s, s => {
        let (gs, gu) = nogil(py, || pendulab_lti::reduction::stabsep(s))?;
        (wrap(py, gs)?, wrap(py, gu)?)
    });
    Ok(StabsepResult {
        stable: gs,
        unstable: gu,
    })
}

/// `hsvd(sys)`: the Hankel singular values `σ₁ ≥ … ≥ σₙ ≥ 0`, `σᵢ = √λᵢ(W_c W_o)` of the
/// controllability and observability Gramians (python-control / MATLAB `hsvd`). For a system
/// with unstable poles, those of the stable part of `stabsep` preceded by one `inf` per
/// unstable state (MATLAB's convention): `n` values in all.
///
/// Raises `pendulab.InvalidArgumentError` for an eigenvalue on the stability boundary (as
/// `stabsep`); `pendulab.LinAlgError` from the Lyapunov solver.
#[pyfunction]
pub fn hsvd<'py>(sys: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let py = sys.py();
    let s = system(sys)?;
    let hsv = nogil(py, || with_sys!(&s, s => pendulab_lti::reduction::hsvd(s)))?;
    Ok(slice_to_numpy(py, &hsv).into_any())
}

result_class!(
    BalrealResult, "BalrealResult",
    "A balanced realisation; unpacks as MATLAB's `sysb, g, T, Ti = balreal(sys)`.",
    array none,
    unpack {
        sysb as "sysb": "The balanced StateSpace: both Gramians of its stable part equal diag(g) (state [x_u; x_b], the unstable states first).",
        g as "g": "The Hankel singular values, descending, inf for each unstable state.",
        t as "T": "x_b = T x (MATLAB's T), shape (n, n).",
        ti as "Ti": "x = Ti x_b, the inverse of T.",
    }
    also {}
);

impl BalrealResult {
    fn from_balanced<D: TimeDomain>(py: Python<'_>, b: Balanced<D>) -> PyResult<Self> {
        Ok(Self {
            g: slice_to_numpy(py, &b.hsv).into_any().unbind(),
            t: matrix_to_numpy(py, &b.t_inv).into_any().unbind(),
            ti: matrix_to_numpy(py, &b.t).into_any().unbind(),
            sysb: wrap(py, b.system)?,
        })
    }
}

/// `balreal(sys)`: the balanced realisation of a minimal system by the square-root method
/// (Laub, Heath, Paige & Ward 1987): with `W_c = R Rᵀ`, `W_o = L Lᵀ` and `Lᵀ R = U Σ Vᵀ`,
/// `x = R V Σ^{−1/2} x_b`, so that both Gramians of the balanced system are `Σ`. With unstable
/// poles (MATLAB's behaviour) the stable part of `stabsep` is balanced and the unstable part
/// added back (its states first, `g` = `inf` for them). Returns `BalrealResult`
/// (`sysb, g, T, Ti`).
///
/// Raises `pendulab.LinAlgError` (variant `Singular`) if a Hankel singular value is zero to
/// working precision (a non-minimal realisation: use `balred` to a lower order);
/// `pendulab.InvalidArgumentError` for an eigenvalue on the stability boundary.
#[pyfunction]
pub fn balreal(sys: &Bound<'_, PyAny>) -> PyResult<BalrealResult> {
    let py = sys.py();
    let s = system(sys)?;
    with_sys!(&s, s => BalrealResult::from_balanced(py, nogil(py, || lti_balreal(s))?))
}

/// Reads `method` of `balred` (python-control's `'truncate'`/`'matchdc'`, case-insensitive).
fn balred_method(method: &str) -> PyResult<BalredMethod> {
    match method.to_ascii_lowercase().as_str() {
        "truncate" => Ok(BalredMethod::Truncate),
        "matchdc" => Ok(BalredMethod::MatchDc),
        other => Err(new_err(
            Kind::InvalidArgument,
            format!("balred method {other:?}: expected 'truncate' or 'matchdc'"),
            None,
        )),
    }
}

/// `balred(sys, orders, method='truncate')`: balanced reduction to `orders` states
/// (python-control / MATLAB `balred`); `orders` an integer gives one `StateSpace`, a
/// sequence of integers a list of them. `'truncate'` keeps the `r` leading balanced states
/// (`A_r = T_r⁻¹ A T_r`, …, `D_r = D`); `'matchdc'` residualises the others
/// (`A_r = A₁₁ − A₁₂ A₂₂⁻¹ A₂₁`, …, `A₂₂ − I` in discrete time), keeping `G(0)` (`G(1)`).
/// Either way `σ_{r+1} ≤ ‖G − G_r‖∞ ≤ 2 Σ_{i>r} σᵢ` (Glover 1984), `σ` from `hsvd`. With
/// unstable poles (MATLAB's behaviour) every unstable mode is kept and the stable part
/// reduced to `r − n_u` states, so the bound holds with the stable part's `σ`.
///
/// Raises `pendulab.InvalidArgumentError` for an order above the number of states or below
/// the number of unstable states, an unknown method or an eigenvalue on the stability
/// boundary; `pendulab.LinAlgError` (`Singular`) if `σ_r` is zero to working precision (ask
/// for fewer states) or, for `'matchdc'`, if `A₂₂` (`A₂₂ − I`) is singular.
#[pyfunction]
#[pyo3(signature = (sys, orders, method = "truncate"))]
pub fn balred(
    sys: &Bound<'_, PyAny>,
    orders: &Bound<'_, PyAny>,
    method: &str,
) -> PyResult<Py<PyAny>> {
    let py = sys.py();
    let m = balred_method(method)?;
    let s = system(sys)?;
    let one = |r: usize| -> PyResult<Py<PyAny>> {
        with_sys!(&s, s => wrap(py, nogil(py, || lti_balred(s, r, m))?.system))
    };
    if let Ok(r) = orders.extract::<usize>() {
        return one(r);
    }
    let list: Vec<usize> = orders.extract().map_err(|_| {
        new_err(
            Kind::InvalidArgument,
            format!(
                "balred orders must be a non-negative integer or a sequence of them, got {}",
                orders.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            ),
            None,
        )
    })?;
    let out = PyList::empty(py);
    for r in list {
        out.append(one(r)?)?;
    }
    Ok(out.into_any().unbind())
}

result_class!(
    HinfnormResult, "HinfnormResult",
    "The H∞ norm; unpacks as MATLAB's `ninf, fpeak = hinfnorm(sys)`.",
    array none,
    unpack {
        ninf as "ninf": "‖G‖∞ = sup_ω σ̄(G(jω)) (sup over |z| = 1 in discrete time); inf for an unstable system.",
        fpeak as "fpeak": "The frequency in rad/s where it is attained (inf for the feedthrough's σ̄(D) at infinite frequency, nan if unstable).",
    }
    also {
        upper_bound as "upper_bound": "(1 + 2 tol)·ninf, a certified upper bound on the norm.",
    }
);

/// `hinfnorm(sys, tol=1e-10)`: the H∞ norm `‖G‖∞ = sup_ω σ̄(G(jω))` by the Hamiltonian
/// bisection of Boyd–Balakrishnan–Bruinsma–Steinbuch (MATLAB `hinfnorm`; python-control's
/// `norm(sys, 'inf')`), to the relative tolerance `tol`. Returns `HinfnormResult`
/// (`ninf, fpeak`).
///
/// Raises `pendulab.InvalidArgumentError` for `tol` outside (0, 1).
#[pyfunction]
#[pyo3(signature = (sys, tol = 1e-10))]
pub fn hinfnorm(sys: &Bound<'_, PyAny>, tol: f64) -> PyResult<HinfnormResult> {
    let py = sys.py();
    let s = system(sys)?;
    let h = nogil(py, || with_sys!(&s, s => hinf_norm(s, tol)))?;
    Ok(HinfnormResult {
        ninf: obj(py, h.value)?,
        fpeak: obj(py, h.peak_frequency)?,
        upper_bound: obj(py, h.upper_bound)?,
    })
}
