//! Test systems of the simulator's tests (independent of pendulab-plants): the cart-type
//! pendulum of `docs/model.md` §1 (book eqs 3.7 and 3.21) written from its equations, its
//! linearisation at the upright rest (the closed form of pendulab-testkit), and the controllers
//! the tests run on it.
#![allow(dead_code)]

use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_sim::Dynamics;
use pendulab_testkit::cart::{self, CartParams, Rest};

/// Book table 3.5 (`docs/model.md` §1).
#[derive(Debug, Clone, Copy)]
pub struct CartPendulum {
    pub ac: f64,
    pub bc: f64,
    pub mp: f64,
    pub lp: f64,
    pub jp: f64,
    pub mup: f64,
    pub g: f64,
}

impl Default for CartPendulum {
    /// Book table 3.5 (`docs/model.md` §1).
    fn default() -> Self {
        let p = CartParams::book();
        Self {
            ac: p.a_c,
            bc: p.b_c,
            mp: p.m_p,
            lp: p.l_p,
            jp: p.J_p,
            mup: p.mu_p,
            g: p.g,
        }
    }
}

impl CartPendulum {
    /// The same numbers as pendulab-testkit's parameter set.
    pub fn params(&self) -> CartParams {
        CartParams {
            a_c: self.ac,
            b_c: self.bc,
            m_p: self.mp,
            l_p: self.lp,
            J_p: self.jp,
            mu_p: self.mup,
            g: self.g,
        }
    }

    /// J = J_p + m_p l_p².
    pub fn j(&self) -> f64 {
        self.params().inertia()
    }

    /// The linearisation at the upright rest, `docs/model.md` §1 (pendulab-testkit's closed
    /// form), with the full state measured: `C = I`, `D = 0`.
    pub fn linear(&self) -> StateSpace<Continuous> {
        let (a, b) = self.params().linearization(Rest::Upright);
        StateSpace::continuous(a, b, Mat::identity(4, 4), Mat::zeros(4, 1)).unwrap()
    }

    /// Analytic Jacobians (∂f/∂x, ∂f/∂u) at any state and input, differentiated by hand:
    /// z̈ = −a ż + b v, θ̈ = (m g l sin θ − μ θ̇ − m l cos θ z̈)/J.
    pub fn jacobians(&self, x: &[f64], v: f64) -> (Mat, Mat) {
        let (m, l, j) = (self.mp, self.lp, self.j());
        let (s, c) = x[1].sin_cos();
        let zdd = -self.ac * x[2] + self.bc * v;
        let a = Mat::from_row_slice(
            4,
            4,
            &[
                0.0,
                0.0,
                1.0,
                0.0,
                0.0,
                0.0,
                0.0,
                1.0,
                0.0,
                0.0,
                -self.ac,
                0.0,
                0.0,
                (m * self.g * l * c + m * l * s * zdd) / j,
                self.ac * m * l * c / j,
                -self.mup / j,
            ],
        );
        let b = Mat::from_row_slice(4, 1, &[0.0, 0.0, self.bc, -m * l * c * self.bc / j]);
        (a, b)
    }
}

impl Dynamics for CartPendulum {
    fn nx(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    #[inline]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        let zdd = -self.ac * x[2] + self.bc * u[0];
        let (s, c) = x[1].sin_cos();
        let thdd = (self.mp * self.g * self.lp * s - self.mup * x[3] - self.mp * self.lp * c * zdd)
            / self.j();
        dx[0] = x[2];
        dx[1] = x[3];
        dx[2] = zdd;
        dx[3] = thdd;
    }
}

/// Row-major entries of a matrix.
pub fn entries(m: &Mat) -> Vec<f64> {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| (i, j)))
        .map(|(i, j)| m[(i, j)])
        .collect()
}

/// `M v`.
pub fn mul(m: &Mat, v: &[f64]) -> Vec<f64> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)] * v[j]).sum())
        .collect()
}

/// The continuous LQ integral servo of the linearised cart with the cart position measured,
/// `Q = diag(1, 10, 0, 0, 50)` on `[x; w]`, `R = 1`, designed by pendulab-lti (the tests use
/// it as a controller to run, not as a reference value). Also returns the measured model.
pub fn cart_lq_servo(
    plant: &CartPendulum,
) -> (StateSpace<Continuous>, pendulab_lti::design::LqServo) {
    let lin = plant.linear();
    let cz = StateSpace::continuous(
        lin.a().clone(),
        lin.b().clone(),
        Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[
        1.0, 10.0, 0.0, 0.0, 50.0,
    ]));
    let design = pendulab_lti::design::lq_servo(&cz, &q, &Mat::identity(1, 1)).unwrap();
    (cz, design)
}

/// The stabilising state feedback the tests run on the cart: `u = −K x`, `K` the LQR gain of
/// [`CartPendulum::linear`] with the book's weights `Q = diag(10, 10, 0, 0)`, `R = 1`
/// (pendulab-testkit), designed by pendulab-lti (a controller to run, not a reference value).
pub fn cart_lqr_gain(plant: &CartPendulum) -> Mat {
    let (q, r) = cart::lqr_weights();
    pendulab_lti::design::lqr(&plant.linear(), &q, &r, None)
        .unwrap()
        .gain
}
