//! Controller files: what `pendulab rig run --controller FILE.toml` runs.
//!
//! ```toml
//! plant = "cart"                # "cart" or "arm"
//! rate_hz = 1000.0              # loop rate (default 1000)
//!
//! [controller]
//! kind = "state-feedback"       # "state-feedback", "lq-servo", "gain-scheduled", "swing-up-balance"
//! lqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }   # design on the upright linearisation …
//! # k = [-3.16, -13.5, -4.48, -2.26]             # … or a library gain, u = −K (y − reference)
//! # k_book = [3.16, 13.5, 4.48, 2.26]            # … or the book's, u = +K_book y
//! reference = [0.0, 0.0, 0.0, 0.0]
//!
//! [safety]                      # all optional; defaults: ±5 V, 0.4 m / 3 rad, 30°, 20 periods
//! voltage_limit = 5.0
//! travel_limit = 0.4
//! angle_window_deg = 30.0
//! watchdog_periods = 20
//!
//! [estimator]
//! time_constant = 0.02          # pseudo-differentiator s/(T s + 1)
//! ```
//!
//! Controller kinds (the measurement is `y = [q₀, q₁, q̇₀, q̇₁]`, library sign `u = −K y`):
//!
//! | kind | keys | runs |
//! |---|---|---|
//! | `state-feedback` | one of `k`, `k_book`, `lqr = {q, r}`; `reference` | [`StaticStateFeedback`] |
//! | `lq-servo` | `k1` + `k2` (library) or `lqr = {q (5 entries), r}`; `reference` (m or rad, servo output `q₀`), `step_time` | [`LqIntegralServo`] (forward Euler), `lq_servo` design on `C = [1 0 0 0]` |
//! | `gain-scheduled` | `coefficients = [K₀, K₁, …]` (library sign), `schedule = "one-minus-cos-q0"` or `"q0-squared"` | [`GainScheduled`] polynomial in `ρ` |
//! | `swing-up-balance` | `balance = { k | k_book | lqr }`, `switch_deg` (default 17), swing-up gains of `pendulab_control::swing_up::EnergyShapingGains::{cart_rig, arm_rig}` | energy shaping, then the balance gain (latched) |
//!
//! The `lqr` designs use `pendulab_lti::design::lqr` (continuous, `u = −K x`) on the book
//! plant's upright linearisation (`CartPendulum::book()`, `ArmPendulum::book()` at
//! `θ₁ₑ = 0`): the gains of `cdip_lqr_sim` and `adip_lqr_sim`.

use crate::RigError;
use crate::emulator::PlantKind;
use crate::runtime::Safety;
use pendulab_control::swing_up::{
    ArmEnergyShaping, CartEnergyShaping, EnergyShapingGains, swing_up_then_balance,
};
use pendulab_lti::design::{lq_servo, lqr};
use pendulab_lti::{Mat, StateSpace};
use pendulab_plants::{ArmEquilibrium, ArmPendulum, CartEquilibrium, CartPendulum};
use pendulab_sim::Controller;
use pendulab_sim::controllers::{
    GainScheduled, IntegrationRule, LqIntegralServo, StaticStateFeedback,
};
use pendulab_sim::signal::Signal;
use serde::Deserialize;
use std::time::Duration;

/// A controller file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerFile {
    /// `"cart"` or `"arm"`.
    pub plant: String,
    /// Loop rate \[Hz\].
    pub rate_hz: Option<f64>,
    /// The controller.
    pub controller: ControllerSpec,
    /// Limits.
    #[serde(default)]
    pub safety: SafetySpec,
    /// Velocity estimator.
    #[serde(default)]
    pub estimator: EstimatorSpec,
}

/// An LQR design request: `Q` diagonal, `R` scalar.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LqrSpec {
    /// Diagonal of `Q`.
    pub q: Vec<f64>,
    /// `R`.
    pub r: f64,
}

/// A balance gain: exactly one of the three.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GainSpec {
    /// Library gain (`u = −K y`).
    pub k: Option<Vec<f64>>,
    /// The book's gain (`u = +K_book y`).
    pub k_book: Option<Vec<f64>>,
    /// An LQR design on the upright linearisation.
    pub lqr: Option<LqrSpec>,
}

/// The `[controller]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerSpec {
    /// Controller kind.
    pub kind: String,
    /// Library gain.
    pub k: Option<Vec<f64>>,
    /// Book gain.
    pub k_book: Option<Vec<f64>>,
    /// LQR design (`q` of length 4, or 5 for the servo).
    pub lqr: Option<LqrSpec>,
    /// Servo state gain `K₁` (library sign).
    pub k1: Option<Vec<f64>>,
    /// Servo integral gain `K₂` (library sign).
    pub k2: Option<f64>,
    /// State reference (4 entries) or servo reference (1 entry).
    pub reference: Option<Vec<f64>>,
    /// Servo reference step time \[s\].
    pub step_time: Option<f64>,
    /// Gain-polynomial coefficients `K₀, K₁, …`.
    pub coefficients: Option<Vec<Vec<f64>>>,
    /// Scheduling variable.
    pub schedule: Option<String>,
    /// Arm angles \[°\] of two LQR designs interpolated linearly in `ρ = 1 − cos θ₁`.
    pub design_points_deg: Option<Vec<f64>>,
    /// Balance gain of `swing-up-balance`.
    pub balance: Option<GainSpec>,
    /// Switch to balance when `|wrap(q₁)|` is below this \[°\].
    pub switch_deg: Option<f64>,
}

/// The `[safety]` table.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SafetySpec {
    /// Clamp \[V\].
    pub voltage_limit: Option<f64>,
    /// Drive travel limit \[m or rad\].
    pub travel_limit: Option<f64>,
    /// Balance window \[°\]; ignored (no window) for `swing-up-balance`.
    pub angle_window_deg: Option<f64>,
    /// Watchdog \[periods\].
    pub watchdog_periods: Option<u32>,
    /// Connect timeout \[s\].
    pub connect_timeout_s: Option<f64>,
}

/// The `[estimator]` table.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatorSpec {
    /// Pseudo-differentiator time constant \[s\].
    pub time_constant: Option<f64>,
}

/// A controller ready to run, with the settings of its file.
pub struct Loaded {
    /// The plant.
    pub plant: PlantKind,
    /// Loop period \[s\].
    pub ts: f64,
    /// The controller.
    pub controller: Box<dyn Controller>,
    /// Limits.
    pub safety: Safety,
    /// Pseudo-differentiator time constant \[s\].
    pub differentiator_t: f64,
    /// The controller kind (for messages).
    pub kind: String,
}

impl std::fmt::Debug for Loaded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Loaded")
            .field("plant", &self.plant)
            .field("ts", &self.ts)
            .field("kind", &self.kind)
            .field("safety", &self.safety)
            .finish_non_exhaustive()
    }
}

fn cfg(msg: impl Into<String>) -> RigError {
    RigError::Config(msg.into())
}

fn finite(what: &str, v: &[f64]) -> Result<(), RigError> {
    if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(cfg(format!("{what}[{i}] = {x}: must be finite")));
    }
    Ok(())
}

fn row(what: &str, v: &[f64], n: usize) -> Result<Mat, RigError> {
    if v.len() != n {
        return Err(cfg(format!("{what} has {} entries, expected {n}", v.len())));
    }
    finite(what, v)?;
    Ok(Mat::from_row_slice(1, n, v))
}

/// The upright linearisation of the book plant (`C = I`).
fn upright(plant: PlantKind) -> Result<StateSpace<pendulab_lti::Continuous>, RigError> {
    match plant {
        PlantKind::Cart => CartPendulum::book().linearize(CartEquilibrium::upright()),
        PlantKind::Arm => ArmPendulum::book().linearize(ArmEquilibrium::upright(0.0)),
    }
    .map_err(|e| cfg(format!("linearising the {} plant: {e}", plant.name())))
}

fn diag(what: &str, q: &[f64], n: usize) -> Result<Mat, RigError> {
    if q.len() != n {
        return Err(cfg(format!(
            "{what} has {} diagonal entries, expected {n}",
            q.len()
        )));
    }
    finite(what, q)?;
    if let Some((i, x)) = q.iter().enumerate().find(|(_, x)| **x < 0.0) {
        return Err(cfg(format!("{what}[{i}] = {x}: must be ≥ 0")));
    }
    Ok(Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q)))
}

fn check_r(r: f64) -> Result<Mat, RigError> {
    if !(r.is_finite() && r > 0.0) {
        return Err(cfg(format!("lqr.r = {r}: must be > 0")));
    }
    Ok(Mat::from_element(1, 1, r))
}

/// The library gain `K` (1 × 4) of a [`GainSpec`]-like triple.
fn gain(
    plant: PlantKind,
    k: &Option<Vec<f64>>,
    k_book: &Option<Vec<f64>>,
    l: &Option<LqrSpec>,
    what: &str,
) -> Result<Mat, RigError> {
    match (k, k_book, l) {
        (Some(k), None, None) => row(&format!("{what}.k"), k, 4),
        (None, Some(kb), None) => Ok(-row(&format!("{what}.k_book"), kb, 4)?),
        (None, None, Some(l)) => {
            let sys = upright(plant)?;
            let d = lqr(
                &sys,
                &diag(&format!("{what}.lqr.q"), &l.q, 4)?,
                &check_r(l.r)?,
                None,
            )
            .map_err(|e| cfg(format!("{what}: LQR design failed: {e}")))?;
            Ok(d.gain)
        }
        _ => Err(cfg(format!("{what}: give exactly one of k, k_book, lqr"))),
    }
}

/// Two LQR designs of the arm at `θ₁ₑ = a, b` (degrees), joined by the line in `ρ = 1 − cos θ₁`
/// through both: `K(ρ) = K_a + (ρ − ρ_a)/(ρ_b − ρ_a)·(K_b − K_a)` as coefficients `[K₀, K₁]`.
fn scheduled_lqr(
    plant: PlantKind,
    l: &LqrSpec,
    pts: &[f64],
    schedule: Option<&str>,
) -> Result<Vec<Mat>, RigError> {
    if plant != PlantKind::Arm {
        return Err(cfg(
            "controller.design_points_deg: only the arm's linearisation depends on the drive position",
        ));
    }
    if schedule.is_some_and(|s| s != "one-minus-cos-q0") {
        return Err(cfg(
            "controller.design_points_deg interpolates in one-minus-cos-q0 only",
        ));
    }
    finite("controller.design_points_deg", pts)?;
    let rho = |deg: f64| 1.0 - deg.to_radians().cos();
    if pts.len() != 2 || (rho(pts[0]) - rho(pts[1])).abs() < 1e-6 {
        return Err(cfg(format!(
            "controller.design_points_deg = {pts:?}: give two angles with different |θ₁|"
        )));
    }
    let q = diag("controller.lqr.q", &l.q, 4)?;
    let r = check_r(l.r)?;
    let mut k = Vec::new();
    for &deg in pts {
        let sys = ArmPendulum::book()
            .linearize(ArmEquilibrium::upright(deg.to_radians()))
            .map_err(|e| cfg(format!("linearising the arm at {deg}°: {e}")))?;
        k.push(
            lqr(&sys, &q, &r, None)
                .map_err(|e| cfg(format!("LQR design at θ₁ = {deg}° failed: {e}")))?
                .gain,
        );
    }
    let (ra, rb) = (rho(pts[0]), rho(pts[1]));
    let k1 = (&k[1] - &k[0]) / (rb - ra);
    let k0 = &k[0] - &k1 * ra;
    Ok(vec![k0, k1])
}

/// Parses and builds a controller file.
///
/// # Errors
/// [`RigError::Config`] naming the key and what is wrong (TOML syntax errors carry the line).
pub fn load(text: &str) -> Result<Loaded, RigError> {
    let file: ControllerFile =
        toml::from_str(text).map_err(|e| cfg(format!("controller file: {e}")))?;
    let plant = PlantKind::parse(&file.plant)?;
    let rate = file.rate_hz.unwrap_or(1000.0);
    if !(rate.is_finite() && (10.0..=50_000.0).contains(&rate)) {
        return Err(cfg(format!("rate_hz = {rate}: must be in [10, 50000]")));
    }
    let ts = 1.0 / rate;
    let c = &file.controller;
    let mut safety = Safety::default_for(plant);
    let s = &file.safety;
    if let Some(v) = s.voltage_limit {
        if !(v.is_finite() && v > 0.0) {
            return Err(cfg(format!("safety.voltage_limit = {v}: must be > 0")));
        }
        safety.voltage_limit = v;
    }
    if let Some(v) = s.travel_limit {
        if !(v.is_finite() && v > 0.0) {
            return Err(cfg(format!("safety.travel_limit = {v}: must be > 0")));
        }
        safety.travel_limit = v;
    }
    if let Some(v) = s.angle_window_deg {
        if !(v.is_finite() && v > 0.0 && v <= 180.0) {
            return Err(cfg(format!(
                "safety.angle_window_deg = {v}: must be in (0, 180]"
            )));
        }
        safety.angle_window = Some(v.to_radians());
    }
    if let Some(v) = s.watchdog_periods {
        if v == 0 {
            return Err(cfg("safety.watchdog_periods = 0: must be ≥ 1"));
        }
        safety.watchdog_periods = v;
    }
    if let Some(v) = s.connect_timeout_s {
        if !(v.is_finite() && v > 0.0 && v < 3600.0) {
            return Err(cfg(format!(
                "safety.connect_timeout_s = {v}: must be in (0, 3600)"
            )));
        }
        safety.connect_timeout = Duration::from_secs_f64(v);
    }
    let differentiator_t = file.estimator.time_constant.unwrap_or(0.02);
    if !(differentiator_t.is_finite() && differentiator_t > 0.0) {
        return Err(cfg(format!(
            "estimator.time_constant = {differentiator_t}: must be > 0"
        )));
    }

    let controller: Box<dyn Controller> = match c.kind.as_str() {
        "state-feedback" => {
            let k = gain(plant, &c.k, &c.k_book, &c.lqr, "controller")?;
            let r = c.reference.clone().unwrap_or(vec![0.0; 4]);
            if r.len() != 4 {
                return Err(cfg(format!(
                    "controller.reference has {} entries, expected 4",
                    r.len()
                )));
            }
            finite("controller.reference", &r)?;
            Box::new(
                StaticStateFeedback::new(k)
                    .and_then(|f| f.with_reference(&r))
                    .map_err(|e| cfg(format!("controller: {e}")))?,
            )
        }
        "lq-servo" => {
            let (k1, k2) = match (&c.k1, c.k2, &c.lqr) {
                (Some(k1), Some(k2), None) => {
                    finite("controller.k2", &[k2])?;
                    (row("controller.k1", k1, 4)?, Mat::from_element(1, 1, k2))
                }
                (None, None, Some(l)) => {
                    let lin = upright(plant)?;
                    let cs = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
                    let sys = StateSpace::continuous(
                        lin.a().clone(),
                        lin.b().clone(),
                        cs,
                        Mat::zeros(1, 1),
                    )
                    .map_err(|e| cfg(format!("servo model: {e}")))?;
                    let d = lq_servo(&sys, &diag("controller.lqr.q", &l.q, 5)?, &check_r(l.r)?)
                        .map_err(|e| cfg(format!("controller: LQ servo design failed: {e}")))?;
                    (d.state_gain, d.integral_gain)
                }
                _ => {
                    return Err(cfg(
                        "controller (lq-servo): give k1 and k2, or lqr = { q = [5 entries], r }",
                    ));
                }
            };
            let r = c.reference.clone().unwrap_or(vec![0.0]);
            if r.len() != 1 {
                return Err(cfg(format!(
                    "controller.reference of an lq-servo is one value (of q0), got {}",
                    r.len()
                )));
            }
            finite("controller.reference", &r)?;
            let t_step = c.step_time.unwrap_or(0.0);
            let sig = Signal::step(t_step, r[0])
                .map_err(|e| cfg(format!("controller.step_time = {t_step}: {e}")))?;
            Box::new(
                LqIntegralServo::new(
                    &k1,
                    &k2,
                    &Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
                    vec![sig],
                    ts,
                    IntegrationRule::ForwardEuler,
                )
                .map_err(|e| cfg(format!("controller: {e}")))?,
            )
        }
        "gain-scheduled" => {
            let mats = match (&c.coefficients, &c.lqr, &c.design_points_deg) {
                (Some(coefs), None, None) => {
                    if coefs.is_empty() {
                        return Err(cfg("controller.coefficients: give at least K0"));
                    }
                    coefs
                        .iter()
                        .enumerate()
                        .map(|(i, k)| row(&format!("controller.coefficients[{i}]"), k, 4))
                        .collect::<Result<Vec<_>, _>>()?
                }
                (None, Some(l), Some(pts)) => scheduled_lqr(plant, l, pts, c.schedule.as_deref())?,
                _ => {
                    return Err(cfg(
                        "controller (gain-scheduled): give coefficients, or lqr with design_points_deg (arm)",
                    ));
                }
            };
            let sched = c.schedule.as_deref().unwrap_or("one-minus-cos-q0");
            let g = match sched {
                "one-minus-cos-q0" => GainScheduled::polynomial(&mats, |y| 1.0 - y[0].cos()),
                "q0-squared" => GainScheduled::polynomial(&mats, |y| y[0] * y[0]),
                other => {
                    return Err(cfg(format!(
                        "controller.schedule = '{other}': expected 'one-minus-cos-q0' or 'q0-squared'"
                    )));
                }
            }
            .map_err(|e| cfg(format!("controller: {e}")))?;
            Box::new(g)
        }
        "swing-up-balance" => {
            let b = c
                .balance
                .as_ref()
                .ok_or_else(|| cfg("controller (swing-up-balance): balance = { … } is missing"))?;
            let k = gain(plant, &b.k, &b.k_book, &b.lqr, "controller.balance")?;
            let sw = c.switch_deg.unwrap_or(17.0);
            if !(sw.is_finite() && sw > 0.0 && sw <= 180.0) {
                return Err(cfg(format!(
                    "controller.switch_deg = {sw}: must be in (0, 180]"
                )));
            }
            let balance =
                StaticStateFeedback::new(k).map_err(|e| cfg(format!("controller: {e}")))?;
            // The pendulum starts hanging: no balance window.
            safety.angle_window = None;
            let windows = vec![(1, sw.to_radians())];
            match plant {
                PlantKind::Cart => Box::new(
                    CartEnergyShaping::new(&CartPendulum::book(), EnergyShapingGains::cart_rig())
                        .and_then(|s| swing_up_then_balance(s, balance, windows))
                        .map_err(|e| cfg(format!("controller: {e}")))?,
                ),
                PlantKind::Arm => Box::new(
                    ArmEnergyShaping::new(&ArmPendulum::book(), EnergyShapingGains::arm_rig())
                        .and_then(|s| swing_up_then_balance(s, balance, windows))
                        .map_err(|e| cfg(format!("controller: {e}")))?,
                ),
            }
        }
        other => {
            return Err(cfg(format!(
                "controller.kind = '{other}': expected state-feedback, lq-servo, gain-scheduled or swing-up-balance"
            )));
        }
    };
    Ok(Loaded {
        plant,
        ts,
        controller,
        safety,
        differentiator_t,
        kind: c.kind.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cart_lqr_design_reproduces_the_book_gain() {
        // examples.md, cdip_lqr_sim: Q = diag(10, 10, 0, 0), R = 1 gives
        // K_book = [3.16228, 13.47175, 4.48137, 2.26289]; u = +K_book x means the library's
        // u = −K x has K = −K_book. The printed digits bound the agreement (5e-5).
        let l = load(
            "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n",
        )
        .unwrap();
        let mut u = [0.0];
        let mut c = l.controller;
        let kb = [3.16228, 13.47175, 4.48137, 2.26289];
        for i in 0..4 {
            let mut y = [0.0; 4];
            y[i] = 1.0;
            c.update(0.0, &y, &mut u);
            assert!((u[0] - kb[i]).abs() < 5e-5, "K[{i}] = {}", u[0]);
        }
        assert_eq!(l.safety.angle_window, Some(30f64.to_radians()));
    }

    #[test]
    fn cart_lq_servo_design_reproduces_the_book_gains() {
        // examples.md, cdip_lqr_servo_sim: Q = diag(1, 5, 0, 0, 100), R = 1 gives
        // K1_book = [10.39942, 17.76307, 6.79089, 3.04513], K2_book = −10 (u = K1 x + K2 w,
        // w = ∫(r − z)). At rest with y = e_i and r = 0 the first command is +K1_book·e_i
        // (forward Euler: w is still 0). Printed digits bound the agreement (5e-5).
        let text = "plant = \"cart\"\n[controller]\nkind = \"lq-servo\"\nlqr = { q = [1.0, 5.0, 0.0, 0.0, 100.0], r = 1.0 }\nreference = [0.0]\n";
        let k1b = [10.39942, 17.76307, 6.79089, 3.04513];
        for i in 0..4 {
            let mut c = load(text).unwrap().controller;
            let mut y = [0.0; 4];
            y[i] = 1.0;
            let mut u = [0.0];
            c.update(0.0, &y, &mut u);
            assert!((u[0] - k1b[i]).abs() < 5e-5, "K1[{i}] = {}", u[0]);
        }
        // Integral gain: with y = 0 and r = 1, w = ts after the first period and
        // u = K2_book · w = −10 · 1e-3 at the second.
        let mut c = load(&text.replace("[0.0]", "[1.0]")).unwrap().controller;
        let mut u = [0.0];
        c.update(0.0, &[0.0; 4], &mut u);
        assert_eq!(u[0], 0.0);
        c.update(1e-3, &[0.0; 4], &mut u);
        assert!((u[0] - (-10.0 * 1e-3)).abs() < 5e-8, "{}", u[0]);
    }

    #[test]
    fn bad_files_are_typed_errors_naming_the_key() {
        let cases = [
            (
                "plant = \"boat\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n",
                "boat",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0]\n",
                "controller.k",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"nope\"\n",
                "controller.kind",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\n",
                "exactly one",
            ),
            (
                "plant = \"cart\"\nrate_hz = -1.0\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n",
                "rate_hz",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\n[safety]\nvoltage_limit = 0.0\n",
                "voltage_limit",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [1.0, -1.0, 0.0, 0.0], r = 1.0 }\n",
                "lqr.q[1]",
            ),
            (
                "plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nk = [1.0,1.0,1.0,1.0]\ntypo = 3\n",
                "typo",
            ),
            ("plant = \"cart\"\n[controller\n", "controller file"),
        ];
        for (text, needle) in cases {
            let e = load(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{e:?} should mention {needle:?}");
        }
    }

    #[test]
    fn scheduled_lqr_interpolates_the_two_designs_exactly_at_their_points() {
        // At θ₁ = 0 and 60° the scheduled gain must equal the LQR designed at that angle
        // (the defining property of the interpolation), to rounding.
        let text = "plant = \"arm\"\n[controller]\nkind = \"gain-scheduled\"\nlqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 }\ndesign_points_deg = [0.0, 60.0]\n";
        let sys = |deg: f64| {
            ArmPendulum::book()
                .linearize(ArmEquilibrium::upright(deg.to_radians()))
                .unwrap()
        };
        let q = diag("q", &[5.0, 10.0, 0.1, 0.1], 4).unwrap();
        let r = check_r(1.0).unwrap();
        for deg in [0.0, 60.0] {
            let k = lqr(&sys(deg), &q, &r, None).unwrap().gain;
            let th = deg.to_radians();
            let mut c = load(text).unwrap().controller;
            let mut u0 = [0.0];
            c.update(0.0, &[th, 0.0, 0.0, 0.0], &mut u0);
            if deg != 0.0 {
                // u = −K(ρ)·[θ₁, 0, 0, 0] = −K₀₀(ρ) θ₁.
                let k0 = -u0[0] / th;
                assert!((k0 - k[(0, 0)]).abs() < 1e-9 * k[(0, 0)].abs(), "{k0}");
            }
            for i in 1..4 {
                // The law is linear in y at fixed ρ (ρ depends on θ₁ only).
                let mut y = [th, 0.0, 0.0, 0.0];
                y[i] = 1.0;
                let mut u1 = [0.0];
                c.update(0.0, &y, &mut u1);
                let ki = -(u1[0] - u0[0]);
                assert!(
                    (ki - k[(0, i)]).abs() < 1e-9 * k[(0, i)].abs().max(1.0),
                    "{deg}° K[{i}]: {ki} vs {}",
                    k[(0, i)]
                );
            }
        }
    }

    #[test]
    fn swing_up_balance_has_no_angle_window() {
        let l = load(
            "plant = \"arm\"\n[controller]\nkind = \"swing-up-balance\"\nbalance = { lqr = { q = [5.0, 10.0, 0.1, 0.1], r = 1.0 } }\n",
        )
        .unwrap();
        assert_eq!(l.safety.angle_window, None);
        assert_eq!((l.controller.ny(), l.controller.nu()), (4, 1));
    }
}
