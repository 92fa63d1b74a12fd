//! The C ABI the page's loader (`web/src/lab.js`) calls: plain exported functions over two
//! linear-memory buffers, no generated glue (`docs/web.md`, "Interface").
//!
//! - `pl_io()`: [`IO_LEN`] `f64`s, the numbers in and out of every call (layouts below).
//! - `pl_text_in(len)`: a byte buffer of `len` bytes for UTF-8 text in (a plant file);
//!   `pl_text_out()`/`pl_text_out_len()`: text out (a controller file, an error message).
//!
//! Every function returning `i32` returns `-1` on failure with the error's message in the text
//! out buffer, else `0` or a count. Nothing panics across the boundary: bad input is an error.
//! The lab itself is one value held by the module ([`crate::Lab`]).
//!
//! | function | in | out (`io`) |
//! |---|---|---|
//! | `pl_init(kind)` | 0 cart, 1 arm: the book plant, its book LQR, the rig "with quantizer" | — |
//! | `pl_load_plant(len)` | a plant file or a lab file (`[plant]`) in the text buffer | — |
//! | `pl_design(method, r)` | 0 LQR (`q` in `io[0..4]`), 1 servo (`io[0..5]`), 2 placement (poles `re, im` in `io[0..8]`), 3 LMI (`q` in `io[0..n]`, `n = io[5]` 4 or 5, `α = io[6]`) | [`DESIGN_GAIN`], [`DESIGN_N`], [`DESIGN_POLES`], [`DESIGN_A`], [`DESIGN_B`], [`DESIGN_OPEN`]; LMI: [`DESIGN_LMI`] and the certificate in words in the text buffer |
//! | `pl_mode(swing_up)` | 0 balance, 1 swing-up then balance | — |
//! | `pl_reset(q0, q1)` | the state `[q0, q1, 0, 0]` at `t = 0` | — |
//! | `pl_poke(dq0, dq1)`, `pl_hold(q1, on)` | added to the state; pendulum held at `q1` | — |
//! | `pl_reference(r)`, `pl_effect(which, on)`, `pl_delay(samples)` | reference; [`Effect`] by number; delay | — |
//! | `pl_advance(samples, every)` | samples to run, record every `every`-th | `io[0..16]` the [`STATE`] block, records of [`RECORD`] from `io[16]`; returns the record count |
//! | `pl_response(kind, amplitude, duration, every)` | 0: from `q₁ = amplitude`; 1: a reference step of `amplitude` | records `[t, q₀, q₁, u]` from `io[0]`; returns the count |
//! | `pl_compare(duration, every)` | the arm only: a gain-scheduled servo's controller file in the text buffer; the constant servo's `q` in `io[0..5]`, `R` in `io[5]`; `k = io[6]` reference steps `(time, value)` from `io[7]` | records of [`crate::compare::COMPARED`] from `io[0]`; returns the count |
//! | `pl_controller_toml()`, `pl_plant_toml()` | — | the file in the text buffer; returns its length |

use crate::compare::{COMPARED, compare_servos, read_controller, steps_scenario};
use crate::design::{Design, Designer, LmiCertificate, Method, Mode, design};
use crate::error::WebError;
use crate::export::controller_file;
use crate::lab::{Effect, Lab, RECORD};
use pendulab_control::scenario::simulate;
use pendulab_lmi::Status;
use pendulab_lti::Complex64;
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantSpec;
use pendulab_sim::scenario::{Imperfections, ScenarioSpec, SignalSpec};
use std::cell::RefCell;

/// Length of the number buffer (`f64`s).
pub const IO_LEN: usize = 16384;
/// Offset of the gain in a design's output (5 entries; the fifth is 0 for `n = 4`).
pub const DESIGN_GAIN: usize = 0;
/// Offset of the order `n` (4, or 5 for the servo).
pub const DESIGN_N: usize = 5;
/// Offset of the closed-loop poles (`re, im`, 5 pairs).
pub const DESIGN_POLES: usize = 6;
/// Offset of `A` (4 × 4, row-major).
pub const DESIGN_A: usize = 16;
/// Offset of `B` (4 entries).
pub const DESIGN_B: usize = 32;
/// Offset of the open-loop poles `eig(A)` (`re, im`, 4 pairs).
pub const DESIGN_OPEN: usize = 36;
/// Offset of an LMI design's certificate (`pl_design` method 3): `[status (1 solved, 2
/// solved to reduced accuracy), iterations, constraints rechecked, smallest slack, tr X,
/// poles in the region (1/0)]` ([`crate::design::LmiCertificate`]).
pub const DESIGN_LMI: usize = 44;
/// The state block of `pl_advance`: `[t, q₀, q₁, q̇₀, q̇₁, u, wrap(q₁), p₁ₓ, p₁ᵧ, p₂ₓ, p₂ᵧ]`
/// (the pose: cart pivot or arm tip, then the pendulum's tip, m), 16 slots.
pub const STATE: usize = 16;

struct State {
    lab: Option<Lab>,
    /// The shared part of the designs on the lab's plant (set with the lab).
    designer: Option<Designer>,
    io: Vec<f64>,
    text_in: Vec<u8>,
    text_out: Vec<u8>,
}

thread_local! {
    static STATE_CELL: RefCell<State> = RefCell::new(State {
        lab: None,
        designer: None,
        io: vec![0.0; IO_LEN],
        text_in: Vec::new(),
        text_out: Vec::new(),
    });
}

/// Runs `f` on the module's state, turning an error into `-1` and its message.
fn with<F: FnOnce(&mut State) -> Result<i32, WebError>>(f: F) -> i32 {
    STATE_CELL.with(|cell| {
        let mut s = cell.borrow_mut();
        match f(&mut s) {
            Ok(v) => v,
            Err(e) => {
                s.text_out = e.to_string().into_bytes();
                -1
            }
        }
    })
}

fn lab(s: &mut State) -> Result<&mut Lab, WebError> {
    running(&mut s.lab)
}

fn running(lab: &mut Option<Lab>) -> Result<&mut Lab, WebError> {
    lab.as_mut().ok_or(WebError::OutOfRange {
        what: "lab",
        value: 0.0,
        range: "initialised by pl_init first",
    })
}

/// The book's LQ weights of each rig (`docs/rig/examples/cart_lqr.toml`, `arm_lqr.toml`: the
/// IP Toolbox's `cdip_lqr_sim` and `adip_lqr_sim`).
pub fn book_weights(kind: PlantKind) -> (Vec<f64>, f64) {
    match kind {
        PlantKind::Cart => (vec![10.0, 10.0, 0.0, 0.0], 1.0),
        PlantKind::Arm => (vec![5.0, 10.0, 0.1, 0.1], 1.0),
    }
}

fn start(s: &mut State, plant: PlantSpec) -> Result<i32, WebError> {
    let (q, r) = book_weights(plant.kind());
    let designer = Designer::new(&plant)?;
    let d = designer.design(&Method::Lqr { q, r })?;
    s.designer = Some(designer);
    s.lab = Some(Lab::new(
        plant,
        d,
        Mode::Balance,
        Imperfections::with_quantizer(),
        &[0.0; 4],
    )?);
    Ok(0)
}

/// The number buffer ([`IO_LEN`] `f64`s; its address is the same for the module's life, so
/// the page keeps one view of it).
#[unsafe(no_mangle)]
pub extern "C" fn pl_io() -> *mut f64 {
    STATE_CELL.with(|cell| cell.borrow_mut().io.as_mut_ptr())
}

/// A text-in buffer of `len` bytes (its old content dropped).
#[unsafe(no_mangle)]
pub extern "C" fn pl_text_in(len: u32) -> *mut u8 {
    STATE_CELL.with(|cell| {
        let mut s = cell.borrow_mut();
        s.text_in = vec![0; len as usize];
        s.text_in.as_mut_ptr()
    })
}

/// The text-out buffer.
#[unsafe(no_mangle)]
pub extern "C" fn pl_text_out() -> *const u8 {
    STATE_CELL.with(|cell| cell.borrow().text_out.as_ptr())
}

/// Length of the text out \[bytes\].
#[unsafe(no_mangle)]
pub extern "C" fn pl_text_out_len() -> u32 {
    STATE_CELL.with(|cell| cell.borrow().text_out.len() as u32)
}

/// Starts the lab on the book's cart (`kind = 0`) or arm (`1`).
#[unsafe(no_mangle)]
pub extern "C" fn pl_init(kind: u32) -> i32 {
    with(|s| {
        let kind = match kind {
            0 => PlantKind::Cart,
            1 => PlantKind::Arm,
            _ => {
                return Err(WebError::OutOfRange {
                    what: "kind",
                    value: kind as f64,
                    range: "0 (cart) or 1 (arm)",
                });
            }
        };
        start(s, PlantSpec::book(kind))
    })
}

/// Starts the lab on the plant file (or a lab file's `[plant]` table) in the text buffer.
#[unsafe(no_mangle)]
pub extern "C" fn pl_load_plant() -> i32 {
    with(|s| {
        let text = String::from_utf8_lossy(&s.text_in).into_owned();
        start(s, read_plant(&text)?)
    })
}

/// A plant spec from a plant file, or from the `[plant]` table of a lab file.
///
/// # Errors
/// [`WebError::PlantSpec`] naming the key (the plant file's error when the text has no
/// `[plant]` table).
pub fn read_plant(text: &str) -> Result<PlantSpec, WebError> {
    match PlantSpec::from_toml(text) {
        Ok(p) => Ok(p),
        Err(e) => {
            let table = text.parse::<toml::Table>().ok();
            match table
                .as_ref()
                .and_then(|t| t.get("plant"))
                .and_then(|p| p.as_table())
            {
                Some(p) => Ok(PlantSpec::from_toml(&p.to_string())?),
                None => Err(e.into()),
            }
        }
    }
}

/// Designs on the lab's plant and runs the result (module table; `method`: 0 LQR, 1 servo,
/// 2 placement).
#[unsafe(no_mangle)]
pub extern "C" fn pl_design(method: u32, r: f64) -> i32 {
    with(|s| {
        let io = &s.io;
        let m = match method {
            0 => Method::Lqr {
                q: io[..4].to_vec(),
                r,
            },
            1 => Method::Servo {
                q: io[..5].to_vec(),
                r,
            },
            2 => Method::Place {
                poles: (0..4)
                    .map(|i| Complex64::new(io[2 * i], io[2 * i + 1]))
                    .collect(),
            },
            3 => Method::Lmi {
                q: io[..if io[5] == 5.0 { 5 } else { 4 }].to_vec(),
                r,
                alpha: io[6],
            },
            _ => {
                return Err(WebError::OutOfRange {
                    what: "method",
                    value: method as f64,
                    range: "0 (LQR), 1 (servo), 2 (placement) or 3 (LMI)",
                });
            }
        };
        let State {
            lab: l,
            designer,
            io,
            text_out,
            ..
        } = s;
        let lab = running(l)?;
        let d = match designer {
            Some(designer) => designer.design_from(m, Some(lab.design()))?,
            None => design(lab.plant(), &m)?,
        };
        let mode = if d.is_servo() {
            Mode::Balance
        } else {
            current_mode(lab)
        };
        lab.set_design(d, mode)?;
        let d = lab.design();
        write_design(io, d);
        if let Some(c) = &d.lmi {
            *text_out = certificate_text(c).into_bytes();
        }
        Ok(0)
    })
}

fn current_mode(lab: &Lab) -> Mode {
    if lab.swings_up() {
        Mode::SwingUp
    } else {
        Mode::Balance
    }
}

fn write_design(io: &mut [f64], d: &Design) {
    io[DESIGN_GAIN..DESIGN_GAIN + 5].fill(0.0);
    io[DESIGN_GAIN..DESIGN_GAIN + d.gain.len()].copy_from_slice(&d.gain);
    io[DESIGN_N] = d.gain.len() as f64;
    io[DESIGN_POLES..DESIGN_POLES + 10].fill(0.0);
    for (i, p) in d.poles.iter().take(5).enumerate() {
        io[DESIGN_POLES + 2 * i] = p.re;
        io[DESIGN_POLES + 2 * i + 1] = p.im;
    }
    for i in 0..4 {
        for j in 0..4 {
            io[DESIGN_A + 4 * i + j] = d.a()[(i, j)];
        }
        io[DESIGN_B + i] = d.b()[(i, 0)];
    }
    io[DESIGN_OPEN..DESIGN_OPEN + 8].fill(0.0);
    for (i, p) in d.open_loop().iter().take(4).enumerate() {
        io[DESIGN_OPEN + 2 * i] = p.re;
        io[DESIGN_OPEN + 2 * i + 1] = p.im;
    }
    io[DESIGN_LMI..DESIGN_LMI + 6].fill(0.0);
    if let Some(c) = &d.lmi {
        io[DESIGN_LMI..DESIGN_LMI + 6].copy_from_slice(&[
            if c.status == Status::Solved { 1.0 } else { 2.0 },
            f64::from(c.iterations),
            c.constraints as f64,
            c.min_slack,
            c.trace_x,
            if c.poles_in_region { 1.0 } else { 0.0 },
        ]);
    }
}

/// An LMI design's certificate in one sentence (the page shows it).
pub fn certificate_text(c: &LmiCertificate) -> String {
    format!(
        "{} by pendulab-lmi's dense interior-point method in {} iterations; {} LMIs rechecked on X, L (smallest slack {:.2e}); tr X = {:.4}; closed-loop poles {} the region",
        if c.status == Status::Solved {
            "solved"
        } else {
            "solved to reduced accuracy"
        },
        c.iterations,
        c.constraints,
        c.min_slack,
        c.trace_x,
        if c.poles_in_region {
            "inside"
        } else {
            "NOT inside"
        }
    )
}

/// Balance (`0`) or swing up from hanging, then balance (`1`), with the running state-feedback
/// gain (a servo gain stays the servo).
#[unsafe(no_mangle)]
pub extern "C" fn pl_mode(swing_up: u32) -> i32 {
    with(|s| {
        let lab = lab(s)?;
        let d = lab.design().clone();
        let mode = if swing_up != 0 {
            Mode::SwingUp
        } else {
            Mode::Balance
        };
        lab.set_design(d, mode)?;
        Ok(0)
    })
}

/// Restarts at `[q0, q1, 0, 0]`, `t = 0`.
#[unsafe(no_mangle)]
pub extern "C" fn pl_reset(q0: f64, q1: f64) -> i32 {
    with(|s| {
        lab(s)?.reset(&[q0, q1, 0.0, 0.0])?;
        Ok(0)
    })
}

/// Adds `dq0` to the drive position and `dq1` \[rad\] to the pendulum angle.
#[unsafe(no_mangle)]
pub extern "C" fn pl_poke(dq0: f64, dq1: f64) -> i32 {
    with(|s| {
        lab(s)?.poke(dq0, dq1);
        Ok(0)
    })
}

/// Holds the pendulum at `q1` \[rad\] (`on = 1`) or lets it go.
#[unsafe(no_mangle)]
pub extern "C" fn pl_hold(q1: f64, on: u32) -> i32 {
    with(|s| {
        lab(s)?.hold((on != 0).then_some(q1));
        Ok(0)
    })
}

/// Steps the drive-position reference to `r` \[m or rad\].
#[unsafe(no_mangle)]
pub extern "C" fn pl_reference(r: f64) -> i32 {
    with(|s| {
        lab(s)?.set_reference(r)?;
        Ok(0)
    })
}

/// Switches imperfection `which` ([`Effect`] by number) on or off.
#[unsafe(no_mangle)]
pub extern "C" fn pl_effect(which: u32, on: u32) -> i32 {
    with(|s| {
        let effect = Effect::from_index(which).ok_or(WebError::OutOfRange {
            what: "effect",
            value: which as f64,
            range: "0 … 6",
        })?;
        lab(s)?.set_effect(effect, on != 0)?;
        Ok(0)
    })
}

/// Sets the computation delay \[samples\].
#[unsafe(no_mangle)]
pub extern "C" fn pl_delay(samples: u32) -> i32 {
    with(|s| {
        lab(s)?.set_delay(samples as usize)?;
        Ok(0)
    })
}

/// Runs `samples` samples (module table).
#[unsafe(no_mangle)]
pub extern "C" fn pl_advance(samples: u32, every: u32) -> i32 {
    with(|s| {
        let room = (IO_LEN - STATE) / RECORD;
        let every = every as usize;
        if every > 0 && (samples as usize).div_ceil(every) > room {
            return Err(WebError::OutOfRange {
                what: "samples / every",
                value: samples as f64 / every as f64,
                range: "at most 2728 records per call",
            });
        }
        let State { lab: l, io, .. } = s;
        let lab = running(l)?;
        let mut out = Vec::with_capacity(RECORD * 32);
        let result = lab.advance(samples as usize, every, &mut out);
        let n = out.len() / RECORD;
        io[STATE..STATE + out.len()].copy_from_slice(&out);
        io[0] = lab.time();
        io[1..5].copy_from_slice(lab.state());
        io[5] = lab.input();
        io[6] = lab.angle();
        let pose = lab.pose()?;
        io[7..9].copy_from_slice(&pose[0]);
        io[9..11].copy_from_slice(&pose[1]);
        result?;
        Ok(n as i32)
    })
}

/// The predicted run of the running design (`pendulab_control::scenario::simulate` with the
/// lab's imperfections): `kind = 0` from the pendulum at `amplitude` \[rad\], `1` a step of the
/// drive reference to `amplitude` at `t = 0`; `duration` \[s\], every `every`-th sample.
#[unsafe(no_mangle)]
pub extern "C" fn pl_response(kind: u32, amplitude: f64, duration: f64, every: u32) -> i32 {
    with(|s| {
        let lab = lab(s)?;
        let spec = lab.design().controller(Mode::Balance, 0.0, 0.0);
        let mut scenario = if kind == 0 {
            ScenarioSpec::new(vec![0.0, amplitude, 0.0, 0.0], duration)
        } else {
            let mut sc = ScenarioSpec::new(vec![0.0; 4], duration);
            sc.reference = SignalSpec::Step {
                time: 0.0,
                amplitude,
            };
            sc
        };
        scenario.imperfections = lab.imperfections().clone();
        let every = (every as usize).max(1);
        let run = simulate(lab.plant(), &spec, &scenario)?;
        let n = run.t.len().div_ceil(every).min(IO_LEN / 4);
        for (j, k) in (0..run.t.len()).step_by(every).take(n).enumerate() {
            s.io[4 * j..4 * j + 4].copy_from_slice(&[run.t[k], run.x[k][0], run.x[k][1], run.u[k]]);
        }
        Ok(n as i32)
    })
}

/// The gain-scheduled servo of the controller file in the text buffer beside the constant LQ
/// servo, on the lab's plant and imperfections (module table, [`crate::compare`]).
#[unsafe(no_mangle)]
pub extern "C" fn pl_compare(duration: f64, every: u32) -> i32 {
    with(|s| {
        let text = String::from_utf8_lossy(&s.text_in).into_owned();
        let scheduled = read_controller(&text)?;
        let io = &s.io;
        let k = io[6];
        if !((1.0..=16.0).contains(&k) && k.fract() == 0.0) {
            return Err(WebError::OutOfRange {
                what: "reference steps",
                value: k,
                range: "1 … 16",
            });
        }
        let steps: Vec<(f64, f64)> = (0..k as usize)
            .map(|i| (io[7 + 2 * i], io[8 + 2 * i]))
            .collect();
        let (q, r) = (io[..5].to_vec(), io[5]);
        let every = (every as usize).max(1);
        let lab = lab(s)?;
        let ts = lab.plant().rig().sample_time;
        if !(duration.is_finite() && duration > 0.0)
            || (duration / ts / every as f64) as usize + 1 >= IO_LEN / COMPARED
        {
            return Err(WebError::OutOfRange {
                what: "duration / every",
                value: duration,
                range: "positive, at most 2047 records",
            });
        }
        let scenario = steps_scenario(&steps, duration, lab.imperfections());
        let out = compare_servos(lab.plant(), &scheduled, &q, r, &scenario, every)?;
        s.io[..out.len()].copy_from_slice(&out);
        Ok((out.len() / COMPARED) as i32)
    })
}

/// The running controller as a controller file (text buffer), headed by its design.
#[unsafe(no_mangle)]
pub extern "C" fn pl_controller_toml() -> i32 {
    with(|s| {
        let lab = lab(s)?;
        let head = describe(lab.design());
        let text = controller_file(lab.plant(), &lab.controller_spec(), &head)?;
        s.text_out = text.into_bytes();
        Ok(s.text_out.len() as i32)
    })
}

/// The lab's plant as a plant file (text buffer).
#[unsafe(no_mangle)]
pub extern "C" fn pl_plant_toml() -> i32 {
    with(|s| {
        let text = lab(s)?.plant().to_toml()?;
        s.text_out = text.into_bytes();
        Ok(s.text_out.len() as i32)
    })
}

/// One line per fact of the design, for the head of an exported controller file.
pub fn describe(d: &Design) -> String {
    let list = |q: &[f64]| {
        q.iter()
            .map(|v| format!("{v}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let what = match &d.method {
        Method::Lqr { q, r } => format!(
            "LQR on the upright linearisation: Q = diag({}), R = {r}",
            list(q)
        ),
        Method::Servo { q, r } => {
            format!("LQ integral servo on q0: Q = diag({}), R = {r}", list(q))
        }
        Method::Lmi { q, r, alpha } => format!(
            "LMI guaranteed-cost LQ{} (dense interior-point method): Q = diag({}), R = {r}, decay rate {alpha} 1/s",
            if q.len() == 5 {
                " integral servo on q0"
            } else {
                ""
            },
            list(q)
        ),
        Method::Place { poles } => format!(
            "pole placement: poles {}",
            poles
                .iter()
                .map(|p| format!("{:.4}{:+.4}i", p.re, p.im))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    format!(
        "Designed in the pendulab browser lab (docs/web.md).\n{what}\nGain in library sign, u = -K y; closed-loop poles {}",
        d.poles
            .iter()
            .map(|p| format!("{:.4}{:+.4}i", p.re, p.im))
            .collect::<Vec<_>>()
            .join(", ")
    )
}
