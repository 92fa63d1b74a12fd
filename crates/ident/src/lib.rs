//! # pendulab-ident — parameter identification of the pendulum rigs
//!
//! The book's identification chapter (part 1 §2.2.1, §3.2, §3.3; eqs 3.43–3.47) as a library that
//! takes plain data — `&[f64]` columns sampled uniformly, or a [`Dataset`] built from CSV text or a
//! [`pendulab_lti::Trajectory`] — and returns named result structs with their diagnostics.
//!
//! | step | module | what it does |
//! |---|---|---|
//! | data | [`data`] | [`Dataset`]: named columns, CSV parsing, uniform-time check, windows; errors name file, column, line |
//! | derivatives | [`differentiate`] | the book's three-point formulas (eq. 3.47, [`three_point`], [`three_point_twice`]); Savitzky–Golay ([`savitzky_golay`], [`savgol_coefficients`]) |
//! | filtering | [`filter`] | `1/(T_f s + 1)³` discretised exactly ([`LowPass3`], ZOH or FOH), causal or forward–backward zero-phase ([`Prefilter`]) |
//! | least squares | [`least_squares`](mod@least_squares) | Householder QR, streamed in blocks ([`QrAccumulator`]); estimates, standard errors, residual RMS, condition number ([`LeastSquares`]) |
//! | the book's regressions | [`regression`] | [`cart_drive_ls`] `[a_c, b_c]`, [`cart_pendulum_ls`] `[J_p, μ_p]`, [`arm_drive_ls`] `[a₁, b₁]`, [`arm_pendulum_ls`] `[α₂, μ₂] → J₂`, options in [`LsOptions`]; the filtered columns themselves (for plots) from `regression::*_regression` as a [`Regression`] |
//! | feature methods | [`features`] | P-control step ([`p_step`]: `T_p`, overshoot → `a`, `b`), open-loop velocity steps ([`velocity_step`]: `K`, `T`), free oscillation ([`free_oscillation`] → [`pendulum_from_oscillation`]) |
//! | black box | [`blackbox`] | ARX by least squares ([`arx`], order selection by AIC [`arx_order_selection`]) and subspace identification (PO-MOESP, [`moesp`]) from one or several records |
//! | validation | [`validation`] | simulate the identified model on the measured input ([`validate_drive`] by `lsim`, nonlinear pendulums by RK4) and score it with MATLAB's `compare` fit ([`fit_percent`]) |
//!
//! The book's least-squares recipe on the real cart data (`data/rig/cdip_least_square_data.csv`,
//! 1–5 s) — three-point derivatives, every column filtered by the causal `1/(0.075 s + 1)³`,
//! QR least squares — lands within 1 % of table 3.5:
//!
//! ```
//! use pendulab_ident::{cart_drive_ls, cart_pendulum_ls, CartPendulumConstants, Dataset, LsOptions};
//! # fn main() -> Result<(), pendulab_ident::IdentError> {
//! let text = include_str!("../../../data/rig/cdip_least_square_data.csv");
//! let data = Dataset::from_csv_str("cdip_least_square_data.csv", text)?.window(Some(1.0), Some(5.0))?;
//! let ts = data.sample_time()?;
//! let (z, phi, v) = (data.column("z")?, data.column("phi")?, data.column("v")?);
//! let opts = LsOptions::default(); // three-point, causal 1/(0.075 s + 1)^3
//! let drive = cart_drive_ls(ts, z, v, &opts)?;
//! let pend = cart_pendulum_ls(ts, z, phi, &CartPendulumConstants::default(), &opts)?;
//! assert!((drive.a / 6.25 - 1.0).abs() < 0.01 && (drive.b / 4.36 - 1.0).abs() < 0.01);
//! assert!((pend.jp / 1.59e-3 - 1.0).abs() < 0.01 && (pend.mup / 2.35e-4 - 1.0).abs() < 0.01);
//! println!("a_c = {:.4} ± {:.1e}, cond = {:.1}", drive.a, drive.lsq.std_error[0], drive.lsq.condition);
//! # Ok(()) }
//! ```
//!
//! With the book's recipe the `*_ls` functions stream the data through derivative, filter and
//! QR in blocks that stay in cache, never building the regressor: 10⁶ samples take a few
//! milliseconds (`pendulab bench ident-1e6`).
//!
//! **Refusing to guess.** The `*_ls` functions compute whatever the data give (the book
//! studies failures such as the unfiltered regression); before an estimate is believed, the
//! checks decide whether it means anything: [`Dataset::sample_time`] (a time step plausible
//! for the declared [`TimeUnit`]), [`LsOptions::check_data`] (enough samples for the
//! differentiator, a prefilter time constant short against the record and long against the
//! sample time, derivatives accurate over the band used), `check_range` on the known
//! constants, and `check` on the results (finite, condition number within [`MAX_CONDITION`],
//! physically meaningful, resolved by the record). Each failure is a typed [`IdentError`];
//! `pendulab identify` refuses the estimate, or with `--force` prints it with the failures as
//! warnings.
//!
//! Conventions: SI units and radians; angles of the cart rig and the arm pendulum measured from
//! the hanging rest (`φ = θ − π`), the arm angle `φ₁ = θ₁` from the upward vertical, as in the
//! book's data. Errors are [`IdentError`] values naming the data source, column and sample;
//! estimates that make no physical sense are reported by `check_plausible` methods, never
//! silently returned by the command-line tool.

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod blackbox;
pub mod data;
pub mod differentiate;
pub mod error;
pub mod features;
pub mod filter;
pub mod least_squares;
pub mod regression;
pub mod validation;

pub use blackbox::{
    Arx, ArxCandidate, ArxOrderSelection, ArxOrders, Experiment, IoRecord, Moesp, MoespOptions,
    arx, arx_order_selection, moesp,
};
pub use data::{Dataset, MAX_RECORD_SPAN, MAX_SAMPLE_TIME, MIN_SAMPLE_TIME, TimeUnit};
pub use differentiate::{
    Derivatives, Differentiator, savgol_coefficients, savitzky_golay, three_point,
    three_point_twice,
};
pub use error::{IdentError, Result, SamplePos, show_name};
pub use features::{
    Oscillation, OscillationOptions, PStepEstimate, PStepOptions, Peak, PendulumFeatures,
    PeriodCorrection, VelocityStep, VelocityStepOptions, VelocityStepsEstimate,
    drive_from_velocity_steps, free_oscillation, p_step, pendulum_from_oscillation, velocity_step,
};
pub use filter::{BOOK_TF, FilterHold, LowPass3, Prefilter};
pub use least_squares::{LeastSquares, MAX_CONDITION, QrAccumulator, least_squares};
pub use regression::{
    ArmPendulumConstants, ArmPendulumLs, CartPendulumConstants, CartPendulumLs, DriveLs,
    GRAVITY_RANGE, LENGTH_RANGE, LsOptions, MASS_RANGE, MAX_DERIVATIVE_ERROR, MAX_POLE_TIMES_TS,
    MAX_TF_FRACTION, MIN_STENCILS, Regression, arm_drive_ls, arm_pendulum_ls, cart_drive_ls,
    cart_pendulum_ls,
};
pub use validation::{
    Validation, fit_percent, validate_arm_pendulum, validate_cart_pendulum, validate_drive,
    validate_free_pendulum, validate_oscillation, validate_p_step,
};
