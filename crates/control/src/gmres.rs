//! Matrix-free GMRES with a fixed iteration budget, allocation-free after construction.
//!
//! GMRES (Saad & Schultz, "GMRES: a generalized minimal residual algorithm for solving
//! nonsymmetric linear systems", SIAM J. Sci. Stat. Comput. 7, 1986) finds, after `k`
//! iterations from the initial guess `x₀`, the `x ∈ x₀ + K_k(A, r₀)` minimising `‖b − A x‖₂`,
//! where `r₀ = b − A x₀` and `K_k = span{r₀, A r₀, …, A^{k−1} r₀}`. The Krylov basis is built
//! by Arnoldi's process with modified Gram–Schmidt, the small least-squares problem with the
//! upper Hessenberg matrix is reduced by Givens rotations, whose last entry gives the residual
//! norm without another product with `A`.
//!
//! The operator is a closure `y ← A v`, so `A` never has to be formed: C/GMRES passes a
//! forward-difference approximation of a Jacobian–vector product (Kelley, *Iterative Methods
//! for Linear and Nonlinear Equations*, SIAM 1995, §3.5 and ch. 6).

/// Preallocated storage for [`solve`] on problems of size `n` with at most `kmax` iterations.
#[derive(Debug, Clone)]
pub struct GmresWorkspace {
    n: usize,
    kmax: usize,
    /// Krylov basis `v₀ … v_kmax`, row `j` = `v_j` (`(kmax + 1) × n`).
    basis: Vec<f64>,
    /// Hessenberg matrix, column-major `(kmax + 1) × kmax`, overwritten by `R` of its QR.
    hess: Vec<f64>,
    cs: Vec<f64>,
    sn: Vec<f64>,
    g: Vec<f64>,
    y: Vec<f64>,
    w: Vec<f64>,
}

/// What one [`solve`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GmresReport {
    /// Arnoldi iterations performed (≤ `kmax`; fewer on breakdown or when the tolerance is
    /// met).
    pub iterations: usize,
    /// `‖b − A x₀‖₂` at the initial guess.
    pub initial_residual: f64,
    /// `‖b − A x‖₂` at the returned `x`, as given by the Givens recurrence (exact in exact
    /// arithmetic for a linear operator).
    pub residual: f64,
}

impl GmresWorkspace {
    /// Storage for systems of dimension `n` and at most `kmax` iterations (`kmax ≥ 1`; it is
    /// clamped to `n`, since the Krylov space cannot grow beyond it).
    pub fn new(n: usize, kmax: usize) -> Self {
        let kmax = kmax.clamp(1, n.max(1));
        Self {
            n,
            kmax,
            basis: vec![0.0; (kmax + 1) * n],
            hess: vec![0.0; (kmax + 1) * kmax],
            cs: vec![0.0; kmax],
            sn: vec![0.0; kmax],
            g: vec![0.0; kmax + 1],
            y: vec![0.0; kmax],
            w: vec![0.0; n],
        }
    }

    /// Problem dimension `n`.
    pub fn dimension(&self) -> usize {
        self.n
    }

    /// Iteration budget `kmax` (after clamping to `n`).
    pub fn max_iterations(&self) -> usize {
        self.kmax
    }
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[inline]
fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Solves `A x = b` approximately by at most `kmax` GMRES iterations from the initial guess
/// held in `x`, writing the iterate into `x`. `op(v, y)` must write `y = A v`. Iteration stops
/// early when the residual is `≤ tolerance` (pass `0.0` to always use the full budget, as
/// C/GMRES does) or on a (lucky) breakdown of Arnoldi's process.
///
/// Preconditions: `b.len() == x.len() == ws.dimension()`; the caller guarantees them
/// (violations panic in debug builds only through slice indexing). No allocation.
pub fn solve<F: FnMut(&[f64], &mut [f64])>(
    ws: &mut GmresWorkspace,
    mut op: F,
    b: &[f64],
    x: &mut [f64],
    tolerance: f64,
) -> GmresReport {
    let n = ws.n;
    debug_assert_eq!(b.len(), n);
    debug_assert_eq!(x.len(), n);
    let kmax = ws.kmax;
    let ldh = kmax + 1;
    // r₀ = b − A x₀ into v₀.
    op(x, &mut ws.w);
    for i in 0..n {
        ws.basis[i] = b[i] - ws.w[i];
    }
    let beta = norm(&ws.basis[..n]);
    let mut report = GmresReport {
        iterations: 0,
        initial_residual: beta,
        residual: beta,
    };
    if beta == 0.0 || !beta.is_finite() || beta <= tolerance {
        return report;
    }
    for v in &mut ws.basis[..n] {
        *v /= beta;
    }
    ws.g.iter_mut().for_each(|g| *g = 0.0);
    ws.g[0] = beta;
    let mut k_done = 0;
    for k in 0..kmax {
        // w = A v_k.
        {
            let (head, tail) = ws.basis.split_at_mut((k + 1) * n);
            let vk = &head[k * n..(k + 1) * n];
            let w = &mut tail[..n];
            op(vk, w);
            // Modified Gram–Schmidt against v₀ … v_k.
            for j in 0..=k {
                let vj = &head[j * n..(j + 1) * n];
                let h = dot(w, vj);
                ws.hess[j + k * ldh] = h;
                for (wi, vi) in w.iter_mut().zip(vj) {
                    *wi -= h * vi;
                }
            }
            let hn = norm(w);
            ws.hess[k + 1 + k * ldh] = hn;
            if hn > 0.0 {
                for wi in w.iter_mut() {
                    *wi /= hn;
                }
            }
        }
        // Apply the previous rotations to the new column.
        for j in 0..k {
            let (c, s) = (ws.cs[j], ws.sn[j]);
            let a = ws.hess[j + k * ldh];
            let bb = ws.hess[j + 1 + k * ldh];
            ws.hess[j + k * ldh] = c * a + s * bb;
            ws.hess[j + 1 + k * ldh] = -s * a + c * bb;
        }
        let a = ws.hess[k + k * ldh];
        let bb = ws.hess[k + 1 + k * ldh];
        let breakdown = bb <= f64::EPSILON * a.abs().max(beta * f64::EPSILON);
        let r = a.hypot(bb);
        let (c, s) = if r == 0.0 {
            (1.0, 0.0)
        } else {
            (a / r, bb / r)
        };
        ws.cs[k] = c;
        ws.sn[k] = s;
        ws.hess[k + k * ldh] = r;
        ws.hess[k + 1 + k * ldh] = 0.0;
        ws.g[k + 1] = -s * ws.g[k];
        ws.g[k] *= c;
        k_done = k + 1;
        if breakdown || ws.g[k + 1].abs() <= tolerance {
            break;
        }
    }
    // Back substitution R y = g.
    for i in (0..k_done).rev() {
        let mut s = ws.g[i];
        for j in i + 1..k_done {
            s -= ws.hess[i + j * ldh] * ws.y[j];
        }
        let rii = ws.hess[i + i * ldh];
        ws.y[i] = if rii != 0.0 { s / rii } else { 0.0 };
    }
    for j in 0..k_done {
        let yj = ws.y[j];
        let vj = &ws.basis[j * n..(j + 1) * n];
        for (xi, vi) in x.iter_mut().zip(vj) {
            *xi += yj * vi;
        }
    }
    report.iterations = k_done;
    report.residual = ws.g[k_done].abs();
    report
}
