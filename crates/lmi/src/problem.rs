//! [`Problem`]: decision variables, parameters, constraints and the objective of an LMI/SOS
//! program, and [`Problem::solve`].

use crate::error::{LmiError, Result};
use crate::expr::{Affine, Expr, Lin, Monomial, VarId};
use crate::solution::{Solution, SolveOptions};
use crate::sos::SosRecord;
use pendulab_lti::Mat;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};

static NEXT_PROBLEM_ID: AtomicU64 = AtomicU64::new(1);

/// Handle of a constraint of a [`Problem`] (its index in [`Problem::constraint_names`] and in
/// [`Solution::checks`](crate::Solution::checks)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ConstraintId(pub usize);

/// The relation a constraint imposes on its expression `F`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Relation {
    /// `F ⪰ 0` (symmetric `F`).
    PositiveSemidefinite,
    /// `F ≻ 0`, imposed as `F ⪰ ε I` with the explicit margin `ε > 0`.
    PositiveDefinite {
        /// The margin `ε`.
        margin: f64,
    },
    /// `F ⪯ 0`.
    NegativeSemidefinite,
    /// `F ≺ 0`, imposed as `F ⪯ −ε I`.
    NegativeDefinite {
        /// The margin `ε`.
        margin: f64,
    },
    /// `F = 0` (entrywise; for a symmetric `F` only one triangle is imposed).
    Zero,
    /// `F ≥ 0` entrywise.
    NonNegative,
}

impl Relation {
    /// The margin `ε` of a strict inequality (0 otherwise).
    pub fn margin(&self) -> f64 {
        match self {
            Relation::PositiveDefinite { margin } | Relation::NegativeDefinite { margin } => {
                *margin
            }
            _ => 0.0,
        }
    }
}

/// Where a constraint comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Origin {
    /// Added by the user.
    User,
    /// `R ⪰ 0` of an SOS multiplier (see [`Problem::sos_multiplier`]).
    SosMultiplier,
    /// The Gram matrix `Q ⪰ 0` of an SOS constraint (see [`Problem::sos`]).
    SosGram,
    /// The coefficients of an SOS constraint that no Gram entry can produce, set to zero.
    SosMatching,
}

/// The cone a constraint lands in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cone {
    /// Every listed entry of `G` is zero.
    Zero,
    /// Every entry of `G` is `≥ 0`.
    NonNegative,
    /// `G ⪰ 0` (symmetric; the solver sees its upper triangle).
    Psd,
}

/// A constraint as stored: the user's expression and relation, and its normalised form
/// `G(x)` (`= 0`, `≥ 0` or `⪰ 0`) that the solver sees.
#[derive(Debug, Clone)]
pub(crate) struct ConstraintSpec {
    pub(crate) name: String,
    pub(crate) relation: Relation,
    pub(crate) origin: Origin,
    /// `F`: the user's expression (parameter-free), for the recheck.
    pub(crate) expr: Affine,
    pub(crate) cone: Cone,
    /// `G`: `F − εI`, `−F − εI`, `F` ... (symmetrised for PSD cones).
    pub(crate) g: Affine,
    /// For `Cone::Zero`: impose only the upper triangle (symmetric `F`).
    pub(crate) upper_only: bool,
}

/// Whether the problem minimises or maximises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    /// Minimise the objective.
    Minimize,
    /// Maximise the objective.
    Maximize,
}

/// A matrix decision variable.
#[derive(Debug, Clone)]
pub(crate) struct VariableInfo {
    pub(crate) name: String,
}

/// An SOS multiplier `S(ρ) = (I ⊗ z(ρ))ᵀ R (I ⊗ z(ρ))` with its Gram matrix `R ⪰ 0`.
#[derive(Debug, Clone)]
pub struct Multiplier {
    /// `S(ρ)`, `size × size`, polynomial in the parameters, affine in `R`.
    pub s: Expr,
    /// The Gram matrix `R` (symmetric decision variable of size `size · len(z)`).
    pub gram: Expr,
    /// The constraint `R ⪰ 0`.
    pub constraint: ConstraintId,
}

/// Handle of an SOS constraint (index into [`Solution::sos_checks`](crate::Solution::sos_checks)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SosId(pub usize);

/// An LMI / SOS program:
///
/// ```text
/// minimise (or maximise)  cᵀx
/// subject to              F_k(x) ⪰ ε_k I,  G_k(x) = 0,  h_k(x) ≥ 0,
///                         M_k(ρ; x) is a sum of squares in the parameters ρ
/// ```
///
/// with `F_k`, `G_k`, `h_k`, `M_k` affine in the decision variables `x`. Variables are
/// matrices ([`symmetric`](Self::symmetric), [`matrix`](Self::matrix),
/// [`scalar`](Self::scalar)); every constraint has a name that reappears in the solution's
/// recheck.
///
/// ```
/// use pendulab_lmi::{Problem, SolveOptions, Status};
/// use pendulab_lti::Mat;
///
/// // Lyapunov: find P ≻ 0 with AᵀP + PA ≺ 0.
/// let a = Mat::from_row_slice(2, 2, &[0.0, 1.0, -2.0, -3.0]);
/// let mut p = Problem::new();
/// let pv = p.symmetric("P", 2);
/// p.positive_definite("P ≻ 0", &pv, 1e-6)?;
/// p.negative_definite("AᵀP + PA ≺ 0", &(&a.transpose() * &pv).he(), 1e-6)?;
/// let sol = p.solve(&SolveOptions::default())?;
/// assert!(matches!(sol.status, Status::Solved));
/// assert!(sol.all_checks_pass());
/// let p_value = sol.value(&pv)?;
/// # Ok::<(), pendulab_lmi::LmiError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Problem {
    id: u64,
    nvars: usize,
    variables: Vec<VariableInfo>,
    params: Vec<String>,
    pub(crate) constraints: Vec<ConstraintSpec>,
    pub(crate) objective: Option<(Sense, Affine)>,
    pub(crate) sos: Vec<SosRecord>,
}

impl Default for Problem {
    fn default() -> Self {
        Self::new()
    }
}

/// Relative tolerance on `|F_ij − F_ji|` accepted as round-off when checking that a matrix
/// inequality is symmetric: products such as `(Q^½ X)ᵀ` and `X Q^½` are summed in different
/// orders and differ by a few ulps.
const SYMMETRY_TOL: f64 = 1e-10;

impl Problem {
    /// An empty problem (no variables, no constraints, no objective: a feasibility problem).
    pub fn new() -> Self {
        Self {
            id: NEXT_PROBLEM_ID.fetch_add(1, Ordering::Relaxed),
            nvars: 0,
            variables: Vec::new(),
            params: Vec::new(),
            constraints: Vec::new(),
            objective: None,
            sos: Vec::new(),
        }
    }

    pub(crate) fn id(&self) -> u64 {
        self.id
    }

    /// Number of scalar decision variables (a symmetric `n × n` variable counts `n(n+1)/2`).
    pub fn num_scalar_variables(&self) -> usize {
        self.nvars
    }

    /// Names of the constraints, indexed by [`ConstraintId`].
    pub fn constraint_names(&self) -> Vec<&str> {
        self.constraints.iter().map(|c| c.name.as_str()).collect()
    }

    /// Names of the matrix variables, in creation order.
    pub fn variable_names(&self) -> Vec<&str> {
        self.variables.iter().map(|v| v.name.as_str()).collect()
    }

    pub(crate) fn allocate(&mut self, name: &str, count: usize) -> VarId {
        let first = self.nvars as VarId;
        self.variables.push(VariableInfo {
            name: name.to_string(),
        });
        self.nvars += count;
        first
    }

    fn variable_expr(&self, rows: usize, cols: usize, lin: Vec<Lin>) -> Expr {
        let mut a = Affine {
            constant: Mat::zeros(rows, cols),
            lin,
        };
        a.canonicalize();
        let mut map = BTreeMap::new();
        map.insert(Monomial::one(), a);
        Expr::from_terms(rows, cols, Some(self.id), map)
    }

    /// A symmetric `n × n` matrix variable (`n(n+1)/2` scalars).
    pub fn symmetric(&mut self, name: &str, n: usize) -> Expr {
        let first = self.allocate(name, n * (n + 1) / 2);
        let mut lin = Vec::with_capacity(n * n);
        let mut k = first;
        for j in 0..n {
            for i in 0..=j {
                lin.push(Lin {
                    row: i as u32,
                    col: j as u32,
                    var: k,
                    coef: 1.0,
                });
                if i != j {
                    lin.push(Lin {
                        row: j as u32,
                        col: i as u32,
                        var: k,
                        coef: 1.0,
                    });
                }
                k += 1;
            }
        }
        self.variable_expr(n, n, lin)
    }

    /// A full (unstructured) `rows × cols` matrix variable.
    pub fn matrix(&mut self, name: &str, rows: usize, cols: usize) -> Expr {
        let first = self.allocate(name, rows * cols);
        let lin = (0..cols)
            .flat_map(|j| {
                (0..rows).map(move |i| Lin {
                    row: i as u32,
                    col: j as u32,
                    var: first + (i + j * rows) as VarId,
                    coef: 1.0,
                })
            })
            .collect();
        self.variable_expr(rows, cols, lin)
    }

    /// A scalar variable (a `1 × 1` expression).
    pub fn scalar(&mut self, name: &str) -> Expr {
        self.matrix(name, 1, 1)
    }

    /// A scalar parameter `ρ` (a `1 × 1` polynomial expression). Parameters are not decision
    /// variables: expressions polynomial in them are constrained with [`Problem::sos`] (for
    /// all values of the parameters, or on a set via S-procedure multipliers).
    pub fn parameter(&mut self, name: &str) -> Expr {
        let p = self.params.len();
        self.params.push(name.to_string());
        let mut map = BTreeMap::new();
        map.insert(
            Monomial::power(p, 1),
            Affine {
                constant: Mat::from_element(1, 1, 1.0),
                lin: Vec::new(),
            },
        );
        Expr::from_terms(1, 1, Some(self.id), map)
    }

    /// Names of the parameters, indexed by parameter id.
    pub fn parameter_names(&self) -> Vec<&str> {
        self.params.iter().map(|s| s.as_str()).collect()
    }

    /// Validates an expression for use in this problem.
    pub(crate) fn own(&self, e: &Expr, what: &str) -> Result<()> {
        e.check()?;
        let foreign = e.owner().is_some_and(|o| o != self.id)
            || e.max_var().is_some_and(|v| v as usize >= self.nvars);
        if foreign {
            return Err(LmiError::ForeignExpression {
                op: what.to_string(),
            });
        }
        Ok(())
    }

    fn parameter_free(&self, e: &Expr, what: &str) -> Result<Affine> {
        self.own(e, what)?;
        if e.is_parametric() {
            return Err(LmiError::ParameterDependent {
                what: what.to_string(),
            });
        }
        Ok(e.constant_term())
    }

    /// Checks symmetry (up to round-off) and returns the symmetrised affine matrix.
    pub(crate) fn symmetrised(a: &Affine, what: &str) -> Result<Affine> {
        let n = a.nrows();
        if a.ncols() != n {
            return Err(LmiError::NotSquare {
                what: what.to_string(),
                rows: n,
                cols: a.ncols(),
            });
        }
        let scale = a
            .constant
            .iter()
            .map(|v| v.abs())
            .chain(a.lin.iter().map(|l| l.coef.abs()))
            .fold(0.0, f64::max);
        let tol = SYMMETRY_TOL * scale.max(f64::MIN_POSITIVE);
        for j in 0..n {
            for i in 0..j {
                let d = (a.constant[(i, j)] - a.constant[(j, i)]).abs();
                if d > tol {
                    return Err(LmiError::NotSymmetric {
                        what: what.to_string(),
                        row: i,
                        col: j,
                        difference: d,
                    });
                }
            }
        }
        // Linear part: compare with the transpose entry by entry (both canonical).
        let mut t: Vec<Lin> = a
            .lin
            .iter()
            .map(|l| Lin {
                row: l.col,
                col: l.row,
                ..*l
            })
            .collect();
        t.sort_unstable_by_key(|l| (l.col, l.row, l.var));
        let (mut p, mut q) = (0, 0);
        while p < a.lin.len() || q < t.len() {
            let kp = a.lin.get(p).map(|l| (l.col, l.row, l.var));
            let kq = t.get(q).map(|l| (l.col, l.row, l.var));
            let (row, col, d) = match (kp, kq) {
                (Some(x), Some(y)) if x == y => {
                    let d = (a.lin[p].coef - t[q].coef).abs();
                    p += 1;
                    q += 1;
                    (x.1, x.0, d)
                }
                (Some(x), Some(y)) if x < y => {
                    p += 1;
                    (x.1, x.0, a.lin[p - 1].coef.abs())
                }
                (Some(x), None) => {
                    p += 1;
                    (x.1, x.0, a.lin[p - 1].coef.abs())
                }
                (_, Some(y)) => {
                    q += 1;
                    (y.1, y.0, t[q - 1].coef.abs())
                }
                (None, None) => break,
            };
            if d > tol {
                return Err(LmiError::NotSymmetric {
                    what: what.to_string(),
                    row: row as usize,
                    col: col as usize,
                    difference: d,
                });
            }
        }
        // Symmetrise: (A + Aᵀ)/2.
        let mut lin = a.lin.clone();
        lin.extend(t);
        lin.iter_mut().for_each(|l| l.coef *= 0.5);
        let mut s = Affine {
            constant: (&a.constant + a.constant.transpose()) * 0.5,
            lin,
        };
        s.canonicalize();
        Ok(s)
    }

    fn check_margin(name: &str, margin: f64, strict: bool) -> Result<()> {
        if !margin.is_finite() || margin < 0.0 || (strict && margin == 0.0) {
            return Err(LmiError::InvalidArgument {
                what: format!("margin of '{name}'"),
                reason: format!("must be finite and > 0, got {margin}"),
            });
        }
        Ok(())
    }

    pub(crate) fn push_constraint(
        &mut self,
        name: &str,
        f: &Expr,
        relation: Relation,
        origin: Origin,
    ) -> Result<ConstraintId> {
        let what = format!("constraint '{name}'");
        let a = self.parameter_free(f, &what)?;
        let (cone, g, upper_only, expr) = match relation {
            Relation::PositiveSemidefinite
            | Relation::PositiveDefinite { .. }
            | Relation::NegativeSemidefinite
            | Relation::NegativeDefinite { .. } => {
                let strict = matches!(
                    relation,
                    Relation::PositiveDefinite { .. } | Relation::NegativeDefinite { .. }
                );
                Self::check_margin(name, relation.margin(), strict)?;
                let s = Self::symmetrised(&a, &what)?;
                let sign = match relation {
                    Relation::NegativeSemidefinite | Relation::NegativeDefinite { .. } => -1.0,
                    _ => 1.0,
                };
                let mut g = s.clone();
                if sign < 0.0 {
                    g.constant *= -1.0;
                    g.lin.iter_mut().for_each(|l| l.coef = -l.coef);
                }
                let n = g.nrows();
                for i in 0..n {
                    g.constant[(i, i)] -= relation.margin();
                }
                (Cone::Psd, g, false, s)
            }
            Relation::Zero => {
                let symmetric = a.nrows() == a.ncols() && Self::symmetrised(&a, &what).is_ok();
                let g = if symmetric {
                    Self::symmetrised(&a, &what)?
                } else {
                    a.clone()
                };
                (Cone::Zero, g, symmetric, a)
            }
            Relation::NonNegative => (Cone::NonNegative, a.clone(), false, a),
        };
        self.constraints.push(ConstraintSpec {
            name: name.to_string(),
            relation,
            origin,
            expr,
            cone,
            g,
            upper_only,
        });
        Ok(ConstraintId(self.constraints.len() - 1))
    }

    /// `F ⪰ 0`.
    ///
    /// # Errors
    /// The expression's deferred error; [`LmiError::NotSquare`], [`LmiError::NotSymmetric`],
    /// [`LmiError::ParameterDependent`], [`LmiError::ForeignExpression`].
    pub fn positive_semidefinite(&mut self, name: &str, f: &Expr) -> Result<ConstraintId> {
        self.push_constraint(name, f, Relation::PositiveSemidefinite, Origin::User)
    }

    /// `F ≻ 0`, imposed as `F ⪰ ε I` with the explicit margin `ε > 0` (the book uses
    /// `ε = 1e-6`).
    ///
    /// # Errors
    /// As [`positive_semidefinite`](Self::positive_semidefinite), and
    /// [`LmiError::InvalidArgument`] for a margin that is not finite and positive.
    pub fn positive_definite(&mut self, name: &str, f: &Expr, margin: f64) -> Result<ConstraintId> {
        self.push_constraint(name, f, Relation::PositiveDefinite { margin }, Origin::User)
    }

    /// `F ⪯ 0`.
    ///
    /// # Errors
    /// As [`positive_semidefinite`](Self::positive_semidefinite).
    pub fn negative_semidefinite(&mut self, name: &str, f: &Expr) -> Result<ConstraintId> {
        self.push_constraint(name, f, Relation::NegativeSemidefinite, Origin::User)
    }

    /// `F ≺ 0`, imposed as `F ⪯ −ε I` with the explicit margin `ε > 0`.
    ///
    /// # Errors
    /// As [`positive_definite`](Self::positive_definite).
    pub fn negative_definite(&mut self, name: &str, f: &Expr, margin: f64) -> Result<ConstraintId> {
        self.push_constraint(name, f, Relation::NegativeDefinite { margin }, Origin::User)
    }

    /// `L = R` entrywise (only one triangle is imposed when `L − R` is symmetric).
    ///
    /// # Errors
    /// Deferred errors, [`LmiError::ShapeMismatch`], [`LmiError::ParameterDependent`].
    pub fn equal(&mut self, name: &str, lhs: &Expr, rhs: &Expr) -> Result<ConstraintId> {
        self.push_constraint(name, &(lhs - rhs), Relation::Zero, Origin::User)
    }

    /// `f ≥ 0` entrywise.
    ///
    /// # Errors
    /// Deferred errors, [`LmiError::ParameterDependent`].
    pub fn nonnegative(&mut self, name: &str, f: &Expr) -> Result<ConstraintId> {
        self.push_constraint(name, f, Relation::NonNegative, Origin::User)
    }

    /// `lhs ≤ rhs` entrywise.
    ///
    /// # Errors
    /// Deferred errors, [`LmiError::ShapeMismatch`], [`LmiError::ParameterDependent`].
    pub fn less_equal(&mut self, name: &str, lhs: &Expr, rhs: &Expr) -> Result<ConstraintId> {
        self.push_constraint(name, &(rhs - lhs), Relation::NonNegative, Origin::User)
    }

    fn set_objective(&mut self, sense: Sense, f: &Expr) -> Result<()> {
        let a = self.parameter_free(f, "the objective")?;
        if (a.nrows(), a.ncols()) != (1, 1) {
            return Err(LmiError::ShapeMismatch {
                op: "objective (must be 1x1; use .trace() for a matrix)".into(),
                left: (1, 1),
                right: (a.nrows(), a.ncols()),
            });
        }
        self.objective = Some((sense, a));
        Ok(())
    }

    /// Minimise the `1 × 1` affine expression `f` (e.g. `X.trace()` or `γ`).
    ///
    /// # Errors
    /// Deferred errors, a non-scalar or parameter-dependent `f`.
    pub fn minimize(&mut self, f: &Expr) -> Result<()> {
        self.set_objective(Sense::Minimize, f)
    }

    /// Maximise the `1 × 1` affine expression `f`.
    ///
    /// # Errors
    /// As [`minimize`](Self::minimize).
    pub fn maximize(&mut self, f: &Expr) -> Result<()> {
        self.set_objective(Sense::Maximize, f)
    }

    /// Removes the objective (the problem becomes a feasibility problem; the interior-point
    /// solver then returns a point well inside the feasible set).
    pub fn clear_objective(&mut self) {
        self.objective = None;
    }

    /// An SOS multiplier `S(ρ) = (I_size ⊗ z(ρ))ᵀ R (I_size ⊗ z(ρ))` with a new symmetric Gram
    /// variable `R ⪰ 0` of size `size · len(z)`; `z` is a column of polynomials in the
    /// parameters (usually monomials, e.g. [`Expr::monomials`]`(ρ, 3)` = `[1, ρ, ρ², ρ³]ᵀ`).
    /// `S(ρ) ⪰ 0` for every `ρ`, so `g(ρ) · S(ρ)` is an S-procedure term that is `⪰ 0`
    /// wherever `g(ρ) ≥ 0`.
    ///
    /// # Errors
    /// Deferred errors; [`LmiError::DecisionDependent`] if `z` has decision variables;
    /// [`LmiError::ShapeMismatch`] if `z` is not a column.
    pub fn sos_multiplier(&mut self, name: &str, size: usize, z: &Expr) -> Result<Multiplier> {
        self.own(z, &format!("monomial vector of '{name}'"))?;
        if z.has_variables() {
            return Err(LmiError::DecisionDependent {
                what: format!("monomial vector of '{name}'"),
            });
        }
        if z.ncols() != 1 || z.nrows() == 0 {
            return Err(LmiError::ShapeMismatch {
                op: format!("monomial vector of '{name}' (must be a non-empty column)"),
                left: (z.nrows().max(1), 1),
                right: z.shape(),
            });
        }
        let r = self.symmetric(name, size * z.nrows());
        let constraint = self.push_constraint(
            name,
            &r,
            Relation::PositiveSemidefinite,
            Origin::SosMultiplier,
        )?;
        let zz = Expr::kron(&Expr::identity(size), z);
        let s = zz.t() * &r * &zz;
        s.check()?;
        Ok(Multiplier {
            s,
            gram: r,
            constraint,
        })
    }

    /// Solves the problem with Clarabel and rechecks every constraint on the returned values.
    ///
    /// Infeasibility, unboundedness and solver trouble are reported in
    /// [`Solution::status`](crate::Solution::status), not as errors.
    ///
    /// # Errors
    /// [`LmiError::InvalidArgument`] for bad options, [`LmiError::Solver`] if the solver
    /// rejects the data.
    pub fn solve(&self, options: &SolveOptions) -> Result<Solution> {
        crate::solution::solve(self, options)
    }
}

/// A scalar affine form `c + Σ coef · x_var` (used by the SOS coefficient matching).
#[derive(Debug, Clone, Default)]
pub(crate) struct ScalarAffine {
    pub(crate) constant: f64,
    pub(crate) terms: Vec<(VarId, f64)>,
}

impl ScalarAffine {
    pub(crate) fn is_zero(&self) -> bool {
        self.constant == 0.0 && self.terms.is_empty()
    }
}
