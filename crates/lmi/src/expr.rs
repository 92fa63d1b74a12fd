//! Matrix expressions: polynomial in scalar parameters, affine in the decision variables.
//!
//! An [`Expr`] is an `r × c` matrix
//!
//! ```text
//! E(ρ; x) = Σ_m  ρ^m · ( C_m + Σ_v x_v C_{m,v} )
//! ```
//!
//! where `ρ^m` runs over monomials in the problem's parameters (ρ, ρ̇, ...; see
//! [`crate::Problem::parameter`]), `x_v` over the scalar decision variables and the `C` are
//! constant matrices. A plain LMI expression is the special case with only the monomial `1`.
//! Expressions are built with ordinary operators (`+`, `-`, `*` with other expressions, with
//! [`Mat`] constants and with `f64` scalars) and the methods below (transpose, `He`, blocks,
//! Kronecker products, trace, sub-blocks, parameter substitution).
//!
//! **Errors are deferred.** Operators cannot return `Result`, so an invalid operation (shape
//! mismatch, product of two decision-dependent expressions, mixing two problems, non-finite
//! constant) yields an expression that carries the error; every later operation propagates
//! it, and it surfaces as an [`LmiError`] when the expression reaches a constraint, the
//! objective or an evaluation ([`Expr::check`] reports it on demand). Nothing panics.
//!
//! A `1 × 1` expression multiplies like a scalar (`g(ρ) · S(ρ)` for an S-procedure term).
//!
//! This file holds [`Monomial`], [`Expr`] with its constructors, accessors and the
//! bookkeeping of sums and products; beside it in `expr/`: `affine.rs` (the affine matrices
//! each term is made of), `blocks.rs` (transpose, `He`, blocks, Kronecker products, trace),
//! `params.rs` (parameters, substitution, evaluation) and `ops.rs` (conversions and
//! operators).

use crate::error::{LmiError, Result};
use pendulab_lti::Mat;
use std::collections::BTreeMap;
use std::sync::Arc;

mod affine;
mod blocks;
mod ops;
mod params;

pub(crate) use affine::{Affine, Lin};

/// Index of a scalar decision variable inside its problem.
pub(crate) type VarId = u32;

/// A monomial `ρ₀^e₀ ρ₁^e₁ …` in the parameters, stored as its exponent vector (indexed by
/// parameter id, trailing zeros trimmed so that equal monomials compare equal).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Monomial(Vec<u32>);

impl Monomial {
    /// The monomial `1`.
    pub fn one() -> Self {
        Self(Vec::new())
    }

    /// `ρ_p^e`.
    pub(crate) fn power(p: usize, e: u32) -> Self {
        let mut v = vec![0; p + 1];
        v[p] = e;
        let mut m = Self(v);
        m.trim();
        m
    }

    pub(crate) fn from_exponents(mut e: Vec<u32>) -> Self {
        while e.last() == Some(&0) {
            e.pop();
        }
        Self(e)
    }

    fn trim(&mut self) {
        while self.0.last() == Some(&0) {
            self.0.pop();
        }
    }

    /// Exponent of parameter `p`.
    pub fn exponent(&self, p: usize) -> u32 {
        self.0.get(p).copied().unwrap_or(0)
    }

    /// Exponents, indexed by parameter id (trailing zeros omitted).
    pub fn exponents(&self) -> &[u32] {
        &self.0
    }

    /// Total degree.
    pub fn degree(&self) -> u32 {
        self.0.iter().sum()
    }

    /// Whether this is the monomial `1`.
    pub fn is_one(&self) -> bool {
        self.0.is_empty()
    }

    /// Product of two monomials.
    pub fn times(&self, other: &Monomial) -> Monomial {
        let n = self.0.len().max(other.0.len());
        let e = (0..n)
            .map(|p| self.exponent(p) + other.exponent(p))
            .collect();
        Monomial::from_exponents(e)
    }

    /// Value at the parameter values `rho` (indexed by parameter id; missing ones count as 0).
    pub fn eval(&self, rho: &[f64]) -> f64 {
        self.0
            .iter()
            .enumerate()
            .filter(|(_, e)| **e > 0)
            .map(|(p, e)| rho.get(p).copied().unwrap_or(0.0).powi(*e as i32))
            .product()
    }
}

/// A matrix expression, polynomial in the parameters and affine in the decision variables.
/// See the [module documentation](self).
#[derive(Clone, Debug)]
pub struct Expr {
    rows: usize,
    cols: usize,
    /// Id of the problem whose variables/parameters appear (None: a pure constant).
    owner: Option<u64>,
    /// Nonzero terms, sorted by monomial, each an `rows × cols` affine matrix.
    terms: Vec<(Monomial, Affine)>,
    error: Option<Arc<LmiError>>,
}

impl Expr {
    pub(crate) fn from_terms(
        rows: usize,
        cols: usize,
        owner: Option<u64>,
        map: BTreeMap<Monomial, Affine>,
    ) -> Expr {
        let terms = map.into_iter().filter(|(_, a)| !a.is_zero()).collect();
        Expr {
            rows,
            cols,
            owner,
            terms,
            error: None,
        }
    }

    pub(crate) fn failed(err: LmiError) -> Expr {
        Expr {
            rows: 0,
            cols: 0,
            owner: None,
            terms: Vec::new(),
            error: Some(Arc::new(err)),
        }
    }

    /// A constant matrix. A non-finite entry gives an expression carrying
    /// [`LmiError::NonFinite`].
    pub fn constant(m: &Mat) -> Expr {
        for j in 0..m.ncols() {
            for i in 0..m.nrows() {
                if !m[(i, j)].is_finite() {
                    return Expr::failed(LmiError::NonFinite {
                        what: "constant matrix".into(),
                        row: i,
                        col: j,
                        value: m[(i, j)],
                    });
                }
            }
        }
        let mut map = BTreeMap::new();
        map.insert(
            Monomial::one(),
            Affine {
                constant: m.clone(),
                lin: Vec::new(),
            },
        );
        Expr::from_terms(m.nrows(), m.ncols(), None, map)
    }

    /// The `r × c` zero matrix.
    pub fn zeros(r: usize, c: usize) -> Expr {
        Expr::from_terms(r, c, None, BTreeMap::new())
    }

    /// The `n × n` identity.
    pub fn identity(n: usize) -> Expr {
        Expr::constant(&Mat::identity(n, n))
    }

    /// The `1 × 1` constant `v`.
    pub fn scalar(v: f64) -> Expr {
        Expr::constant(&Mat::from_element(1, 1, v))
    }

    /// `(rows, columns)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.cols
    }

    /// The deferred error of this expression, if an operation that built it was invalid.
    ///
    /// # Errors
    /// The first [`LmiError`] met while building the expression.
    pub fn check(&self) -> Result<()> {
        match &self.error {
            Some(e) => Err((**e).clone()),
            None => Ok(()),
        }
    }

    /// Whether any decision variable appears.
    pub fn has_variables(&self) -> bool {
        self.terms.iter().any(|(_, a)| !a.lin.is_empty())
    }

    /// Whether any parameter appears (a monomial other than `1` has a nonzero coefficient).
    pub fn is_parametric(&self) -> bool {
        self.terms.iter().any(|(m, _)| !m.is_one())
    }

    pub(crate) fn owner(&self) -> Option<u64> {
        self.owner
    }

    pub(crate) fn terms(&self) -> &[(Monomial, Affine)] {
        &self.terms
    }

    /// The coefficient of the monomial `1` (the whole expression when not parametric).
    pub(crate) fn constant_term(&self) -> Affine {
        self.terms
            .iter()
            .find(|(m, _)| m.is_one())
            .map(|(_, a)| a.clone())
            .unwrap_or_else(|| Affine::zeros(self.rows, self.cols))
    }

    pub(crate) fn max_var(&self) -> Option<VarId> {
        self.terms.iter().filter_map(|(_, a)| a.max_var()).max()
    }

    /// Deferred-error and owner bookkeeping for a binary operation.
    fn join(a: &Expr, b: &Expr, op: &str) -> std::result::Result<Option<u64>, Expr> {
        if let Some(e) = a.error.as_ref().or(b.error.as_ref()) {
            return Err(Expr {
                error: Some(e.clone()),
                ..Expr::zeros(0, 0)
            });
        }
        match (a.owner, b.owner) {
            (Some(x), Some(y)) if x != y => Err(Expr::failed(LmiError::ForeignExpression {
                op: op.to_string(),
            })),
            (x, y) => Ok(x.or(y)),
        }
    }

    fn add_impl(a: &Expr, b: &Expr, sign: f64, op: &str) -> Expr {
        let owner = match Expr::join(a, b, op) {
            Ok(o) => o,
            Err(e) => return e,
        };
        if a.shape() != b.shape() {
            return Expr::failed(LmiError::ShapeMismatch {
                op: op.to_string(),
                left: a.shape(),
                right: b.shape(),
            });
        }
        let mut map: BTreeMap<Monomial, Affine> = a.terms.iter().cloned().collect();
        for (m, t) in &b.terms {
            match map.get_mut(m) {
                Some(s) => *s = s.add(t, sign),
                None => {
                    map.insert(m.clone(), t.scale(sign));
                }
            }
        }
        Expr::from_terms(a.rows, a.cols, owner, map)
    }

    fn mul_impl(a: &Expr, b: &Expr) -> Expr {
        let owner = match Expr::join(a, b, "*") {
            Ok(o) => o,
            Err(e) => return e,
        };
        let a_scalar = a.shape() == (1, 1);
        let b_scalar = b.shape() == (1, 1) && !a_scalar;
        let (rows, cols) = if a_scalar {
            b.shape()
        } else if b_scalar {
            a.shape()
        } else if a.cols == b.rows {
            (a.rows, b.cols)
        } else {
            return Expr::failed(LmiError::ShapeMismatch {
                op: "*".into(),
                left: a.shape(),
                right: b.shape(),
            });
        };
        let mut map: BTreeMap<Monomial, Affine> = BTreeMap::new();
        for (ma, ta) in &a.terms {
            for (mb, tb) in &b.terms {
                let prod = if a_scalar {
                    if ta.lin.is_empty() {
                        tb.scale(ta.constant[(0, 0)])
                    } else if tb.lin.is_empty() {
                        Affine::kron_const(&tb.constant, ta, true)
                    } else {
                        return Expr::failed(LmiError::NotAffine { op: "*".into() });
                    }
                } else if b_scalar {
                    if tb.lin.is_empty() {
                        ta.scale(tb.constant[(0, 0)])
                    } else if ta.lin.is_empty() {
                        Affine::kron_const(&ta.constant, tb, true)
                    } else {
                        return Expr::failed(LmiError::NotAffine { op: "*".into() });
                    }
                } else if ta.lin.is_empty() {
                    Affine::left_mul(&ta.constant, tb)
                } else if tb.lin.is_empty() {
                    Affine::right_mul(ta, &tb.constant)
                } else {
                    return Expr::failed(LmiError::NotAffine { op: "*".into() });
                };
                let m = ma.times(mb);
                match map.get_mut(&m) {
                    Some(s) => *s = s.add(&prod, 1.0),
                    None => {
                        map.insert(m, prod);
                    }
                }
            }
        }
        Expr::from_terms(rows, cols, owner, map)
    }

    pub(crate) fn with_owner(mut self, owner: u64) -> Expr {
        self.owner = Some(owner);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var_expr(rows: usize, cols: usize, first: u32) -> Expr {
        let mut a = Affine::zeros(rows, cols);
        let mut v = first;
        for j in 0..cols {
            for i in 0..rows {
                a.lin.push(Lin {
                    row: i as u32,
                    col: j as u32,
                    var: v,
                    coef: 1.0,
                });
                v += 1;
            }
        }
        a.canonicalize();
        let mut map = BTreeMap::new();
        map.insert(Monomial::one(), a);
        Expr::from_terms(rows, cols, Some(1), map)
    }

    #[test]
    fn products_evaluate_like_matrices() {
        let x = var_expr(2, 2, 0);
        let a = Mat::from_row_slice(3, 2, &[1.0, 2.0, 0.0, -1.0, 3.0, 0.5]);
        let b = Mat::from_row_slice(2, 2, &[0.0, 1.0, 4.0, -2.0]);
        let e = &a * &x * &b + (&a * &x * &b).scale(0.5);
        let xv = [0.3, -1.2, 2.0, 0.7];
        let xm = Mat::from_column_slice(2, 2, &xv);
        let expect = (&a * &xm * &b) * 1.5;
        assert!((e.eval(&xv, &[]) - expect).norm() < 1e-14);
        let k = Expr::kron(&Expr::constant(&b), &x);
        let kv = b.kronecker(&xm);
        assert!((k.eval(&xv, &[]) - kv).norm() < 1e-14);
        let k2 = Expr::kron(&x, &Expr::constant(&b));
        assert!((k2.eval(&xv, &[]) - xm.kronecker(&b)).norm() < 1e-14);
        assert!((x.he().eval(&xv, &[]) - (&xm + xm.transpose())).norm() < 1e-14);
        assert!((x.trace().eval(&xv, &[])[(0, 0)] - xm.trace()).abs() < 1e-14);
    }

    #[test]
    fn invalid_operations_are_deferred() {
        let x = var_expr(2, 2, 0);
        let bad = &x * &x;
        assert!(matches!(bad.check(), Err(LmiError::NotAffine { .. })));
        let mis = &x + &Expr::zeros(3, 3);
        assert!(matches!(mis.check(), Err(LmiError::ShapeMismatch { .. })));
        // The error propagates through later operations.
        assert!((mis.t() * 2.0).check().is_err());
    }
}
