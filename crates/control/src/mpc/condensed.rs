//! The condensed MPC [`LinearMpc`]: the horizon's prediction matrices `X = Φ x₀ + Γ U`, the
//! QP's Hessian `H = Γᵀ Q̄ Γ + R̄`, its constraint rows `G U ≤ w₀ + W_x x₀ + W_u u₋₁` stage by
//! stage, and the solve at each sample with its warm start.

use super::qp::{DualActiveSetQp, QpStatus};
use super::settings::{MpcSettings, Terminal, WarmStart};
use crate::error::{ControlError, Result, check_matrix, check_vector};
use pendulab_lti::equations::{RiccatiOptions, dare};
use pendulab_lti::{Continuous, Discretization, Mat, StateSpace};

/// The condensed MPC of a discrete model (module documentation): its QP data and the QP
/// method, reused across samples.
#[derive(Debug, Clone)]
pub struct LinearMpc {
    nx: usize,
    nu: usize,
    horizon: usize,
    h: Mat,
    /// `g = F x₀`.
    f: Mat,
    /// Constraint matrix `G`.
    a: Mat,
    w0: Vec<f64>,
    /// `W_x` (`m × n_x`, row-major).
    wx: Vec<f64>,
    /// `W_u` (`m × n_u`, row-major).
    wu: Vec<f64>,
    rows_per_stage: usize,
    terminal: Mat,
    lq_gain: Mat,
    qp: DualActiveSetQp,
    g: Vec<f64>,
    w: Vec<f64>,
    warm: Vec<usize>,
}

impl LinearMpc {
    /// Builds the condensed problem of `x_{k+1} = A x_k + B u_k` (`a_d`: `n_x × n_x`, `b_d`:
    /// `n_x × n_u`) with `settings`.
    ///
    /// # Errors
    /// [`ControlError::ShapeMismatch`]/[`ControlError::DimensionMismatch`]/
    /// [`ControlError::NonFinite`] for data of the wrong size or NaN;
    /// [`ControlError::InvalidParameter`] naming `horizon`, `u_min`/`u_max` (`min > max`),
    /// `du_max` (not > 0), `state_bounds[i]` (index out of range, `min > max`);
    /// [`ControlError::Lti`] if the DARE has no stabilising solution; [`ControlError::Singular`]
    /// if `R` is not positive definite.
    pub fn new(a_d: &Mat, b_d: &Mat, settings: &MpcSettings) -> Result<Self> {
        let nx = a_d.nrows();
        check_matrix("MPC model A", a_d, nx, nx)?;
        let nu = b_d.ncols();
        check_matrix("MPC model B", b_d, nx, nu)?;
        check_matrix("MPC weight Q", &settings.q, nx, nx)?;
        check_matrix("MPC weight R", &settings.r, nu, nu)?;
        settings.check(nx, nu)?;
        let n_h = settings.horizon;
        let terminal = terminal_weight(a_d, b_d, settings)?;
        let (phi, gamma) = prediction(a_d, b_d, n_h);
        let (h, f) = condensed_cost(&phi, &gamma, &terminal, settings);
        let nv = n_h * nu;
        let rows = constraint_rows(settings, &phi, &gamma, nx, nu);
        let m = rows.len();
        let rows_per_stage = m / n_h;
        let (a, w0, wx, wu) = stack_rows(rows, nv, nx, nu);
        let qp = DualActiveSetQp::new(&h, &a, settings.qp)?;
        let lq_gain = lq_gain(a_d, b_d, &terminal, &settings.r)?;
        Ok(Self {
            nx,
            nu,
            horizon: n_h,
            h,
            f,
            a,
            w0,
            wx,
            wu,
            rows_per_stage,
            terminal,
            lq_gain,
            qp,
            g: vec![0.0; nv],
            w: vec![0.0; m],
            warm: Vec::with_capacity(nv),
        })
    }

    /// [`LinearMpc::new`] on the ZOH sampling of the continuous model `sys` at the prediction
    /// step `dt` \[s\] (only `A` and `B` of `sys` are used).
    ///
    /// # Errors
    /// As [`LinearMpc::new`]; [`ControlError::Lti`] if `dt` is not a positive finite time.
    pub fn sampled(sys: &StateSpace<Continuous>, dt: f64, settings: &MpcSettings) -> Result<Self> {
        let d = sys.c2d(dt, Discretization::Zoh)?;
        Self::new(d.a(), d.b(), settings)
    }

    /// State count `n_x`.
    pub fn nx(&self) -> usize {
        self.nx
    }
    /// Input count `n_u`.
    pub fn nu(&self) -> usize {
        self.nu
    }
    /// Horizon `N`.
    pub fn horizon(&self) -> usize {
        self.horizon
    }
    /// The condensed Hessian `H` (`N n_u × N n_u`).
    pub fn hessian(&self) -> &Mat {
        &self.h
    }
    /// The constraint matrix `G` (`m × N n_u`).
    pub fn constraint_matrix(&self) -> &Mat {
        &self.a
    }
    /// Constraint rows per stage (the rows of stage `s` are `s·rows_per_stage …`).
    pub fn rows_per_stage(&self) -> usize {
        self.rows_per_stage
    }
    /// The terminal weight `P` in use.
    pub fn terminal_weight(&self) -> &Mat {
        &self.terminal
    }
    /// `K = (R + BᵀPB)⁻¹BᵀPA` (`n_u × n_x`): the first move `u₀ = −K x₀` when no constraint is
    /// active (with [`Terminal::Dare`], the discrete LQR gain).
    pub fn lq_gain(&self) -> &Mat {
        &self.lq_gain
    }

    /// The QP's varying data at `x0` (length `n_x`) and `u_prev` (`n_u`): `g` (length
    /// `N n_u`) and `w` (length `m`), written into the slices.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`] for slices of the wrong length.
    pub fn qp_vectors(
        &self,
        x0: &[f64],
        u_prev: &[f64],
        g: &mut [f64],
        w: &mut [f64],
    ) -> Result<()> {
        check_vector("x0", x0, self.nx)?;
        check_vector("u_prev", u_prev, self.nu)?;
        if g.len() != self.g.len() || w.len() != self.w.len() {
            return Err(ControlError::DimensionMismatch {
                what: "qp_vectors: g, w".into(),
                expected: self.g.len() + self.w.len(),
                found: g.len() + w.len(),
            });
        }
        fill(
            &self.f,
            &self.w0,
            &self.wx,
            &self.wu,
            (self.nx, self.nu),
            x0,
            u_prev,
            g,
            w,
        );
        Ok(())
    }

    /// Solves the QP at `x0` and `u_prev` starting from `warm`; the plan is
    /// [`LinearMpc::plan`], the first move its first `n_u` entries. Allocation-free.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`]/[`ControlError::NonFinite`] for `x0` (`n_x`) or
    /// `u_prev` (`n_u`). Infeasibility is the status [`QpStatus::Infeasible`].
    pub fn solve(&mut self, x0: &[f64], u_prev: &[f64], warm: WarmStart) -> Result<QpStatus> {
        check_vector("x0", x0, self.nx)?;
        check_vector("u_prev", u_prev, self.nu)?;
        fill(
            &self.f,
            &self.w0,
            &self.wx,
            &self.wu,
            (self.nx, self.nu),
            x0,
            u_prev,
            &mut self.g,
            &mut self.w,
        );
        self.warm.clear();
        match warm {
            WarmStart::Cold => {}
            WarmStart::Same => self.warm.extend_from_slice(self.qp.active_set()),
            WarmStart::Shifted => {
                let rps = self.rows_per_stage;
                self.warm.extend(
                    self.qp
                        .active_set()
                        .iter()
                        .filter(|&&r| r >= rps)
                        .map(|&r| r - rps),
                );
            }
        }
        Ok(self.qp.solve_unchecked(&self.g, &self.w, &self.warm))
    }

    /// The plan `U = [u₀; …; u_{N−1}]` of the last solve.
    pub fn plan(&self) -> &[f64] {
        self.qp.solution()
    }

    /// The QP method (its multipliers, active set, iterations, certificate).
    pub fn qp(&self) -> &DualActiveSetQp {
        &self.qp
    }

    /// `g` and `w` of the last solve.
    pub fn last_qp_vectors(&self) -> (&[f64], &[f64]) {
        (&self.g, &self.w)
    }
}

/// The terminal weight `P`: the stabilising DARE solution of `(A, B, Q, R)` or the given one.
fn terminal_weight(a_d: &Mat, b_d: &Mat, settings: &MpcSettings) -> Result<Mat> {
    let nx = a_d.nrows();
    Ok(match &settings.terminal {
        Terminal::Dare => {
            dare(
                a_d,
                b_d,
                &settings.q,
                &settings.r,
                None,
                &RiccatiOptions::default(),
            )?
            .x
        }
        Terminal::Weight(p) => {
            check_matrix("MPC terminal weight P", p, nx, nx)?;
            p.clone()
        }
    })
}

/// The prediction `X = Φ x₀ + Γ U` over the horizon `n_h`: `Φ` the stacked `A^k` (`k = 1 … N`),
/// `Γ` the block lower-triangular `A^{k−j} B`.
fn prediction(a_d: &Mat, b_d: &Mat, n_h: usize) -> (Mat, Mat) {
    let (nx, nu) = (a_d.nrows(), b_d.ncols());
    // Φ (stacked A^k, k = 1…N) and Γ.
    let mut phi = Mat::zeros(n_h * nx, nx);
    let mut gamma = Mat::zeros(n_h * nx, n_h * nu);
    let mut ak = a_d.clone();
    // A^{k} B blocks: powers[k] = A^k B.
    let mut powers = vec![b_d.clone()];
    for k in 1..n_h {
        let next = a_d * &powers[k - 1];
        powers.push(next);
    }
    for k in 0..n_h {
        phi.view_mut((k * nx, 0), (nx, nx)).copy_from(&ak);
        ak = a_d * &ak;
        for j in 0..=k {
            gamma
                .view_mut((k * nx, j * nu), (nx, nu))
                .copy_from(&powers[k - j]);
        }
    }
    (phi, gamma)
}

/// The condensed cost: `H = Γᵀ Q̄ Γ + R̄` (symmetrised) and `F = Γᵀ Q̄ Φ` (`g = F x₀`), with
/// `Q̄ = diag(Q, …, Q, P)`.
fn condensed_cost(phi: &Mat, gamma: &Mat, terminal: &Mat, settings: &MpcSettings) -> (Mat, Mat) {
    let (n_h, nu, nx) = (settings.horizon, settings.r.nrows(), phi.ncols());
    let mut qbar = Mat::zeros(n_h * nx, n_h * nx);
    for k in 0..n_h {
        let wk = if k + 1 == n_h { terminal } else { &settings.q };
        qbar.view_mut((k * nx, k * nx), (nx, nx)).copy_from(wk);
    }
    let gt_q = gamma.transpose() * &qbar;
    let mut h = &gt_q * gamma;
    for k in 0..n_h {
        let mut blk = h.view_mut((k * nu, k * nu), (nu, nu));
        blk += &settings.r;
    }
    let h = (&h + h.transpose()) * 0.5;
    let f = &gt_q * phi;
    (h, f)
}

/// The constraint rows stage by stage (module documentation): stage `s` the input bounds of
/// `u_s`, the rate bounds of `u_s − u_{s−1}`, the state bounds of `x_{s+1}`; infinite bounds
/// give no row.
fn constraint_rows(
    settings: &MpcSettings,
    phi: &Mat,
    gamma: &Mat,
    nx: usize,
    nu: usize,
) -> Vec<Row> {
    let n_h = settings.horizon;
    let mut rows: Vec<Row> = Vec::new();
    let nv = n_h * nu;
    for s in 0..n_h {
        for i in 0..nu {
            for (sign, bound) in [(1.0, settings.u_max[i]), (-1.0, settings.u_min[i])] {
                if bound.is_finite() {
                    let mut g = vec![0.0; nv];
                    g[s * nu + i] = sign;
                    rows.push((g, sign * bound, vec![0.0; nx], vec![0.0; nu]));
                }
            }
        }
        if let Some(du) = &settings.du_max {
            for i in 0..nu {
                if du[i].is_finite() {
                    for sign in [1.0, -1.0] {
                        let mut g = vec![0.0; nv];
                        g[s * nu + i] = sign;
                        let mut wu = vec![0.0; nu];
                        if s > 0 {
                            g[(s - 1) * nu + i] = -sign;
                        } else {
                            wu[i] = sign;
                        }
                        rows.push((g, du[i], vec![0.0; nx], wu));
                    }
                }
            }
        }
        for sb in &settings.state_bounds {
            let r = s * nx + sb.index;
            for (sign, bound) in [(1.0, sb.max), (-1.0, sb.min)] {
                if bound.is_finite() {
                    let g: Vec<f64> = (0..nv).map(|c| sign * gamma[(r, c)]).collect();
                    let wx: Vec<f64> = (0..nx).map(|c| -sign * phi[(r, c)]).collect();
                    rows.push((g, sign * bound, wx, vec![0.0; nu]));
                }
            }
        }
    }
    rows
}

/// The rows as `G` (`m × nv`), `w₀`, `W_x` and `W_u` (row-major).
fn stack_rows(
    rows: Vec<Row>,
    nv: usize,
    nx: usize,
    nu: usize,
) -> (Mat, Vec<f64>, Vec<f64>, Vec<f64>) {
    let m = rows.len();
    let mut a = Mat::zeros(m, nv);
    let mut w0 = vec![0.0; m];
    let mut wx = vec![0.0; m * nx];
    let mut wu = vec![0.0; m * nu];
    for (i, (g, b, x, u)) in rows.into_iter().enumerate() {
        for c in 0..nv {
            a[(i, c)] = g[c];
        }
        w0[i] = b;
        wx[i * nx..(i + 1) * nx].copy_from_slice(&x);
        wu[i * nu..(i + 1) * nu].copy_from_slice(&u);
    }
    (a, w0, wx, wu)
}

/// `K = (R + BᵀPB)⁻¹ BᵀPA`, the unconstrained law of the terminal cost.
fn lq_gain(a_d: &Mat, b_d: &Mat, terminal: &Mat, r: &Mat) -> Result<Mat> {
    let btp = b_d.transpose() * terminal;
    Ok((r + &btp * b_d)
        .cholesky()
        .ok_or(ControlError::Singular {
            what: "R + BᵀPB".into(),
            value: 0.0,
        })?
        .solve(&(&btp * a_d)))
}

/// One constraint row while the MPC is built: `G_i`, `w₀,i`, `W_x,i`, `W_u,i`.
type Row = (Vec<f64>, f64, Vec<f64>, Vec<f64>);

/// `g = F x₀`, `w = w₀ + W_x x₀ + W_u u₋₁`.
#[allow(clippy::too_many_arguments)]
fn fill(
    f: &Mat,
    w0: &[f64],
    wx: &[f64],
    wu: &[f64],
    (nx, nu): (usize, usize),
    x0: &[f64],
    u_prev: &[f64],
    g: &mut [f64],
    w: &mut [f64],
) {
    for (i, gi) in g.iter_mut().enumerate() {
        *gi = (0..nx).map(|c| f[(i, c)] * x0[c]).sum();
    }
    for (i, wi) in w.iter_mut().enumerate() {
        let sx: f64 = wx[i * nx..(i + 1) * nx]
            .iter()
            .zip(x0)
            .map(|(a, b)| a * b)
            .sum();
        let su: f64 = wu[i * nu..(i + 1) * nu]
            .iter()
            .zip(u_prev)
            .map(|(a, b)| a * b)
            .sum();
        *wi = w0[i] + sx + su;
    }
}
