//! Matrix operations on expressions: transpose, `He`, scaling, trace, sub-blocks, block
//! matrices, stacking and Kronecker products, each term by term with deferred errors.
//!
//! Neighbours: [`super`] holds [`Expr`] and its bookkeeping; `affine.rs` the affine matrices
//! the terms are made of; `params.rs` parameters and evaluation; `ops.rs` the operators.

use super::affine::{Affine, Lin};
use super::{Expr, Monomial};
use crate::error::LmiError;
use pendulab_lti::Mat;
use std::collections::BTreeMap;

impl Expr {
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
}
