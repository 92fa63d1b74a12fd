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

use crate::error::{LmiError, Result};
use pendulab_lti::Mat;
use std::collections::BTreeMap;
use std::ops::{Add, Mul, Neg, Sub};
use std::sync::Arc;

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

/// One entry of the linear part of an affine matrix: `(row, col) += coef · x[var]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lin {
    pub(crate) row: u32,
    pub(crate) col: u32,
    pub(crate) var: VarId,
    pub(crate) coef: f64,
}

/// An affine matrix `C + Σ_v x_v C_v`: the constant part dense, the linear part as a list of
/// [`Lin`] entries kept canonical (sorted by column, row, variable; no duplicates; no zeros).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Affine {
    pub(crate) constant: Mat,
    pub(crate) lin: Vec<Lin>,
}

impl Affine {
    pub(crate) fn zeros(r: usize, c: usize) -> Self {
        Self {
            constant: Mat::zeros(r, c),
            lin: Vec::new(),
        }
    }

    pub(crate) fn nrows(&self) -> usize {
        self.constant.nrows()
    }

    pub(crate) fn ncols(&self) -> usize {
        self.constant.ncols()
    }

    /// Sorts by (column, row, variable), merges duplicates and drops exact zeros.
    pub(crate) fn canonicalize(&mut self) {
        self.lin.sort_unstable_by_key(|l| (l.col, l.row, l.var));
        let mut out: Vec<Lin> = Vec::with_capacity(self.lin.len());
        for l in self.lin.drain(..) {
            match out.last_mut() {
                Some(p) if p.col == l.col && p.row == l.row && p.var == l.var => p.coef += l.coef,
                _ => out.push(l),
            }
        }
        out.retain(|l| l.coef != 0.0);
        self.lin = out;
    }

    pub(crate) fn is_zero(&self) -> bool {
        self.lin.is_empty() && self.constant.iter().all(|v| *v == 0.0)
    }

    fn add(&self, other: &Affine, sign: f64) -> Affine {
        let mut lin = Vec::with_capacity(self.lin.len() + other.lin.len());
        lin.extend_from_slice(&self.lin);
        lin.extend(other.lin.iter().map(|l| Lin {
            coef: sign * l.coef,
            ..*l
        }));
        let mut a = Affine {
            constant: &self.constant + &other.constant * sign,
            lin,
        };
        a.canonicalize();
        a
    }

    fn scale(&self, s: f64) -> Affine {
        let mut a = Affine {
            constant: &self.constant * s,
            lin: self
                .lin
                .iter()
                .map(|l| Lin {
                    coef: l.coef * s,
                    ..*l
                })
                .collect(),
        };
        if s == 0.0 {
            a.lin.clear();
        }
        a
    }

    fn transpose(&self) -> Affine {
        let mut a = Affine {
            constant: self.constant.transpose(),
            lin: self
                .lin
                .iter()
                .map(|l| Lin {
                    row: l.col,
                    col: l.row,
                    ..*l
                })
                .collect(),
        };
        a.canonicalize();
        a
    }

    /// `c · a` for a constant `c`.
    fn left_mul(c: &Mat, a: &Affine) -> Affine {
        // Nonzeros of each column k of c: (i, c_ik).
        let cols: Vec<Vec<(u32, f64)>> = (0..c.ncols())
            .map(|k| {
                (0..c.nrows())
                    .filter(|&i| c[(i, k)] != 0.0)
                    .map(|i| (i as u32, c[(i, k)]))
                    .collect()
            })
            .collect();
        let mut lin = Vec::new();
        for l in &a.lin {
            for &(i, cik) in &cols[l.row as usize] {
                lin.push(Lin {
                    row: i,
                    col: l.col,
                    var: l.var,
                    coef: cik * l.coef,
                });
            }
        }
        let mut out = Affine {
            constant: c * &a.constant,
            lin,
        };
        out.canonicalize();
        out
    }

    /// `a · c` for a constant `c`.
    fn right_mul(a: &Affine, c: &Mat) -> Affine {
        let rows: Vec<Vec<(u32, f64)>> = (0..c.nrows())
            .map(|k| {
                (0..c.ncols())
                    .filter(|&j| c[(k, j)] != 0.0)
                    .map(|j| (j as u32, c[(k, j)]))
                    .collect()
            })
            .collect();
        let mut lin = Vec::new();
        for l in &a.lin {
            for &(j, ckj) in &rows[l.col as usize] {
                lin.push(Lin {
                    row: l.row,
                    col: j,
                    var: l.var,
                    coef: l.coef * ckj,
                });
            }
        }
        let mut out = Affine {
            constant: &a.constant * c,
            lin,
        };
        out.canonicalize();
        out
    }

    /// `c ⊗ a` (`left = true`) or `a ⊗ c` for a constant `c`.
    fn kron_const(c: &Mat, a: &Affine, left: bool) -> Affine {
        let (ar, ac) = (a.nrows(), a.ncols());
        let (cr, cc) = (c.nrows(), c.ncols());
        let mut lin = Vec::new();
        for q in 0..cc {
            for p in 0..cr {
                let cpq = c[(p, q)];
                if cpq == 0.0 {
                    continue;
                }
                for l in &a.lin {
                    let (row, col) = if left {
                        (p * ar + l.row as usize, q * ac + l.col as usize)
                    } else {
                        (l.row as usize * cr + p, l.col as usize * cc + q)
                    };
                    lin.push(Lin {
                        row: row as u32,
                        col: col as u32,
                        var: l.var,
                        coef: cpq * l.coef,
                    });
                }
            }
        }
        let constant = if left {
            c.kronecker(&a.constant)
        } else {
            a.constant.kronecker(c)
        };
        let mut out = Affine { constant, lin };
        out.canonicalize();
        out
    }

    /// Copies `self` into `into` at offset `(r0, c0)` (entries not yet canonical in `into`).
    fn place(&self, r0: usize, c0: usize, into: &mut Affine) {
        into.constant
            .view_mut((r0, c0), (self.nrows(), self.ncols()))
            .copy_from(&self.constant);
        into.lin.extend(self.lin.iter().map(|l| Lin {
            row: l.row + r0 as u32,
            col: l.col + c0 as u32,
            ..*l
        }));
    }

    /// The `nr × nc` sub-block at `(r0, c0)`.
    fn sub_block(&self, r0: usize, c0: usize, nr: usize, nc: usize) -> Affine {
        let lin = self
            .lin
            .iter()
            .filter(|l| {
                let (r, c) = (l.row as usize, l.col as usize);
                r >= r0 && r < r0 + nr && c >= c0 && c < c0 + nc
            })
            .map(|l| Lin {
                row: l.row - r0 as u32,
                col: l.col - c0 as u32,
                ..*l
            })
            .collect();
        Affine {
            constant: self.constant.view((r0, c0), (nr, nc)).into_owned(),
            lin,
        }
    }

    /// Value at the decision vector `x`.
    pub(crate) fn eval(&self, x: &[f64]) -> Mat {
        let mut m = self.constant.clone();
        for l in &self.lin {
            m[(l.row as usize, l.col as usize)] += l.coef * x[l.var as usize];
        }
        m
    }

    /// The linear entries at `(i, j)` (a contiguous run thanks to the canonical order).
    pub(crate) fn entry_lin(&self, i: usize, j: usize) -> &[Lin] {
        let key = (j as u32, i as u32);
        let start = self.lin.partition_point(|l| (l.col, l.row) < key);
        let end = self.lin[start..].partition_point(|l| (l.col, l.row) <= key) + start;
        &self.lin[start..end]
    }

    /// Whether entry `(i, j)` is structurally nonzero (nonzero constant or any variable).
    pub(crate) fn entry_is_structural(&self, i: usize, j: usize) -> bool {
        self.constant[(i, j)] != 0.0 || !self.entry_lin(i, j).is_empty()
    }

    /// Largest variable index used, if any.
    fn max_var(&self) -> Option<VarId> {
        self.lin.iter().map(|l| l.var).max()
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

    /// Applies `f` to every term (same shape, same owner).
    fn map_terms(&self, rows: usize, cols: usize, f: impl Fn(&Affine) -> Affine) -> Expr {
        if self.error.is_some() {
            return self.clone();
        }
        let map = self.terms.iter().map(|(m, a)| (m.clone(), f(a))).collect();
        Expr::from_terms(rows, cols, self.owner, map)
    }

    /// Transpose `Eᵀ`.
    pub fn t(&self) -> Expr {
        self.map_terms(self.cols, self.rows, Affine::transpose)
    }

    /// `He(E) = E + Eᵀ` (the symmetric part times two), for square `E`.
    pub fn he(&self) -> Expr {
        Expr::add_impl(self, &self.t(), 1.0, "He")
    }

    /// `s · E`.
    pub fn scale(&self, s: f64) -> Expr {
        if !s.is_finite() {
            return Expr::failed(LmiError::NonFinite {
                what: "scalar factor".into(),
                row: 0,
                col: 0,
                value: s,
            });
        }
        self.map_terms(self.rows, self.cols, |a| a.scale(s))
    }

    /// Trace `tr E` as a `1 × 1` expression, for square `E`.
    pub fn trace(&self) -> Expr {
        if self.error.is_none() && self.rows != self.cols {
            return Expr::failed(LmiError::NotSquare {
                what: "argument of trace".into(),
                rows: self.rows,
                cols: self.cols,
            });
        }
        self.map_terms(1, 1, |a| {
            let mut out = Affine {
                constant: Mat::from_element(1, 1, a.constant.trace()),
                lin: a
                    .lin
                    .iter()
                    .filter(|l| l.row == l.col)
                    .map(|l| Lin {
                        row: 0,
                        col: 0,
                        ..*l
                    })
                    .collect(),
            };
            out.canonicalize();
            out
        })
    }

    /// The `nr × nc` sub-block starting at `(r0, c0)`.
    pub fn sub_block(&self, r0: usize, c0: usize, nr: usize, nc: usize) -> Expr {
        if self.error.is_none() && (r0 + nr > self.rows || c0 + nc > self.cols) {
            return Expr::failed(LmiError::ShapeMismatch {
                op: format!("sub_block at ({r0}, {c0}) of size {nr}x{nc}"),
                left: self.shape(),
                right: (nr, nc),
            });
        }
        self.map_terms(nr, nc, |a| a.sub_block(r0, c0, nr, nc))
    }

    /// Block matrix `[[E₁₁, E₁₂, …], [E₂₁, …], …]`: the blocks of a block row share their
    /// number of rows, those of a block column their number of columns.
    pub fn block(rows: &[&[&Expr]]) -> Expr {
        let mut owner: Option<u64> = None;
        for (bi, r) in rows.iter().enumerate() {
            for e in r.iter() {
                if let Some(err) = &e.error {
                    return Expr {
                        error: Some(err.clone()),
                        ..Expr::zeros(0, 0)
                    };
                }
                match (owner, e.owner) {
                    (Some(x), Some(y)) if x != y => {
                        return Expr::failed(LmiError::ForeignExpression {
                            op: format!("block row {bi}"),
                        });
                    }
                    (None, y) => owner = y,
                    _ => {}
                }
            }
        }
        let ncols_blocks = rows.first().map_or(0, |r| r.len());
        let mut heights = Vec::with_capacity(rows.len());
        for (bi, r) in rows.iter().enumerate() {
            if r.len() != ncols_blocks {
                return Expr::failed(LmiError::ShapeMismatch {
                    op: format!(
                        "block row {bi} has {} blocks, row 0 has {ncols_blocks}",
                        r.len()
                    ),
                    left: (rows.len(), ncols_blocks),
                    right: (1, r.len()),
                });
            }
            let h = r.first().map_or(0, |e| e.rows);
            for (bj, e) in r.iter().enumerate() {
                if e.rows != h {
                    return Expr::failed(LmiError::ShapeMismatch {
                        op: format!("block ({bi}, {bj}): heights in a block row differ"),
                        left: r[0].shape(),
                        right: e.shape(),
                    });
                }
            }
            heights.push(h);
        }
        let mut widths = Vec::with_capacity(ncols_blocks);
        for bj in 0..ncols_blocks {
            let w = rows[0][bj].cols;
            for (bi, r) in rows.iter().enumerate() {
                if r[bj].cols != w {
                    return Expr::failed(LmiError::ShapeMismatch {
                        op: format!("block ({bi}, {bj}): widths in a block column differ"),
                        left: rows[0][bj].shape(),
                        right: r[bj].shape(),
                    });
                }
            }
            widths.push(w);
        }
        let total_r: usize = heights.iter().sum();
        let total_c: usize = widths.iter().sum();
        let mut map: BTreeMap<Monomial, Affine> = BTreeMap::new();
        let mut r0 = 0;
        for (bi, r) in rows.iter().enumerate() {
            let mut c0 = 0;
            for (bj, e) in r.iter().enumerate() {
                for (m, a) in &e.terms {
                    let target = map
                        .entry(m.clone())
                        .or_insert_with(|| Affine::zeros(total_r, total_c));
                    a.place(r0, c0, target);
                }
                c0 += widths[bj];
            }
            r0 += heights[bi];
        }
        for a in map.values_mut() {
            a.canonicalize();
        }
        Expr::from_terms(total_r, total_c, owner, map)
    }

    /// Horizontal concatenation `[E₁, E₂, …]`.
    pub fn hstack(items: &[&Expr]) -> Expr {
        Expr::block(&[items])
    }

    /// Vertical concatenation `[E₁; E₂; …]`.
    pub fn vstack(items: &[&Expr]) -> Expr {
        let rows: Vec<[&Expr; 1]> = items.iter().map(|e| [*e]).collect();
        let refs: Vec<&[&Expr]> = rows.iter().map(|r| r.as_slice()).collect();
        Expr::block(&refs)
    }

    /// Kronecker product `A ⊗ B`; one of the two must be free of decision variables.
    pub fn kron(a: &Expr, b: &Expr) -> Expr {
        let owner = match Expr::join(a, b, "kron") {
            Ok(o) => o,
            Err(e) => return e,
        };
        let (rows, cols) = (a.rows * b.rows, a.cols * b.cols);
        let mut map: BTreeMap<Monomial, Affine> = BTreeMap::new();
        for (ma, ta) in &a.terms {
            for (mb, tb) in &b.terms {
                let prod = if ta.lin.is_empty() {
                    Affine::kron_const(&ta.constant, tb, true)
                } else if tb.lin.is_empty() {
                    Affine::kron_const(&tb.constant, ta, false)
                } else {
                    return Expr::failed(LmiError::NotAffine { op: "kron".into() });
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

    /// Id of the parameter this expression is (`ρ` itself, as returned by
    /// [`crate::Problem::parameter`]).
    pub(crate) fn as_parameter(&self) -> Result<usize> {
        self.check()?;
        let not = || LmiError::NotAParameter {
            what: format!("a {}x{} expression", self.rows, self.cols),
        };
        if self.shape() != (1, 1) || self.terms.len() != 1 {
            return Err(not());
        }
        let (m, a) = &self.terms[0];
        let nz: Vec<(usize, u32)> =
            m.0.iter()
                .enumerate()
                .filter(|(_, e)| **e > 0)
                .map(|(p, e)| (p, *e))
                .collect();
        if nz.len() != 1 || nz[0].1 != 1 || !a.lin.is_empty() || a.constant[(0, 0)] != 1.0 {
            return Err(not());
        }
        Ok(nz[0].0)
    }

    /// Substitutes the value `value` for the parameter `param` (a parameter expression from
    /// [`crate::Problem::parameter`]).
    pub fn at(&self, param: &Expr, value: f64) -> Expr {
        if self.error.is_some() {
            return self.clone();
        }
        let p = match param.as_parameter() {
            Ok(p) => p,
            Err(e) => return Expr::failed(e),
        };
        if !value.is_finite() {
            return Expr::failed(LmiError::NonFinite {
                what: "parameter value".into(),
                row: 0,
                col: 0,
                value,
            });
        }
        let mut map: BTreeMap<Monomial, Affine> = BTreeMap::new();
        for (m, a) in &self.terms {
            let e = m.exponent(p);
            let mut rest = m.0.clone();
            if p < rest.len() {
                rest[p] = 0;
            }
            let rest = Monomial::from_exponents(rest);
            let t = a.scale(value.powi(e as i32));
            match map.get_mut(&rest) {
                Some(s) => *s = s.add(&t, 1.0),
                None => {
                    map.insert(rest, t);
                }
            }
        }
        Expr::from_terms(self.rows, self.cols, self.owner, map)
    }

    /// The column of monomials `[1, ρ, ρ², …, ρ^degree]ᵀ` of a parameter `ρ`.
    pub fn monomials(param: &Expr, degree: u32) -> Expr {
        let p = match param.as_parameter() {
            Ok(p) => p,
            Err(e) => return Expr::failed(e),
        };
        let n = degree as usize + 1;
        let mut map = BTreeMap::new();
        for k in 0..n {
            let mut a = Affine::zeros(n, 1);
            a.constant[(k, 0)] = 1.0;
            map.insert(Monomial::power(p, k as u32), a);
        }
        Expr::from_terms(n, 1, param.owner, map)
    }

    /// Value at decision vector `x` and parameter values `rho` (indexed by parameter id).
    pub(crate) fn eval(&self, x: &[f64], rho: &[f64]) -> Mat {
        let mut m = Mat::zeros(self.rows, self.cols);
        for (mono, a) in &self.terms {
            m += a.eval(x) * mono.eval(rho);
        }
        m
    }

    /// Value of a decision-free expression at parameter values `rho`.
    pub(crate) fn eval_constant(&self, rho: &[f64]) -> Mat {
        let mut m = Mat::zeros(self.rows, self.cols);
        for (mono, a) in &self.terms {
            m += &a.constant * mono.eval(rho);
        }
        m
    }

    /// The numeric value of an expression that contains no decision variables and no
    /// parameters.
    ///
    /// # Errors
    /// The deferred error, or [`LmiError::DecisionDependent`] / [`LmiError::ParameterDependent`].
    pub fn to_constant(&self) -> Result<Mat> {
        self.check()?;
        if self.has_variables() {
            return Err(LmiError::DecisionDependent {
                what: "the expression".into(),
            });
        }
        if self.is_parametric() {
            return Err(LmiError::ParameterDependent {
                what: "the expression".into(),
            });
        }
        Ok(self.eval_constant(&[]))
    }

    pub(crate) fn with_owner(mut self, owner: u64) -> Expr {
        self.owner = Some(owner);
        self
    }
}

impl From<&Mat> for Expr {
    fn from(m: &Mat) -> Expr {
        Expr::constant(m)
    }
}

impl From<Mat> for Expr {
    fn from(m: Mat) -> Expr {
        Expr::constant(&m)
    }
}

impl From<f64> for Expr {
    fn from(v: f64) -> Expr {
        Expr::scalar(v)
    }
}

// ---------------------------------------------------------------------------------------------
// Operators: every combination of owned/borrowed expressions, constants and scalars.

macro_rules! expr_binops {
    ($($lhs:ty, $rhs:ty);* $(;)?) => {$(
        impl Add<$rhs> for $lhs {
            type Output = Expr;
            fn add(self, rhs: $rhs) -> Expr {
                Expr::add_impl(&self, &rhs, 1.0, "+")
            }
        }
        impl Sub<$rhs> for $lhs {
            type Output = Expr;
            fn sub(self, rhs: $rhs) -> Expr {
                Expr::add_impl(&self, &rhs, -1.0, "-")
            }
        }
        impl Mul<$rhs> for $lhs {
            type Output = Expr;
            fn mul(self, rhs: $rhs) -> Expr {
                Expr::mul_impl(&self, &rhs)
            }
        }
    )*};
}
expr_binops!(Expr, Expr; Expr, &Expr; &Expr, Expr; &Expr, &Expr);

macro_rules! const_binops {
    ($($lhs:ty, $rhs:ty, $conv_l:expr, $conv_r:expr);* $(;)?) => {$(
        impl Add<$rhs> for $lhs {
            type Output = Expr;
            fn add(self, rhs: $rhs) -> Expr {
                Expr::add_impl(&$conv_l(self), &$conv_r(rhs), 1.0, "+")
            }
        }
        impl Sub<$rhs> for $lhs {
            type Output = Expr;
            fn sub(self, rhs: $rhs) -> Expr {
                Expr::add_impl(&$conv_l(self), &$conv_r(rhs), -1.0, "-")
            }
        }
        impl Mul<$rhs> for $lhs {
            type Output = Expr;
            fn mul(self, rhs: $rhs) -> Expr {
                Expr::mul_impl(&$conv_l(self), &$conv_r(rhs))
            }
        }
    )*};
}

fn own(e: Expr) -> Expr {
    e
}
fn borrowed(e: &Expr) -> Expr {
    e.clone()
}
fn mat(m: &Mat) -> Expr {
    Expr::constant(m)
}
fn scal(v: f64) -> Expr {
    Expr::scalar(v)
}

const_binops!(
    &Mat, Expr, mat, own;
    &Mat, &Expr, mat, borrowed;
    Expr, &Mat, own, mat;
    &Expr, &Mat, borrowed, mat;
    f64, Expr, scal, own;
    f64, &Expr, scal, borrowed;
    Expr, f64, own, scal;
    &Expr, f64, borrowed, scal;
);

impl Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        self.scale(-1.0)
    }
}

impl Neg for &Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        self.scale(-1.0)
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
