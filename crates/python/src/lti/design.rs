//! Design: `lqr`, `dlqr`, `lqe`, `dlqe`, `place`, `acker`, `place_observer`, `lqi`,
//! `lqr_sampled_data`, `reg`, `minimal_order_observer` (pendulab-lti's `design` module).
//!
//! **Sign convention.** Every gain is for `u = −K x` (closed loop `A − BK`), observer gains
//! for `A − LC`, as in python-control and MATLAB. The textbook 「倒立振子で学ぶ制御工学」
//! writes `u = +K x`: its gain is `K_book = −K` (Part 1 §5; pendulab-lti's `StateFeedback`).

use super::nogil;
use super::results::{obj, result_class};
use super::system::{StateSpace, Sys, is_system, system, with_sys};
use crate::convert::{OneD, complex_to_numpy, complex_vector, matrix, matrix_to_numpy};
use crate::errors::{Kind, lti, new_err};
use pendulab_lti::design::{self, Kalman, Lqr, PolePlacement};
use pendulab_lti::{Continuous, Discrete, Mat, StateSpace as Ss};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

result_class!(
    LqrResult, "LqrResult",
    "An LQ-optimal state feedback u = −K x; unpacks as python-control's `K, S, E`.",
    array none,
    unpack {
        k as "K": "The gain K (m × n), control law u = −K x (the book's gain is −K).",
        s as "S": "The stabilising Riccati solution (n × n); the optimal cost from x₀ is x₀ᵀ S x₀.",
        e as "E": "Closed-loop poles, the eigenvalues of A − B K (complex).",
    }
    also {
        residual as "residual": "Relative residual of the Riccati equation at S.",
    }
);

impl LqrResult {
    fn new(py: Python<'_>, l: &Lqr) -> PyResult<Self> {
        Ok(Self {
            k: matrix_to_numpy(py, &l.gain).into_any().unbind(),
            s: matrix_to_numpy(py, &l.riccati).into_any().unbind(),
            e: complex_to_numpy(py, &l.closed_loop_poles)
                .into_any()
                .unbind(),
            residual: obj(py, l.residual)?,
        })
    }
}

/// The system and weights of `lqr(sys, Q, R[, N])` / `lqr(A, B, Q, R[, N])`; `discrete`
/// makes an `(A, B)` pair discrete (the sample time does not enter the DARE).
fn lq_problem(
    args: &Bound<'_, PyTuple>,
    n_kw: Option<&Bound<'_, PyAny>>,
    discrete: bool,
    name: &str,
) -> PyResult<(Sys, Mat, Mat, Option<Mat>)> {
    let first = args.get_item(0).map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} takes (sys, Q, R[, N]) or (A, B, Q, R[, N])"
        ))
    })?;
    let (sys, rest) = if is_system(&first) {
        (system(&first)?, 1)
    } else {
        let a = matrix(&first, "A", OneD::Row)?;
        let b_one_d = if a.nrows() == 1 {
            OneD::Row
        } else {
            OneD::Column
        };
        let b = matrix(&args.get_item(1)?, "B", b_one_d)?;
        let (n, m) = (a.nrows(), b.ncols());
        let (c, d) = (Mat::zeros(0, n), Mat::zeros(0, m));
        let sys = if discrete {
            Sys::Discrete(Ss::discrete(a, b, c, d, 1.0).map_err(lti)?)
        } else {
            Sys::Continuous(Ss::continuous(a, b, c, d).map_err(lti)?)
        };
        (sys, 2)
    };
    let count = args.len() - rest;
    if !(count == 2 || count == 3 && n_kw.is_none()) {
        return Err(PyTypeError::new_err(format!(
            "{name} takes (sys, Q, R[, N]) or (A, B, Q, R[, N]), got {} positional arguments",
            args.len()
        )));
    }
    let q = matrix(&args.get_item(rest)?, "Q", OneD::Row)?;
    let r = matrix(&args.get_item(rest + 1)?, "R", OneD::Row)?;
    let n_obj = if count == 3 {
        Some(args.get_item(rest + 2)?)
    } else {
        n_kw.cloned()
    };
    let n_one_d = if q.nrows() == 1 {
        OneD::Row
    } else {
        OneD::Column
    };
    let n = match n_obj {
        Some(n) if !n.is_none() => Some(matrix(&n, "N", n_one_d)?),
        _ => None,
    };
    Ok((sys, q, r, n))
}

/// `lqr(sys, Q, R[, N])` or `lqr(A, B, Q, R[, N])`: the LQ regulator `u = −K x`.
///
/// Continuous time minimises `∫₀^∞ (xᵀQx + uᵀRu + 2xᵀNu) dt` through the CARE
/// `AᵀS + SA − (SB + N)R⁻¹(BᵀS + Nᵀ) + Q = 0`, `K = R⁻¹(BᵀS + Nᵀ)`. A discrete `sys`
/// (`dt > 0`) gives the discrete regulator of `dlqr`. `[[Q, N], [Nᵀ, R]]` must be positive
/// semidefinite and `R` positive definite. Returns `LqrResult` (`K, S, E = lqr(...)`).
///
/// The book writes `u = +K_book x` with `K_book = −K`.
///
/// Raises `pendulab.NotStabilizableError` when no stabilising solution exists (e.g. an
/// uncontrollable unstable mode), `pendulab.InvalidArgumentError` for indefinite weights,
/// `pendulab.ShapeError`/`NotFiniteError` for malformed data.
#[pyfunction]
#[pyo3(signature = (*args, N = None))]
#[allow(non_snake_case)]
pub fn lqr(
    py: Python<'_>,
    args: &Bound<'_, PyTuple>,
    N: Option<&Bound<'_, PyAny>>,
) -> PyResult<LqrResult> {
    let (sys, q, r, n) = lq_problem(args, N, false, "lqr")?;
    let l = nogil(
        py,
        || with_sys!(&sys, s => design::lqr(s, &q, &r, n.as_ref())),
    )?;
    LqrResult::new(py, &l)
}

/// `dlqr(sys, Q, R[, N])` or `dlqr(A, B, Q, R[, N])`: the discrete LQ regulator
/// `u[k] = −K x[k]` minimising `Σ (xᵀQx + uᵀRu + 2xᵀNu)` for `x[k+1] = A x[k] + B u[k]`,
/// through the DARE, `K = (BᵀSB + R)⁻¹(BᵀSA + Nᵀ)`. Returns `LqrResult` (`K, S, E`).
///
/// Raises as `lqr`, and `pendulab.InvalidArgumentError` for a continuous-time `sys`.
#[pyfunction]
#[pyo3(signature = (*args, N = None))]
#[allow(non_snake_case)]
pub fn dlqr(
    py: Python<'_>,
    args: &Bound<'_, PyTuple>,
    N: Option<&Bound<'_, PyAny>>,
) -> PyResult<LqrResult> {
    let (sys, q, r, n) = lq_problem(args, N, true, "dlqr")?;
    let Sys::Discrete(s) = sys else {
        return Err(new_err(
            Kind::InvalidArgument,
            "dlqr needs a discrete-time system (dt > 0); use lqr for continuous time".into(),
            None,
        ));
    };
    let l = nogil(py, || design::lqr(&s, &q, &r, n.as_ref()))?;
    LqrResult::new(py, &l)
}

result_class!(
    LqeResult, "LqeResult",
    "A steady-state Kalman (LQE) estimator gain; unpacks as python-control's `L, P, E`.",
    array none,
    unpack {
        l as "L": "The estimator gain L (n × p): x̂' = A x̂ + B u + L (y − C x̂ − D u).",
        p as "P": "Steady-state error covariance (discrete: one-step-ahead prediction covariance).",
        e as "E": "Estimator poles, the eigenvalues of A − L C (complex).",
    }
    also {
        residual as "residual": "Relative residual of the dual Riccati equation.",
    }
);

fn lqe_common(
    py: Python<'_>,
    args: &Bound<'_, PyTuple>,
    discrete: bool,
    name: &str,
) -> PyResult<LqeResult> {
    let usage = || {
        PyTypeError::new_err(format!(
            "{name} takes (sys, QN, RN[, NN]) or (A, G, C, QN, RN[, NN]), got {} positional arguments",
            args.len()
        ))
    };
    let first = args.get_item(0).map_err(|_| usage())?;
    let (sys, g, rest) = if is_system(&first) {
        let sys = system(&first)?;
        let g = with_sys!(&sys, s => s.b().clone());
        (sys, g, 1)
    } else {
        if args.len() < 5 {
            return Err(usage());
        }
        let a = matrix(&first, "A", OneD::Row)?;
        let col = if a.nrows() == 1 {
            OneD::Row
        } else {
            OneD::Column
        };
        let g = matrix(&args.get_item(1)?, "G", col)?;
        let c = matrix(&args.get_item(2)?, "C", OneD::Row)?;
        let (n, p) = (a.nrows(), c.nrows());
        let (b, d) = (Mat::zeros(n, 0), Mat::zeros(p, 0));
        let sys = if discrete {
            Sys::Discrete(Ss::discrete(a, b, c, d, 1.0).map_err(lti)?)
        } else {
            Sys::Continuous(Ss::continuous(a, b, c, d).map_err(lti)?)
        };
        (sys, g, 3)
    };
    let count = args.len() - rest;
    if !(count == 2 || count == 3) {
        return Err(usage());
    }
    let qn = matrix(&args.get_item(rest)?, "QN", OneD::Row)?;
    let rn = matrix(&args.get_item(rest + 1)?, "RN", OneD::Row)?;
    let nn = if count == 3 {
        Some(matrix(&args.get_item(rest + 2)?, "NN", OneD::Column)?)
    } else {
        None
    };
    if discrete && matches!(sys, Sys::Continuous(_)) {
        return Err(new_err(
            Kind::InvalidArgument,
            format!("{name} needs a discrete-time system (dt > 0)"),
            None,
        ));
    }
    let k: Kalman = nogil(
        py,
        || with_sys!(&sys, s => design::lqe(s, &g, &qn, &rn, nn.as_ref())),
    )?;
    Ok(LqeResult {
        l: matrix_to_numpy(py, &k.gain).into_any().unbind(),
        p: matrix_to_numpy(py, &k.covariance).into_any().unbind(),
        e: complex_to_numpy(py, &k.estimator_poles).into_any().unbind(),
        residual: obj(py, k.residual)?,
    })
}

/// `lqe(sys, QN, RN[, NN])` (G = sys.B) or `lqe(A, G, C, QN, RN[, NN])`: the steady-state
/// Kalman gain for `ẋ = Ax + Bu + Gw`, `y = Cx + Du + v`, `E[wwᵀ] = QN`, `E[vvᵀ] = RN`,
/// `E[wvᵀ] = NN`: `L = (P Cᵀ + G NN) RN⁻¹` with `P` from the dual CARE. A discrete `sys`
/// gives the predictor gain of `dlqe`. Returns `LqeResult` (`L, P, E = lqe(...)`).
///
/// Raises `pendulab.NotStabilizableError` if `(C, A)` is not detectable.
#[pyfunction]
#[pyo3(signature = (*args))]
pub fn lqe(py: Python<'_>, args: &Bound<'_, PyTuple>) -> PyResult<LqeResult> {
    lqe_common(py, args, false, "lqe")
}

/// `dlqe(sys, QN, RN[, NN])` or `dlqe(A, G, C, QN, RN[, NN])`: the discrete steady-state
/// Kalman predictor gain `L = (A P Cᵀ + G NN)(C P Cᵀ + RN)⁻¹` with `P` from the dual DARE.
#[pyfunction]
#[pyo3(signature = (*args))]
pub fn dlqe(py: Python<'_>, args: &Bound<'_, PyTuple>) -> PyResult<LqeResult> {
    lqe_common(py, args, true, "dlqe")
}

result_class!(
    PlaceResult, "PlaceResult",
    "A pole-placement gain with its accuracy; behaves as the gain array (`numpy.asarray(result)`), as python-control's `place` returns it.",
    array k,
    unpack {
        k as "K": "The gain: K (m × n, closed loop A − BK) from place/acker, L (n × p, observer A − LC) from place_observer.",
    }
    also {
        poles as "poles": "The achieved poles, eigenvalues of the closed loop (complex).",
        requested_poles as "requested_poles": "The requested poles, sorted (complex).",
        max_relative_error as "max_relative_error": "max |λ_achieved − λ_requested| / max(1, |λ_requested|).",
        eigenvector_condition as "eigenvector_condition": "2-norm condition number of the closed-loop eigenvector matrix (nan if not formed).",
        method as "method": "The algorithm used.",
    }
);

impl PlaceResult {
    fn new(py: Python<'_>, p: &PolePlacement) -> PyResult<Self> {
        Ok(Self {
            k: matrix_to_numpy(py, &p.gain).into_any().unbind(),
            poles: complex_to_numpy(py, &p.achieved_poles).into_any().unbind(),
            requested_poles: complex_to_numpy(py, &p.requested_poles).into_any().unbind(),
            max_relative_error: obj(py, p.max_relative_error)?,
            eigenvector_condition: obj(py, p.eigenvector_condition)?,
            method: obj(py, format!("{:?}", p.method))?,
        })
    }
}

type Placer = fn(&Mat, &Mat, &[pendulab_lti::Complex64]) -> pendulab_lti::Result<PolePlacement>;

fn placement(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
    b_name: &str,
    b_one_d: OneD,
    f: Placer,
) -> PyResult<PlaceResult> {
    let py = a.py();
    let a = matrix(a, "A", OneD::Row)?;
    let one_d = if a.nrows() == 1 { OneD::Row } else { b_one_d };
    let b = matrix(b, b_name, one_d)?;
    let p = complex_vector(p, "poles")?;
    let r = nogil(py, || f(&a, &b, &p))?;
    PlaceResult::new(py, &r)
}

/// `place(A, B, p)`: a gain K with `eig(A − BK) = p` (robust assignment of Kautsky, Nichols
/// & Van Dooren for several inputs or distinct poles, Ackermann in Hessenberg coordinates
/// otherwise). Returns `PlaceResult`, usable as the array K; check `max_relative_error`.
///
/// Raises `pendulab.NotControllableError` for an uncontrollable pair,
/// `pendulab.InvalidArgumentError` for a wrong number of poles or a complex pole without its
/// conjugate.
#[pyfunction]
#[pyo3(name = "place")]
#[allow(non_snake_case)]
pub fn place_py(
    A: &Bound<'_, PyAny>,
    B: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
) -> PyResult<PlaceResult> {
    placement(A, B, p, "B", OneD::Column, design::place)
}

/// `acker(A, B, p)`: Ackermann's formula `K = e_nᵀ M_c⁻¹ φ(A)` (single input), the
/// textbook's formula; ill-conditioned beyond a few states (prefer `place`).
#[pyfunction]
#[pyo3(name = "acker")]
#[allow(non_snake_case)]
pub fn acker_py(
    A: &Bound<'_, PyAny>,
    B: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
) -> PyResult<PlaceResult> {
    placement(A, B, p, "B", OneD::Column, design::acker)
}

/// `place_observer(A, C, p)`: an observer gain L (n × p) with `eig(A − LC) = p`, by duality
/// (MATLAB `place(A', C', p)'`).
#[pyfunction]
#[pyo3(name = "place_observer")]
#[allow(non_snake_case)]
pub fn place_observer_py(
    A: &Bound<'_, PyAny>,
    C: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
) -> PyResult<PlaceResult> {
    placement(A, C, p, "C", OneD::Row, design::place_observer)
}

result_class!(
    LqiResult, "LqiResult",
    "An LQ integral servo u = −K₁ x − K₂ w, w = ∫(r − y) dt; unpacks as MATLAB's `lqi` triple `K, S, E` with K = [K₁, K₂].",
    array none,
    unpack {
        k as "K": "The augmented gain [K₁, K₂] (m × (n + p)).",
        s as "S": "Riccati solution of the augmented problem.",
        e as "E": "Closed-loop poles of the augmented system (complex).",
    }
    also {
        state_gain as "state_gain": "K₁ (m × n); the book's gain is −K₁.",
        integral_gain as "integral_gain": "K₂ (m × p); the book's gain is −K₂.",
        residual as "residual": "Relative residual of the Riccati equation.",
    }
);

/// `lqi(sys, Q, R)`: the LQ integral servo of the book (Part 1 §6.3, eq. 6.40): the LQR of
/// the plant augmented with `w = ∫(r − y) dt` (continuous) or `w[k+1] = w[k] + r[k] − y[k]`
/// (discrete), `Q` weighting `[x; w]` ((n + p) × (n + p)), giving `u = −K₁ x − K₂ w`.
///
/// Raises `pendulab.NotStabilizableError` if the plant has a transmission zero at s = 0
/// (z = 1) or is not stabilisable.
#[pyfunction]
#[allow(non_snake_case)]
pub fn lqi(
    sys: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
) -> PyResult<LqiResult> {
    let py = sys.py();
    let s = system(sys)?;
    let q = matrix(Q, "Q", OneD::Row)?;
    let r = matrix(R, "R", OneD::Row)?;
    let servo = nogil(py, || with_sys!(&s, s => design::lq_servo(s, &q, &r)))?;
    Ok(LqiResult {
        k: matrix_to_numpy(py, &servo.lqr.gain).into_any().unbind(),
        s: matrix_to_numpy(py, &servo.lqr.riccati).into_any().unbind(),
        e: complex_to_numpy(py, &servo.lqr.closed_loop_poles)
            .into_any()
            .unbind(),
        state_gain: matrix_to_numpy(py, &servo.state_gain).into_any().unbind(),
        integral_gain: matrix_to_numpy(py, &servo.integral_gain)
            .into_any()
            .unbind(),
        residual: obj(py, servo.lqr.residual)?,
    })
}

result_class!(
    SampledDataLqrResult, "SampledDataLqrResult",
    "A sampled-data LQR (MATLAB `lqrd`); unpacks as `K, S, E` of the discrete design.",
    array none,
    unpack {
        k as "K": "The discrete gain K_d: u(t) = −K_d x(k Ts) held over each interval.",
        s as "S": "Riccati solution of the discrete design.",
        e as "E": "Closed-loop poles (z plane, complex).",
    }
    also {
        system as "system": "The ZOH discretisation of the plant at Ts (pendulab.StateSpace).",
        qd as "Qd": "Van Loan's discretised state weight.",
        rd as "Rd": "Discretised input weight.",
        nd as "Nd": "Discretised cross weight (non-zero even when N = 0).",
        residual as "residual": "Relative residual of the DARE.",
    }
);

/// `lqr_sampled_data(sys, Q, R, Ts, N=None)` (MATLAB `lqrd`): the discrete gain that
/// minimises the continuous cost `∫ (xᵀQx + uᵀRu + 2xᵀNu) dt` over zero-order-hold inputs,
/// through Van Loan's discretisation of the cost and the DARE with its cross term (book
/// Part 2 §2.4.4).
#[pyfunction]
#[pyo3(signature = (sys, Q, R, Ts, N = None))]
#[allow(non_snake_case)]
pub fn lqr_sampled_data(
    sys: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
    Ts: f64,
    N: Option<&Bound<'_, PyAny>>,
) -> PyResult<SampledDataLqrResult> {
    let py = sys.py();
    let Sys::Continuous(s) = system(sys)? else {
        return Err(new_err(
            Kind::InvalidArgument,
            "lqr_sampled_data needs a continuous-time system (dt = 0)".into(),
            None,
        ));
    };
    let q = matrix(Q, "Q", OneD::Row)?;
    let r = matrix(R, "R", OneD::Row)?;
    let n = match N {
        Some(n) if !n.is_none() => Some(matrix(n, "N", OneD::Column)?),
        _ => None,
    };
    let d = nogil(py, || design::lqr_sampled_data(&s, &q, &r, n.as_ref(), Ts))?;
    Ok(SampledDataLqrResult {
        k: matrix_to_numpy(py, &d.lqr.gain).into_any().unbind(),
        s: matrix_to_numpy(py, &d.lqr.riccati).into_any().unbind(),
        e: complex_to_numpy(py, &d.lqr.closed_loop_poles)
            .into_any()
            .unbind(),
        system: StateSpace::wrap(py, Sys::Discrete(d.system))?,
        qd: matrix_to_numpy(py, &d.cost.q).into_any().unbind(),
        rd: matrix_to_numpy(py, &d.cost.r).into_any().unbind(),
        nd: matrix_to_numpy(py, &d.cost.n).into_any().unbind(),
        residual: obj(py, d.lqr.residual)?,
    })
}

/// `reg(sys, K, L)` (MATLAB `reg`): the observer-based output-feedback controller from `y` to
/// `u`: `x̂' = (A − BK − LC + LDK) x̂ + L y`, `u = −K x̂`, for `u = −K x` and a full-order
/// observer `A − LC`; returns a `pendulab.StateSpace`.
#[pyfunction]
#[allow(non_snake_case)]
pub fn reg(
    sys: &Bound<'_, PyAny>,
    K: &Bound<'_, PyAny>,
    L: &Bound<'_, PyAny>,
) -> PyResult<Py<PyAny>> {
    let py = sys.py();
    let s = system(sys)?;
    let k = matrix(K, "K", OneD::Row)?;
    let l = matrix(L, "L", OneD::Column)?;
    let out = match &s {
        Sys::Continuous(s) => {
            Sys::Continuous(design::observer_controller::<Continuous>(s, &k, &l).map_err(lti)?)
        }
        Sys::Discrete(s) => {
            Sys::Discrete(design::observer_controller::<Discrete>(s, &k, &l).map_err(lti)?)
        }
    };
    StateSpace::wrap(py, out)
}

result_class!(
    MinimalObserverResult, "MinimalObserverResult",
    "A minimal-order (Gopinath) observer (book Part 1 §7); unpacks as `system, L`.",
    array none,
    unpack {
        system as "system": "The observer: inputs [u; y], state ζ (n − p), output x̂ (n) (pendulab.StateSpace).",
        l as "L": "The gain L ((n − p) × p) placing eig(A₂₂ − L A₁₂).",
    }
    also {
        t as "T": "The transformation T = [C; R] (x̄ = T x).",
        poles as "poles": "The achieved error poles (complex).",
        max_relative_error as "max_relative_error": "Relative error of the achieved poles.",
    }
);

/// `minimal_order_observer(sys, p)`: a minimal-order observer with the `n − p` error poles
/// `p` (book Part 1 §7).
///
/// Raises `pendulab.InvalidArgumentError` unless C has full row rank p < n and n − p poles
/// are given; `pendulab.NotControllableError` if `(C, A)` is not observable.
#[pyfunction]
pub fn minimal_order_observer(
    sys: &Bound<'_, PyAny>,
    p: &Bound<'_, PyAny>,
) -> PyResult<MinimalObserverResult> {
    let py = sys.py();
    let s = system(sys)?;
    let poles = complex_vector(p, "poles")?;
    let (obs_sys, gain, t, placement) = match &s {
        Sys::Continuous(s) => {
            let o = nogil(py, || design::minimal_order_observer(s, &poles))?;
            (
                Sys::Continuous(o.system),
                o.gain,
                o.transformation,
                o.placement,
            )
        }
        Sys::Discrete(s) => {
            let o = nogil(py, || design::minimal_order_observer(s, &poles))?;
            (
                Sys::Discrete(o.system),
                o.gain,
                o.transformation,
                o.placement,
            )
        }
    };
    Ok(MinimalObserverResult {
        system: StateSpace::wrap(py, obs_sys)?,
        l: matrix_to_numpy(py, &gain).into_any().unbind(),
        t: matrix_to_numpy(py, &t).into_any().unbind(),
        poles: complex_to_numpy(py, &placement.achieved_poles)
            .into_any()
            .unbind(),
        max_relative_error: obj(py, placement.max_relative_error)?,
    })
}
