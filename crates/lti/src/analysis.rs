//! Analysis of state-space systems: poles, zeros, DC gain, stability, damping,
//! controllability/observability (matrices, ranks, staircase forms, PBH margins),
//! stabilisability/detectability, gramians and canonical forms.
//!
//! | question | function | MATLAB |
//! |---|---|---|
//! | poles | [`StateSpace::poles`] | `pole`, `eig(A)` |
//! | invariant (transmission) zeros, any shape | [`StateSpace::zeros`] | `tzero`, `zero` |
//! | DC gain | [`StateSpace::dc_gain`] | `dcgain` |
//! | stability | [`StateSpace::is_stable`], [`StateSpace::stability_margin`] | `isstable` |
//! | natural frequency, damping | [`StateSpace::damp`] | `damp` |
//! | controllability matrix, observability matrix | [`ctrb`], [`obsv`] | `ctrb`, `obsv` |
//! | numerical rank with its tolerance | [`rank`] | `rank` |
//! | controllable subspace (orthogonal staircase) | [`controllability_staircase`] | `ctrbf` |
//! | PBH margins of every mode | [`pbh_controllability`], [`pbh_observability`] | — |
//! | controllable / stabilisable / observable / detectable | [`StateSpace::is_controllable`] … | — |
//! | gramians | [`gramian`] | `gram` |
//! | canonical forms | [`controllable_canonical_form`], [`observable_canonical_form`] | `canon(…,'companion')` |
//!
//! **Numerical decisions.** Controllability and observability are decided on the orthogonal
//! staircase form (Van Dooren 1981; Varga, SLICOT `TB01MD`), not on the rank of `ctrb`, whose
//! columns `AᵏB` lose the information in rounding for moderately large `n` or `‖A‖`. Each
//! decision states its tolerance; the PBH margins are reported as distances (how far the pair
//! is from one with an uncontrollable mode), not as decisions.

use crate::domain::TimeDomain;
use crate::equations::MatrixEquationSolution;
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat, check_finite, check_shape, check_square};
use crate::state_space::StateSpace;

mod canonical;
pub use canonical::{CanonicalForm, controllable_canonical_form, observable_canonical_form};

/// Natural frequency and damping ratio of one pole (MATLAB `damp`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damping {
    /// The pole (`s` in continuous time, `z` in discrete time).
    pub pole: Complex64,
    /// Natural frequency `ωₙ = |s|` in rad/s (for a discrete pole `s = ln(z)/ts`; `∞` for
    /// `z = 0`).
    pub natural_frequency: f64,
    /// Damping ratio `ζ = −cos(∠s) = −Re s/|s|` (MATLAB's convention: `−1` for a pole at the
    /// origin, negative for unstable poles).
    pub damping_ratio: f64,
    /// Time constant `τ = −1/Re s` in seconds (`∞` for `Re s = 0`, negative if unstable).
    pub time_constant: f64,
}

/// The numerical rank of a matrix with the tolerance that decided it.
#[derive(Debug, Clone, PartialEq)]
pub struct RankInfo {
    /// Number of singular values above `tolerance`.
    pub rank: usize,
    /// The tolerance used: `max(rows, cols) · ε · σ_max` (MATLAB's `rank` default) unless
    /// given explicitly.
    pub tolerance: f64,
    /// Singular values, descending.
    pub singular_values: Vec<f64>,
}

/// Numerical rank of `m` from its singular values with MATLAB's default tolerance
/// `max(rows, cols) · ε · σ_max`.
pub fn rank(m: &Mat) -> RankInfo {
    rank_with_tolerance(m, None)
}

/// Numerical rank of `m`: the number of singular values `> tolerance` (default as [`rank`]).
pub fn rank_with_tolerance(m: &Mat, tolerance: Option<f64>) -> RankInfo {
    if m.nrows() == 0 || m.ncols() == 0 {
        return RankInfo {
            rank: 0,
            tolerance: tolerance.unwrap_or(0.0),
            singular_values: Vec::new(),
        };
    }
    let mut sv: Vec<f64> = m
        .clone()
        .svd(false, false)
        .singular_values
        .iter()
        .copied()
        .collect();
    sv.sort_by(|a, b| b.total_cmp(a));
    let tol = tolerance.unwrap_or_else(|| m.nrows().max(m.ncols()) as f64 * f64::EPSILON * sv[0]);
    RankInfo {
        rank: sv.iter().filter(|&&s| s > tol).count(),
        tolerance: tol,
        singular_values: sv,
    }
}

/// Controllability matrix `M_c = [B, AB, …, Aⁿ⁻¹B]` (`n × n·m`, MATLAB `ctrb`).
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::DimensionMismatch`], [`LtiError::NonFinite`].
pub fn ctrb(a: &Mat, b: &Mat) -> Result<Mat> {
    check_square("A", a)?;
    check_shape("B", b, a.nrows(), b.ncols())?;
    check_finite("A", a)?;
    check_finite("B", b)?;
    let (n, m) = (a.nrows(), b.ncols());
    let mut out = Mat::zeros(n, n * m);
    let mut blk = b.clone();
    for k in 0..n {
        out.view_mut((0, k * m), (n, m)).copy_from(&blk);
        blk = a * blk;
    }
    Ok(out)
}

/// Observability matrix `M_o = [C; CA; …; CAⁿ⁻¹]` (`n·p × n`, MATLAB `obsv`).
///
/// # Errors
/// As [`ctrb`].
pub fn obsv(a: &Mat, c: &Mat) -> Result<Mat> {
    check_square("A", a)?;
    check_shape("C", c, c.nrows(), a.nrows())?;
    Ok(ctrb(&a.transpose(), &c.transpose())?.transpose())
}

/// Householder QR with column pivoting, `M P = Q R`, with the full orthogonal `Q`
/// (`rows × rows`) accumulated. Returns `(Q, R, permutation)`; `perm[j]` is the original
/// column in position `j`.
pub(crate) fn qr_column_pivoting(m: &Mat) -> (Mat, Mat, Vec<usize>) {
    let (rows, cols) = m.shape();
    let mut r = m.clone();
    let mut q = Mat::identity(rows, rows);
    let mut perm: Vec<usize> = (0..cols).collect();
    for j in 0..rows.min(cols) {
        // Pivot: the remaining column of largest norm (recomputed; sizes here are small).
        let (best, _) = (j..cols)
            .map(|c| (c, r.view((j, c), (rows - j, 1)).norm()))
            .fold((j, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
        if best != j {
            r.swap_columns(j, best);
            perm.swap(j, best);
        }
        let x = r.view((j, j), (rows - j, 1)).clone_owned();
        let alpha = x.norm();
        if alpha == 0.0 {
            continue;
        }
        let sign = if x[0] >= 0.0 { 1.0 } else { -1.0 };
        let mut v = x;
        v[0] += sign * alpha;
        let vnorm2 = v.norm_squared();
        if vnorm2 == 0.0 {
            continue;
        }
        // R ← (I − 2vvᵀ/vᵀv) R on rows j.., Q ← Q (I − 2vvᵀ/vᵀv) on columns j...
        {
            let mut sub = r.view_mut((j, 0), (rows - j, cols));
            let w = v.transpose() * &sub; // 1 × cols
            sub -= &v * (w * (2.0 / vnorm2));
        }
        {
            let mut sub = q.view_mut((0, j), (rows, rows - j));
            let w = &sub * &v; // rows × 1
            sub -= w * (v.transpose() * (2.0 / vnorm2));
        }
        r[(j, j)] = -sign * alpha;
        for i in j + 1..rows {
            r[(i, j)] = 0.0;
        }
    }
    (q, r, perm)
}

/// The orthogonal controllability staircase form of `(A, B)` (MATLAB `ctrbf`, with the
/// controllable part first).
///
/// `Ã = Zᵀ A Z = [[A_c, A₁₂], [0, A_uc]]`, `B̃ = Zᵀ B = [B_c; 0]`, with `(A_c, B_c)`
/// controllable of dimension [`controllable_dimension`](Self::controllable_dimension) and
/// `A_uc` holding the uncontrollable modes. `Z` is orthogonal (`x = Z x̃`).
#[derive(Debug, Clone, PartialEq)]
pub struct Staircase {
    /// `Zᵀ A Z` in block upper-triangular form.
    pub a: Mat,
    /// `Zᵀ B`, zero below the controllable part.
    pub b: Mat,
    /// The orthogonal transformation `Z` (`x = Z x̃`).
    pub z: Mat,
    /// Dimension of the controllable subspace.
    pub controllable_dimension: usize,
    /// Sizes of the staircase blocks (the controllability indices' conjugate partition).
    pub block_sizes: Vec<usize>,
    /// Rank-decision tolerance used.
    pub tolerance: f64,
}

impl Staircase {
    /// Eigenvalues of the uncontrollable block `A_uc`.
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`] if the eigenvalue iteration fails.
    pub fn uncontrollable_modes(&self) -> Result<Vec<Complex64>> {
        let n = self.a.nrows();
        let k = self.controllable_dimension;
        crate::linalg::eigenvalues(&self.a.view((k, k), (n - k, n - k)).clone_owned())
    }
}

/// Default staircase tolerance `10 · n · ε · max(‖A‖_F, ‖B‖_F)`: rank decisions at the level
/// of the rounding errors the orthogonal transformations themselves commit (scale-invariant:
/// multiplying `A` and `B` by a common factor does not change a decision).
fn staircase_tolerance(a: &Mat, b: &Mat) -> f64 {
    let n = a.nrows().max(1) as f64;
    10.0 * n * f64::EPSILON * a.norm().max(b.norm())
}

/// Computes the controllability staircase form of `(A, B)` by successive rank-revealing
/// (column-pivoted Householder) QR factorisations of the sub-diagonal blocks (Van Dooren,
/// "The generalized eigenstructure problem in linear system theory", IEEE TAC 26(1), 1981).
///
/// `tolerance` (default `10 · n · ε · max(‖A‖_F, ‖B‖_F)`) decides which diagonal entries of
/// `R` count as zero.
///
/// # Errors
/// [`LtiError::NotSquare`], [`LtiError::DimensionMismatch`], [`LtiError::NonFinite`].
#[doc(alias = "ctrbf")]
pub fn controllability_staircase(a: &Mat, b: &Mat, tolerance: Option<f64>) -> Result<Staircase> {
    check_square("A", a)?;
    check_shape("B", b, a.nrows(), b.ncols())?;
    check_finite("A", a)?;
    check_finite("B", b)?;
    let n = a.nrows();
    let tol = tolerance.unwrap_or_else(|| staircase_tolerance(a, b));
    let mut at = a.clone();
    let mut bt = b.clone();
    let mut z = Mat::identity(n, n);
    let mut k = 0usize;
    let mut blocks = Vec::new();
    // Columns (of Ã, or of B̃ on the first step) whose rows k.. form the next block.
    let mut prev: Option<(usize, usize)> = None;
    while k < n {
        let panel = match prev {
            None => bt.view((k, 0), (n - k, bt.ncols())).clone_owned(),
            Some((c0, w)) => at.view((k, c0), (n - k, w)).clone_owned(),
        };
        if panel.ncols() == 0 {
            break;
        }
        let (q, r, _) = qr_column_pivoting(&panel);
        let r_rank = (0..r.nrows().min(r.ncols()))
            .take_while(|&i| r[(i, i)].abs() > tol)
            .count();
        if r_rank == 0 {
            break;
        }
        // Apply Qᵀ on rows k.. of Ã (and B̃) and Q on columns k.. of Ã and Z.
        let rows = at.view((k, 0), (n - k, n)).clone_owned();
        at.view_mut((k, 0), (n - k, n))
            .copy_from(&(q.transpose() * rows));
        let cols = at.view((0, k), (n, n - k)).clone_owned();
        at.view_mut((0, k), (n, n - k)).copy_from(&(cols * &q));
        let zc = z.view((0, k), (n, n - k)).clone_owned();
        z.view_mut((0, k), (n, n - k)).copy_from(&(zc * &q));
        let brows = bt.view((k, 0), (n - k, bt.ncols())).clone_owned();
        bt.view_mut((k, 0), (n - k, bt.ncols()))
            .copy_from(&(q.transpose() * brows));
        // Exact zeros below the revealed rank in the panel just reduced.
        match prev {
            None => {
                for i in k + r_rank..n {
                    for j in 0..bt.ncols() {
                        bt[(i, j)] = 0.0;
                    }
                }
            }
            Some((c0, w)) => {
                for i in k + r_rank..n {
                    for j in c0..c0 + w {
                        at[(i, j)] = 0.0;
                    }
                }
            }
        }
        blocks.push(r_rank);
        prev = Some((k, r_rank));
        k += r_rank;
    }
    Ok(Staircase {
        a: at,
        b: bt,
        z,
        controllable_dimension: k,
        block_sizes: blocks,
        tolerance: tol,
    })
}

/// PBH margin of one mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PbhMode {
    /// The eigenvalue `λ` of `A`.
    pub eigenvalue: Complex64,
    /// `σ_min([A − λI, B]) / max(1, ‖[A, B]‖₂)` (controllability) or its dual: the relative
    /// distance to a pair in which `λ` is uncontrollable (unobservable).
    pub margin: f64,
}

/// PBH (Popov–Belevitch–Hautus) margins of every mode, for controllability of `(A, B)` or
/// observability of `(C, A)`.
#[derive(Debug, Clone, PartialEq)]
pub struct PbhReport {
    /// One entry per eigenvalue of `A` (sorted as [`sort_eigenvalues`](crate::linalg::sort_eigenvalues)).
    pub modes: Vec<PbhMode>,
    /// The smallest margin (`∞` for `n = 0`).
    pub min_margin: f64,
}

/// PBH controllability margins of `(A, B)`: for each eigenvalue `λ` of `A`, the smallest
/// singular value of `[A − λI, B]` relative to `max(1, ‖[A, B]‖₂)`
/// ([`pbh_margin`](crate::linalg::pbh_margin)). A margin at rounding level (≲ 1e-13 for a
/// well-conditioned eigenvalue) means the mode is numerically uncontrollable; the margin is a
/// distance, the decision is [`controllability_staircase`]'s.
///
/// # Errors
/// As [`ctrb`], and [`LtiError::NoConvergence`] if the eigenvalues cannot be computed.
pub fn pbh_controllability(a: &Mat, b: &Mat) -> Result<PbhReport> {
    check_square("A", a)?;
    check_shape("B", b, a.nrows(), b.ncols())?;
    check_finite("B", b)?;
    let ev = crate::linalg::eigenvalues(a)?;
    let modes: Vec<PbhMode> = ev
        .into_iter()
        .map(|l| PbhMode {
            eigenvalue: l,
            margin: crate::linalg::pbh_margin(a, b, l),
        })
        .collect();
    let min_margin = modes.iter().map(|m| m.margin).fold(f64::INFINITY, f64::min);
    Ok(PbhReport { modes, min_margin })
}

/// PBH observability margins of `(C, A)` (the controllability margins of `(Aᵀ, Cᵀ)`).
///
/// # Errors
/// As [`pbh_controllability`].
pub fn pbh_observability(a: &Mat, c: &Mat) -> Result<PbhReport> {
    check_square("A", a)?;
    check_shape("C", c, c.nrows(), a.nrows())?;
    pbh_controllability(&a.transpose(), &c.transpose())
}

/// Tolerance for "strictly inside the stability region": a pole counts as stable when its
/// [`stability_distance`](TimeDomain::stability_distance) is below `−100 ε max(1, ‖A‖_F)`,
/// so a pole that is on the boundary in exact arithmetic (an integrator, `z = 1`) and was
/// computed a rounding error inside is not called stable.
fn stability_tolerance(a: &Mat) -> f64 {
    100.0 * f64::EPSILON * a.norm().max(1.0)
}

impl<D: TimeDomain> StateSpace<D> {
    /// Poles: the eigenvalues of `A`, sorted as
    /// [`sort_eigenvalues`](crate::linalg::sort_eigenvalues).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`] if the eigenvalue iteration fails.
    #[doc(alias = "pole")]
    #[doc(alias = "eig")]
    pub fn poles(&self) -> Result<Vec<Complex64>> {
        crate::linalg::eigenvalues(self.a())
    }

    /// Invariant (transmission) zeros: the finite `s` where the system matrix
    /// `[[sI − A, −B], [C, D]]` loses rank below its normal rank (MATLAB `tzero`), for any
    /// number of inputs and outputs. They include the input- and output-decoupling zeros of
    /// a non-minimal realisation, so that for SISO systems
    /// `num/den = k Π(s − zᵢ)/Π(s − pᵢ)` holds for every realisation.
    ///
    /// Method: orthogonal deflation in the spirit of Emami-Naeini & Van Dooren ("Computation
    /// of zeros of linear multivariable systems", Automatica 18(4), 1982), which removes the
    /// infinite zeros one structural step at a time and keeps the finite ones:
    /// - `D` of rank `σ > 0`: compress its rows and columns with rank-revealing QR, solve the
    ///   `σ` outputs that see the input directly for `σ` input directions
    ///   (`v₁ = −D̄₁⁻¹ C̄₁ x`), and continue with the remaining outputs (no feedthrough) and
    ///   inputs;
    /// - `D = 0`: compress `C` onto its row space; a zero output forces those `ρ` state
    ///   components to vanish, which leaves `n − ρ` states with the new "output"
    ///   `A₂₁x₁ + B₂u = 0`;
    /// - no outputs left: the zeros are the uncontrollable modes of what remains (the
    ///   staircase form), all eigenvalues if no inputs remain.
    ///
    /// Rank decisions use `max(n + p, n + m) · ε · ‖[[A, B], [C, D]]‖_F`. For SISO systems
    /// this reduces to `eig(A − BD⁻¹C)` (`D ≠ 0`) or the eigenvalues after the relative
    /// degree has been deflated. An identically zero transfer function has no zeros (an
    /// empty list).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`] from the eigenvalue computations.
    #[doc(alias = "tzero")]
    #[doc(alias = "zero")]
    pub fn zeros(&self) -> Result<Vec<Complex64>> {
        if self.nu() == 1 && self.ny() == 1 {
            return Ok(
                siso_zeros(self.a(), self.b(), self.c(), self.d()[(0, 0)])?.unwrap_or_default()
            );
        }
        invariant_zeros(self.a(), self.b(), self.c(), self.d())
    }

    /// Frequency response `G(s₀) = D + C (s₀I − A)⁻¹ B` at one complex point (`s` or `z`).
    ///
    /// # Errors
    /// [`LtiError::PoleAtEvaluationPoint`] if `s₀I − A` is singular to working precision
    /// (reciprocal 2-norm condition number below `n ε`).
    pub fn evaluate(&self, s0: Complex64) -> Result<crate::linalg::CMat> {
        evaluate_at(
            self.a(),
            self.b(),
            self.c(),
            self.d(),
            s0,
            "frequency response",
        )
    }

    /// Steady-state (DC) gain: `G(0) = D − C A⁻¹ B` in continuous time, `G(1) = D + C (I −
    /// A)⁻¹ B` in discrete time (MATLAB `dcgain`), `ny × nu`.
    ///
    /// # Errors
    /// [`LtiError::PoleAtEvaluationPoint`] if the system has a pole at `s = 0` (`z = 1`) to
    /// working precision (an integrator): the gain is infinite. A pole there that a
    /// non-minimal realisation cancels is reported the same way; remove it first.
    #[doc(alias = "dcgain")]
    pub fn dc_gain(&self) -> Result<Mat> {
        let s0 = match self.domain().sample_time() {
            None => Complex64::new(0.0, 0.0),
            Some(_) => Complex64::new(1.0, 0.0),
        };
        let g = evaluate_at(self.a(), self.b(), self.c(), self.d(), s0, "DC gain")?;
        Ok(g.map(|z| z.re))
    }

    /// Largest [`stability_distance`](TimeDomain::stability_distance) over the poles:
    /// `max Re λ` (continuous) or `max |λ| − 1` (discrete). Negative means asymptotically
    /// stable; `−∞` for a system without states.
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    pub fn stability_margin(&self) -> Result<f64> {
        let d = self.domain();
        Ok(self
            .poles()?
            .into_iter()
            .map(|p| d.stability_distance(p))
            .fold(f64::NEG_INFINITY, f64::max))
    }

    /// `true` if every pole is strictly inside the stability region (open left half-plane,
    /// open unit disc) by more than `100 ε max(1, ‖A‖_F)`, so that poles on the boundary in
    /// exact arithmetic are not called stable because of rounding (MATLAB `isstable`).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    #[doc(alias = "isstable")]
    pub fn is_stable(&self) -> Result<bool> {
        Ok(self.stability_margin()? < -stability_tolerance(self.a()))
    }

    /// Natural frequency, damping ratio and time constant of every pole (MATLAB `damp`).
    /// Discrete poles are mapped to `s = ln(z)/ts` first.
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    pub fn damp(&self) -> Result<Vec<Damping>> {
        let ts = self.domain().sample_time();
        Ok(self
            .poles()?
            .into_iter()
            .map(|p| damping_of(p, ts))
            .collect())
    }

    /// `true` if `(A, B)` is controllable, decided on the staircase form
    /// ([`controllability_staircase`] with its default tolerance).
    ///
    /// # Errors
    /// As [`controllability_staircase`].
    pub fn is_controllable(&self) -> Result<bool> {
        Ok(
            controllability_staircase(self.a(), self.b(), None)?.controllable_dimension
                == self.nx(),
        )
    }

    /// `true` if `(C, A)` is observable (the staircase form of `(Aᵀ, Cᵀ)`).
    ///
    /// # Errors
    /// As [`controllability_staircase`].
    pub fn is_observable(&self) -> Result<bool> {
        Ok(
            controllability_staircase(&self.a().transpose(), &self.c().transpose(), None)?
                .controllable_dimension
                == self.nx(),
        )
    }

    /// `true` if every uncontrollable mode of `(A, B)` is strictly stable (in this system's
    /// domain, with the margin of [`is_stable`](Self::is_stable)).
    ///
    /// # Errors
    /// As [`controllability_staircase`].
    #[doc(alias = "stabilisable")]
    pub fn is_stabilizable(&self) -> Result<bool> {
        uncontrollable_modes_stable(self.a(), self.b(), self.domain())
    }

    /// `true` if every unobservable mode of `(C, A)` is strictly stable.
    ///
    /// # Errors
    /// As [`controllability_staircase`].
    pub fn is_detectable(&self) -> Result<bool> {
        uncontrollable_modes_stable(&self.a().transpose(), &self.c().transpose(), self.domain())
    }
}

fn uncontrollable_modes_stable<D: TimeDomain>(a: &Mat, b: &Mat, domain: D) -> Result<bool> {
    let st = controllability_staircase(a, b, None)?;
    let tol = stability_tolerance(a);
    Ok(st
        .uncontrollable_modes()?
        .into_iter()
        .all(|l| domain.stability_distance(l) < -tol))
}

pub(crate) fn damping_of(p: Complex64, ts: Option<f64>) -> Damping {
    let s = match ts {
        None => p,
        Some(ts) => {
            if p.norm() == 0.0 {
                return Damping {
                    pole: p,
                    natural_frequency: f64::INFINITY,
                    damping_ratio: 1.0,
                    time_constant: 0.0,
                };
            }
            p.ln() / ts
        }
    };
    let wn = s.norm();
    let zeta = if wn == 0.0 { -1.0 } else { -s.re / wn };
    Damping {
        pole: p,
        natural_frequency: wn,
        damping_ratio: zeta,
        time_constant: if s.re == 0.0 {
            f64::INFINITY
        } else {
            -1.0 / s.re
        },
    }
}

/// `D + C (s₀I − A)⁻¹ B` by a complex LU solve, refusing `s₀` at a pole.
pub(crate) fn evaluate_at(
    a: &Mat,
    b: &Mat,
    c: &Mat,
    d: &Mat,
    s0: Complex64,
    what: &str,
) -> Result<crate::linalg::CMat> {
    use crate::linalg::CMat;
    let n = a.nrows();
    let dc: CMat = d.map(|v| Complex64::new(v, 0.0));
    if n == 0 {
        return Ok(dc);
    }
    let mut m: CMat = a.map(|v| Complex64::new(-v, 0.0));
    for i in 0..n {
        m[(i, i)] += s0;
    }
    // Reciprocal condition of s₀I − A in the 2-norm from its singular values.
    let sv = m.clone().svd(false, false).singular_values;
    let (smax, smin) = (sv.max(), sv.min());
    if smin <= n as f64 * f64::EPSILON * smax.max(f64::MIN_POSITIVE) {
        return Err(LtiError::PoleAtEvaluationPoint {
            what: what.to_string(),
            pole: s0,
        });
    }
    let bc: CMat = b.map(|v| Complex64::new(v, 0.0));
    let x = m.lu().solve(&bc).ok_or(LtiError::PoleAtEvaluationPoint {
        what: what.to_string(),
        pole: s0,
    })?;
    let cc: CMat = c.map(|v| Complex64::new(v, 0.0));
    Ok(cc * x + dc)
}

/// Invariant zeros of a general realisation (see [`StateSpace::zeros`]).
pub(crate) fn invariant_zeros(a: &Mat, b: &Mat, c: &Mat, d: &Mat) -> Result<Vec<Complex64>> {
    let (n0, m0, p0) = (a.nrows(), b.ncols(), c.nrows());
    let snorm = (a.norm_squared() + b.norm_squared() + c.norm_squared() + d.norm_squared()).sqrt();
    let tol = (n0 + p0).max(n0 + m0).max(1) as f64 * f64::EPSILON * snorm.max(f64::MIN_POSITIVE);
    let (mut a, mut b, mut c, mut d) = (a.clone(), b.clone(), c.clone(), d.clone());
    loop {
        let (n, m, p) = (a.nrows(), b.ncols(), c.nrows());
        if n == 0 {
            return Ok(Vec::new());
        }
        if p == 0 {
            if m == 0 {
                return crate::linalg::eigenvalues(&a);
            }
            return controllability_staircase(&a, &b, Some(tol))?.uncontrollable_modes();
        }
        let rank_of = |r: &Mat| {
            (0..r.nrows().min(r.ncols()))
                .take_while(|&i| r[(i, i)].abs() > tol)
                .count()
        };
        // Rank of D by rank-revealing QR: D P = Q R.
        let (qd, rd, _) = qr_column_pivoting(&d);
        let sigma = if m == 0 { 0 } else { rank_of(&rd) };
        if sigma > 0 {
            // Rows: U = Qᵀ puts D's row space first: U D = [D̄ (σ × m); 0].
            let ud = qd.transpose() * &d;
            let uc = qd.transpose() * &c;
            let dbar = ud.rows(0, sigma).clone_owned();
            // Columns: D̄ W = [D̄₁ (σ × σ, invertible), 0] with W from the QR of D̄ᵀ.
            let (w, _, _) = qr_column_pivoting(&dbar.transpose());
            let dw = &dbar * &w;
            let d1 = dw.columns(0, sigma).clone_owned();
            let w1 = w.columns(0, sigma).clone_owned();
            let w2 = w.columns(sigma, m - sigma).clone_owned();
            let c1 = uc.rows(0, sigma).clone_owned();
            let lu = d1.lu();
            let f = lu.solve(&c1).ok_or(LtiError::Singular {
                what: "feedthrough block in the zero computation".into(),
                rcond: 0.0,
            })?;
            a = &a - &b * &w1 * f;
            b = &b * w2;
            c = uc.rows(sigma, p - sigma).clone_owned();
            d = Mat::zeros(p - sigma, m - sigma);
            continue;
        }
        // D = 0: compress C onto its row space, Cᵀ P = Q R, C Q = [C_a (ρ columns), 0].
        let (qc, rc, _) = qr_column_pivoting(&c.transpose());
        let rho = rank_of(&rc);
        if rho == 0 {
            c = Mat::zeros(0, n);
            d = Mat::zeros(0, m);
            continue;
        }
        let at = qc.transpose() * &a * &qc;
        let bt = qc.transpose() * &b;
        // x = Q [x_a; x_b]; y = 0 forces x_a = 0, leaving x_b with the constraint
        // A_ab x_b + B_a u = 0 as the new output.
        let nb = n - rho;
        let new_a = at.view((rho, rho), (nb, nb)).clone_owned();
        let new_b = bt.rows(rho, nb).clone_owned();
        let new_c = at.view((0, rho), (rho, nb)).clone_owned();
        let new_d = bt.rows(0, rho).clone_owned();
        a = new_a;
        b = new_b;
        c = new_c;
        d = new_d;
    }
}

/// Invariant zeros of a SISO realisation; `None` if the transfer function is identically 0.
pub(crate) fn siso_zeros(a: &Mat, b: &Mat, c: &Mat, d: f64) -> Result<Option<Vec<Complex64>>> {
    let n = a.nrows();
    if d != 0.0 {
        if n == 0 {
            return Ok(Some(Vec::new()));
        }
        let m = a - b * c / d;
        return crate::linalg::eigenvalues(&m).map(Some);
    }
    let anorm = a.norm();
    let mut a = a.clone();
    let mut b = b.column(0).clone_owned();
    let mut c: crate::linalg::Vector = c.row(0).transpose().column(0).clone_owned();
    let mut first = true;
    loop {
        let k = a.nrows();
        let cnorm = c.norm();
        let bnorm = b.norm();
        // c (or b) numerically zero: no path from input to output.
        let c_tol = if first {
            0.0
        } else {
            10.0 * k.max(1) as f64 * f64::EPSILON * anorm
        };
        if k == 0 || cnorm <= c_tol || bnorm == 0.0 {
            return Ok(None);
        }
        // Householder H (symmetric, orthogonal) with H c = −sign(c_last)·‖c‖ e_k, so that
        // c̃ = cᵀH is a multiple of the last unit row.
        let mut v = c.clone();
        let sign = if c[k - 1] >= 0.0 { 1.0 } else { -1.0 };
        v[k - 1] += sign * cnorm;
        let vn2 = v.norm_squared();
        let apply = |m: &Mat| -> Mat {
            // H M H with H = I − 2vvᵀ/vᵀv.
            let hm = m - &v * ((v.transpose() * m) * (2.0 / vn2));
            &hm - (&hm * &v) * (v.transpose() * (2.0 / vn2))
        };
        let at = apply(&a);
        let bt = &b - &v * (v.dot(&b) * 2.0 / vn2);
        let b2 = bt[k - 1];
        let err_scale = if first { 1.0 } else { 1.0 + anorm / cnorm };
        let b_tol = 10.0 * k as f64 * f64::EPSILON * bnorm * err_scale;
        let a11 = at.view((0, 0), (k - 1, k - 1)).clone_owned();
        let b1 = bt.rows(0, k - 1).clone_owned();
        let a21: crate::linalg::Vector = at
            .view((k - 1, 0), (1, k - 1))
            .transpose()
            .column(0)
            .clone_owned();
        if b2.abs() > b_tol {
            if k == 1 {
                return Ok(Some(Vec::new()));
            }
            let m = &a11 - &b1 * a21.transpose() / b2;
            return crate::linalg::eigenvalues(&m).map(Some);
        }
        a = a11;
        b = b1;
        c = a21;
        first = false;
    }
}

/// Controllability or observability gramian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GramianKind {
    /// `W_c`: `A W + W Aᵀ + B Bᵀ = 0` (continuous), `A W Aᵀ − W + B Bᵀ = 0` (discrete).
    Controllability,
    /// `W_o`: `Aᵀ W + W A + Cᵀ C = 0` (continuous), `Aᵀ W A − W + Cᵀ C = 0` (discrete).
    Observability,
}

/// Controllability or observability gramian of a stable system (MATLAB `gram`), from the
/// Lyapunov solvers ([`lyap`](crate::equations::lyap), [`dlyap`](crate::equations::dlyap)),
/// with their relative residual.
///
/// # Errors
/// [`LtiError::InvalidArgument`] if the system is not asymptotically stable (the infinite
/// integral diverges); the Lyapunov solver's errors.
#[doc(alias = "gram")]
pub fn gramian<D: TimeDomain>(
    sys: &StateSpace<D>,
    kind: GramianKind,
) -> Result<MatrixEquationSolution> {
    if !sys.is_stable()? {
        return Err(LtiError::InvalidArgument(format!(
            "gramian needs an asymptotically stable system; largest pole stability distance is {:e}",
            sys.stability_margin()?
        )));
    }
    let (a, q) = match kind {
        GramianKind::Controllability => (sys.a().clone(), sys.b() * sys.b().transpose()),
        GramianKind::Observability => (sys.a().transpose(), sys.c().transpose() * sys.c()),
    };
    let q = crate::linalg::symmetrize(&q);
    match sys.domain().sample_time() {
        None => crate::equations::lyap(&a, &q),
        Some(_) => crate::equations::dlyap(&a, &q),
    }
}

/// 2-norm condition number from the singular values (`∞` if singular).
pub(crate) fn cond2(m: &Mat) -> f64 {
    if m.nrows() == 0 {
        return 1.0;
    }
    let sv = m.clone().svd(false, false).singular_values;
    let (mx, mn) = (sv.max(), sv.min());
    if mn == 0.0 { f64::INFINITY } else { mx / mn }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::from_rows;

    #[test]
    fn pivoted_qr_reconstructs() {
        let m = from_rows(&[&[1.0, 2.0], &[3.0, 4.0], &[5.0, 7.0]]).unwrap();
        let (q, r, perm) = qr_column_pivoting(&m);
        let mut mp = Mat::zeros(3, 2);
        for (j, &p) in perm.iter().enumerate() {
            mp.set_column(j, &m.column(p));
        }
        assert!((&q * &r - mp).norm() < 1e-14);
        assert!((q.transpose() * &q - Mat::identity(3, 3)).norm() < 1e-14);
        assert_eq!(r[(2, 0)], 0.0);
    }
}
