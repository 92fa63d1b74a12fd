//! Conversions and operators for expressions: every combination of owned/borrowed
//! expressions, [`Mat`] constants and `f64` scalars with `+`, `-`, `*`, and negation.
//!
//! Neighbours: [`super`] holds [`Expr`] and the sums and products the operators call;
//! `affine.rs` the affine matrices; `blocks.rs` the matrix operations; `params.rs` parameters
//! and evaluation.

use super::Expr;
use pendulab_lti::Mat;
use std::ops::{Add, Mul, Neg, Sub};

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
