//! Multi-input multi-output transfer functions: a `p × m` matrix of SISO
//! [`TransferFunction`]s (MATLAB and python-control `tf` with cell arrays / lists of lists).
//!
//! - Arithmetic (MATLAB's `G + H`, `G − H`, `G * H`, `G / H`, `−G`): entry by entry
//!   polynomial arithmetic, nothing cancelled (as [`interconnect`](crate::interconnect)'s
//!   `series_tf`/`parallel_tf`); [`TransferMatrix::minreal`] cancels common pole-zero pairs of
//!   each entry afterwards. A shape or sample-time mismatch is never a panic: the methods
//!   ([`TransferMatrix::try_add`], …) and the operators `+ − * /` on values and references
//!   return [`Result`]; only unary `−` cannot fail.
//! - `*` is the matrix product; a `1 × 1` factor on either side multiplies every entry (a
//!   scalar, as in MATLAB). `G / H` is `G H⁻¹`: for a `1 × 1` `H = h` every entry is divided
//!   by `h` (polynomially, so `1/h` may be improper); for a square `H` the inverse is the
//!   state-space inverse of its minimal realisation, `(A − B D⁻¹ C, B D⁻¹, −D⁻¹ C, D⁻¹)`,
//!   which requires an invertible feedthrough `D = H(∞)` (a biproper `H` whose inverse is
//!   proper); otherwise it is an error.
//! - [`TransferMatrix::feedback`] (MATLAB `feedback(G, K, sign)`): `(I − σ G K)⁻¹ G`, by
//!   polynomials for `1 × 1` loops and through the minimal realisations and
//!   [`interconnect::feedback`](crate::interconnect::feedback) otherwise.
//! - [`TransferMatrix::from_state_space`] (`tf(sys)`): each entry is the transfer function of
//!   the minimal realisation ([`minreal`]) of the SISO channel `(A, B e_j, e_iᵀ C, D_ij)`, by
//!   [`TransferFunction::from_state_space`], so every entry is exact and coprime.
//! - [`TransferMatrix::to_state_space`] (`ss(G)`, **minimal**): the controllable canonical
//!   realisation of every entry, stacked block-diagonally (entry `(i, j)` driven by input `j`
//!   and read by output `i`), then [`minreal`]; its order is the McMillan degree of `G`
//!   (at `minreal`'s rank tolerance).
//! - [`TransferMatrix::to_zpk`] (`zpkdata`): zeros, poles and gain per entry.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::interconnect::{FeedbackSign, feedback, feedback_tf, parallel_tf, series_tf};
use crate::linalg::{CMat, Complex64, Mat};
use crate::reduction::minreal;
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;

/// A `p × m` transfer-function matrix in time domain `D` (outputs × inputs), entries stored
/// row by row.
///
/// Invariants: at least one row and one column; every entry in the same domain (equal sample
/// times).
#[doc(alias = "tf")]
#[derive(Debug, Clone, PartialEq)]
pub struct TransferMatrix<D: TimeDomain> {
    rows: usize,
    cols: usize,
    entries: Vec<TransferFunction<D>>,
    domain: D,
}

/// Zeros, poles and gain of one entry (as [`TransferFunction::to_zpk`]).
pub type Zpk = (Vec<Complex64>, Vec<Complex64>, f64);

impl<D: TimeDomain> TransferMatrix<D> {
    /// The matrix with the given rows of SISO transfer functions.
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for no rows or an empty row;
    /// [`LtiError::DimensionMismatch`] for rows of different lengths;
    /// [`LtiError::SampleTimeMismatch`] for entries with different sample times.
    pub fn new(rows: Vec<Vec<TransferFunction<D>>>) -> Result<Self> {
        let cols = rows.first().map_or(0, Vec::len);
        if cols == 0 {
            return Err(LtiError::InvalidArgument(
                "a transfer matrix needs at least one row and one column".into(),
            ));
        }
        let nrows = rows.len();
        let mut entries = Vec::with_capacity(nrows * cols);
        for (i, row) in rows.into_iter().enumerate() {
            if row.len() != cols {
                return Err(LtiError::DimensionMismatch {
                    what: format!("transfer matrix row {i} (0-based)"),
                    expected: (1, cols),
                    found: (1, row.len()),
                });
            }
            entries.extend(row);
        }
        let domain = entries[0].domain();
        for e in &entries {
            domain.check_compatible(&e.domain())?;
        }
        Ok(Self {
            rows: nrows,
            cols,
            entries,
            domain,
        })
    }

    /// The matrix from numerator and denominator coefficients (descending powers) per entry,
    /// python-control's `tf(num, den)` with lists of lists: `num[i][j]`, `den[i][j]`.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`] if `num` and `den` differ in shape; as
    /// [`TransferFunction::from_coefficients`] and [`TransferMatrix::new`].
    pub fn from_coefficients(
        num: &[Vec<Vec<f64>>],
        den: &[Vec<Vec<f64>>],
        domain: D,
    ) -> Result<Self> {
        let shape = |x: &[Vec<Vec<f64>>]| (x.len(), x.first().map_or(0, Vec::len));
        if shape(num) != shape(den) || num.iter().zip(den).any(|(a, b)| a.len() != b.len()) {
            return Err(LtiError::DimensionMismatch {
                what: "transfer matrix denominators (must match the numerators' shape)".into(),
                expected: shape(num),
                found: shape(den),
            });
        }
        let rows = num
            .iter()
            .zip(den)
            .map(|(nr, dr)| {
                nr.iter()
                    .zip(dr)
                    .map(|(n, d)| TransferFunction::from_coefficients(n, d, domain))
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        Self::new(rows)
    }

    /// The `1 × 1` matrix of a SISO transfer function.
    pub fn from_siso(g: TransferFunction<D>) -> Self {
        Self {
            rows: 1,
            cols: 1,
            domain: g.domain(),
            entries: vec![g],
        }
    }

    /// The static gain matrix `K` (`p × m`, `p, m ≥ 1`).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for an empty matrix; [`LtiError::NonFinite`].
    pub fn gain(k: &Mat, domain: D) -> Result<Self> {
        let rows = (0..k.nrows())
            .map(|i| {
                (0..k.ncols())
                    .map(|j| TransferFunction::gain(k[(i, j)], domain))
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        Self::new(rows)
    }

    /// The `n × n` identity (`n ≥ 1`).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for `n = 0`.
    pub fn identity(n: usize, domain: D) -> Result<Self> {
        Self::gain(&Mat::identity(n, n), domain)
    }

    /// `(outputs, inputs)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }
    /// Number of outputs `p`.
    pub fn ny(&self) -> usize {
        self.rows
    }
    /// Number of inputs `m`.
    pub fn nu(&self) -> usize {
        self.cols
    }
    /// The time domain.
    pub fn domain(&self) -> D {
        self.domain
    }
    /// Entry `(i, j)` (output `i`, input `j`, 0-based), `None` outside the matrix.
    pub fn get(&self, i: usize, j: usize) -> Option<&TransferFunction<D>> {
        (i < self.rows && j < self.cols).then(|| &self.entries[i * self.cols + j])
    }
    /// The entries row by row.
    pub fn entries(&self) -> &[TransferFunction<D>] {
        &self.entries
    }
    /// `true` if every entry is proper.
    pub fn is_proper(&self) -> bool {
        self.entries.iter().all(TransferFunction::is_proper)
    }

    /// `G(s₀)` (each entry by Horner's rule; `±∞`/NaN at a pole of an entry).
    pub fn eval(&self, s0: Complex64) -> CMat {
        CMat::from_fn(self.rows, self.cols, |i, j| {
            self.entries[i * self.cols + j].eval(s0)
        })
    }

    fn from_fn(
        rows: usize,
        cols: usize,
        domain: D,
        mut f: impl FnMut(usize, usize) -> Result<TransferFunction<D>>,
    ) -> Result<Self> {
        let mut entries = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            for j in 0..cols {
                entries.push(f(i, j)?);
            }
        }
        Ok(Self {
            rows,
            cols,
            entries,
            domain,
        })
    }

    fn check_same_shape(&self, other: &Self, what: &str) -> Result<()> {
        self.domain.check_compatible(&other.domain)?;
        if self.shape() != other.shape() {
            return Err(LtiError::DimensionMismatch {
                what: format!("{what}: the right operand (must have the left one's shape)"),
                expected: self.shape(),
                found: other.shape(),
            });
        }
        Ok(())
    }

    /// `G + H` entry by entry (MATLAB `G + H`, `parallel`).
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`] unless the shapes agree;
    /// [`LtiError::SampleTimeMismatch`].
    pub fn try_add(&self, other: &Self) -> Result<Self> {
        self.check_same_shape(other, "transfer matrix sum")?;
        Self::from_fn(self.rows, self.cols, self.domain, |i, j| {
            let k = i * self.cols + j;
            parallel_tf(&self.entries[k], &other.entries[k])
        })
    }

    /// `G − H` entry by entry.
    ///
    /// # Errors
    /// As [`TransferMatrix::try_add`].
    pub fn try_sub(&self, other: &Self) -> Result<Self> {
        self.try_add(&other.neg())
    }

    /// `−G`.
    #[allow(clippy::should_implement_trait)]
    pub fn neg(&self) -> Self {
        let entries = self
            .entries
            .iter()
            .map(|g| TransferFunction::new(-g.num(), g.den().clone(), g.domain()))
            .collect::<Result<Vec<_>>>()
            .expect("negating finite coefficients of a monic denominator cannot fail");
        Self {
            entries,
            ..self.clone()
        }
    }

    /// Every entry times the SISO `g` (`g G`, which equals `G g`).
    ///
    /// # Errors
    /// [`LtiError::SampleTimeMismatch`].
    pub fn scale(&self, g: &TransferFunction<D>) -> Result<Self> {
        self.domain.check_compatible(&g.domain())?;
        Self::from_fn(self.rows, self.cols, self.domain, |i, j| {
            series_tf(&self.entries[i * self.cols + j], g)
        })
    }

    /// The matrix product `G H` (MATLAB `G * H`: `H` first, then `G`); a `1 × 1` operand
    /// scales the other.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`] unless `nu(G) = ny(H)` (or one is `1 × 1`);
    /// [`LtiError::SampleTimeMismatch`].
    pub fn try_mul(&self, other: &Self) -> Result<Self> {
        self.domain.check_compatible(&other.domain)?;
        if other.shape() == (1, 1) {
            return self.scale(&other.entries[0]);
        }
        if self.shape() == (1, 1) {
            return other.scale(&self.entries[0]);
        }
        if self.cols != other.rows {
            return Err(LtiError::DimensionMismatch {
                what: "transfer matrix product G H: the outputs of H (must equal the inputs of G)"
                    .into(),
                expected: (self.cols, other.cols),
                found: other.shape(),
            });
        }
        Self::from_fn(self.rows, other.cols, self.domain, |i, j| {
            let mut acc = series_tf(&self.entries[i * self.cols], &other.entries[j])?;
            for k in 1..self.cols {
                let term = series_tf(
                    &self.entries[i * self.cols + k],
                    &other.entries[k * other.cols + j],
                )?;
                acc = parallel_tf(&acc, &term)?;
            }
            Ok(acc)
        })
    }

    /// `G H⁻¹` (MATLAB `G / H`, module documentation): a `1 × 1` `H` divides every entry; a
    /// square `H` is inverted by [`TransferMatrix::inverse`].
    ///
    /// # Errors
    /// As [`TransferMatrix::inverse`] and [`TransferMatrix::try_mul`].
    pub fn try_div(&self, other: &Self) -> Result<Self> {
        self.try_mul(&other.inverse()?)
    }

    /// `H⁻¹` of a square matrix (module documentation): `1/h` polynomially for `1 × 1`, the
    /// state-space inverse of the minimal realisation otherwise.
    ///
    /// # Errors
    /// [`LtiError::NotSquare`]; [`LtiError::Singular`] for a zero `1 × 1` entry or a singular
    /// feedthrough `H(∞)` (the inverse would be improper); [`LtiError::Improper`] for an
    /// improper entry of a larger matrix.
    pub fn inverse(&self) -> Result<Self> {
        if self.rows != self.cols {
            return Err(LtiError::NotSquare {
                what: "transfer matrix to invert".into(),
                rows: self.rows,
                cols: self.cols,
            });
        }
        if self.rows == 1 {
            let h = &self.entries[0];
            if h.num().is_zero() {
                return Err(LtiError::Singular {
                    what: "transfer function to invert (identically zero)".into(),
                    rcond: 0.0,
                });
            }
            return Ok(Self::from_siso(TransferFunction::new(
                h.den().clone(),
                h.num().clone(),
                self.domain,
            )?));
        }
        let sys = self.to_state_space()?;
        let n = self.rows;
        let d = sys.d();
        let rcond = 1.0 / crate::analysis::cond2(d);
        let singular = || LtiError::Singular {
            what: "feedthrough H(∞) of the transfer matrix to invert (the inverse is improper)"
                .into(),
            rcond,
        };
        if rcond.is_nan() || rcond <= n as f64 * f64::EPSILON {
            return Err(singular());
        }
        let dinv = d
            .clone()
            .lu()
            .solve(&Mat::identity(n, n))
            .ok_or_else(singular)?;
        let inv = StateSpace::new(
            sys.a() - sys.b() * &dinv * sys.c(),
            sys.b() * &dinv,
            -(&dinv * sys.c()),
            dinv,
            self.domain,
        )?;
        Self::from_state_space(&inv)
    }

    /// The closed loop `(I − σ G K)⁻¹ G` of `y = G e`, `e = r + σ K y` (MATLAB
    /// `feedback(G, K, sign)`, `σ = −1` for [`FeedbackSign::Negative`]); module documentation.
    ///
    /// # Errors
    /// [`LtiError::DimensionMismatch`] unless `K` is `nu(G) × ny(G)`;
    /// [`LtiError::SampleTimeMismatch`]; [`LtiError::Singular`] for an ill-posed loop;
    /// [`LtiError::Improper`] for an improper entry of a MIMO loop.
    pub fn feedback(&self, k: &Self, sign: FeedbackSign) -> Result<Self> {
        self.domain.check_compatible(&k.domain)?;
        if k.shape() != (self.cols, self.rows) {
            return Err(LtiError::DimensionMismatch {
                what: "feedback: K outputs x inputs (must be G's inputs x outputs)".into(),
                expected: (self.cols, self.rows),
                found: k.shape(),
            });
        }
        if self.shape() == (1, 1) {
            return Ok(Self::from_siso(feedback_tf(
                &self.entries[0],
                &k.entries[0],
                sign,
            )?));
        }
        let closed = feedback(&self.to_state_space()?, &k.to_state_space()?, sign)?;
        Self::from_state_space(&closed)
    }

    /// Every entry with its common pole-zero pairs cancelled (each entry through
    /// [`minreal`] of its realisation; improper entries are kept as they are).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`] from the zero and pole computations.
    pub fn minreal(&self) -> Result<Self> {
        Self::from_fn(self.rows, self.cols, self.domain, |i, j| {
            let g = &self.entries[i * self.cols + j];
            if !g.is_proper() {
                return Ok(g.clone());
            }
            TransferFunction::from_state_space(&minreal(&g.to_state_space()?, None)?.system)
        })
    }

    /// The transfer matrix of a state-space system, each entry from the minimal realisation
    /// of its channel (module documentation; MATLAB `tf(sys)`).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] for a system without inputs or outputs;
    /// [`LtiError::NoConvergence`].
    #[doc(alias = "ss2tf")]
    pub fn from_state_space(sys: &StateSpace<D>) -> Result<Self> {
        if sys.ny() == 0 || sys.nu() == 0 {
            return Err(LtiError::InvalidArgument(format!(
                "transfer matrix of a system with {} outputs and {} inputs",
                sys.ny(),
                sys.nu()
            )));
        }
        Self::from_fn(sys.ny(), sys.nu(), sys.domain(), |i, j| {
            let channel = StateSpace::new(
                sys.a().clone(),
                sys.b().columns(j, 1).clone_owned(),
                sys.c().rows(i, 1).clone_owned(),
                Mat::from_element(1, 1, sys.d()[(i, j)]),
                sys.domain(),
            )?;
            TransferFunction::from_state_space(&minreal(&channel, None)?.system)
        })
    }

    /// A minimal state-space realisation (module documentation; MATLAB `ss(G)` followed by
    /// `minreal`); its order is the McMillan degree.
    ///
    /// # Errors
    /// [`LtiError::Improper`] if an entry is improper.
    #[doc(alias = "tf2ss")]
    pub fn to_state_space(&self) -> Result<StateSpace<D>> {
        let parts = self
            .entries
            .iter()
            .map(TransferFunction::to_state_space)
            .collect::<Result<Vec<_>>>()?;
        let n: usize = parts.iter().map(StateSpace::nx).sum();
        let (mut a, mut b) = (Mat::zeros(n, n), Mat::zeros(n, self.cols));
        let (mut c, mut d) = (Mat::zeros(self.rows, n), Mat::zeros(self.rows, self.cols));
        let mut at = 0;
        for (k, p) in parts.iter().enumerate() {
            let (i, j, nk) = (k / self.cols, k % self.cols, p.nx());
            a.view_mut((at, at), (nk, nk)).copy_from(p.a());
            b.view_mut((at, j), (nk, 1)).copy_from(p.b());
            c.view_mut((i, at), (1, nk)).copy_from(p.c());
            d[(i, j)] = p.d()[(0, 0)];
            at += nk;
        }
        let stacked = StateSpace::new(a, b, c, d, self.domain)?;
        Ok(minreal(&stacked, None)?.system)
    }

    /// Zeros, poles and gain of every entry, row by row (MATLAB `zpkdata`).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    #[doc(alias = "zpk")]
    pub fn to_zpk(&self) -> Result<Vec<Vec<Zpk>>> {
        self.entries
            .chunks(self.cols)
            .map(|row| row.iter().map(TransferFunction::to_zpk).collect())
            .collect()
    }

    /// The matrix with entry `(i, j)` equal to `k_ij Π(s − z)/Π(s − p)` from
    /// `zpk[i][j] = (zeros, poles, k)` (MATLAB `zpk` with cell arrays).
    ///
    /// # Errors
    /// As [`TransferFunction::from_zpk`] and [`TransferMatrix::new`].
    pub fn from_zpk(zpk: &[Vec<Zpk>], domain: D) -> Result<Self> {
        Self::new(
            zpk.iter()
                .map(|row| {
                    row.iter()
                        .map(|(z, p, k)| TransferFunction::from_zpk(z, p, *k, domain))
                        .collect::<Result<Vec<_>>>()
                })
                .collect::<Result<Vec<_>>>()?,
        )
    }
}

impl<D: TimeDomain> From<TransferFunction<D>> for TransferMatrix<D> {
    fn from(g: TransferFunction<D>) -> Self {
        Self::from_siso(g)
    }
}

impl<D: TimeDomain> TryFrom<&StateSpace<D>> for TransferMatrix<D> {
    type Error = LtiError;
    fn try_from(sys: &StateSpace<D>) -> Result<Self> {
        Self::from_state_space(sys)
    }
}

impl<D: TimeDomain> TryFrom<&TransferMatrix<D>> for StateSpace<D> {
    type Error = LtiError;
    fn try_from(g: &TransferMatrix<D>) -> Result<Self> {
        g.to_state_space()
    }
}

/// The operators on all four value/reference combinations, each returning the fallible
/// method's [`Result`].
macro_rules! fallible_operator {
    ($trait:ident, $op:ident, $method:ident) => {
        impl<D: TimeDomain> std::ops::$trait<&TransferMatrix<D>> for &TransferMatrix<D> {
            type Output = Result<TransferMatrix<D>>;
            fn $op(self, rhs: &TransferMatrix<D>) -> Self::Output {
                self.$method(rhs)
            }
        }
        impl<D: TimeDomain> std::ops::$trait<TransferMatrix<D>> for TransferMatrix<D> {
            type Output = Result<TransferMatrix<D>>;
            fn $op(self, rhs: TransferMatrix<D>) -> Self::Output {
                self.$method(&rhs)
            }
        }
        impl<D: TimeDomain> std::ops::$trait<&TransferMatrix<D>> for TransferMatrix<D> {
            type Output = Result<TransferMatrix<D>>;
            fn $op(self, rhs: &TransferMatrix<D>) -> Self::Output {
                self.$method(rhs)
            }
        }
        impl<D: TimeDomain> std::ops::$trait<TransferMatrix<D>> for &TransferMatrix<D> {
            type Output = Result<TransferMatrix<D>>;
            fn $op(self, rhs: TransferMatrix<D>) -> Self::Output {
                self.$method(&rhs)
            }
        }
    };
}

fallible_operator!(Add, add, try_add);
fallible_operator!(Sub, sub, try_sub);
fallible_operator!(Mul, mul, try_mul);
fallible_operator!(Div, div, try_div);

impl<D: TimeDomain> std::ops::Neg for &TransferMatrix<D> {
    type Output = TransferMatrix<D>;
    fn neg(self) -> TransferMatrix<D> {
        TransferMatrix::neg(self)
    }
}

impl<D: TimeDomain> std::ops::Neg for TransferMatrix<D> {
    type Output = TransferMatrix<D>;
    fn neg(self) -> TransferMatrix<D> {
        TransferMatrix::neg(&self)
    }
}

impl<D: TimeDomain> std::fmt::Display for TransferMatrix<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (k, g) in self.entries.iter().enumerate() {
            let (i, j) = (k / self.cols, k % self.cols);
            writeln!(f, "G[{i}][{j}] = {g}")?;
        }
        Ok(())
    }
}

/// `feedback(G, K, sign)` as a free function (MATLAB spelling); see
/// [`TransferMatrix::feedback`].
///
/// # Errors
/// As [`TransferMatrix::feedback`].
pub fn feedback_tm<D: TimeDomain>(
    g: &TransferMatrix<D>,
    k: &TransferMatrix<D>,
    sign: FeedbackSign,
) -> Result<TransferMatrix<D>> {
    g.feedback(k, sign)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Continuous;

    #[test]
    fn shape_mismatch_is_an_error_not_a_panic() {
        let g = TransferMatrix::identity(2, Continuous).unwrap();
        let h = TransferMatrix::identity(3, Continuous).unwrap();
        assert!(matches!(&g + &h, Err(LtiError::DimensionMismatch { .. })));
        assert!(matches!(&g * &h, Err(LtiError::DimensionMismatch { .. })));
        let row =
            TransferMatrix::gain(&Mat::from_row_slice(1, 2, &[1.0, 2.0]), Continuous).unwrap();
        assert!(matches!(row.inverse(), Err(LtiError::NotSquare { .. })));
        assert!(TransferMatrix::<Continuous>::new(vec![]).is_err());
        let one = TransferFunction::gain(1.0, Continuous).unwrap();
        assert!(matches!(
            TransferMatrix::new(vec![vec![one.clone(), one.clone()], vec![one]]),
            Err(LtiError::DimensionMismatch { .. })
        ));
    }
}
