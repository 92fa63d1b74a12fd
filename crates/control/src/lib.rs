//! # pendulab-control — nonlinear and digital control
//!
//! The controllers of the book's part 1 ch. 7–8 and part 2 ch. 2–3 that go beyond a static
//! gain: receding-horizon control, quantised inputs, sliding mode, energy swing-up and output
//! feedback. Designs return named results with their diagnostics; every controller implements
//! [`pendulab_sim::Controller`] (measurement in, held command out, allocation-free `update`),
//! so the same value runs in the simulator and on the rig. Where `pendulab-sim` already has the
//! run-time controller (discrete linear controllers, observer-based feedback, switching), this
//! crate designs what it runs rather than repeating it.
//!
//! | module | what it holds | book |
//! |---|---|---|
//! | [`cgmres`] | C/GMRES (Ohtsuka 2004): [`OptimalControlProblem`](cgmres::OptimalControlProblem) (`f`, `Hₓ`, `H_u`, `φₓ`), dummy-input bounds ([`InputBounds`](cgmres::InputBounds)), the solver ([`Cgmres`](cgmres::Cgmres): Newton–GMRES initialisation, one continuation step per sample with `kmax` forward-difference GMRES iterations, horizon `T(t) = T_f(1 − e^{−αt})`), [`NmpcController`](cgmres::NmpcController), [`TimedController`](cgmres::TimedController) | §3.3 |
//! | [`gmres`] | matrix-free GMRES with a fixed budget, allocation-free | — |
//! | [`nmpc`] | the arm pendulum's swing-up problem on the plant's Jacobian and the book's settings ([`arm_swing_up_controller`](nmpc::arm_swing_up_controller)) | `p2c33_adip_nmpc_swing_up` |
//! | [`quantizer`] | static and optimal dynamic quantizers (Azuma–Sugie): closed form ([`odq_analytic`](quantizer::odq_analytic)), LP design on Clarabel with FIR or Ho–Kalman realisation ([`odq_lp`](quantizer::odq_lp)), the worst-case output deviation of any quantizer ([`quantizer_cost`](quantizer::quantizer_cost)), [`QuantizedController`](quantizer::QuantizedController) | `p2c234_ex1_cdip_odq` |
//! | [`sliding_mode`] | the LQ-optimal switching surface via the regular form and the reduced Riccati equation ([`lq_sliding_surface`](sliding_mode::lq_sliding_surface)), the sliding-mode law with sign or boundary-layer switching | `p2c323_ex1_cdip_swing_up` |
//! | [`swing_up`] | the book's energy pumping, Åström–Furuta energy shaping for the cart and the arm (with tuned gains for both rigs), the latched swing-up → balance switch with wrapped angles ([`swing_up_then_balance`](swing_up::swing_up_then_balance)) | `p2c323_ex1_cdip_swing_up` |
//! | [`spec`] | controller specifications as serde data ([`ControllerSpec`](spec::ControllerSpec): state feedback, LQ integral servo, gain-scheduled `K(ρ)`, swing-up + balance, observer-based output feedback, the PID family with I–PD, the arm's NMPC; each with an optional design record, [`DesignRecord`](spec::DesignRecord); library sign `u = −K y`, the book's `k_book` converted) and the factory [`build`](spec::build) that designs and builds one for a book rig; the rig's controller files and the front ends read these | `cdip_lqr_sim`, `adip_lqr_sim`, `p1c74_ex1_cdip_ob_design`, `p1c224_i_pdcont`, `p2c33_adip_nmpc_swing_up` |
//! | [`scenario`] | the one simulate path: [`simulate`](scenario::simulate)`(&PlantSpec, &ControllerSpec, &ScenarioSpec)` builds plant, controller and the rig's chains and runs the sampled-data loop; the run as arrays with its summary (settling, overshoot, peak voltage, saturation time, angle window) | — |
//! | [`estimation`] | the observer-based controller `(A + BK_b + L_b C, −L_b, K_b)` discretised by ZOH/Tustin ([`output_feedback_controller`](estimation::output_feedback_controller)), the steady-state Kalman filter ([`kalman_filter`](estimation::kalman_filter)) and state feedback on its current estimate ([`kalman_controller`](estimation::kalman_controller)) | `p1c74_ex1`, `p1c83_ex2`, `p1c84_ex4` |
//! | [`kalman`] | the time-varying Kalman filter ([`KalmanFilter`](kalman::KalmanFilter), `A_k, B_k, C_k` per sample), the extended and unscented filters of any `Dynamics` sampled by RK4 ([`ExtendedKalmanFilter`](kalman::ExtendedKalmanFilter), [`UnscentedKalmanFilter`](kalman::UnscentedKalmanFilter) with scaled sigma points), encoder quantisation as measurement noise `q²/12`, NIS and NEES | — |
//! | [`inspect`] | a controller that hands every update (with its wall-clock time) to an inspector, for benchmarks and tests ([`Inspected`](inspect::Inspected)) | — |
//! | [`trim`] | operating points of any `Dynamics` with fixed states, inputs and outputs by Levenberg–Marquardt ([`find_operating_point`](trim::find_operating_point), MATLAB `findop`) | — |
//!
//! Conventions: SI units, volts, radians with angles from the **upward** vertical (as
//! `pendulab-plants`); state feedback `u = −K x` (the book's `u = +K_b x` converts through
//! [`StateFeedback`](pendulab_lti::design::StateFeedback)); errors are [`ControlError`] values
//! naming what is wrong.
//!
//! ```
//! use pendulab_control::sliding_mode::{lq_sliding_surface, ReducedWeight, RegularForm};
//! use pendulab_plants::{CartEquilibrium, CartPendulum};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // The book's LQ-optimal sliding surface for the cart pendulum, Q = diag(10, 100, 1, 1).
//! let lin = CartPendulum::book().linearize(CartEquilibrium::upright())?;
//! let q = pendulab_lti::Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 100.0, 1.0, 1.0]));
//! let s = lq_sliding_surface(lin.a(), lin.b(), &q, RegularForm::BookShear, ReducedWeight::BookScript)?;
//! // On σ = Sᵀx = 0 the motion is the reduced LQ closed loop: three stable poles.
//! assert_eq!(s.sliding_poles.len(), 3);
//! assert!(s.sliding_poles.iter().all(|p| p.re < 0.0));
//! # Ok(()) }
//! ```
#![warn(missing_docs)]

pub mod cgmres;
pub mod error;
pub mod estimation;
pub mod gmres;
pub mod inspect;
pub mod kalman;
pub mod mpc;
pub mod nmpc;
pub mod quantizer;
pub mod scenario;
pub mod sliding_mode;
pub mod spec;
pub mod swing_up;
pub mod trim;

pub use error::{ControlError, Result};
