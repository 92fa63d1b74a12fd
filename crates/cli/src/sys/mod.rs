//! MATLAB's verbs for any linear system: `pendulab ss|eig|ctrb|obsv|step|stepinfo|impulse|
//! initial|lsim|bode|nyquist|nichols|rlocus|margin|diskmargin|sigma|norm|minreal|hsvd|balred|
//! c2d|d2c|place|lqe SYSFILE …` and `pade`.
//!
//! Each verb reads one system ([`input`]: a TOML/JSON system file or the matrices on the command
//! line), calls the `pendulab-lti` function of the same MATLAB name, prints a summary (or one
//! JSON object with `--json`) and, for the responses, draws a figure with `--out FILE.svg|.png`.
//! Conventions are MATLAB's and python-control's: state feedback `u = −K x` (the book's
//! `u = +K x` is printed beside it, labelled), frequencies in rad/s, gains in dB, phases in
//! degrees, responses indexed `[output][input][sample]` as python-control's MIMO responses.
//! `c2d`/`d2c`/`ss --save FILE` write the resulting system as a system file that the next verb
//! reads.

pub mod input;
mod loop_verbs;
mod synth_verbs;
mod verbs;

pub use input::SysArgs;
pub use verbs::run;
pub(crate) use verbs::write_system;

use std::path::PathBuf;

/// The frequency grid of `bode`, `nichols` and `sigma`: MATLAB's automatic range, or `points`
/// log-spaced frequencies on `[w_min, w_max]` (rad/s).
#[derive(Debug, Clone, clap::Args)]
pub struct FreqArgs {
    /// Lowest frequency in rad/s (default: MATLAB's automatic range).
    #[arg(long, allow_hyphen_values = true)]
    pub w_min: Option<f64>,
    /// Highest frequency in rad/s.
    #[arg(long, allow_hyphen_values = true)]
    pub w_max: Option<f64>,
    /// Number of frequencies (log-spaced) when a range is given.
    #[arg(long, default_value_t = 200)]
    pub points: usize,
}

/// Response options shared by `step`, `impulse`, `initial` and `lsim`.
#[derive(Debug, Clone, clap::Args)]
pub struct FigureArgs {
    /// Write the figure to this file (`.svg` or `.png`).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// Output of the verbs that produce a system (`ss`, `c2d`, `d2c`, `minreal`, `balred`).
#[derive(Debug, Clone, clap::Args)]
pub struct SystemOut {
    /// Write the resulting system to this file (`.toml` or `.json`), as a system file the next
    /// verb reads.
    #[arg(long, value_name = "FILE")]
    pub save: Option<PathBuf>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// Time grid options of `step`, `impulse` and `initial`.
#[derive(Debug, Clone, clap::Args)]
pub struct TimeArgs {
    /// Final time in seconds (default: from the slowest pole, see the `step` documentation).
    #[arg(long, allow_hyphen_values = true)]
    pub t_final: Option<f64>,
    /// Time step of a continuous system's response in seconds (default: t_final/1000;
    /// a discrete system steps at its dt).
    #[arg(long, allow_hyphen_values = true)]
    pub step_size: Option<f64>,
}

/// The MATLAB verbs.
#[derive(Debug, clap::Subcommand)]
pub enum SysCommand {
    /// H∞ synthesis for a standard plant (MATLAB `hinfsyn(P, nmeas, ncon)`): the optimal level
    /// γ by γ-iteration (or the controller at `--gamma`), the controller u = K y and the
    /// closed-loop poles; `--out` writes the controller as a system file.
    Hinfsyn {
        #[command(flatten)]
        plant: synth_verbs::PlantArgs,
        /// Design at this level instead of the optimal one.
        #[arg(long)]
        gamma: Option<f64>,
        /// Relative tolerance of the γ-iteration (Riccati method).
        #[arg(long, default_value_t = 1e-6)]
        gamma_tol: f64,
    },
    /// H2 (LQG) synthesis for a standard plant (MATLAB `h2syn(P, nmeas, ncon)`): the optimal
    /// ‖T_zw‖₂, the controller u = K y and the closed-loop poles; `--out` writes the
    /// controller as a system file.
    H2syn {
        #[command(flatten)]
        plant: synth_verbs::PlantArgs,
    },
    /// Print a linear system's realisation (A, B, C, D, dt) and its poles (MATLAB `ss`);
    /// `--save` writes it as a system file.
    Ss {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        out: SystemOut,
    },
    /// Poles of a system with natural frequency, damping ratio and time constant (MATLAB `eig`,
    /// `damp`).
    Eig {
        #[command(flatten)]
        sys: SysArgs,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Controllability matrix [B AB … Aⁿ⁻¹B], its rank and singular values (MATLAB `ctrb`).
    Ctrb {
        #[command(flatten)]
        sys: SysArgs,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Observability matrix [C; CA; …; CAⁿ⁻¹], its rank and singular values (MATLAB `obsv`).
    Obsv {
        #[command(flatten)]
        sys: SysArgs,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Step response, one per input (MATLAB `step`), with MATLAB's `stepinfo` figures of each
    /// channel.
    Step {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        time: TimeArgs,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Step-response characteristics of every channel (MATLAB `stepinfo`: 10–90 % rise time,
    /// 2 % settling time, overshoot, undershoot, peak and peak time).
    Stepinfo {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        time: TimeArgs,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Gain, phase and delay margins of a SISO loop L (MATLAB `margin`, `allmargin`): every
    /// crossing, and the reported margins.
    Margin {
        #[command(flatten)]
        sys: SysArgs,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// H2 norm, or with --inf the H∞ norm and its peak frequency (MATLAB `norm(sys)`,
    /// `norm(sys, Inf)`).
    Norm {
        #[command(flatten)]
        sys: SysArgs,
        /// The H∞ norm instead of the H2 norm.
        #[arg(long)]
        inf: bool,
        /// Relative tolerance of the H∞ bisection.
        #[arg(long, default_value_t = 1e-8)]
        tol: f64,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Minimal realisation: remove uncontrollable and unobservable states (MATLAB `minreal`).
    Minreal {
        #[command(flatten)]
        sys: SysArgs,
        /// Rank tolerance (default: the staircase's own, scaled to the data).
        #[arg(long)]
        tol: Option<f64>,
        #[command(flatten)]
        out: SystemOut,
    },
    /// Hankel singular values (MATLAB `hsvd`); an unstable system's unstable states are listed
    /// first as ∞ (null in JSON), then those of its stable part (`stabsep`).
    Hsvd {
        #[command(flatten)]
        sys: SysArgs,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Balanced truncation to `--order` states (MATLAB `balred`), truncating or matching the
    /// DC gain; prints the error bound 2 Σ of the discarded Hankel singular values.
    Balred {
        #[command(flatten)]
        sys: SysArgs,
        /// Order of the reduced system.
        #[arg(long)]
        order: usize,
        /// truncate (default) or matchdc.
        #[arg(long, default_value = "truncate")]
        method: String,
        #[command(flatten)]
        out: SystemOut,
    },
    /// Impulse response, one per input (MATLAB `impulse`).
    Impulse {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        time: TimeArgs,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Zero-input response from an initial state (MATLAB `initial`).
    Initial {
        #[command(flatten)]
        sys: SysArgs,
        /// Initial state x0 (n values, inline "1 0" or a file).
        #[arg(long, allow_hyphen_values = true)]
        x0: String,
        #[command(flatten)]
        time: TimeArgs,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Response to sampled inputs (MATLAB `lsim`): the input file has the columns t, u1 … um.
    Lsim {
        #[command(flatten)]
        sys: SysArgs,
        /// Input samples: a text file (as `pendulab lqr` reads) with columns t, u1 … um;
        /// t uniformly spaced.
        #[arg(long, value_name = "FILE")]
        input: PathBuf,
        /// Initial state x0 (default zeros).
        #[arg(long, allow_hyphen_values = true)]
        x0: Option<String>,
        /// Interpolation of a continuous system's input between samples: foh (default,
        /// python-control's) or zoh.
        #[arg(long, default_value = "foh")]
        hold: String,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Bode diagram of every channel (MATLAB `bode`): gain in dB, unwrapped phase in degrees.
    Bode {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        freq: FreqArgs,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Nyquist curve of a SISO loop L with the encirclements of −1 and the Nyquist criterion
    /// Z = N + P (MATLAB `nyquist`; python-control's indentation to the right of imaginary-axis
    /// poles).
    Nyquist {
        #[command(flatten)]
        sys: SysArgs,
        /// Indentation radius around imaginary-axis poles (rad/s).
        #[arg(long, default_value_t = 1e-4)]
        indent_radius: f64,
        /// Clipping radius of the figure (python-control's max_curve_magnitude).
        #[arg(long, default_value_t = 20.0)]
        max_magnitude: f64,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Nichols curve of a SISO loop (MATLAB `nichols`), the figure with the closed-loop grid.
    Nichols {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        freq: FreqArgs,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Root locus of a SISO loop under negative feedback u = −K y (MATLAB `rlocus`): branches,
    /// asymptotes, break points; --at s0 gives the gain there (MATLAB `rlocfind`).
    Rlocus {
        #[command(flatten)]
        sys: SysArgs,
        /// Gains (inline "0 0.5 1" or a file; default: an adaptive grid).
        #[arg(long, allow_hyphen_values = true)]
        gains: Option<String>,
        /// A point of the plane ("-1+2i"): its gain K = −D(s0)/N(s0), annotated in the figure.
        #[arg(long, allow_hyphen_values = true)]
        at: Option<String>,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Disk margins (MATLAB `diskmargin`, Seiler–Packard–Gahinet 2020): α, the gain interval
    /// and phase margin it guarantees, the critical frequency; for a square MIMO loop each
    /// channel's loop-at-a-time margin and the multi-loop margin (μ bounds, peak frequency).
    Diskmargin {
        #[command(flatten)]
        sys: SysArgs,
        /// Skew σ of the disk (0 balanced, 1 for S, −1 for T).
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        skew: f64,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Singular values of the frequency response (MATLAB `sigma`), any number of channels.
    Sigma {
        #[command(flatten)]
        sys: SysArgs,
        #[command(flatten)]
        freq: FreqArgs,
        #[command(flatten)]
        fig: FigureArgs,
    },
    /// Discretise a continuous system (MATLAB `c2d`).
    C2d {
        #[command(flatten)]
        sys: SysArgs,
        /// Sample time in seconds.
        #[arg(long, allow_hyphen_values = true)]
        ts: f64,
        /// zoh (default), foh, tustin, euler (forward), backward, matched (pole-zero
        /// matching, SISO) or impulse (impulse invariant, D = 0).
        #[arg(long, default_value = "zoh")]
        method: String,
        /// Tustin prewarp frequency in rad/s.
        #[arg(long, allow_hyphen_values = true)]
        prewarp: Option<f64>,
        #[command(flatten)]
        out: SystemOut,
    },
    /// Padé approximant of the delay e^(−sT) (MATLAB `pade(T, n)`): numerator and
    /// denominator coefficients in descending powers of s; `--save` writes its realisation.
    Pade {
        /// The delay T in seconds.
        #[arg(long, allow_hyphen_values = true)]
        delay: f64,
        /// The order n ≥ 1 (numerator and denominator degree).
        #[arg(long, default_value_t = 1)]
        order: usize,
        #[command(flatten)]
        out: SystemOut,
    },
    /// Convert a discrete system to continuous time (MATLAB `d2c`).
    D2c {
        #[command(flatten)]
        sys: SysArgs,
        /// zoh (default), foh, tustin, euler (forward) or backward.
        #[arg(long, default_value = "zoh")]
        method: String,
        /// Tustin prewarp frequency in rad/s.
        #[arg(long, allow_hyphen_values = true)]
        prewarp: Option<f64>,
        #[command(flatten)]
        out: SystemOut,
    },
    /// State-feedback gain K placing the poles of A − BK (MATLAB `place`).
    Place {
        #[command(flatten)]
        sys: SysArgs,
        /// Desired poles: "-1 -2", complex as "-1+2i -1-2i" (conjugate pairs complete).
        #[arg(long, allow_hyphen_values = true)]
        poles: String,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Steady-state Kalman estimator gain (MATLAB `lqe(A, G, C, Qn, Rn)`).
    Lqe {
        #[command(flatten)]
        sys: SysArgs,
        /// Process-noise input matrix G (n×g; default: identity).
        #[arg(long, allow_hyphen_values = true)]
        g: Option<String>,
        /// Process-noise covariance Qn (g×g).
        #[arg(long, allow_hyphen_values = true)]
        qn: String,
        /// Measurement-noise covariance Rn (p×p).
        #[arg(long, allow_hyphen_values = true)]
        rn: String,
        /// Print one JSON object instead of a summary.
        #[arg(long)]
        json: bool,
    },
}
