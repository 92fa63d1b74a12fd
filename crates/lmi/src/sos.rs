//! Sum-of-squares constraints on parameter-dependent matrices.
//!
//! A symmetric `p × p` matrix `M(ρ; x)`, polynomial in the parameters `ρ` and affine in the
//! decision variables `x`, is a *sum of squares* (SOS) if
//!
//! ```text
//! M(ρ) = Z(ρ)ᵀ Q Z(ρ),   Q ⪰ 0,   Z(ρ) = blockdiag(z₁(ρ), …, z_p(ρ)),
//! ```
//!
//! with monomial columns `z_i` (one per row of `M`). Then `M(ρ) ⪰ 0` for *every* `ρ`; with
//! S-procedure terms `−Σ g_k(ρ) S_k(ρ)` (multipliers from [`Problem::sos_multiplier`])
//! inside `M`, it certifies `M ⪰ 0` on the set where all `g_k ≥ 0`.
//!
//! **Monomials.** Row `i` only needs the monomials of half the Newton polytope of its
//! diagonal entry `M_ii` (Reznick, "Extremal PSD forms with few terms", Duke Math. J. 45,
//! 1978: the monomials of any SOS decomposition of `f` lie in `½ N(f)`; for a matrix the
//! diagonal entry `M_ii = Σ_k (row i of the factor)²` gives it row by row). We take the box
//! and total-degree slab around `½ N(M_ii)` computed from the structurally nonzero terms — a
//! superset, so nothing is lost — which is exact for one parameter.
//!
//! **Coefficient matching in image form.** Each entry `Q_{(i,a),(j,b)}` (`a ∈ z_i`,
//! `b ∈ z_j`) contributes to exactly one coefficient: that of `ρ^{a+b}` in `M_ij`. So the
//! matching equations partition the Gram entries into groups; in each group one entry is
//! solved for (it equals the coefficient of `M` minus the others) and the others become free
//! variables. `Q` is then an affine expression in `(x, free variables)` and `Q ⪰ 0` is one
//! LMI — no equality constraints, and the fewest variables the Gram parametrisation allows.
//! Coefficients of `M` that no Gram entry can produce (e.g. odd powers of a parameter in
//! which `M` is affine) must vanish: they become equality constraints on `x`.
//!
//! **Residual check.** After solving, `M`'s coefficients are evaluated from the user's
//! expression and compared with those of `Z(ρ)ᵀ Q Z(ρ)` computed from the numeric Gram
//! matrix; together with `λ_min(Q)` this certifies the decomposition independently of how it
//! was parametrised ([`SosCheck`](crate::SosCheck)).

use crate::error::{LmiError, Result};
use crate::expr::{Affine, Expr, Lin, Monomial, VarId};
use crate::problem::{ConstraintId, Origin, Problem, Relation, ScalarAffine, SosId};
use pendulab_lti::Mat;
use std::collections::BTreeMap;

/// What is kept of an SOS constraint for the residual check.
#[derive(Debug, Clone)]
pub(crate) struct SosRecord {
    pub(crate) name: String,
    /// `M(ρ)` as given.
    pub(crate) m: Expr,
    /// Monomial basis of each row.
    pub(crate) bases: Vec<Vec<Monomial>>,
    /// The Gram matrix `Q` (parameter-free, affine in the variables).
    pub(crate) gram: Affine,
    /// The constraint `Q ⪰ 0`.
    pub(crate) gram_constraint: ConstraintId,
    /// The constraint on unmatched coefficients, if any.
    pub(crate) matching_constraint: Option<ConstraintId>,
}

/// Exponent bounds of a set of monomials: per parameter and in total degree.
struct Bounds {
    lo: Vec<u32>,
    hi: Vec<u32>,
    lo_t: u32,
    hi_t: u32,
}

fn bounds(support: &[&Monomial], nparams: usize) -> Bounds {
    let mut b = Bounds {
        lo: vec![u32::MAX; nparams],
        hi: vec![0; nparams],
        lo_t: u32::MAX,
        hi_t: 0,
    };
    for m in support {
        for p in 0..nparams {
            let e = m.exponent(p);
            b.lo[p] = b.lo[p].min(e);
            b.hi[p] = b.hi[p].max(e);
        }
        b.lo_t = b.lo_t.min(m.degree());
        b.hi_t = b.hi_t.max(m.degree());
    }
    b
}

/// Monomials `e` with `⌈lo_p/2⌉ ≤ e_p ≤ ⌊hi_p/2⌋` and `⌈lo_t/2⌉ ≤ |e| ≤ ⌊hi_t/2⌋`, in graded
/// order.
fn half_box(b: &Bounds) -> Vec<Monomial> {
    let n = b.lo.len();
    let mut out = Vec::new();
    let mut e = vec![0u32; n];
    fn rec(p: usize, e: &mut Vec<u32>, b: &Bounds, out: &mut Vec<Monomial>) {
        if p == e.len() {
            let t: u32 = e.iter().sum();
            if 2 * t >= b.lo_t && 2 * t <= b.hi_t {
                out.push(Monomial::from_exponents(e.clone()));
            }
            return;
        }
        for v in b.lo[p].div_ceil(2)..=b.hi[p] / 2 {
            e[p] = v;
            rec(p + 1, e, b, out);
        }
        e[p] = 0;
    }
    rec(0, &mut e, b, &mut out);
    out.sort_by(|x, y| x.degree().cmp(&y.degree()).then(y.cmp(x)));
    out
}

/// One Gram entry in a matching group: position `(r, c)` (`r ≤ c`) and its weight in the
/// coefficient (2 for an off-diagonal entry of a diagonal block, which appears twice).
#[derive(Clone, Copy)]
struct GramEntry {
    r: usize,
    c: usize,
    w: f64,
}

impl Problem {
    /// Requires the symmetric matrix polynomial `M(ρ)` to be a sum of squares (see the
    /// [module documentation](crate::sos)). With multiplier terms inside `M` this is the
    /// S-procedure certificate of `M(ρ) ⪰ 0` on a semialgebraic set; see also
    /// [`psd_on_set`](Self::psd_on_set).
    ///
    /// Adds a Gram matrix (its free entries as new hidden variables `"<name>.gram"`), the
    /// LMI `Q ⪰ 0` (constraint `"<name>.gram"`) and, if needed, equality constraints on the
    /// coefficients no Gram entry can produce (constraint `"<name>.matching"`).
    ///
    /// # Errors
    /// Deferred errors; [`LmiError::NotSquare`], [`LmiError::NotSymmetric`] (checked
    /// coefficient by coefficient); [`LmiError::ForeignExpression`].
    pub fn sos(&mut self, name: &str, m: &Expr) -> Result<SosId> {
        let what = format!("SOS constraint '{name}'");
        self.own(m, &what)?;
        let p = m.nrows();
        if m.ncols() != p {
            return Err(LmiError::NotSquare {
                what,
                rows: p,
                cols: m.ncols(),
            });
        }
        // Symmetrise each coefficient (checking symmetry).
        let terms: Vec<(Monomial, Affine)> = m
            .terms()
            .iter()
            .map(|(mono, a)| Ok((mono.clone(), Problem::symmetrised(a, &what)?)))
            .collect::<Result<_>>()?;
        let nparams = self.parameter_names().len();

        // Monomial basis of each row from the support of its diagonal entry.
        let bases: Vec<Vec<Monomial>> = (0..p)
            .map(|i| {
                let support: Vec<&Monomial> = terms
                    .iter()
                    .filter(|(_, a)| a.entry_is_structural(i, i))
                    .map(|(mono, _)| mono)
                    .collect();
                if support.is_empty() {
                    Vec::new()
                } else {
                    half_box(&bounds(&support, nparams))
                }
            })
            .collect();
        let offsets: Vec<usize> = bases
            .iter()
            .scan(0, |acc, b| {
                let o = *acc;
                *acc += b.len();
                Some(o)
            })
            .collect();
        let size: usize = bases.iter().map(|b| b.len()).sum();

        // Coefficients of M: (i, j, monomial) -> scalar affine form, i ≤ j.
        let mut coeffs: BTreeMap<(usize, usize, Monomial), ScalarAffine> = BTreeMap::new();
        for (mono, a) in &terms {
            for j in 0..p {
                for i in 0..=j {
                    let lin = a.entry_lin(i, j);
                    let c = a.constant[(i, j)];
                    if c != 0.0 || !lin.is_empty() {
                        coeffs.insert(
                            (i, j, mono.clone()),
                            ScalarAffine {
                                constant: c,
                                terms: lin.iter().map(|l| (l.var, l.coef)).collect(),
                            },
                        );
                    }
                }
            }
        }

        // Matching groups: (i, j, monomial) -> Gram entries producing it.
        let mut groups: BTreeMap<(usize, usize, Monomial), Vec<GramEntry>> = BTreeMap::new();
        for j in 0..p {
            for i in 0..=j {
                for (ia, a) in bases[i].iter().enumerate() {
                    for (jb, b) in bases[j].iter().enumerate() {
                        if i == j && jb < ia {
                            continue;
                        }
                        let (r, c) = (offsets[i] + ia, offsets[j] + jb);
                        let w = if i == j && ia != jb { 2.0 } else { 1.0 };
                        groups
                            .entry((i, j, a.times(b)))
                            .or_default()
                            .push(GramEntry { r, c, w });
                    }
                }
            }
        }

        let mut gram = Affine::zeros(size, size);
        // Image form: in each group one entry is determined, the others are free variables.
        let nfree: usize = groups.values().map(|g| g.len() - 1).sum();
        let first = self.allocate(&format!("{name}.gram"), nfree);
        let mut next: VarId = first;
        let zero = ScalarAffine::default();
        for (key, entries) in &groups {
            let coeff = coeffs.get(key).unwrap_or(&zero);
            // Pivot: a diagonal Gram entry if the group has one (it carries the positive
            // mass of the coefficient), else the first.
            let pivot = entries.iter().position(|e| e.r == e.c).unwrap_or(0);
            let wp = entries[pivot].w;
            let mut put = |r: usize, c: usize, constant: f64, lin: &[(VarId, f64)]| {
                gram.constant[(r, c)] = constant;
                gram.constant[(c, r)] = constant;
                for &(var, coef) in lin {
                    gram.lin.push(Lin {
                        row: r as u32,
                        col: c as u32,
                        var,
                        coef,
                    });
                    if r != c {
                        gram.lin.push(Lin {
                            row: c as u32,
                            col: r as u32,
                            var,
                            coef,
                        });
                    }
                }
            };
            let mut pivot_lin: Vec<(VarId, f64)> =
                coeff.terms.iter().map(|&(v, c)| (v, c / wp)).collect();
            for (k, e) in entries.iter().enumerate() {
                if k == pivot {
                    continue;
                }
                put(e.r, e.c, 0.0, &[(next, 1.0)]);
                pivot_lin.push((next, -e.w / wp));
                next += 1;
            }
            let ep = entries[pivot];
            put(ep.r, ep.c, coeff.constant / wp, &pivot_lin);
        }
        gram.canonicalize();

        // Coefficients no Gram entry produces must vanish.
        let unmatched: Vec<&ScalarAffine> = coeffs
            .iter()
            .filter(|(k, c)| !groups.contains_key(*k) && !c.is_zero())
            .map(|(_, c)| c)
            .collect();
        let gram_expr = {
            let mut map = BTreeMap::new();
            map.insert(Monomial::one(), gram.clone());
            Expr::from_terms(size, size, None, map).with_owner(self.id())
        };
        let gram_constraint = self.push_constraint(
            &format!("{name}.gram"),
            &gram_expr,
            Relation::PositiveSemidefinite,
            Origin::SosGram,
        )?;
        let matching_constraint = if unmatched.is_empty() {
            None
        } else {
            let k = unmatched.len();
            let mut a = Affine::zeros(k, 1);
            for (r, c) in unmatched.iter().enumerate() {
                a.constant[(r, 0)] = c.constant;
                a.lin.extend(c.terms.iter().map(|&(var, coef)| Lin {
                    row: r as u32,
                    col: 0,
                    var,
                    coef,
                }));
            }
            a.canonicalize();
            let mut map = BTreeMap::new();
            map.insert(Monomial::one(), a);
            let e = Expr::from_terms(k, 1, None, map).with_owner(self.id());
            Some(self.push_constraint(
                &format!("{name}.matching"),
                &e,
                Relation::Zero,
                Origin::SosMatching,
            )?)
        };
        self.sos.push(SosRecord {
            name: name.to_string(),
            m: m.clone(),
            bases,
            gram,
            gram_constraint,
            matching_constraint,
        });
        Ok(SosId(self.sos.len() - 1))
    }

    /// `M(ρ) ⪰ 0` on the set `{ρ : g_k(ρ) ≥ 0 for all k}` by the S-procedure: for each
    /// `(g_k, z_k)` a multiplier `S_k = (I ⊗ z_k)ᵀ R_k (I ⊗ z_k)`, `R_k ⪰ 0`, is created
    /// (named `"<name>.mult<k>"`) and `M − Σ_k g_k S_k` is required to be SOS.
    ///
    /// # Errors
    /// As [`sos`](Self::sos) and [`sos_multiplier`](Self::sos_multiplier); each `g_k` must be
    /// a `1 × 1` polynomial without decision variables.
    pub fn psd_on_set(&mut self, name: &str, m: &Expr, set: &[(&Expr, &Expr)]) -> Result<SosId> {
        let mut rest = m.clone();
        for (k, (g, z)) in set.iter().enumerate() {
            self.own(g, &format!("set polynomial {k} of '{name}'"))?;
            if g.has_variables() || g.shape() != (1, 1) {
                return Err(LmiError::DecisionDependent {
                    what: format!("set polynomial {k} of '{name}' (must be a 1x1 polynomial)"),
                });
            }
            let mult = self.sos_multiplier(&format!("{name}.mult{k}"), m.nrows(), z)?;
            rest = rest - *g * &mult.s;
        }
        self.sos(name, &rest)
    }
}

/// Residual check of one SOS decomposition at a numeric solution.
pub(crate) fn check(record: &SosRecord, x: &[f64]) -> (f64, f64, f64) {
    let p = record.m.nrows();
    let offsets: Vec<usize> = record
        .bases
        .iter()
        .scan(0, |acc, b| {
            let o = *acc;
            *acc += b.len();
            Some(o)
        })
        .collect();
    let q = record.gram.eval(x);
    // Coefficients of Zᵀ Q Z.
    let mut zqz: BTreeMap<(usize, usize, Monomial), f64> = BTreeMap::new();
    for j in 0..p {
        for i in 0..=j {
            for (ia, a) in record.bases[i].iter().enumerate() {
                for (jb, b) in record.bases[j].iter().enumerate() {
                    *zqz.entry((i, j, a.times(b))).or_default() +=
                        q[(offsets[i] + ia, offsets[j] + jb)];
                }
            }
        }
    }
    // Coefficients of M from the user's expression.
    let mut mc: BTreeMap<(usize, usize, Monomial), f64> = BTreeMap::new();
    let mut scale: f64 = 0.0;
    for (mono, a) in record.m.terms() {
        let v: Mat = a.eval(x);
        for j in 0..p {
            for i in 0..=j {
                let s = 0.5 * (v[(i, j)] + v[(j, i)]);
                if s != 0.0 {
                    mc.insert((i, j, mono.clone()), s);
                    scale = scale.max(s.abs());
                }
            }
        }
    }
    let mut residual: f64 = 0.0;
    for (k, v) in &mc {
        residual = residual.max((v - zqz.get(k).copied().unwrap_or(0.0)).abs());
    }
    for (k, v) in &zqz {
        if !mc.contains_key(k) {
            residual = residual.max(v.abs());
        }
    }
    let min_eig = if q.nrows() == 0 {
        0.0
    } else if q.iter().any(|v| !v.is_finite()) {
        f64::NAN
    } else {
        q.clone()
            .symmetric_eigenvalues()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    };
    (residual, scale, min_eig)
}
