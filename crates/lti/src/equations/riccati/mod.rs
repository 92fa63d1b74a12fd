//! Algebraic Riccati equations, continuous ([`care`]) and discrete ([`dare`]), with cross term.
//!
//! Continuous (CARE):
//! `AᵀX + XA − (XB + N) R⁻¹ (BᵀX + Nᵀ) + Q = 0`, stabilising gain `K = R⁻¹(BᵀX + Nᵀ)`,
//! closed loop `A − BK` Hurwitz.
//!
//! Discrete (DARE):
//! `AᵀXA − X − (AᵀXB + N)(BᵀXB + R)⁻¹(BᵀXA + Nᵀ) + Q = 0`, stabilising gain
//! `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)`, closed loop `A − BK` Schur-stable.
//!
//! Both return a [`RiccatiSolution`] carrying the solution, the gain, the closed-loop poles and
//! the relative residual (module [`equations`](crate::equations) defines it).
//!
//! ## How a solution is computed and checked
//! 1. The data are validated (shapes, finiteness, symmetry, `R ≻ 0`).
//! 2. The cross term is removed: `Ã = A − B R⁻¹ Nᵀ`, `Q̃ = Q − N R⁻¹ Nᵀ`, `G = B R⁻¹ Bᵀ`.
//! 3. With `scaling`, `Q̃` and `G` are balanced by `X = s Y`, `s = sqrt(‖Q̃‖_F / ‖G‖_F)` (the
//!    equation for `Y` has `sG`, `Q̃/s`; SLICOT `SB02MD`'s scaling).
//! 4. The stabilising solution is computed by the chosen [`RiccatiMethod`].
//! 5. Newton refinement (Kleinman for the CARE, Hewer for the DARE, in residual-correction
//!    form: one Lyapunov/Stein solve per step) is applied while the relative residual is above
//!    the rounding level `REFINEMENT_FLOOR · n · ε` ([`REFINEMENT_FLOOR`]); a step is kept only
//!    if it lowers the residual, and the iteration stops when a step gains less than a factor 2.
//!    After Laub's method the CARE steps first reuse the ordered Schur form of the Hamiltonian
//!    (`A − BK = U₁T₁₁U₁⁻¹`, so no Schur decomposition of `A − BK` is needed), and after the
//!    doubling method they are solved by the Smith iteration under the doubling's own Cayley
//!    shift (matrix products only, see `smith.rs`); when such a step does not lower the
//!    residual or gains less than a factor 2, the exact step follows.
//! 6. The closed-loop poles are computed and judged once, for every method, by the boundary
//!    verdict of `boundary.rs`: a pole on or beyond the stability boundary fails, and so does
//!    a pole nearer to it than the reach `ρ(λ) = κ(λ)·η·(‖L‖_F + |λ|‖M‖_F)` of the
//!    solution's backward error `η` (its relative residual), `κ(λ)` the eigenvalue condition
//!    number of the Hamiltonian matrix `L = H`, `M = I` (symplectic pencil `L − zM`) — the
//!    computed `X` is exact for data perturbed by `η`, which can move that eigenvalue by
//!    `ρ(λ)`, so it might lie on the boundary ([`LtiError::BoundaryEigenvalue`], naming the
//!    poles and their mirror images); a distance below [`BOUNDARY_ROUNDING`]`·ε·‖L‖_F` always
//!    fails. Only poles within [`BOUNDARY_SCREEN`] of the boundary
//!    are judged this way (at most [`BOUNDARY_MAX_TESTED`]). The relative residual is
//!    required to be below [`RESIDUAL_LIMIT`].
//!
//! A Hamiltonian (symplectic) eigenvalue of multiplicity two exactly on the stability
//! boundary is split by rounding into a pair at distance `O(sqrt(ε))` on either side of it;
//! its eigenvalue condition number is then `O(1/sqrt(ε))` and the verdict rejects it (CAREX
//! 2.5 at `ε = 0`: poles `−3·10⁻⁸ ± j`, `d/ρ ≈ 0.1–0.7`). A genuine near-boundary pole with a
//! well-conditioned eigenvalue passes however near it is: the `−5·10⁻¹³ ± j` poles of
//! CAREX 2.8 (`d/ρ ≈ 190`), the `1 − 2·10⁻⁸` pole of DAREX 2.5 (`d/ρ ≈ 2·10⁸`), the
//! `−10⁻⁶ ± j` poles of CAREX 2.5 at `ε = 10⁻⁶` (`d/ρ ≈ 970`).
//!
//! Fail fast: above [`FAIL_FAST_MIN_STATES`] states, a stable-subspace basis `U₁` that is
//! singular to working precision ends the solve with [`LtiError::IllConditioned`] and its
//! estimated condition number, without trying the other methods or the diagnosis.
//!
//! [`RiccatiMethod::Auto`] tries its methods in order and returns the first accepted solution
//! whose residual is at most [`GOOD_RESIDUAL`], otherwise the most accurate accepted one. When
//! all fail, the data are diagnosed (PBH tests on the unstable and boundary modes) so that the
//! error names the cause: [`LtiError::NotStabilizable`], [`LtiError::NotDetectable`] or
//! [`LtiError::BoundaryEigenvalue`]. For the CARE, `Auto` first makes one bounded doubling
//! attempt accepted only under strict rules (relative residual `≤ 100·n·ε` after refinement,
//! Hurwitz closed loop, `X ⪰ 0` for LQR data); see [`care`].

mod boundary;
mod care;
mod compact;
mod dare;
mod small;
mod smith;

pub use boundary::{BOUNDARY_MAX_TESTED, BOUNDARY_ROUNDING, BOUNDARY_SCREEN};
pub use care::care;
pub use compact::{COMPACT_MAX, CompactCare, care_compact};
pub use dare::dare;

use crate::error::{LtiError, Result};
use crate::linalg::{
    Complex64, Mat, check_finite, check_shape, check_square, check_symmetric, pbh_margin,
    symmetrize,
};

/// The relative residual above which a computed solution is rejected with
/// [`LtiError::Inaccurate`] (after every method and refinement has been tried). A
/// backward-stable method reaches `≈ 1e-15`; even badly conditioned problems (CAREX/DAREX)
/// stay far below this limit, so exceeding it signals a breakdown, not ill conditioning.
pub const RESIDUAL_LIMIT: f64 = 1e-8;

/// Newton refinement stops once the relative residual is at most `REFINEMENT_FLOOR · n · ε`:
/// a backward-stable solution cannot be improved further by a step.
pub const REFINEMENT_FLOOR: f64 = 10.0;

/// A solution from [`RiccatiMethod::Auto`] with a relative residual at most this is returned
/// at once; a larger (but acceptable) residual makes `Auto` try its other methods and return
/// the most accurate solution.
pub const GOOD_RESIDUAL: f64 = 1e-12;

/// Above this many states, a method that finds the stable-subspace basis `U₁` singular to
/// working precision (estimated condition number above `1/(n·ε)`) ends the solve with
/// [`LtiError::IllConditioned`]: no other method and no diagnosis is tried. The diagnosis
/// tests every non-stable mode by a PBH singular value decomposition, `O(n³)` each (0.7 s at
/// `n = 600`, with about `n/2` such modes on random data); below the limit it runs as usual
/// and names the cause.
pub const FAIL_FAST_MIN_STATES: usize = 64;

/// Relative PBH margin below which a mode counts as numerically uncontrollable (unobservable)
/// when a failure is diagnosed (`≈ 100·sqrt(ε)`).
pub const PBH_TOLERANCE: f64 = 1e-6;

/// The algorithm used to compute the stabilising solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RiccatiMethod {
    /// Choose automatically: for the CARE the Schur method, then the doubling method; for the
    /// DARE the doubling method, then the Schur method. The first accepted result with a
    /// residual at most [`GOOD_RESIDUAL`] is returned, otherwise the most accurate accepted one.
    ///
    /// Every CARE first tries the doubling method under strict acceptance — a relative
    /// residual at most `100·n·ε` after refinement, a Hurwitz closed loop and (for `Q̃ ⪰ 0`)
    /// `X ⪰ 0`; such a result reports [`RiccatiMethod::Doubling`]. Small CAREs (`n ≤ 8`
    /// states, `m ≤ n` inputs) use fixed-size, stack-allocated matrices; larger ones the
    /// general doubling code with a bound of 11 doubling steps, so that a slowly converging
    /// attempt is abandoned early. When the attempt declines, the general path above runs
    /// (see [`care`]).
    #[default]
    Auto,
    /// Ordered real Schur form of the Hamiltonian matrix (CARE) or of the symplectic matrix
    /// (DARE, requires `A − B R⁻¹ Nᵀ` invertible), Laub's method.
    Schur,
    /// Structure-preserving doubling (SDA; Chu, Fan, Lin, Wang 2004 for the DARE and, after a
    /// Cayley transform, Chu, Fan, Lin 2005 for the CARE): quadratically convergent iteration
    /// on `n × n` matrices, refined by Newton's method. Requires `R ≻ 0`.
    Doubling,
}

/// Options for [`care`] and [`dare`], with documented defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiccatiOptions {
    /// Algorithm (default [`RiccatiMethod::Auto`]).
    pub method: RiccatiMethod,
    /// Scale the data before solving (default `true`); the solution is returned unscaled.
    pub scaling: bool,
    /// Maximum number of Newton (Kleinman / Hewer) refinement steps applied to the computed
    /// solution (default 8). A step is kept only if it lowers the relative residual; no step
    /// is attempted when the residual is already at rounding level
    /// (`≤ REFINEMENT_FLOOR · n · ε`), and the refinement stops when a step gains less than a
    /// factor 2 (Newton converges quadratically near the solution, so a well-conditioned
    /// problem needs at most one step).
    pub max_refinement_steps: usize,
}

impl Default for RiccatiOptions {
    fn default() -> Self {
        Self {
            method: RiccatiMethod::Auto,
            scaling: true,
            max_refinement_steps: 8,
        }
    }
}

/// Stabilising solution of an algebraic Riccati equation, with diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct RiccatiSolution {
    /// The stabilising solution `X` (symmetric).
    pub x: Mat,
    /// The optimal gain `K` (the control law is `u = −K x`).
    pub gain: Mat,
    /// Eigenvalues of `A − B K`, sorted as [`sort_eigenvalues`](crate::linalg::sort_eigenvalues).
    pub closed_loop_poles: Vec<Complex64>,
    /// Relative residual of the equation at `X`.
    pub residual: f64,
    /// The algorithm that produced `X`.
    pub method: RiccatiMethod,
    /// Newton refinement steps applied.
    pub refinement_steps: usize,
}

/// Shapes `(n, m)` of validated Riccati data.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RiccatiDims {
    pub n: usize,
    pub m: usize,
}

/// Validates Riccati data: `A` `n×n`, `B` `n×m`, `Q` `n×n` symmetric, `R` `m×m` symmetric
/// (positive definite if `require_r_pd`), `N` `n×m`; all finite.
pub(crate) fn validate(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    require_r_pd: bool,
) -> Result<RiccatiDims> {
    check_square("A", a)?;
    let nx = a.nrows();
    check_shape("B", b, nx, b.ncols())?;
    let m = b.ncols();
    check_shape("Q", q, nx, nx)?;
    check_shape("R", r, m, m)?;
    for (name, mat) in [("A", a), ("B", b), ("Q", q), ("R", r)] {
        check_finite(name, mat)?;
    }
    if let Some(nm) = n {
        check_shape("N", nm, nx, m)?;
        check_finite("N", nm)?;
    }
    // Symmetry to a few hundred ulps of the matrix's own size: data typed in by hand or
    // computed as MᵀM passes, a genuinely non-symmetric weight does not.
    check_symmetric("Q", q, 1e-12)?;
    check_symmetric("R", r, 1e-12)?;
    if require_r_pd && m > 0 {
        // A 1×1 R is its own eigenvalue (no eigensolver call on the single-input fast path).
        let min = if m == 1 {
            r[(0, 0)]
        } else {
            crate::linalg::symmetric_eigenvalues(r)
                .into_iter()
                .fold(f64::INFINITY, f64::min)
        };
        if min.is_nan() || min <= r.norm() * f64::EPSILON * (m as f64) {
            return Err(LtiError::NotPositiveDefinite {
                what: "R".into(),
                min_eigenvalue: min,
            });
        }
    }
    Ok(RiccatiDims { n: nx, m })
}

/// Riccati data with the cross term removed and `R` factored (step 2 of the module docs).
pub(crate) struct Reduced {
    /// Cholesky factor `L` of `R = L Lᵀ`.
    pub l: Mat,
    /// `Ã = A − B R⁻¹ Nᵀ`.
    pub a: Mat,
    /// `G = B R⁻¹ Bᵀ` (symmetric positive semidefinite).
    pub g: Mat,
    /// `Q̃ = Q − N R⁻¹ Nᵀ` (symmetric).
    pub q: Mat,
}

/// Lower Cholesky factor of a symmetric positive definite matrix, or
/// [`LtiError::NotPositiveDefinite`] with its smallest eigenvalue.
pub(crate) fn cholesky_lower(what: &str, r: &Mat) -> Result<Mat> {
    match r.clone().cholesky() {
        Some(c) => Ok(c.l()),
        None => Err(LtiError::NotPositiveDefinite {
            what: what.into(),
            min_eigenvalue: crate::linalg::symmetric_eigenvalues(r)
                .first()
                .copied()
                .unwrap_or(f64::NAN),
        }),
    }
}

/// Solves `L Y = M` for lower-triangular `L`.
fn lower_solve(l: &Mat, m: &Mat) -> Mat {
    let mut y = m.clone();
    let k = l.nrows();
    for j in 0..y.ncols() {
        for i in 0..k {
            let mut v = y[(i, j)];
            for p in 0..i {
                v -= l[(i, p)] * y[(p, j)];
            }
            y[(i, j)] = v / l[(i, i)];
        }
    }
    y
}

/// Solves `R Y = M` with `R = L Lᵀ`.
pub(crate) fn chol_solve(l: &Mat, m: &Mat) -> Mat {
    let y = lower_solve(l, m);
    // Lᵀ Z = Y.
    let k = l.nrows();
    let mut z = y;
    for j in 0..z.ncols() {
        for i in (0..k).rev() {
            let mut v = z[(i, j)];
            for p in i + 1..k {
                v -= l[(p, i)] * z[(p, j)];
            }
            z[(i, j)] = v / l[(i, i)];
        }
    }
    z
}

/// Step 2: removes the cross term and forms `G`.
pub(crate) fn reduce(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>) -> Result<Reduced> {
    let l = cholesky_lower("R", r)?;
    let w = lower_solve(&l, &b.transpose()); // L⁻¹ Bᵀ
    let g = symmetrize(&(w.transpose() * &w));
    let (ar, qr) = match n {
        Some(nm) => {
            let v = lower_solve(&l, &nm.transpose()); // L⁻¹ Nᵀ
            (
                a - w.transpose() * &v,
                symmetrize(&(q - v.transpose() * &v)),
            )
        }
        None => (a.clone(), symmetrize(q)),
    };
    Ok(Reduced { l, a: ar, g, q: qr })
}

/// Scale factor of step 3.
pub(crate) fn scale_factor(red: &Reduced, scaling: bool) -> f64 {
    let qn = red.q.norm();
    let gn = red.g.norm();
    if scaling && qn > 0.0 && gn > 0.0 && (qn / gn).is_finite() {
        (qn / gn).sqrt()
    } else {
        1.0
    }
}

/// CARE residual matrix and relative residual.
pub(crate) fn care_residual_full(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r_chol: &Mat,
    n: Option<&Mat>,
    x: &Mat,
) -> (Mat, f64) {
    let atx = a.transpose() * x;
    let xa = atx.transpose();
    let mut xbn = x * b;
    if let Some(nm) = n {
        xbn += nm;
    }
    let w = lower_solve(r_chol, &xbn.transpose()); // L⁻¹ (XB + N)ᵀ
    let g = w.transpose() * &w;
    let res = symmetrize(&(&atx + &xa - &g + q));
    let rel = super::relative_residual(&res, &[atx.norm(), xa.norm(), g.norm(), q.norm()]);
    (res, rel)
}

/// Relative residual of the CARE at `x` (see [`equations`](crate::equations)):
/// `‖AᵀX + XA − (XB+N)R⁻¹(BᵀX+Nᵀ) + Q‖_F` divided by the sum of the Frobenius norms of the
/// four terms.
pub fn care_residual(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> f64 {
    let atx = a.transpose() * x;
    let xa = x * a;
    let mut xbn = x * b;
    if let Some(nm) = n {
        xbn += nm;
    }
    // (XB + N) R⁻¹ (XB + N)ᵀ through a Cholesky factor of R when possible.
    let g = match r.clone().cholesky() {
        Some(ch) => &xbn * ch.solve(&xbn.transpose()),
        None => match r.clone().lu().solve(&xbn.transpose()) {
            Some(sol) => &xbn * sol,
            None => return f64::INFINITY,
        },
    };
    let res = &atx + &xa - &g + q;
    super::relative_residual(&res, &[atx.norm(), xa.norm(), g.norm(), q.norm()])
}

/// DARE residual matrix and relative residual; `None` if `BᵀXB + R` is singular.
pub(crate) fn dare_residual_full(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    x: &Mat,
) -> Option<(Mat, f64)> {
    let xa = x * a;
    let atxa = symmetrize(&(a.transpose() * &xa));
    let mut atxb = xa.transpose() * b;
    if let Some(nm) = n {
        atxb += nm;
    }
    let s = symmetrize(&(b.transpose() * x * b + r));
    let g = match s.clone().cholesky() {
        Some(ch) => &atxb * ch.solve(&atxb.transpose()),
        None => &atxb * s.lu().solve(&atxb.transpose())?,
    };
    let res = symmetrize(&(&atxa - x - &g + q));
    let rel = super::relative_residual(&res, &[atxa.norm(), x.norm(), g.norm(), q.norm()]);
    Some((res, rel))
}

/// Relative residual of the DARE at `x` (see [`equations`](crate::equations)):
/// `‖AᵀXA − X − (AᵀXB+N)(BᵀXB+R)⁻¹(BᵀXA+Nᵀ) + Q‖_F` divided by the sum of the Frobenius norms
/// of the four terms; `+∞` if `BᵀXB + R` is singular.
pub fn dare_residual(a: &Mat, b: &Mat, q: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> f64 {
    dare_residual_full(a, b, q, r, n, x).map_or(f64::INFINITY, |(_, rel)| rel)
}

/// CARE gain `K = R⁻¹(BᵀX + Nᵀ)`.
pub(crate) fn care_gain(l: &Mat, b: &Mat, n: Option<&Mat>, x: &Mat) -> Mat {
    let mut rhs = b.transpose() * x;
    if let Some(nm) = n {
        rhs += nm.transpose();
    }
    chol_solve(l, &rhs)
}

/// DARE gain `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)`; `None` if `BᵀXB + R` is singular.
pub(crate) fn dare_gain(a: &Mat, b: &Mat, r: &Mat, n: Option<&Mat>, x: &Mat) -> Option<Mat> {
    let xb = x * b;
    let s = symmetrize(&(b.transpose() * &xb + r));
    let mut rhs = xb.transpose() * a;
    if let Some(nm) = n {
        rhs += nm.transpose();
    }
    match s.clone().cholesky() {
        Some(ch) => Some(ch.solve(&rhs)),
        None => s.lu().solve(&rhs),
    }
}

/// Time domain of a Riccati problem, for the shared diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Domain {
    Continuous,
    Discrete,
}

impl Domain {
    /// Distance of `λ` from the stability boundary, positive inside the stable region.
    pub(crate) fn stability_margin(self, l: Complex64) -> f64 {
        match self {
            Domain::Continuous => -l.re,
            Domain::Discrete => 1.0 - l.norm(),
        }
    }
}

/// Explains a failure from the data: an uncontrollable mode that is not stable
/// ([`LtiError::NotStabilizable`]), or an unobservable (through `Q̃`) mode on the stability
/// boundary ([`LtiError::NotDetectable`]). `a`, `q` are the cross-term-free `Ã`, `Q̃`.
pub(crate) fn diagnose(domain: Domain, a: &Mat, b: &Mat, q: &Mat) -> Option<LtiError> {
    let ev = crate::linalg::eigenvalues(a).ok()?;
    let scale = match domain {
        Domain::Continuous => a.norm().max(1.0),
        Domain::Discrete => 1.0,
    };
    let tol_region = 1e-8 * scale;
    // Stabilisability: every mode with margin ≤ tol (not stable) must be controllable.
    let mut worst: Option<(f64, Complex64)> = None;
    for &l in &ev {
        if domain.stability_margin(l) <= tol_region {
            let m = pbh_margin(a, b, l);
            if worst.is_none_or(|w| m < w.0) {
                worst = Some((m, l));
            }
        }
    }
    if let Some((margin, eigenvalue)) = worst
        && margin <= PBH_TOLERANCE
    {
        return Some(LtiError::NotStabilizable { eigenvalue, margin });
    }
    // Detectability on the boundary: (Q̃, Ã) must have no unobservable boundary mode.
    let mut worst: Option<(f64, Complex64)> = None;
    for &l in &ev {
        if domain.stability_margin(l).abs() <= tol_region {
            let m = pbh_margin(&a.transpose(), q, l.conj());
            if worst.is_none_or(|w| m < w.0) {
                worst = Some((m, l));
            }
        }
    }
    if let Some((margin, eigenvalue)) = worst
        && margin <= PBH_TOLERANCE
    {
        return Some(LtiError::NotDetectable { eigenvalue, margin });
    }
    None
}

/// Step 5 and 6 for either domain: refinement, gain, poles and acceptance checks.
pub(crate) struct Finisher<'a> {
    pub domain: Domain,
    pub a: &'a Mat,
    pub b: &'a Mat,
    pub q: &'a Mat,
    pub r: &'a Mat,
    pub n: Option<&'a Mat>,
    pub red: &'a Reduced,
    /// Apply the boundary verdict ([`boundary::certify`]) to the result (`false` only for
    /// an intermediate problem whose result is finished again, e.g. the shifted DARE of a
    /// singular `R`).
    pub certify: bool,
}

impl Finisher<'_> {
    fn gain(&self, x: &Mat) -> Option<Mat> {
        match self.domain {
            Domain::Continuous => Some(care_gain(&self.red.l, self.b, self.n, x)),
            Domain::Discrete => dare_gain(self.a, self.b, self.r, self.n, x),
        }
    }

    fn residual(&self, x: &Mat) -> Option<(Mat, f64)> {
        match self.domain {
            Domain::Continuous => Some(care_residual_full(
                self.a,
                self.b,
                self.q,
                &self.red.l,
                self.n,
                x,
            )),
            Domain::Discrete => dare_residual_full(self.a, self.b, self.q, self.r, self.n, x),
        }
    }

    /// Refines `x`, computes the diagnostics and checks them.
    pub(crate) fn finish(
        &self,
        x: Mat,
        method: RiccatiMethod,
        options: &RiccatiOptions,
    ) -> Result<RiccatiSolution> {
        self.finish_with(Computed { x, hint: None }, method, options)
    }

    /// [`Finisher::finish`] for a computed solution that may carry a [`NewtonHint`]: the
    /// Newton steps then use it (no Schur decomposition of `A − BK`) as long as they lower the
    /// residual; after the first step that does not, the exact step (Schur decomposition of
    /// `A − BK`) is tried before giving up.
    pub(crate) fn finish_with(
        &self,
        computed: Computed,
        method: RiccatiMethod,
        options: &RiccatiOptions,
    ) -> Result<RiccatiSolution> {
        let Computed { x, hint } = computed;
        let mut hint = hint.filter(|_| self.domain == Domain::Continuous);
        let nx = self.a.nrows();
        let mut x = symmetrize(&x);
        let bad = |what: &str| LtiError::Inaccurate {
            what: format!("{what}: BᵀXB + R is singular at the computed solution"),
            residual: f64::INFINITY,
            tolerance: RESIDUAL_LIMIT,
        };
        let mut k = self.gain(&x).ok_or_else(|| bad("DARE gain"))?;
        let (mut res_mat, mut residual) = self.residual(&x).ok_or_else(|| bad("DARE residual"))?;
        let mut steps = 0;
        let floor = REFINEMENT_FLOOR * nx as f64 * f64::EPSILON;
        while steps < options.max_refinement_steps && residual > floor && residual.is_finite() {
            // Newton step in correction form: L_K(Δ) = −Res(X), with L_K the Fréchet
            // derivative at X: (A−BK)ᵀΔ + Δ(A−BK) (Kleinman) or (A−BK)ᵀΔ(A−BK) − Δ (Hewer).
            let delta = match &hint {
                Some(NewtonHint::Schur(h)) => h.newton_step(&res_mat),
                Some(NewtonHint::Smith(h)) => h.newton_step(&(self.a - self.b * &k), &res_mat),
                None => {
                    let ak = self.a - self.b * &k;
                    match self.domain {
                        Domain::Continuous => kleinman_step(&ak, &res_mat),
                        Domain::Discrete => {
                            crate::equations::dlyap(&ak.transpose(), &res_mat).map(|d| d.x)
                        }
                    }
                }
            };
            let Ok(delta) = delta else {
                if hint.take().is_some() {
                    continue;
                }
                break;
            };
            let x_new = symmetrize(&(&x + &delta));
            let Some(k_new) = self.gain(&x_new) else {
                break;
            };
            let Some((rm, rel)) = self.residual(&x_new) else {
                break;
            };
            if rel < residual {
                let gain = residual / rel;
                x = x_new;
                k = k_new;
                res_mat = rm;
                residual = rel;
                steps += 1;
                // A small gain ends the refinement; after a step from the Hamiltonian's Schur
                // data the exact step is tried first.
                if gain < 2.0 && hint.take().is_none() {
                    break;
                }
            } else if hint.take().is_none() {
                break;
            }
            // Otherwise the step from the Schur data of the Hamiltonian did not help: the exact
            // one is tried next.
        }
        let acl = self.a - self.b * &k;
        let poles = crate::linalg::eigenvalues(&acl)?;
        if self.certify {
            boundary::certify(self.domain, self.red, (&x, &acl), &poles, residual)?;
        }
        if residual.is_nan() || residual > RESIDUAL_LIMIT {
            return Err(LtiError::Inaccurate {
                what: match self.domain {
                    Domain::Continuous => "CARE solution",
                    Domain::Discrete => "DARE solution",
                }
                .into(),
                residual,
                tolerance: RESIDUAL_LIMIT,
            });
        }
        Ok(RiccatiSolution {
            x,
            gain: k,
            closed_loop_poles: poles,
            residual,
            method,
            refinement_steps: steps,
        })
    }
}

/// The Kleinman–Newton correction: `Δ` with `FᵀΔ + ΔF = −Res` for the closed loop `F`, by
/// Bartels–Stewart on the real Schur form `Fᵀ = USUᵀ` (`SY + YSᵀ = −UᵀResU`, `Δ = UYUᵀ`) —
/// the computation of [`lyap`](crate::equations::lyap) without its input checks and its
/// residual evaluation (the caller evaluates the Riccati residual of `X + Δ` instead). An
/// eigenvalue collision `λᵢ(F) + λⱼ(F) ≈ 0` (no unique correction) is an error.
fn kleinman_step(f: &Mat, res: &Mat) -> Result<Mat> {
    let (s, u) = crate::linalg::schur::real_schur(&f.transpose())?.into_parts();
    let mut y = -(u.transpose() * res * &u);
    y = symmetrize(&y);
    let perturbed = crate::equations::triangular::solve_quasi_sylvester(
        &s,
        &s,
        crate::equations::triangular::RightCoef::TransposeOfUpper,
        &mut y,
    );
    if perturbed {
        return Err(LtiError::Singular {
            what: "Lyapunov operator of the Newton step (closed loop not stable)".into(),
            rcond: 0.0,
        });
    }
    let d = symmetrize(&(&u * y * u.transpose()));
    check_finite("Newton correction", &d)?;
    Ok(d)
}

/// Runs the candidate methods in order and returns the first accepted solution with a
/// residual at most [`GOOD_RESIDUAL`], else the most accurate accepted one; when none is
/// accepted the data are diagnosed and the most informative error is returned.
pub(crate) fn solve_with_fallback(
    fin: &Finisher<'_>,
    candidates: &[RiccatiMethod],
    options: &RiccatiOptions,
    compute: impl FnMut(RiccatiMethod) -> Result<Computed>,
) -> Result<RiccatiSolution> {
    solve_with_fallback_prior(fin, candidates, options, None, compute)
}

/// [`solve_with_fallback`] with the finished result of one candidate already known (`prior`,
/// used in its place instead of computing it again).
pub(crate) fn solve_with_fallback_prior(
    fin: &Finisher<'_>,
    candidates: &[RiccatiMethod],
    options: &RiccatiOptions,
    mut prior: Option<(RiccatiMethod, Result<RiccatiSolution>)>,
    mut compute: impl FnMut(RiccatiMethod) -> Result<Computed>,
) -> Result<RiccatiSolution> {
    let mut first_err: Option<LtiError> = None;
    let mut best: Option<RiccatiSolution> = None;
    for &m in candidates {
        let attempt = match prior.take_if(|(pm, _)| *pm == m) {
            Some((_, known)) => known,
            None => compute(m).and_then(|c| fin.finish_with(c, m, options)),
        };
        match attempt {
            Ok(sol) => {
                if sol.residual <= GOOD_RESIDUAL {
                    return Ok(sol);
                }
                if best.as_ref().is_none_or(|b| sol.residual < b.residual) {
                    best = Some(sol);
                }
            }
            // Fail fast: a large problem whose stable subspace cannot be inverted stops
            // here, before the remaining methods and the O(k·n³) diagnosis (PBH tests on
            // every non-stable mode) that would otherwise take minutes at n = 600.
            Err(e @ LtiError::IllConditioned { .. }) if fin.a.nrows() > FAIL_FAST_MIN_STATES => {
                return Err(e);
            }
            Err(e) => {
                if first_err.is_none() {
                    first_err = Some(e);
                }
            }
        }
    }
    if let Some(sol) = best {
        return Ok(sol);
    }
    if let Some(d) = diagnose(fin.domain, &fin.red.a, fin.b, &fin.red.q) {
        return Err(d);
    }
    Err(first_err.unwrap_or_else(|| LtiError::InvalidArgument("no Riccati method selected".into())))
}

/// The stabilising solution of the empty problem (`n = 0`).
pub(crate) fn empty_solution(m: usize, method: RiccatiMethod) -> RiccatiSolution {
    RiccatiSolution {
        x: Mat::zeros(0, 0),
        gain: Mat::zeros(m, 0),
        closed_loop_poles: Vec::new(),
        residual: 0.0,
        method,
        refinement_steps: 0,
    }
}

/// Basis `[U1; U2]` (`2n × n`, orthonormal columns) of a stable invariant/deflating subspace →
/// `X = U2 U1⁻¹` (symmetrised), with a conditioning check on `U1`.
pub(crate) fn solution_from_subspace(u1: &Mat, u2: &Mat) -> Result<Mat> {
    solution_and_factor_from_subspace(u1, u2).map(|(x, _)| x)
}

/// [`solution_from_subspace`], also returning the LU factorisation of `U1`.
pub(crate) fn solution_and_factor_from_subspace(
    u1: &Mat,
    u2: &Mat,
) -> Result<(Mat, crate::linalg::dense::Lu)> {
    let n = u1.nrows();
    let lu = crate::linalg::dense::Lu::new(u1);
    let rcond = lu.rcond();
    if rcond.is_nan() || rcond <= n as f64 * f64::EPSILON {
        return Err(LtiError::IllConditioned {
            what: format!(
                "the Riccati solution X = U2 U1⁻¹ ({n} states; condition number of the \
                 stable subspace basis block U1)"
            ),
            condition: 1.0 / rcond,
            limit: 1.0 / (n as f64 * f64::EPSILON),
        });
    }
    // U1ᵀ Xᵀ = U2ᵀ.
    let mut xt = u2.transpose();
    lu.solve_transpose_in_place(&mut xt);
    Ok((symmetrize(&xt), lu))
}

/// A computed (unrefined) solution, with what its method knows about its closed loop.
pub(crate) struct Computed {
    /// The solution.
    pub x: Mat,
    /// Data for a cheaper Newton step than the exact one (continuous time only).
    pub hint: Option<NewtonHint>,
}

/// What a method knows about the closed loop `A − BK(X)` of its solution, used by
/// [`Finisher::finish_with`] for a Newton step without a Schur decomposition of `A − BK`.
pub(crate) enum NewtonHint {
    /// `A − BK(X) = U₁ T₁₁ U₁⁻¹` from the ordered Schur form of the Hamiltonian (Laub's
    /// method).
    Schur(ClosedLoopSchur),
    /// The Cayley shift under which the doubling method converged, for the Smith iteration
    /// (structure-preserving doubling).
    Smith(smith::CayleySmith),
}

impl From<Mat> for Computed {
    fn from(x: Mat) -> Self {
        Self { x, hint: None }
    }
}

/// The closed loop of a CARE solution from Laub's method: with `H [U₁; U₂] = [U₁; U₂] T₁₁`
/// (stable invariant subspace of the Hamiltonian, `T₁₁` quasi-upper-triangular) and
/// `X = U₂U₁⁻¹`, the first block row gives `(Ã − GX) U₁ = U₁ T₁₁`, i.e.
/// `A − BK = U₁ T₁₁ U₁⁻¹` (also for the scaled Hamiltonian, whose `U₁` and `T₁₁` are those
/// of `H`).
///
/// The Kleinman step `(A−BK)ᵀΔ + Δ(A−BK) = −Res` then becomes, with `Y = U₁ᵀ Δ U₁`, the
/// quasi-triangular Lyapunov equation `T₁₁ᵀ Y + Y T₁₁ = −U₁ᵀ Res U₁`, solved by the
/// Bartels–Stewart back substitution without a new Schur decomposition; `Δ = U₁⁻ᵀ Y U₁⁻¹`.
/// This is the exact Newton step up to rounding amplified by `cond(U₁)` (the step is kept only
/// if it lowers the residual, see [`Finisher::finish_with`]).
pub(crate) struct ClosedLoopSchur {
    /// `U₁`, the top block of the stable subspace basis.
    pub u1: Mat,
    /// LU factorisation of `U₁`.
    pub lu: crate::linalg::dense::Lu,
    /// `T₁₁`, the stable block of the ordered Schur form.
    pub t11: Mat,
}

impl ClosedLoopSchur {
    /// The Newton correction `Δ` for the residual matrix `res` (see the type documentation).
    fn newton_step(&self, res: &Mat) -> Result<Mat> {
        let n = self.t11.nrows();
        let c = -(self.u1.transpose() * res * &self.u1);
        // T₁₁ᵀ is lower quasi-triangular; with the flip J (reversed identity),
        // S = J T₁₁ᵀ J is upper quasi-triangular and S (JYJ) + (JYJ) Sᵀ = J C J.
        let s = Mat::from_fn(n, n, |i, j| self.t11[(n - 1 - j, n - 1 - i)]);
        let mut f = symmetrize(&Mat::from_fn(n, n, |i, j| c[(n - 1 - i, n - 1 - j)]));
        crate::equations::triangular::solve_quasi_sylvester(
            &s,
            &s,
            crate::equations::triangular::RightCoef::TransposeOfUpper,
            &mut f,
        );
        let mut w = Mat::from_fn(n, n, |i, j| f[(n - 1 - i, n - 1 - j)]);
        // Δ = U₁⁻ᵀ Y U₁⁻¹: W = U₁⁻ᵀ Y, then Δᵀ = U₁⁻ᵀ Wᵀ.
        self.lu.solve_transpose_in_place(&mut w);
        let mut d = w.transpose();
        self.lu.solve_transpose_in_place(&mut d);
        check_finite("Newton correction from the Hamiltonian Schur form", &d)?;
        Ok(symmetrize(&d))
    }
}

#[cfg(test)]
mod tests;
