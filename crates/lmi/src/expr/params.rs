//! Parameters and evaluation of expressions: recognising a parameter, substituting a value
//! for it, the monomial basis of a parameter, and the numeric value at given variables and
//! parameters.
//!
//! Neighbours: [`super`] holds [`Expr`] and its bookkeeping; `affine.rs` the affine matrices;
//! `blocks.rs` the matrix operations; `ops.rs` the operators.

use super::affine::Affine;
use super::{Expr, Monomial};
use crate::error::{LmiError, Result};
use pendulab_lti::Mat;
use std::collections::BTreeMap;

impl Expr {
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
}
