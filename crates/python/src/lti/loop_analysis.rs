//! Loop analysis: `nyquist`, `nichols`, `rlocus`, `rlocfind`, `disk_margin`,
//! `disk_margin_mimo`, `mu_diag_complex`, `sigma` (pendulab-lti's `nyquist`, `rlocus`,
//! `disk_margin`, `mu` and `sigma` modules).

use super::nogil;
use super::response::frequencies;
use super::results::{obj, result_class};
use super::system::{system, with_sys};
use crate::convert::{complex_to_numpy, complex_vector, slice_to_numpy, vector};
use crate::errors::{Kind, new_err};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pendulab_lti::disk_margin::DiskMargin;
use pendulab_lti::mu::{self, MuBounds, mu_diag_complex};
use pendulab_lti::{CMat, Complex64};
use pyo3::prelude::*;

result_class!(
    NyquistResult, "NyquistResult",
    "Nyquist curve and encirclement count; unpacks as `count, response, omega` (python-control's `nyquist_response` count: clockwise encirclements of −1).",
    array none,
    unpack {
        count as "count": "N: clockwise encirclements of −1 by the whole (mirrored) curve.",
        response as "response": "L on the upper half of the contour (ω ≥ 0), complex; the lower half is its conjugate.",
        omega as "omega": "The frequency parameter of each contour point, rad/s, ascending from 0.",
    }
    also {
        contour as "contour": "The contour points s (or z = e^{s dt}), indented to the right of imaginary-axis poles (radius indent_radius).",
        winding as "winding": "The unrounded count (far from an integer when the curve passes through −1).",
        open_loop_unstable as "open_loop_unstable": "P: open-loop poles with Re > 0 (|z| > 1).",
        closed_loop_unstable as "closed_loop_unstable": "Z: closed-loop poles with Re ≥ 0 (|z| ≥ 1), from the closed loop's eigenvalues.",
        criterion_holds as "criterion_holds": "Z == N + P.",
        indented_poles as "indented_poles": "Poles of L the contour was indented around (s-plane, Im ≥ 0).",
        min_distance as "min_distance": "min |1 + L| over the contour.",
    }
);

/// `nyquist(sys, indent_radius=1e-4)`: the Nyquist curve of the SISO loop `L` (closed as
/// `u = −L y`) with the clockwise encirclements of −1 and the Nyquist criterion
/// `Z = N + P` (python-control's `nyquist_response` conventions: the contour passes
/// imaginary-axis poles on the right). Returns `NyquistResult` (`count, response, omega`).
///
/// Raises `pendulab.DimensionError` (variant `NotSiso`) for a MIMO system,
/// `pendulab.LinAlgError` (`Singular`) for an ill-posed loop (1 + D = 0).
#[pyfunction]
#[pyo3(signature = (sys, indent_radius = 1e-4))]
pub fn nyquist(sys: &Bound<'_, PyAny>, indent_radius: f64) -> PyResult<NyquistResult> {
    let py = sys.py();
    let s = system(sys)?;
    let opts = pendulab_lti::nyquist::NyquistOptions {
        indent_radius,
        ..Default::default()
    };
    let c = nogil(
        py,
        || with_sys!(&s, s => pendulab_lti::nyquist::nyquist(s, &opts)),
    )?;
    Ok(NyquistResult {
        count: obj(py, c.encirclements)?,
        response: complex_to_numpy(py, &c.response).into_any().unbind(),
        omega: slice_to_numpy(py, &c.w).into_any().unbind(),
        contour: complex_to_numpy(py, &c.contour).into_any().unbind(),
        winding: obj(py, c.winding)?,
        open_loop_unstable: obj(py, c.open_loop_unstable)?,
        closed_loop_unstable: obj(py, c.closed_loop_unstable)?,
        criterion_holds: obj(py, c.criterion_holds())?,
        indented_poles: complex_to_numpy(py, &c.indented_poles).into_any().unbind(),
        min_distance: obj(py, c.min_distance_to_critical)?,
    })
}

result_class!(
    NicholsResult, "NicholsResult",
    "Nichols curve; unpacks as `mag_db, phase_deg, omega`.",
    array none,
    unpack {
        mag_db as "mag_db": "20 log₁₀|L| in dB.",
        phase_deg as "phase_deg": "∠L in degrees, unwrapped along omega and shifted by whole turns so that the first value is in (−360°, 0°].",
        omega as "omega": "Frequencies in rad/s.",
    }
    also {}
);

/// `nichols(sys, omega=None)`: the Nichols curve of a SISO system (MATLAB `nichols` data; no
/// plot). Returns `NicholsResult` (`mag_db, phase_deg, omega`).
#[pyfunction]
#[pyo3(signature = (sys, omega = None))]
pub fn nichols(
    sys: &Bound<'_, PyAny>,
    omega: Option<&Bound<'_, PyAny>>,
) -> PyResult<NicholsResult> {
    let py = sys.py();
    let s = system(sys)?;
    let w = with_sys!(&s, s => frequencies(s, omega))?;
    let n = nogil(
        py,
        || with_sys!(&s, s => pendulab_lti::nyquist::nichols(s, &w)),
    )?;
    Ok(NicholsResult {
        mag_db: slice_to_numpy(py, &n.magnitude_db).into_any().unbind(),
        phase_deg: slice_to_numpy(py, &n.phase_deg).into_any().unbind(),
        omega: slice_to_numpy(py, &n.w).into_any().unbind(),
    })
}

result_class!(
    RootLocusResult, "RootLocusResult",
    "Root locus; unpacks as `roots, gains` (MATLAB's `[r, k] = rlocus(sys)`, python-control's `loci, gains`).",
    array none,
    unpack {
        roots as "roots": "Closed-loop poles, complex, shape (len(gains), n); column b is branch b (continuous where the grid resolves it).",
        gains as "gains": "Gains K ≥ 0, ascending (negative feedback u = −K y).",
    }
    also {
        poles as "poles": "Open-loop poles (K = 0).",
        zeros as "zeros": "Open-loop zeros.",
        centroid as "centroid": "Centroid of the asymptotes (nan without infinite branches).",
        asymptote_angles as "asymptote_angles": "Asymptote angles (2k + 1)π/(n − m), radians.",
        break_points as "break_points": "Break-away/break-in points (roots of N D′ − N′ D with real K ≥ 0), complex.",
        break_gains as "break_gains": "The gain at each break point.",
    }
);

/// `rlocus(sys, gains=None)`: the root locus of the SISO loop (closed-loop poles of
/// `D + K N = 0` over `gains`, or an adaptive grid with the break points' gains), with its
/// asymptotes and break points. Returns `RootLocusResult` (`roots, gains`).
///
/// Raises `pendulab.DimensionError` (`NotSiso`) for a MIMO system; `pendulab.Error`
/// subclasses for a negative gain or the zero loop.
#[pyfunction]
#[pyo3(signature = (sys, gains = None))]
pub fn rlocus(
    sys: &Bound<'_, PyAny>,
    gains: Option<&Bound<'_, PyAny>>,
) -> PyResult<RootLocusResult> {
    let py = sys.py();
    let s = system(sys)?;
    let g: Option<Vec<f64>> = match gains {
        Some(g) if !g.is_none() => Some(vector(g, "gains")?.data.into()),
        _ => None,
    };
    let rl = nogil(
        py,
        || with_sys!(&s, s => pendulab_lti::rlocus::rlocus(s, g.as_deref())),
    )?;
    let n = rl.roots.first().map_or(0, Vec::len);
    let roots =
        Array2::from_shape_fn((rl.roots.len(), n), |(i, j)| rl.roots[i][j]).into_pyarray(py);
    let bp: Vec<Complex64> = rl.break_points.iter().map(|b| b.point).collect();
    let bg: Vec<f64> = rl.break_points.iter().map(|b| b.gain).collect();
    Ok(RootLocusResult {
        roots: roots.into_any().unbind(),
        gains: slice_to_numpy(py, &rl.gains).into_any().unbind(),
        poles: complex_to_numpy(py, &rl.poles).into_any().unbind(),
        zeros: complex_to_numpy(py, &rl.zeros).into_any().unbind(),
        centroid: obj(py, rl.asymptotes.centroid)?,
        asymptote_angles: slice_to_numpy(py, &rl.asymptotes.angles)
            .into_any()
            .unbind(),
        break_points: complex_to_numpy(py, &bp).into_any().unbind(),
        break_gains: slice_to_numpy(py, &bg).into_any().unbind(),
    })
}

result_class!(
    RlocfindResult, "RlocfindResult",
    "The gain at a point of the plane; unpacks as `gain, poles` (MATLAB's `[K, poles] = rlocfind(sys, p)`).",
    array none,
    unpack {
        gain as "gain": "K = Re(−D(s0)/N(s0)).",
        poles as "poles": "Closed-loop poles at that gain.",
    }
    also {
        gain_complex as "gain_complex": "−D(s0)/N(s0) itself (real when s0 is on the locus).",
        distance as "distance": "Distance from s0 to the nearest closed-loop pole (0 on the locus).",
    }
);

/// `rlocfind(sys, s0)`: the gain that places a closed-loop pole at (or nearest) `s0`.
#[pyfunction]
pub fn rlocfind(sys: &Bound<'_, PyAny>, s0: &Bound<'_, PyAny>) -> PyResult<RlocfindResult> {
    let py = sys.py();
    let s = system(sys)?;
    let v = complex_vector(s0, "s0")?;
    let [s0] = v[..] else {
        return Err(new_err(
            Kind::InvalidArgument,
            format!("s0: one complex number expected, got {} values", v.len()),
            None,
        ));
    };
    let f = nogil(
        py,
        || with_sys!(&s, s => pendulab_lti::rlocus::rlocfind(s, s0)),
    )?;
    Ok(RlocfindResult {
        gain: obj(py, f.gain)?,
        poles: complex_to_numpy(py, &f.poles).into_any().unbind(),
        gain_complex: pyo3::types::PyComplex::from_doubles(
            py,
            f.gain_complex.re,
            f.gain_complex.im,
        )
        .into_any()
        .unbind(),
        distance: obj(py, f.distance)?,
    })
}

result_class!(
    DiskMarginResult, "DiskMarginResult",
    "Disk margin; unpacks as `alpha, gain_margin_db, phase_margin_deg` (python-control's `DM, DGM, DPM`).",
    array none,
    unpack {
        alpha as "alpha": "α = 1/‖S + (skew − 1)/2‖∞ (exact peak; 0 for an unstable closed loop).",
        gain_margin_db as "gain_margin_db": "20 log₁₀ min(1/γ₋, γ₊) in dB (inf when unbounded).",
        phase_margin_deg as "phase_margin_deg": "The disk-based phase margin in degrees.",
    }
    also {
        gain_interval as "gain_interval": "(γ₋, γ₊): the gains the disk guarantees (γ₊ may be inf).",
        frequency as "frequency": "The critical frequency in rad/s (inf when approached at infinite frequency, nan if unstable).",
        closed_loop_stable as "closed_loop_stable": "Whether the nominal closed loop is stable.",
        skew as "skew": "The skew σ used.",
    }
);

impl DiskMarginResult {
    /// From pendulab-lti's margin.
    fn from_margin(py: Python<'_>, m: &DiskMargin) -> PyResult<Self> {
        Ok(DiskMarginResult {
            alpha: obj(py, m.alpha)?,
            gain_margin_db: obj(py, m.gain_margin_db())?,
            phase_margin_deg: obj(py, m.phase_margin_deg)?,
            gain_interval: obj(py, (m.gain_interval.0, m.gain_interval.1))?,
            frequency: obj(py, m.frequency)?,
            closed_loop_stable: obj(py, m.closed_loop_stable)?,
            skew: obj(py, m.skew)?,
        })
    }
}

/// `disk_margin(sys, skew=0.0)`: the disk margin of the SISO loop (Seiler, Packard &
/// Gahinet 2020), the gain interval and phase margin it guarantees, the critical frequency.
/// Returns `DiskMarginResult` (`alpha, gain_margin_db, phase_margin_deg`).
#[pyfunction]
#[pyo3(signature = (sys, skew = 0.0))]
pub fn disk_margin(sys: &Bound<'_, PyAny>, skew: f64) -> PyResult<DiskMarginResult> {
    let py = sys.py();
    let s = system(sys)?;
    let m = nogil(
        py,
        || with_sys!(&s, s => pendulab_lti::disk_margin::disk_margin(s, skew)),
    )?;
    DiskMarginResult::from_margin(py, &m)
}

result_class!(
    MuResult, "MuResult",
    "Bounds on the structured singular value μ(M) for Δ = diag(δ₁, …, δ_p), δᵢ ∈ ℂ; unpacks as `upper, lower` (MATLAB mussv's bounds order).",
    array none,
    unpack {
        upper as "upper": "min_D σ̄(D M D⁻¹) at the returned scaling: a guaranteed upper bound (equal to μ for p ≤ 3 up to the optimisation's tolerance).",
        lower as "lower": "ρ(Q M) for the best unitary diagonal Q found: a guaranteed lower bound.",
    }
    also {
        d_scaling as "d_scaling": "The diagonal of the scaling D (positive, d₀ = 1).",
    }
);

impl MuResult {
    fn from_bounds(py: Python<'_>, b: &MuBounds) -> PyResult<Self> {
        Ok(MuResult {
            upper: obj(py, b.upper)?,
            lower: obj(py, b.lower)?,
            d_scaling: slice_to_numpy(py, &b.d_scaling).into_any().unbind(),
        })
    }
}

/// A square complex matrix from any NumPy-convertible 2-d input (real or complex).
///
/// # Errors
/// `InvalidArgumentError` if NumPy cannot read it as complex numbers; `ShapeError` unless it
/// is 2-d (NaN/±Inf and non-square are left to the library, which names the entry).
fn complex_matrix(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<CMat> {
    let py = obj.py();
    let a = py
        .import("numpy")?
        .getattr("asarray")?
        .call1((obj, "complex128"))
        .map_err(|e| {
            new_err(
                Kind::InvalidArgument,
                format!("{what} cannot be read as a complex matrix: {}", e.value(py)),
                None,
            )
        })?;
    let a = a
        .cast_into::<PyArrayDyn<Complex64>>()
        .map_err(|e| new_err(Kind::InvalidArgument, format!("{what}: {e}"), None))?;
    let shape = a.shape().to_vec();
    let [r, c] = shape[..] else {
        return Err(new_err(
            Kind::Shape,
            format!("{what} must be a 2-d matrix, got shape {shape:?}"),
            None,
        ));
    };
    let ro = a.try_readonly()?;
    let v = ro.as_array();
    Ok(CMat::from_fn(r, c, |i, j| v[[i, j]]))
}

/// `mu_diag_complex(M)`: bounds on the structured singular value
/// `μ(M) = 1 / min{σ̄(Δ) : det(I − M Δ) = 0}` for diagonal complex `Δ = diag(δ₁, …, δ_p)`
/// (Packard & Doyle 1993): the upper bound `min_D σ̄(D M D⁻¹)` over positive diagonal `D`
/// (Osborne's balancing, then steepest descent on the convex `log D`), the lower bound
/// `ρ(Q M)` over unitary diagonal `Q` (the Packard–Doyle power iteration). For `p ≤ 3` the
/// upper bound is `μ` itself. `M` is any real or complex square matrix. Returns `MuResult`
/// (`upper, lower`).
///
/// Raises `pendulab.ShapeError` for a non-square or non-2-d `M`, `pendulab.NotFiniteError` for
/// a NaN or infinite entry.
#[pyfunction]
#[pyo3(name = "mu_diag_complex", signature = (M))]
#[allow(non_snake_case)]
pub fn mu_diag_complex_py(M: &Bound<'_, PyAny>) -> PyResult<MuResult> {
    let py = M.py();
    let m = complex_matrix(M, "M")?;
    let b = nogil(py, || mu_diag_complex(&m))?;
    MuResult::from_bounds(py, &b)
}

result_class!(
    MimoDiskMarginResult, "MimoDiskMarginResult",
    "Loop-at-a-time and multi-loop disk margins of a square loop; unpacks as MATLAB's `DM, MM = diskmargin(L)`.",
    array none,
    unpack {
        loop_at_a_time as "loop_at_a_time": "A list of DiskMarginResult, channel i broken with the other loops closed: α = 1/‖S_ii + (skew − 1)/2‖∞ (exact peak).",
        multi_loop as "multi_loop": "DiskMarginResult of simultaneous independent perturbations of every channel: α = 1/μ_upper of S + (skew − 1)/2·I at the peak (conservative).",
    }
    also {
        alpha_bounds as "alpha_bounds": "(1/μ_upper, 1/μ_lower) at the peak: the multi-loop α lies in this interval (both 0 for an unstable closed loop).",
        mu_peak as "mu_peak": "MuResult of S + (skew − 1)/2·I at the peak frequency.",
        peak_frequency as "peak_frequency": "The frequency of the largest μ upper bound, rad/s (inf for the feedthrough of a continuous loop, nan for an unstable closed loop).",
        closed_loop_stable as "closed_loop_stable": "Whether the nominal closed loop is stable.",
    }
);

/// `disk_margin_mimo(L, skew=0.0)`: the disk margins of the square loop `L` closed with
/// negative unit feedback (MATLAB `[DM, MM] = diskmargin(L)`; Seiler, Packard & Gahinet 2020),
/// with `S = (I + L)⁻¹` and `S_σ = S + (skew − 1)/2·I`: loop-at-a-time margins
/// `α_i = 1/‖(S_σ)_ii‖∞` (the SISO `disk_margin` of channel `i` with the other loops closed)
/// and the multi-loop margin `α = 1/sup_ω μ(S_σ(jω))` for simultaneous independent
/// perturbations `f_i ∈ D(α, skew)` of every channel. `μ` is bounded (`mu_diag_complex`) on
/// a logarithmic grid of 40 points per decade, plus `ω = 0` and `∞` (the Nyquist frequency in
/// discrete time), and the peak refined by golden-section search; the reported multi-loop
/// margin uses the upper bound (conservative), `alpha_bounds` brackets the true `α` at the
/// located peak. Returns `MimoDiskMarginResult` (`loop_at_a_time, multi_loop`).
///
/// Raises `pendulab.ShapeError` (variant `NotSquare`) for a non-square `L`,
/// `pendulab.InvalidArgumentError` for a non-finite skew, `pendulab.LinAlgError`
/// (`Singular`) for an ill-posed loop (`I + D` singular).
#[pyfunction]
#[pyo3(signature = (L, skew = 0.0))]
#[allow(non_snake_case)]
pub fn disk_margin_mimo(L: &Bound<'_, PyAny>, skew: f64) -> PyResult<MimoDiskMarginResult> {
    let py = L.py();
    let s = system(L)?;
    let m = nogil(py, || with_sys!(&s, s => mu::disk_margin_mimo(s, skew)))?;
    let lat = m
        .loop_at_a_time
        .iter()
        .map(|d| Py::new(py, DiskMarginResult::from_margin(py, d)?))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(MimoDiskMarginResult {
        loop_at_a_time: obj(py, lat)?,
        multi_loop: Py::new(py, DiskMarginResult::from_margin(py, &m.multi_loop)?)?.into_any(),
        alpha_bounds: obj(py, m.multi_loop_alpha_bounds)?,
        mu_peak: Py::new(py, MuResult::from_bounds(py, &m.mu_peak)?)?.into_any(),
        peak_frequency: obj(py, m.peak_frequency)?,
        closed_loop_stable: obj(py, m.multi_loop.closed_loop_stable)?,
    })
}

result_class!(
    SigmaResult, "SigmaResult",
    "Singular values over frequency; unpacks as `sv, omega`.",
    array none,
    unpack {
        sv as "sv": "Singular values, descending, shape (min(p, m), len(omega)) (python-control's layout).",
        omega as "omega": "Frequencies in rad/s.",
    }
    also {}
);

/// `sigma(sys, omega=None)`: the singular values of `G(jω)` (MATLAB `sigma` data, python-
/// control `singular_values_response`). Returns `SigmaResult` (`sv, omega`).
#[pyfunction]
#[pyo3(signature = (sys, omega = None))]
pub fn sigma(sys: &Bound<'_, PyAny>, omega: Option<&Bound<'_, PyAny>>) -> PyResult<SigmaResult> {
    let py = sys.py();
    let s = system(sys)?;
    let w = with_sys!(&s, s => frequencies(s, omega))?;
    let r = nogil(py, || with_sys!(&s, s => pendulab_lti::sigma::sigma(s, &w)))?;
    let k = r.values.first().map_or(0, Vec::len);
    let sv = Array2::from_shape_fn((k, w.len()), |(i, j)| r.values[j][i]).into_pyarray(py);
    Ok(SigmaResult {
        sv: sv.into_any().unbind(),
        omega: slice_to_numpy(py, &w).into_any().unbind(),
    })
}
