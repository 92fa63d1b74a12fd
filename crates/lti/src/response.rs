//! Time responses: [`lsim`], [`initial`], [`step`], [`impulse`], and the zero-input /
//! zero-state split ([`lsim_split`]). Every response is a [`Trajectory`]. Their time grid
//! from a final time, or from none, is [`response_times`].
//!
//! **Exactness.** A continuous system is simulated on the uniform grid of the time vector by
//! its exact discretisation for the chosen [`InputHold`]: with a zero-order hold the input is
//! constant over each interval, with a first-order hold it is linear between samples (so a
//! sampled smooth input is reproduced to second order, and any piecewise-linear input
//! exactly). The states at the sample times are then exact up to rounding — there is no
//! integration error. Discrete systems are iterated as they are.
//!
//! **Inputs.** `u` has one row per time sample and one column per input (MATLAB's layout).
//! `t` must be uniformly spaced (to `1e-9` of the step plus the rounding of `t` itself); for
//! discrete systems its step must equal the sample time. Violations, NaN/∞ entries and
//! shape mismatches are typed errors naming the offending sample.
//!
//! **Performance.** The recursion runs in [`LsimKernel::run`], allocation-free on flat
//! column-major buffers, specialised at compile time for up to 8 states; [`lsim_outputs`]
//! runs it without recording the states.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::Mat;
use crate::matrix_functions::{foh_integrals, zoh_integrals};
use crate::state_space::StateSpace;
use crate::trajectory::Trajectory;

/// How a continuous-time simulation interpolates the input between samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InputHold {
    /// Zero-order hold: `u(t) = u_k` on `[t_k, t_{k+1})`.
    Zoh,
    /// First-order hold (linear interpolation): `u(t) = u_k + (u_{k+1} − u_k)(t − t_k)/Δt`
    /// (python-control's `forced_response`; MATLAB's `lsim` choice for smooth inputs).
    #[default]
    Foh,
}

/// Options of [`lsim`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LsimOptions {
    /// Input interpolation for continuous systems (default [`InputHold::Foh`]). Discrete
    /// systems take `u` as their input sequence, so the hold does not apply to them.
    pub hold: InputHold,
}

/// Uniform time grid `t_k = k·dt`, `k = 0 … ⌊t_final/dt⌋` (computed as products, so no drift
/// accumulates; a `t_final` within 1e-9 steps of a grid point includes that point).
///
/// # Errors
/// [`LtiError::InvalidArgument`] unless `dt > 0` and `t_final ≥ 0` are finite.
pub fn time_vector(t_final: f64, dt: f64) -> Result<Vec<f64>> {
    if !(dt.is_finite() && dt > 0.0 && t_final.is_finite() && t_final >= 0.0) {
        return Err(LtiError::InvalidArgument(format!(
            "time vector needs finite dt > 0 and t_final ≥ 0, got dt = {dt}, t_final = {t_final}"
        )));
    }
    let n = (t_final / dt + 1e-9).floor() as usize;
    Ok((0..=n).map(|k| k as f64 * dt).collect())
}

/// The default final time of a response of `sys` when none is given (MATLAB's `step(sys)`
/// and python-control's `step_response(sys)` choose one too): 7 time constants of the
/// slowest decaying mode (the response is then within 0.1 % of its final value), shortened
/// to 5 e-folding times of the fastest growing mode when the system is unstable, ten periods
/// of the slowest undamped oscillation, and 10 s when no pole sets a time scale (only
/// integrators, or no states). Discrete poles are mapped by `s = ln(z)/dt`, and a discrete
/// final time is a whole number of 10 … 100 000 steps.
///
/// # Errors
/// [`LtiError::NoConvergence`] from the poles' eigenvalue computation.
pub fn default_final_time<D: TimeDomain>(sys: &StateSpace<D>) -> Result<f64> {
    let dt = sys.domain().sample_time();
    let mut settle: f64 = 0.0;
    let mut grow = f64::INFINITY;
    for p in sys.poles()? {
        let sp = match dt {
            None => p,
            Some(dt) if p.norm() > 0.0 => p.ln() / dt,
            Some(_) => continue, // z = 0: a pure delay, settles in one step
        };
        if sp.re < -1e-12 * sp.norm().max(1.0) {
            settle = settle.max(7.0 / -sp.re);
        } else if sp.re > 1e-12 * sp.norm().max(1.0) {
            grow = grow.min(5.0 / sp.re);
        } else if sp.im.abs() > 0.0 {
            // Undamped oscillation: ten periods.
            settle = settle.max(10.0 * 2.0 * std::f64::consts::PI / sp.im.abs());
        }
    }
    let t = if grow.is_finite() {
        if settle > 0.0 { settle.min(grow) } else { grow }
    } else if settle > 0.0 {
        settle
    } else {
        10.0
    };
    Ok(match dt {
        Some(dt) => (t / dt).ceil().clamp(10.0, 100_000.0) * dt,
        None => t,
    })
}

/// The most samples [`response_times`] gives.
pub const MAX_RESPONSE_SAMPLES: f64 = 1e7;

/// The time grid of a response of `sys` from a final time (MATLAB's `step(sys, tFinal)`,
/// python-control's `T` given as a number): `0, h, …, t_final` ([`time_vector`]) with
/// `t_final` defaulting to [`default_final_time`] and the step `h` to `t_final/1000` for a
/// continuous system (1 001 samples); a discrete system steps at its sample time.
///
/// # Errors
/// [`LtiError::InvalidArgument`] for a `t_final` or `step` that is not finite and > 0, a
/// `step` for a discrete system, or more than [`MAX_RESPONSE_SAMPLES`] samples; the errors of
/// [`default_final_time`].
pub fn response_times<D: TimeDomain>(
    sys: &StateSpace<D>,
    t_final: Option<f64>,
    step: Option<f64>,
) -> Result<Vec<f64>> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let t_final = match t_final {
        Some(t) if !positive(t) => {
            return Err(LtiError::InvalidArgument(format!(
                "final time {t} s: must be finite and > 0"
            )));
        }
        Some(t) => t,
        None => default_final_time(sys)?,
    };
    let h = match (sys.domain().sample_time(), step) {
        (Some(_), Some(_)) => {
            return Err(LtiError::InvalidArgument(
                "a time step applies to continuous systems; a discrete system steps at its dt"
                    .into(),
            ));
        }
        (Some(dt), None) => dt,
        (None, Some(h)) if !positive(h) => {
            return Err(LtiError::InvalidArgument(format!(
                "time step {h} s: must be finite and > 0"
            )));
        }
        (None, Some(h)) => h,
        (None, None) => t_final / 1000.0,
    };
    if t_final / h > MAX_RESPONSE_SAMPLES {
        return Err(LtiError::InvalidArgument(format!(
            "{} samples requested (final time {t_final} s / step {h} s); at most 10⁷",
            (t_final / h).round()
        )));
    }
    time_vector(t_final, h)
}

/// Checks that `t` is non-empty, finite and uniformly spaced; returns its step (0 for one
/// sample). With `expected = Some(ts)` the step must be `ts`.
fn uniform_step(t: &[f64], expected: Option<f64>) -> Result<f64> {
    if t.is_empty() {
        return Err(LtiError::InvalidArgument("time vector is empty".into()));
    }
    if let Some((i, &v)) = t.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LtiError::NonFinite {
            what: "time vector".into(),
            row: i,
            col: 0,
            value: v,
        });
    }
    if t.len() == 1 {
        return Ok(expected.unwrap_or(0.0));
    }
    let dt = expected.unwrap_or((t[t.len() - 1] - t[0]) / (t.len() - 1) as f64);
    if dt <= 0.0 {
        return Err(LtiError::NonUniformTime {
            index: 0,
            step: t[1] - t[0],
            expected: dt,
        });
    }
    // Tolerance per step: 1e-9 of the step plus the rounding of the time values themselves
    // (8ε|t|, so grids built as k·dt or by accumulation pass at any length).
    let tmax = t[0].abs().max(t[t.len() - 1].abs());
    let tol = 1e-9 * dt + 8.0 * f64::EPSILON * tmax;
    let bad = t.windows(2).position(|w| ((w[1] - w[0]) - dt).abs() > tol);
    if let Some(k) = bad {
        return Err(LtiError::NonUniformTime {
            index: k,
            step: t[k + 1] - t[k],
            expected: dt,
        });
    }
    Ok(dt)
}

/// First non-finite entry of a column-major matrix, as `(row, col, value)`.
fn first_non_finite(m: &Mat) -> Option<(usize, usize, f64)> {
    let rows = m.nrows().max(1);
    m.as_slice()
        .iter()
        .position(|v| !v.is_finite())
        .map(|k| (k % rows, k / rows, m.as_slice()[k]))
}

/// The precomputed one-step recursion of a time response:
/// `x_{k+1} = Φ x_k + Γ_a u_k + Γ_b u_{k+1}`, `y_k = C x_k + D u_k`.
///
/// For a continuous system with ZOH `Γ_a = Γ`, `Γ_b = 0`; with FOH `Γ_a = Γ₀ − Γ₁`,
/// `Γ_b = Γ₁` ([`foh_integrals`]); for a discrete system `Φ = A`, `Γ_a = B`, `Γ_b = 0`.
/// Matrices are stored row-major for the inner loop.
#[derive(Debug, Clone, PartialEq)]
pub struct LsimKernel {
    n: usize,
    m: usize,
    p: usize,
    phi: Vec<f64>,
    ga: Vec<f64>,
    gb: Option<Vec<f64>>,
    c: Vec<f64>,
    d: Vec<f64>,
}

fn row_major(m: &Mat) -> Vec<f64> {
    let mut v = Vec::with_capacity(m.len());
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            v.push(m[(i, j)]);
        }
    }
    v
}

impl LsimKernel {
    /// Kernel for `sys` on a grid of step `dt` seconds (continuous systems; ignored for
    /// discrete ones, whose step is their sample time) with the given input hold.
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for a non-finite or non-positive `dt` on a continuous
    /// system; errors of the block exponential.
    pub fn new<D: TimeDomain>(sys: &StateSpace<D>, dt: f64, hold: InputHold) -> Result<Self> {
        let (phi, ga, gb) = match sys.domain().sample_time() {
            Some(_) => (sys.a().clone(), sys.b().clone(), None),
            None => {
                if !(dt.is_finite() && dt > 0.0) {
                    return Err(LtiError::InvalidArgument(format!(
                        "simulation step must be finite and > 0, got {dt}"
                    )));
                }
                match hold {
                    InputHold::Zoh => {
                        let (phi, g) = zoh_integrals(sys.a(), sys.b(), dt)?;
                        (phi, g, None)
                    }
                    InputHold::Foh => {
                        let (phi, g0, g1) = foh_integrals(sys.a(), sys.b(), dt)?;
                        (phi, &g0 - &g1, Some(g1))
                    }
                }
            }
        };
        Ok(Self {
            n: sys.nx(),
            m: sys.nu(),
            p: sys.ny(),
            phi: row_major(&phi),
            ga: row_major(&ga),
            gb: gb.as_ref().map(row_major),
            c: row_major(sys.c()),
            d: row_major(sys.d()),
        })
    }

    /// States, inputs, outputs.
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.n, self.m, self.p)
    }

    /// Runs the recursion over `len` samples without allocating.
    ///
    /// Buffers are column-major with one row per sample (signal `i` occupies
    /// `[i·len, (i+1)·len)`, the layout of [`Trajectory`]'s matrices): `u` has `len·m`
    /// values, `x_out` `len·n` — or none, and the states are not recorded (outputs only) —
    /// `y_out` `len·p`; `x0` has `n`.
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] if a buffer has the wrong length.
    pub fn run(
        &self,
        len: usize,
        u: &[f64],
        x0: &[f64],
        x_out: &mut [f64],
        y_out: &mut [f64],
    ) -> Result<()> {
        let (n, m, p) = (self.n, self.m, self.p);
        let record = !x_out.is_empty();
        for (name, got, want) in [
            ("u", u.len(), len * m),
            ("x0", x0.len(), n),
            ("x_out", x_out.len(), if record { len * n } else { 0 }),
            ("y_out", y_out.len(), len * p),
        ] {
            if got != want {
                return Err(LtiError::InvalidArgument(format!(
                    "lsim kernel: buffer {name} has {got} values, expected {want}"
                )));
            }
        }
        if len == 0 {
            return Ok(());
        }
        if record {
            self.run_sized::<true>(len, u, x0, x_out, y_out);
        } else {
            self.run_sized::<false>(len, u, x0, x_out, y_out);
        }
        Ok(())
    }

    /// The recursion specialised on the state dimension (and on whether states are
    /// recorded, `RECORD`, so that the outputs-only loop carries no store or branch for them).
    fn run_sized<const RECORD: bool>(
        &self,
        len: usize,
        u: &[f64],
        x0: &[f64],
        x_out: &mut [f64],
        y_out: &mut [f64],
    ) {
        match self.n {
            1 => self.run_fixed::<1, RECORD>(len, u, x0, x_out, y_out),
            2 => self.run_fixed::<2, RECORD>(len, u, x0, x_out, y_out),
            3 => self.run_fixed::<3, RECORD>(len, u, x0, x_out, y_out),
            4 => self.run_fixed::<4, RECORD>(len, u, x0, x_out, y_out),
            5 => self.run_fixed::<5, RECORD>(len, u, x0, x_out, y_out),
            6 => self.run_fixed::<6, RECORD>(len, u, x0, x_out, y_out),
            7 => self.run_fixed::<7, RECORD>(len, u, x0, x_out, y_out),
            8 => self.run_fixed::<8, RECORD>(len, u, x0, x_out, y_out),
            _ => self.run_dynamic(len, u, x0, x_out, y_out),
        }
    }

    fn run_fixed<const N: usize, const RECORD: bool>(
        &self,
        len: usize,
        u: &[f64],
        x0: &[f64],
        x_out: &mut [f64],
        y_out: &mut [f64],
    ) {
        let (m, p) = (self.m, self.p);
        let mut phi = [[0.0; N]; N];
        for i in 0..N {
            phi[i].copy_from_slice(&self.phi[i * N..(i + 1) * N]);
        }
        let mut x = [0.0; N];
        x.copy_from_slice(x0);
        // Single-input single-output fast path: the common case and the benchmark's.
        if m == 1 && p <= 1 {
            let mut ga = [0.0; N];
            let mut gb = [0.0; N];
            let mut c = [0.0; N];
            for i in 0..N {
                ga[i] = self.ga[i];
                gb[i] = self.gb.as_ref().map_or(0.0, |g| g[i]);
            }
            if p == 1 {
                c.copy_from_slice(&self.c[..N]);
            }
            let d = if p == 1 { self.d[0] } else { 0.0 };
            let cols: [&mut [f64]; N] = state_columns::<N, RECORD>(x_out, len);
            let u = &u[..len];
            for k in 0..len {
                let uk = u[k];
                if p == 1 {
                    let mut yk = d * uk;
                    for j in 0..N {
                        yk += c[j] * x[j];
                    }
                    y_out[k] = yk;
                }
                if RECORD {
                    for j in 0..N {
                        cols[j][k] = x[j];
                    }
                }
                let uk1 = if k + 1 < len { u[k + 1] } else { uk };
                // Two interleaved partial sums halve the floating-point dependency chain of
                // the state update (the loop's critical path).
                let mut next = [0.0; N];
                for i in 0..N {
                    let mut even = ga[i] * uk;
                    let mut odd = gb[i] * uk1;
                    let mut j = 0;
                    while j + 1 < N {
                        even += phi[i][j] * x[j];
                        odd += phi[i][j + 1] * x[j + 1];
                        j += 2;
                    }
                    if j < N {
                        even += phi[i][j] * x[j];
                    }
                    next[i] = even + odd;
                }
                x = next;
            }
            return;
        }
        let cols: [&mut [f64]; N] = state_columns::<N, RECORD>(x_out, len);
        for k in 0..len {
            for i in 0..p {
                y_out[i * len + k] = self.output(i, &x, u, len, k);
            }
            if RECORD {
                for j in 0..N {
                    cols[j][k] = x[j];
                }
            }
            let k1 = if k + 1 < len { k + 1 } else { k };
            let mut next = [0.0; N];
            for i in 0..N {
                let mut acc = 0.0;
                for j in 0..N {
                    acc += phi[i][j] * x[j];
                }
                next[i] = self.add_input_terms(acc, i, u, len, k, k1);
            }
            x = next;
        }
    }

    fn run_dynamic(&self, len: usize, u: &[f64], x0: &[f64], x_out: &mut [f64], y_out: &mut [f64]) {
        let (n, p) = (self.n, self.p);
        // Two state buffers on the stack would need a bound on n; these two small vectors are
        // the only allocation and happen once per call, outside the loop.
        let mut x = x0.to_vec();
        let mut next = vec![0.0; n];
        let record = !x_out.is_empty();
        for k in 0..len {
            for i in 0..p {
                y_out[i * len + k] = self.output(i, &x, u, len, k);
            }
            if record {
                for j in 0..n {
                    x_out[j * len + k] = x[j];
                }
            }
            let k1 = if k + 1 < len { k + 1 } else { k };
            for i in 0..n {
                let row = &self.phi[i * n..(i + 1) * n];
                let acc: f64 = row.iter().zip(&x).map(|(a, b)| a * b).sum();
                next[i] = self.add_input_terms(acc, i, u, len, k, k1);
            }
            std::mem::swap(&mut x, &mut next);
        }
    }

    /// The output equation `y_i[k] = Σ_j C_ij x_j + Σ_l D_il u_l[k]`, summed in that order
    /// (`x` has the state's length; `u` is column-major, `len` samples per input).
    #[inline(always)]
    fn output(&self, i: usize, x: &[f64], u: &[f64], len: usize, k: usize) -> f64 {
        let (n, m) = (x.len(), self.m);
        let mut yk = 0.0;
        for j in 0..n {
            yk += self.c[i * n + j] * x[j];
        }
        for l in 0..m {
            yk += self.d[i * m + l] * u[l * len + k];
        }
        yk
    }

    /// Adds row `i` of the input terms of the state update to `acc` (`Σ_j Φ_ij x_j`), in
    /// order: `Σ_l Γa_il u_l[k]`, then, for the first-order hold, `Σ_l Γb_il u_l[k1]`.
    #[inline(always)]
    fn add_input_terms(
        &self,
        mut acc: f64,
        i: usize,
        u: &[f64],
        len: usize,
        k: usize,
        k1: usize,
    ) -> f64 {
        let m = self.m;
        for l in 0..m {
            acc += self.ga[i * m + l] * u[l * len + k];
        }
        if let Some(gb) = &self.gb {
            for l in 0..m {
                acc += gb[i * m + l] * u[l * len + k1];
            }
        }
        acc
    }
}

/// Splits a column-major buffer of `N` columns of length `len` into its columns.
fn split_columns<const N: usize>(buf: &mut [f64], len: usize) -> [&mut [f64]; N] {
    let mut it = buf.chunks_exact_mut(len);
    std::array::from_fn(|_| it.next().expect("buffer holds N columns"))
}

/// The `N` state columns of `x_out` when states are recorded; `N` empty slices otherwise
/// (never written).
fn state_columns<const N: usize, const RECORD: bool>(
    x_out: &mut [f64],
    len: usize,
) -> [&mut [f64]; N] {
    if RECORD {
        let (x_cols, _) = x_out.split_at_mut(N * len);
        split_columns(x_cols, len)
    } else {
        std::array::from_fn(|_| <&mut [f64]>::default())
    }
}

fn check_x0(x0: &[f64], n: usize) -> Result<()> {
    if x0.len() != n {
        return Err(LtiError::DimensionMismatch {
            what: "initial state x0".into(),
            expected: (n, 1),
            found: (x0.len(), 1),
        });
    }
    if let Some((i, &v)) = x0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LtiError::NonFinite {
            what: "initial state x0".into(),
            row: i,
            col: 0,
            value: v,
        });
    }
    Ok(())
}

/// Simulates `sys` for the input samples `u` (`t.len() × nu`, one row per sample) at the
/// uniformly spaced times `t`, from the state `x0` at `t[0]` (zero if `None`) (MATLAB
/// `lsim(sys, u, t, x0)`).
///
/// Continuous systems are discretised exactly for the hold of `options`; discrete systems are
/// iterated (`t` must be spaced by their sample time). The returned trajectory holds `t`,
/// the states `x(t_k)`, the inputs `u` and the outputs `y(t_k) = C x(t_k) + D u(t_k)`.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] for `u` or `x0` of the wrong shape;
/// [`LtiError::NonFinite`] for NaN/∞ in `t`, `u` or `x0` (naming sample and column);
/// [`LtiError::NonUniformTime`] for an unevenly spaced `t` or one whose step differs from a
/// discrete system's sample time; [`LtiError::InvalidArgument`] for an empty `t`.
pub fn lsim<D: TimeDomain>(
    sys: &StateSpace<D>,
    u: &Mat,
    t: &[f64],
    x0: Option<&[f64]>,
    options: &LsimOptions,
) -> Result<Trajectory> {
    let len = t.len();
    if u.nrows() != len || u.ncols() != sys.nu() {
        return Err(LtiError::DimensionMismatch {
            what: "input u (rows = time samples, columns = inputs)".into(),
            expected: (len, sys.nu()),
            found: u.shape(),
        });
    }
    if let Some((row, col, value)) = first_non_finite(u) {
        return Err(LtiError::NonFinite {
            what: "input u (row = sample)".into(),
            row,
            col,
            value,
        });
    }
    let zero = vec![0.0; sys.nx()];
    let x0 = x0.unwrap_or(&zero);
    check_x0(x0, sys.nx())?;
    let dt = uniform_step(t, sys.domain().sample_time())?;
    // A single sample needs no step; any positive dt builds a valid kernel.
    let dt_kernel = if dt > 0.0 { dt } else { 1.0 };
    let kernel = LsimKernel::new(sys, dt_kernel, options.hold)?;
    let mut x = vec![0.0; len * sys.nx()];
    let mut y = vec![0.0; len * sys.ny()];
    kernel.run(len, u.as_slice(), x0, &mut x, &mut y)?;
    // `t` was validated above (finite, uniformly increasing).
    Ok(Trajectory::from_validated(
        t.to_vec(),
        Mat::from_vec(len, sys.nx(), x),
        u.clone(),
        Mat::from_vec(len, sys.ny(), y),
    ))
}

/// [`lsim`]'s outputs only, written into `y_out` without recording the states: the same
/// validation, discretisation and recursion (so `y_out` equals [`lsim`]'s outputs bit for
/// bit), for long simulations where the state history is not wanted.
///
/// `u` and `y_out` are column-major with one row per sample (input `l` occupies
/// `u[l·len .. (l+1)·len]`, output `i` `y_out[i·len .. (i+1)·len]`, `len = t.len()`); for one
/// input or output that is simply the signal.
///
/// # Errors
/// As [`lsim`]; [`LtiError::DimensionMismatch`] for a `u` or `y_out` of the wrong length.
pub fn lsim_outputs<D: TimeDomain>(
    sys: &StateSpace<D>,
    u: &[f64],
    t: &[f64],
    x0: Option<&[f64]>,
    options: &LsimOptions,
    y_out: &mut [f64],
) -> Result<()> {
    let len = t.len();
    for (what, got, width) in [
        (
            "input u (column-major, one row per sample)",
            u.len(),
            sys.nu(),
        ),
        (
            "output buffer y (column-major, one row per sample)",
            y_out.len(),
            sys.ny(),
        ),
    ] {
        if got != len * width {
            return Err(LtiError::DimensionMismatch {
                what: what.into(),
                expected: (len, width),
                found: (got / len.max(1), width),
            });
        }
    }
    if let Some(k) = u.iter().position(|v| !v.is_finite()) {
        return Err(LtiError::NonFinite {
            what: "input u (row = sample)".into(),
            row: k % len.max(1),
            col: k / len.max(1),
            value: u[k],
        });
    }
    let zero = vec![0.0; sys.nx()];
    let x0 = x0.unwrap_or(&zero);
    check_x0(x0, sys.nx())?;
    let dt = uniform_step(t, sys.domain().sample_time())?;
    let dt_kernel = if dt > 0.0 { dt } else { 1.0 };
    let kernel = LsimKernel::new(sys, dt_kernel, options.hold)?;
    kernel.run(len, u, x0, &mut [], y_out)
}

/// Zero-input response from `x0` at `t[0]` (MATLAB `initial(sys, x0, t)`); the trajectory's
/// input columns are zero.
///
/// # Errors
/// As [`lsim`].
#[doc(alias = "zero_input_response")]
pub fn initial<D: TimeDomain>(sys: &StateSpace<D>, x0: &[f64], t: &[f64]) -> Result<Trajectory> {
    lsim(
        sys,
        &Mat::zeros(t.len(), sys.nu()),
        t,
        Some(x0),
        &LsimOptions::default(),
    )
}

/// Zero-state response to `u` (the state starts at 0).
///
/// # Errors
/// As [`lsim`].
pub fn zero_state_response<D: TimeDomain>(
    sys: &StateSpace<D>,
    u: &Mat,
    t: &[f64],
    options: &LsimOptions,
) -> Result<Trajectory> {
    lsim(sys, u, t, None, options)
}

/// A response split into its zero-input and zero-state parts (book eq. 4.24:
/// `y = y_zi + y_zs`).
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseSplit {
    /// Response to `x0` with `u = 0`.
    pub zero_input: Trajectory,
    /// Response to `u` from `x = 0`.
    pub zero_state: Trajectory,
    /// Response to both, simulated as one run (not as the sum).
    pub total: Trajectory,
}

/// The total response and its zero-input and zero-state parts, each simulated on its own, so
/// that superposition can be checked (`total = zero_input + zero_state` up to rounding).
///
/// # Errors
/// As [`lsim`].
pub fn lsim_split<D: TimeDomain>(
    sys: &StateSpace<D>,
    u: &Mat,
    t: &[f64],
    x0: &[f64],
    options: &LsimOptions,
) -> Result<ResponseSplit> {
    Ok(ResponseSplit {
        zero_input: initial(sys, x0, t)?,
        zero_state: lsim(sys, u, t, None, options)?,
        total: lsim(sys, u, t, Some(x0), options)?,
    })
}

/// Unit-step responses, one trajectory per input channel `j` (input `j` steps from 0 to 1 at
/// `t[0]`, the others stay 0, zero initial state) (MATLAB `step`).
///
/// The step is exact for continuous systems (both holds reproduce a constant input).
///
/// # Errors
/// As [`lsim`].
pub fn step<D: TimeDomain>(sys: &StateSpace<D>, t: &[f64]) -> Result<Vec<Trajectory>> {
    (0..sys.nu())
        .map(|j| {
            let mut u = Mat::zeros(t.len(), sys.nu());
            u.column_mut(j).fill(1.0);
            lsim(sys, &u, t, None, &LsimOptions::default())
        })
        .collect()
}

/// Impulse responses, one trajectory per input channel (MATLAB `impulse`).
///
/// Continuous time: the response to a Dirac impulse on input `j`, i.e. the zero-input
/// response from `x(t₀⁺) = B e_j` (`y = C e^{A(t−t₀)} B e_j`; a feedthrough `D δ(t)` has no
/// sample value and is omitted, as in MATLAB); the trajectory's input columns are zero.
/// Discrete time: the response to a unit-area pulse, `u_j[0] = 1/ts` (MATLAB's convention
/// since R2012a), recorded in the input columns.
///
/// # Errors
/// As [`lsim`].
pub fn impulse<D: TimeDomain>(sys: &StateSpace<D>, t: &[f64]) -> Result<Vec<Trajectory>> {
    (0..sys.nu())
        .map(|j| match sys.domain().sample_time() {
            None => {
                let x0: Vec<f64> = sys.b().column(j).iter().copied().collect();
                initial(sys, &x0, t)
            }
            Some(ts) => {
                let mut u = Mat::zeros(t.len(), sys.nu());
                if !t.is_empty() {
                    u[(0, j)] = 1.0 / ts;
                }
                lsim(sys, &u, t, None, &LsimOptions::default())
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Mat;

    /// A 5-state SISO system and a MIMO one (2 inputs, 2 outputs, 9 states: the dynamic path).
    fn systems() -> Vec<StateSpace<crate::Continuous>> {
        let mut out = Vec::new();
        for (n, m, p) in [(5, 1, 1), (9, 2, 2), (3, 2, 1)] {
            let a = Mat::from_fn(n, n, |i, j| {
                if i == j {
                    -1.0 - i as f64
                } else {
                    0.1 * ((i * 7 + j * 3) % 5) as f64 - 0.2
                }
            });
            let b = Mat::from_fn(n, m, |i, j| 1.0 / (1.0 + (i + j) as f64));
            let c = Mat::from_fn(p, n, |i, j| ((i + 2 * j) % 3) as f64 - 0.5);
            let d = Mat::from_fn(p, m, |i, j| 0.1 * (i + j) as f64);
            out.push(StateSpace::continuous(a, b, c, d).unwrap());
        }
        out
    }

    #[test]
    fn lsim_outputs_equals_lsim_bit_for_bit() {
        for sys in systems() {
            let len = 501;
            let t = time_vector(5.0, 0.01).unwrap();
            assert_eq!(t.len(), len);
            let u = Mat::from_fn(len, sys.nu(), |k, l| ((k as f64) * 0.03 + l as f64).sin());
            let x0: Vec<f64> = (0..sys.nx()).map(|i| 0.1 * i as f64).collect();
            for hold in [InputHold::Zoh, InputHold::Foh] {
                let o = LsimOptions { hold };
                let full = lsim(&sys, &u, &t, Some(&x0), &o).unwrap();
                let mut y = vec![0.0; len * sys.ny()];
                lsim_outputs(&sys, u.as_slice(), &t, Some(&x0), &o, &mut y).unwrap();
                assert_eq!(&y[..], full.y().as_slice());
            }
        }
    }

    #[test]
    fn lsim_outputs_refuses_what_lsim_refuses() {
        let sys = &systems()[0];
        let t = time_vector(1.0, 0.1).unwrap();
        let o = LsimOptions::default();
        let mut y = vec![0.0; t.len()];
        let mut u = vec![0.0; t.len()];
        assert!(matches!(
            lsim_outputs(sys, &u[1..], &t, None, &o, &mut y),
            Err(LtiError::DimensionMismatch { .. })
        ));
        assert!(matches!(
            lsim_outputs(sys, &u, &t, None, &o, &mut y[1..]),
            Err(LtiError::DimensionMismatch { .. })
        ));
        u[3] = f64::NAN;
        assert!(matches!(
            lsim_outputs(sys, &u, &t, None, &o, &mut y),
            Err(LtiError::NonFinite { row: 3, col: 0, .. })
        ));
        u[3] = 0.0;
        let mut bent = t.clone();
        bent[4] += 0.01;
        assert!(matches!(
            lsim_outputs(sys, &u, &bent, None, &o, &mut y),
            Err(LtiError::NonUniformTime { .. })
        ));
    }
}
