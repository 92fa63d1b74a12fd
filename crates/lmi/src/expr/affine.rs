//! Affine matrices `C + Σ_v x_v C_v`, the coefficient of each monomial of an
//! [`Expr`](super::Expr): the constant part dense, the linear part as canonical [`Lin`]
//! entries, with sums, scaling, transposes, products with constants, Kronecker products with
//! constants and sub-blocks.
//!
//! Neighbours: [`super`] holds [`Monomial`](super::Monomial), [`Expr`](super::Expr) and its
//! bookkeeping; `blocks.rs` the matrix operations on expressions; `params.rs` parameters and
//! evaluation; `ops.rs` the operators.

use super::VarId;
use pendulab_lti::Mat;

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

    pub(super) fn add(&self, other: &Affine, sign: f64) -> Affine {
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

    pub(super) fn scale(&self, s: f64) -> Affine {
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

    pub(super) fn transpose(&self) -> Affine {
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

    /// `c · a` for a constant `c`: entry `(i, col)` of a term at `(k, col)` gets `c_ik` times
    /// its coefficient.
    pub(super) fn left_mul(c: &Mat, a: &Affine) -> Affine {
        // Nonzeros of each column k of c: (i, c_ik).
        let by_k = nonzeros_by(c.ncols(), c.nrows(), |k, i| c[(i, k)]);
        let lin = a
            .lin
            .iter()
            .flat_map(|l| {
                by_k[l.row as usize].iter().map(move |&(i, cik)| Lin {
                    row: i,
                    coef: cik * l.coef,
                    ..*l
                })
            })
            .collect();
        let mut out = Affine {
            constant: c * &a.constant,
            lin,
        };
        out.canonicalize();
        out
    }

    /// `a · c` for a constant `c`: entry `(row, j)` of a term at `(row, k)` gets its
    /// coefficient times `c_kj`.
    pub(super) fn right_mul(a: &Affine, c: &Mat) -> Affine {
        // Nonzeros of each row k of c: (j, c_kj).
        let by_k = nonzeros_by(c.nrows(), c.ncols(), |k, j| c[(k, j)]);
        let lin = a
            .lin
            .iter()
            .flat_map(|l| {
                by_k[l.col as usize].iter().map(move |&(j, ckj)| Lin {
                    col: j,
                    coef: l.coef * ckj,
                    ..*l
                })
            })
            .collect();
        let mut out = Affine {
            constant: &a.constant * c,
            lin,
        };
        out.canonicalize();
        out
    }

    /// `c ⊗ a` (`left = true`) or `a ⊗ c` for a constant `c`.
    pub(super) fn kron_const(c: &Mat, a: &Affine, left: bool) -> Affine {
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
    pub(super) fn place(&self, r0: usize, c0: usize, into: &mut Affine) {
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
    pub(super) fn sub_block(&self, r0: usize, c0: usize, nr: usize, nc: usize) -> Affine {
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
    pub(super) fn max_var(&self) -> Option<VarId> {
        self.lin.iter().map(|l| l.var).max()
    }
}

/// For each `k < outer`, the nonzero entries `(i, entry(k, i))`, `i < inner`, in order of `i`
/// (the nonzeros of a constant's columns or rows, as the products with it need them).
fn nonzeros_by(
    outer: usize,
    inner: usize,
    entry: impl Fn(usize, usize) -> f64,
) -> Vec<Vec<(u32, f64)>> {
    (0..outer)
        .map(|k| {
            (0..inner)
                .map(|i| (i as u32, entry(k, i)))
                .filter(|&(_, v)| v != 0.0)
                .collect()
        })
        .collect()
}
