//! # pendulab-lti — linear time-invariant systems
//!
//! Everything a user of MATLAB's Control System Toolbox reaches for first, in pure Rust.
//!
//! | module | what it holds | MATLAB names |
//! |---|---|---|
//! | [`state_space`] | [`StateSpace<Continuous>`] / [`StateSpace<Discrete>`], time domain in the type ([`domain`]) | `ss` |
//! | [`transfer_function`], [`polynomial`] | SISO [`TransferFunction`], [`Polynomial`], ss↔tf | `tf`, `zpk`, `ss2tf`, `tf2ss`, `roots`, `poly`, `conv` |
//! | [`transfer_matrix`] | MIMO [`TransferMatrix`] with `+ − * /` returning `Result`, feedback, minimal ss↔tf, zpk per entry | `tf` (cell arrays), `feedback`, `minreal` |
//! | [`delay`] | Padé approximant of `e^{−sT}`, Thiran fractional-delay all-pass | `pade`, `thiran` |
//! | [`interconnect`] | series, parallel, feedback (explicit sign), append | `series`, `parallel`, `feedback`, `append` |
//! | [`analysis`] | poles, zeros, DC gain, stability, damping, controllability/observability (staircase, PBH), gramians, canonical forms | `pole`, `tzero`, `dcgain`, `isstable`, `damp`, `ctrb`, `obsv`, `ctrbf`, `gram`, `canon` |
//! | [`frequency_response`] | frequency response, Bode data with unwrapped phase | `freqresp`, `bode`, `logspace` |
//! | [`margins`] | every gain/phase crossing of a SISO loop with gain, phase and delay margins; the gang of four | `allmargin`, `margin`, `loopsens` |
//! | [`nyquist`], [`rlocus`], [`disk_margin`], [`sigma`] | Nyquist curve with the encirclement count and the Nyquist criterion, Nichols curve, root locus (branches, asymptotes, break points, gain at a point), disk margins, singular values over frequency | `nyquist`, `nichols`, `rlocus`, `rlocfind`, `diskmargin`, `sigma` |
//! | [`stepinfo`] | step-response characteristics (rise, settling, overshoot, undershoot, peak) | `stepinfo` |
//! | [`reduction`] | minimal realisation, Hankel singular values, balanced realisation and truncation (truncate, matched DC), stable/unstable decomposition (unstable systems keep their unstable part) | `minreal`, `hsvd`, `balreal`, `balred`, `stabsep` |
//! | [`norms`] | H2 norm (Gramian), H∞ norm with its peak frequency (Hamiltonian bisection), continuous and discrete | `norm`, `hinfnorm` |
//! | [`matrix_functions`] | matrix exponential, logarithm, square root, block exponentials | `expm`, `logm`, `sqrtm` |
//! | [`discretization`] | `c2d` (ZOH, FOH, Tustin with prewarp, Euler, matched pole-zero, impulse invariant), `d2c` | `c2d`, `d2c` |
//! | [`response`] | `lsim` (exact ZOH/FOH), `initial`, `step`, `impulse`, zero-input/zero-state split | `lsim`, `initial`, `step`, `impulse` |
//! | [`design`] | LQR (continuous, discrete, sampled-data), pole placement, observers, Kalman gain, LQ integral servo, [`StateFeedback`](design::StateFeedback) | `lqr`, `dlqr`, `lqrd`, `place`, `acker`, `lqe`, `reg` |
//! | [`equations`] | Sylvester, Lyapunov (`lyap`, `dlyap`), Riccati (`care`, `dare`), each with its relative residual | `sylvester`, `lyap`, `dlyap`, `care`, `dare` |
//! | [`linalg`] | the matrix types ([`Mat`]), checks, eigenvalues, the real Schur kernel with reordering | `eig` |
//! | [`trajectory`] | [`Trajectory`]: the one time-series type of the workspace (rows = samples) | — |
//!
//! Conventions: SI units, radians, frequencies in rad/s; state feedback is `u = −K x` (the
//! textbook's `u = +K x` is converted explicitly, see [`design::StateFeedback`]); errors are
//! [`LtiError`] values naming what is wrong and where; numerical results carry their
//! diagnostics (residuals, achieved poles, conditions).
//!
//! ```
//! use pendulab_lti::{StateSpace, Mat, design, discretization::Discretization};
//! # fn main() -> pendulab_lti::Result<()> {
//! // A double integrator, discretised with a zero-order hold and placed by pole placement.
//! let sys = StateSpace::continuous(
//!     Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
//!     Mat::from_row_slice(2, 1, &[0.0, 1.0]),
//!     Mat::from_row_slice(1, 2, &[1.0, 0.0]),
//!     Mat::zeros(1, 1),
//! )?;
//! let dsys = sys.c2d(0.1, Discretization::Zoh)?;
//! let poles = [0.8.into(), 0.7.into()];
//! let k = design::place(dsys.a(), dsys.b(), &poles)?;
//! assert!(k.max_relative_error < 1e-12);
//! # Ok(()) }
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod analysis;
pub mod delay;
pub mod design;
pub mod discretization;
pub mod disk_margin;
pub mod domain;
pub mod equations;
pub mod error;
pub mod frequency_response;
pub mod interconnect;
pub mod linalg;
pub mod margins;
pub mod matrix_functions;
pub mod mu;
pub mod norms;
pub mod nyquist;
pub mod polynomial;
pub mod random;
pub mod reduction;
pub mod response;
pub mod rlocus;
pub mod sigma;
pub mod state_space;
pub mod stepinfo;
pub mod trajectory;
pub mod transfer_function;
pub mod transfer_matrix;

pub use discretization::Discretization;
pub use domain::{Continuous, Discrete, TimeDomain};
pub use error::{LtiError, Result};
pub use interconnect::FeedbackSign;
pub use linalg::{CMat, Complex64, Mat, Vector};
pub use polynomial::Polynomial;
pub use response::{InputHold, LsimOptions};
pub use state_space::StateSpace;
pub use trajectory::Trajectory;
pub use transfer_function::TransferFunction;
pub use transfer_matrix::TransferMatrix;
