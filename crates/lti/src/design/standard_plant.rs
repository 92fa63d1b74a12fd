//! The standard (generalised) plant of H∞ and H2 synthesis, its assumptions, and the lower
//! linear fractional transformation that closes it with a controller.
//!
//! ```text
//!        ┌─────────┐
//!   w ──▶│         │──▶ z        ẋ = A x + B₁ w + B₂ u
//!        │    P    │             z = C₁ x + D₁₁ w + D₁₂ u
//!   u ──▶│         │──▶ y        y = C₂ x + D₂₁ w + D₂₂ u
//!        └─────────┘
//!          ▲     │               u = K y   (the controller K = (A_k, B_k, C_k, D_k))
//!          └─ K ◀┘
//! ```
//!
//! `P` is one [`StateSpace`] with inputs `[w; u]` and outputs `[z; y]`; the last `ncon`
//! inputs are the controls `u` and the last `nmeas` outputs the measurements `y` (MATLAB
//! `hinfsyn(P, nmeas, ncon)`, python-control `hinfsyn(P, nmeas, ncon)`). The controller is
//! connected with **positive** feedback `u = K y` (the lower LFT `F_l(P, K)`), as in MATLAB
//! and python-control; this differs from the `u = −K x` of the state-feedback gains of
//! [`design`](super).

use crate::analysis::invariant_zeros;
use crate::domain::Continuous;
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat};
use crate::state_space::StateSpace;

/// A standard-plant assumption of the Riccati syntheses ([`hinf_syn`](super::hinf_syn),
/// [`h2_syn`](super::h2_syn)), named in [`LtiError::SynthesisAssumption`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlantAssumption {
    /// `(A, B₂)` stabilisable: some controller stabilises the loop.
    Stabilizable,
    /// `(C₂, A)` detectable.
    Detectable,
    /// `D₁₂` has full column rank (every control is penalised: no singular problem).
    D12FullColumnRank,
    /// `D₂₁` has full row rank (every measurement is noisy).
    D21FullRowRank,
    /// `P₁₂ = (A, B₂, C₁, D₁₂)` has no invariant zero on the imaginary axis.
    P12NoImaginaryZeros,
    /// `P₂₁ = (A, B₁, C₂, D₂₁)` has no invariant zero on the imaginary axis.
    P21NoImaginaryZeros,
    /// `D₁₁ = 0`: the H2 problem needs it (its norm is infinite otherwise), as do the
    /// state-feedback H∞ formulas; the output-feedback H∞ synthesis accepts any `D₁₁`
    /// ([`hinf_syn`](super::hinf_syn): Glover–Doyle formulas) and so does the LMI synthesis of
    /// `pendulab-lmi`.
    D11Zero,
    /// The plant has at least one measurement and one control (output feedback).
    HasMeasurementsAndControls,
}

impl std::fmt::Display for PlantAssumption {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PlantAssumption::Stabilizable => "(A, B2) stabilisable",
            PlantAssumption::Detectable => "(C2, A) detectable",
            PlantAssumption::D12FullColumnRank => "D12 of full column rank",
            PlantAssumption::D21FullRowRank => "D21 of full row rank",
            PlantAssumption::P12NoImaginaryZeros => "P12 without imaginary-axis zeros",
            PlantAssumption::P21NoImaginaryZeros => "P21 without imaginary-axis zeros",
            PlantAssumption::D11Zero => "D11 = 0",
            PlantAssumption::HasMeasurementsAndControls => "nmeas ≥ 1 and ncon ≥ 1",
        })
    }
}

/// Relative tolerance of the rank and imaginary-axis decisions of
/// [`StandardPlant::check_assumptions`]: a singular value of `D₁₂` (`D₂₁`) below
/// `RANK_TOLERANCE · max(1, ‖D₁₂‖₂)` counts as zero, and an invariant zero `ζ` with
/// `|Re ζ| ≤ RANK_TOLERANCE · max(1, |ζ|)` as lying on the imaginary axis.
pub const RANK_TOLERANCE: f64 = 1e-9;

/// A continuous-time standard plant: a state-space system with inputs `[w; u]` and outputs
/// `[z; y]`, `ncon` controls and `nmeas` measurements (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct StandardPlant {
    sys: StateSpace<Continuous>,
    nmeas: usize,
    ncon: usize,
}

/// Block accessors share one shape: rows `r0..r0+nr`, columns `c0..c0+nc` of a matrix.
fn block(m: &Mat, r0: usize, nr: usize, c0: usize, nc: usize) -> Mat {
    m.view((r0, c0), (nr, nc)).clone_owned()
}

impl StandardPlant {
    /// The plant `sys` whose last `nmeas` outputs are the measurements and last `ncon` inputs
    /// the controls. `nmeas = 0` is allowed for the state-feedback (full-information)
    /// syntheses, which use only `A, B₁, B₂, C₁, D₁₁, D₁₂`.
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] if `nmeas > ny` or `ncon > nu` of `sys`.
    pub fn new(sys: StateSpace<Continuous>, nmeas: usize, ncon: usize) -> Result<Self> {
        if nmeas > sys.ny() || ncon > sys.nu() {
            return Err(LtiError::InvalidArgument(format!(
                "standard plant: nmeas = {nmeas}, ncon = {ncon} exceed the system's {} outputs, {} inputs",
                sys.ny(),
                sys.nu()
            )));
        }
        Ok(Self { sys, nmeas, ncon })
    }

    /// The plant from its blocks `A, B₁, B₂, C₁, C₂, D₁₁, D₁₂, D₂₁, D₂₂`.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`] for blocks that do not fit together,
    /// [`LtiError::NonFinite`].
    #[allow(clippy::too_many_arguments)]
    pub fn from_blocks(
        a: &Mat,
        b1: &Mat,
        b2: &Mat,
        c1: &Mat,
        c2: &Mat,
        d11: &Mat,
        d12: &Mat,
        d21: &Mat,
        d22: &Mat,
    ) -> Result<Self> {
        let n = a.nrows();
        let (nw, nu, nz, ny) = (b1.ncols(), b2.ncols(), c1.nrows(), c2.nrows());
        crate::linalg::check_shape("B1", b1, n, nw)?;
        crate::linalg::check_shape("B2", b2, n, nu)?;
        crate::linalg::check_shape("C1", c1, nz, n)?;
        crate::linalg::check_shape("C2", c2, ny, n)?;
        crate::linalg::check_shape("D11", d11, nz, nw)?;
        crate::linalg::check_shape("D12", d12, nz, nu)?;
        crate::linalg::check_shape("D21", d21, ny, nw)?;
        crate::linalg::check_shape("D22", d22, ny, nu)?;
        let mut b = Mat::zeros(n, nw + nu);
        b.view_mut((0, 0), (n, nw)).copy_from(b1);
        b.view_mut((0, nw), (n, nu)).copy_from(b2);
        let mut c = Mat::zeros(nz + ny, n);
        c.view_mut((0, 0), (nz, n)).copy_from(c1);
        c.view_mut((nz, 0), (ny, n)).copy_from(c2);
        let mut d = Mat::zeros(nz + ny, nw + nu);
        d.view_mut((0, 0), (nz, nw)).copy_from(d11);
        d.view_mut((0, nw), (nz, nu)).copy_from(d12);
        d.view_mut((nz, 0), (ny, nw)).copy_from(d21);
        d.view_mut((nz, nw), (ny, nu)).copy_from(d22);
        Self::new(StateSpace::continuous(a.clone(), b, c, d)?, ny, nu)
    }

    /// The whole plant as one system (inputs `[w; u]`, outputs `[z; y]`).
    pub fn system(&self) -> &StateSpace<Continuous> {
        &self.sys
    }

    /// Number of measurements `y` (the last outputs).
    pub fn nmeas(&self) -> usize {
        self.nmeas
    }

    /// Number of controls `u` (the last inputs).
    pub fn ncon(&self) -> usize {
        self.ncon
    }

    /// Number of states `n`.
    pub fn nx(&self) -> usize {
        self.sys.nx()
    }

    /// Number of exogenous inputs `w`.
    pub fn nw(&self) -> usize {
        self.sys.nu() - self.ncon
    }

    /// Number of regulated outputs `z`.
    pub fn nz(&self) -> usize {
        self.sys.ny() - self.nmeas
    }

    /// `A` (`n × n`).
    pub fn a(&self) -> &Mat {
        self.sys.a()
    }

    /// `B₁` (`n × nw`).
    pub fn b1(&self) -> Mat {
        block(self.sys.b(), 0, self.nx(), 0, self.nw())
    }

    /// `B₂` (`n × ncon`).
    pub fn b2(&self) -> Mat {
        block(self.sys.b(), 0, self.nx(), self.nw(), self.ncon)
    }

    /// `C₁` (`nz × n`).
    pub fn c1(&self) -> Mat {
        block(self.sys.c(), 0, self.nz(), 0, self.nx())
    }

    /// `C₂` (`nmeas × n`).
    pub fn c2(&self) -> Mat {
        block(self.sys.c(), self.nz(), self.nmeas, 0, self.nx())
    }

    /// `D₁₁` (`nz × nw`).
    pub fn d11(&self) -> Mat {
        block(self.sys.d(), 0, self.nz(), 0, self.nw())
    }

    /// `D₁₂` (`nz × ncon`).
    pub fn d12(&self) -> Mat {
        block(self.sys.d(), 0, self.nz(), self.nw(), self.ncon)
    }

    /// `D₂₁` (`nmeas × nw`).
    pub fn d21(&self) -> Mat {
        block(self.sys.d(), self.nz(), self.nmeas, 0, self.nw())
    }

    /// `D₂₂` (`nmeas × ncon`).
    pub fn d22(&self) -> Mat {
        block(self.sys.d(), self.nz(), self.nmeas, self.nw(), self.ncon)
    }

    /// Checks the assumptions of the output-feedback Riccati syntheses, in this order:
    /// at least one measurement and control; `D₁₁ = 0` (if `require_d11_zero`); `(A, B₂)`
    /// stabilisable and `(C₂, A)` detectable (the staircase forms of
    /// [`StateSpace::is_stabilizable`]); `D₁₂` of full column rank and `D₂₁` of full row rank
    /// (singular values against [`RANK_TOLERANCE`]); no invariant zero of
    /// `P₁₂ = (A, B₂, C₁, D₁₂)` or `P₂₁ = (A, B₁, C₂, D₂₁)` on the imaginary axis
    /// ([`StateSpace::zeros`]; `|Re ζ| ≤ RANK_TOLERANCE·max(1, |ζ|)`).
    ///
    /// # Errors
    /// [`LtiError::SynthesisAssumption`] naming the first assumption that fails; the
    /// eigenvalue computations' errors.
    pub fn check_assumptions(&self, require_d11_zero: bool) -> Result<()> {
        let fail =
            |assumption, detail: String| Err(LtiError::SynthesisAssumption { assumption, detail });
        if self.nmeas == 0 || self.ncon == 0 {
            return fail(
                PlantAssumption::HasMeasurementsAndControls,
                format!("nmeas = {}, ncon = {}", self.nmeas, self.ncon),
            );
        }
        self.check_d11(require_d11_zero)?;
        let p22 = StateSpace::continuous(self.a().clone(), self.b2(), self.c2(), self.d22())?;
        if !p22.is_stabilizable()? {
            return fail(
                PlantAssumption::Stabilizable,
                "(A, B2) has an uncontrollable mode that is not stable".into(),
            );
        }
        if !p22.is_detectable()? {
            return fail(
                PlantAssumption::Detectable,
                "(C2, A) has an unobservable mode that is not stable".into(),
            );
        }
        self.check_d12_rank()?;
        let d21 = self.d21();
        let s = singular_values(&d21);
        let smin = s.iter().copied().fold(f64::INFINITY, f64::min);
        if s.len() < d21.nrows() || smin <= RANK_TOLERANCE * s.iter().copied().fold(1.0, f64::max) {
            return fail(
                PlantAssumption::D21FullRowRank,
                format!(
                    "D21 is {}x{} with smallest singular value {:e}",
                    d21.nrows(),
                    d21.ncols(),
                    if s.len() < d21.nrows() { 0.0 } else { smin }
                ),
            );
        }
        self.check_p12_zeros()?;
        if let Some(z) = imaginary_zero(self.a(), &self.b1(), &self.c2(), &d21)? {
            return fail(
                PlantAssumption::P21NoImaginaryZeros,
                format!("invariant zero at {}{:+}j", z.re, z.im),
            );
        }
        Ok(())
    }

    /// `D₁₁ = 0` when required (state-feedback and output-feedback formulas alike).
    pub(crate) fn check_d11(&self, require_d11_zero: bool) -> Result<()> {
        let d11 = self.d11();
        if require_d11_zero && d11.iter().any(|v| *v != 0.0) {
            return Err(LtiError::SynthesisAssumption {
                assumption: PlantAssumption::D11Zero,
                detail: format!("‖D11‖_F = {:e}", d11.norm()),
            });
        }
        Ok(())
    }

    /// `D₁₂` of full column rank.
    pub(crate) fn check_d12_rank(&self) -> Result<()> {
        let d12 = self.d12();
        let s = singular_values(&d12);
        let smin = s.iter().copied().fold(f64::INFINITY, f64::min);
        if s.len() < d12.ncols() || smin <= RANK_TOLERANCE * s.iter().copied().fold(1.0, f64::max) {
            return Err(LtiError::SynthesisAssumption {
                assumption: PlantAssumption::D12FullColumnRank,
                detail: format!(
                    "D12 is {}x{} with smallest singular value {:e}",
                    d12.nrows(),
                    d12.ncols(),
                    if s.len() < d12.ncols() { 0.0 } else { smin }
                ),
            });
        }
        Ok(())
    }

    /// `P₁₂` without invariant zeros on the imaginary axis.
    pub(crate) fn check_p12_zeros(&self) -> Result<()> {
        if let Some(z) = imaginary_zero(self.a(), &self.b2(), &self.c1(), &self.d12())? {
            return Err(LtiError::SynthesisAssumption {
                assumption: PlantAssumption::P12NoImaginaryZeros,
                detail: format!("invariant zero at {}{:+}j", z.re, z.im),
            });
        }
        Ok(())
    }

    /// The closed loop `F_l(P, K)` from `w` to `z` with the controller `u = K y`
    /// (`K`: `nmeas` inputs, `ncon` outputs), states `[x; x_k]`. With `E = (I − D_k D₂₂)⁻¹`,
    /// `u = E (D_k C₂ x + C_k x_k + D_k D₂₁ w)` and `y = C₂ x + D₂₁ w + D₂₂ u`.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`] for a controller of the wrong size;
    /// [`LtiError::Singular`] if `I − D_k D₂₂` is singular (an ill-posed loop).
    #[doc(alias = "lft")]
    pub fn close_loop(&self, k: &StateSpace<Continuous>) -> Result<StateSpace<Continuous>> {
        let (n, nk, nw, nz, ny, nu) = (
            self.nx(),
            k.nx(),
            self.nw(),
            self.nz(),
            self.nmeas,
            self.ncon,
        );
        if k.nu() != ny || k.ny() != nu {
            return Err(LtiError::DimensionMismatch {
                what: "controller K (outputs x inputs = ncon x nmeas)".into(),
                expected: (nu, ny),
                found: (k.ny(), k.nu()),
            });
        }
        let (c2, d21, d22) = (self.c2(), self.d21(), self.d22());
        let e = (Mat::identity(nu, nu) - k.d() * &d22)
            .try_inverse()
            .ok_or(LtiError::Singular {
                what: "I − Dk D22 of the closed loop (ill-posed interconnection)".into(),
                rcond: 0.0,
            })?;
        // u = U [x; x_k; w], y = Y [x; x_k; w].
        let m = n + nk + nw;
        let mut mu = Mat::zeros(nu, m);
        mu.view_mut((0, 0), (nu, n)).copy_from(&(k.d() * &c2));
        mu.view_mut((0, n), (nu, nk)).copy_from(k.c());
        mu.view_mut((0, n + nk), (nu, nw))
            .copy_from(&(k.d() * &d21));
        let u = &e * mu;
        let mut y = &d22 * &u;
        {
            let mut v = y.view_mut((0, 0), (ny, n));
            v += &c2;
        }
        {
            let mut v = y.view_mut((0, n + nk), (ny, nw));
            v += &d21;
        }
        // [ẋ; ẋ_k; z] = G [x; x_k; w].
        let mut g = Mat::zeros(n + nk + nz, m);
        g.view_mut((0, 0), (n, n)).copy_from(self.a());
        g.view_mut((0, n + nk), (n, nw)).copy_from(&self.b1());
        g.view_mut((n, n), (nk, nk)).copy_from(k.a());
        g.view_mut((n + nk, 0), (nz, n)).copy_from(&self.c1());
        g.view_mut((n + nk, n + nk), (nz, nw))
            .copy_from(&self.d11());
        {
            let mut v = g.view_mut((0, 0), (n, m));
            v += self.b2() * &u;
        }
        {
            let mut v = g.view_mut((n, 0), (nk, m));
            v += k.b() * &y;
        }
        {
            let mut v = g.view_mut((n + nk, 0), (nz, m));
            v += self.d12() * &u;
        }
        let s = n + nk;
        StateSpace::continuous(
            block(&g, 0, s, 0, s),
            block(&g, 0, s, s, nw),
            block(&g, s, nz, 0, s),
            block(&g, s, nz, s, nw),
        )
    }

    /// The controller for this plant from `k0`, a controller designed for the same plant with
    /// `D₂₂ = 0` (loop shifting): `k0` sees `y₀ = y − D₂₂ u`, so with `M = (I + D_k D₂₂)⁻¹`,
    /// `A_k' = A_k − B_k D₂₂ M C_k`, `B_k' = B_k (I − D₂₂ M D_k)`, `C_k' = M C_k`,
    /// `D_k' = M D_k`. Returns `k0` unchanged when `D₂₂ = 0`.
    ///
    /// # Errors
    /// [`LtiError::Singular`] if `I + D_k D₂₂` is singular; shape errors.
    pub fn shift_d22(&self, k0: StateSpace<Continuous>) -> Result<StateSpace<Continuous>> {
        let d22 = self.d22();
        if d22.iter().all(|v| *v == 0.0) {
            return Ok(k0);
        }
        let nu = self.ncon;
        let m = (Mat::identity(nu, nu) + k0.d() * &d22)
            .try_inverse()
            .ok_or(LtiError::Singular {
                what: "I + Dk D22 of the D22 loop shift".into(),
                rcond: 0.0,
            })?;
        let (ak, bk, ck, dk) = k0.into_parts();
        let ny = self.nmeas;
        let a = &ak - &bk * &d22 * &m * &ck;
        let b = &bk * (Mat::identity(ny, ny) - &d22 * &m * &dk);
        StateSpace::continuous(a, b, &m * ck, &m * dk)
    }

    /// The same plant with `D₂₂` set to zero (the design plant of [`Self::shift_d22`]).
    pub fn without_d22(&self) -> Result<Self> {
        let mut d = self.sys.d().clone();
        let (nz, nw) = (self.nz(), self.nw());
        d.view_mut((nz, nw), (self.nmeas, self.ncon)).fill(0.0);
        Self::new(
            StateSpace::continuous(
                self.a().clone(),
                self.sys.b().clone(),
                self.sys.c().clone(),
                d,
            )?,
            self.nmeas,
            self.ncon,
        )
    }
}

/// Singular values of a real matrix (empty for an empty matrix).
pub(crate) fn singular_values(m: &Mat) -> Vec<f64> {
    if m.nrows() == 0 || m.ncols() == 0 {
        return Vec::new();
    }
    crate::linalg::svd::svd(m)
        .singular_values
        .iter()
        .copied()
        .collect()
}

/// An invariant zero of `(A, B, C, D)` on the imaginary axis, if any.
fn imaginary_zero(a: &Mat, b: &Mat, c: &Mat, d: &Mat) -> Result<Option<Complex64>> {
    Ok(invariant_zeros(a, b, c, d)?
        .into_iter()
        .find(|z| z.re.abs() <= RANK_TOLERANCE * z.norm().max(1.0)))
}
