//! `kind = "gain-scheduled"`: state feedback whose gain follows a scheduling variable `ρ`
//! measured at every sample, as a regulator or as an LQ integral servo.
//!
//! # The gain
//!
//! The gain `K(ρ)` is given in one of three ways (exactly one):
//!
//! | keys | `K(ρ)` | source |
//! |---|---|---|
//! | `coefficients = [K₀, K₁, …]` | `K₀ + ρ K₁ + ρ² K₂ + …` | any polynomial design |
//! | `lqr` + `design_points_deg` | the line in `ρ` through two LQR designs of the arm | [`GainScheduledSpec::design_points_deg`] |
//! | `x_coefficients = [X₀, X₁, …]` + `l_coefficients = [L₀, L₁, …]` | `−L(ρ) X(ρ)⁻¹`, `X(ρ) = X₀ + ρ X₁ + …`, `L(ρ) = L₀ + ρ L₁ + …` | the SOS/LMI gain-scheduled LQ design (book part 2 §1.5, example 1.7, `pendulab_lmi::synthesis::gain_scheduled_lq`) |
//!
//! All gains are in the library's sign, `u = −K(ρ) z` (the crate's [`super`] conventions). The
//! book's M-file `p2c15_ex7_adip_oc_gs_servo.m` writes the same law as `u = K z` with
//! `K = L*inv(X)` (its `X_0, X_1, X_2`, `L_0, L_1, L_2` are `x_coefficients`,
//! `l_coefficients` here, unchanged): its `K` is `K_book = −K(ρ) = L(ρ) X(ρ)⁻¹`.
//!
//! The scheduling variable is `schedule`: `"one-minus-cos-q0"` (default), the book's
//! `ρ = 1 − cos θ₁` (the M-file's `rho`, `para = 1 - cos(th)`), or `"q0-squared"`,
//! `ρ = q₀²`; `q₀` is the measured drive position (the arm angle `θ₁` \[rad\]).
//!
//! Where `X(ρ)` is not positive definite — only outside the range the design certified — the
//! `−L X⁻¹` gain has no meaning and the command is 0 V there (as the book example's
//! controller). `X(0)` must be positive definite: every run starts near `q₀ = 0`, `ρ = 0`.
//!
//! # Regulator or integral servo
//!
//! The width `n` of the gain decides (every coefficient the same width):
//!
//! - `n = 4`: the regulator `u = −K(ρ) y`, `y = [q₀, q₁, q̇₀, q̇₁]`; no `reference`.
//! - `n = 5`: the LQ integral servo of the drive position on `z = [y; w]`,
//!   `w = ∫(r − q₀) dt` (the M-file's augmented state, `At = [A 0; −C 0]`,
//!   `C = [1 0 0 0]`): `u = −K(ρ) z = −K₁(ρ) y − K₂(ρ) w`. The integrator, the reference
//!   and its checks are those of `lq-servo`: `pendulab_sim::controllers::LqIntegralServo`'s
//!   forward Euler at the loop period (`w_k = w_{k−1} + ts (r_{k−1} − q₀,ₖ₋₁)`), the
//!   reference `reference` (one value, m or rad, default 0) as a step at `step_time` \[s\]
//!   (default 0), or a scenario's reference signal instead of both.

use super::{ControllerSpec, LqrSpec, SpecError, check_r, diag, drive_reference, finite, row};
use nalgebra::SMatrix;
use pendulab_lti::Mat;
use pendulab_lti::design::lqr;
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::PlantParameters;
use pendulab_sim::Controller;
use pendulab_sim::controllers::{GainScheduled, IntegrationRule, LqIntegralServo};
use pendulab_sim::signal::Signal;

kind_keys! {
    /// Keys of `kind = "gain-scheduled"` (module documentation of [`crate::spec::scheduled`]):
    /// `coefficients`; or `lqr` with `design_points_deg`; or `x_coefficients` with
    /// `l_coefficients`; `schedule`; `reference` and `step_time` for a 5-state (servo) gain.
    pub struct GainScheduledSpec {
        /// Gain-polynomial coefficients `K₀, K₁, …` (library sign, `u = −K(ρ) z`): 4 entries each
        /// (regulator; \[V/m or V/rad, V/rad, V·s/m or V·s/rad, V·s/rad\]) or 5 (integral servo,
        /// the fifth \[V/(m·s) or V/(rad·s)\] on `w`); `K_i` multiplies `ρ^i`.
        pub coefficients: Option<Vec<Vec<f64>>>,
        /// Scheduling variable `ρ`: `"one-minus-cos-q0"` (`ρ = 1 − cos q₀`, default; the book's
        /// `ρ = 1 − cos θ₁`) or `"q0-squared"` (`ρ = q₀²`).
        pub schedule: Option<String>,
        /// LQR design at each of `design_points_deg`.
        pub lqr: Option<LqrSpec>,
        /// Arm angles \[°\] of two LQR designs interpolated linearly in `ρ = 1 − cos θ₁`.
        pub design_points_deg: Option<Vec<f64>>,
        /// Coefficients `X₀, X₁, …` of `X(ρ) = Σ ρ^i X_i` (the M-file's `X_0, X_1, X_2`), each
        /// an `n × n` symmetric matrix as `n` rows, `n` = 4 (regulator) or 5 (servo on
        /// `[y; w]`). `z X(ρ)⁻¹ z` is the design's Lyapunov function (so `X_i` has the units of
        /// `z zᵀ`: m², rad², …). With `l_coefficients`: `K(ρ) = −L(ρ) X(ρ)⁻¹`.
        pub x_coefficients: Option<Vec<Vec<Vec<f64>>>>,
        /// Coefficients `L₀, L₁, …` of `L(ρ) = Σ ρ^i L_i` (the M-file's `L_0, L_1, L_2`), each a
        /// row of `n` entries (`L = K_book X`: volts times the units of `z`).
        pub l_coefficients: Option<Vec<Vec<f64>>>,
        /// Servo reference of `q₀` (one entry, m or rad, default 0), applied as a step at
        /// `step_time`; 5-state gains only.
        pub reference: Option<Vec<f64>>,
        /// Time of the reference step \[s\], from 0 to [`super::DURATION_MAX`] (default 0);
        /// 5-state gains only.
        pub step_time: Option<f64>,
    }
}

/// The measured states `y = [q₀, q₁, q̇₀, q̇₁]`.
const NY: usize = 4;
/// The servo's gain width: `[y; w]`.
const NZ: usize = NY + 1;

/// The scheduling variable `φ(z)` named by `schedule` (default `"one-minus-cos-q0"`).
fn schedule_fn(schedule: Option<&str>) -> Result<fn(&[f64]) -> f64, SpecError> {
    let phi: fn(&[f64]) -> f64 = match schedule.unwrap_or("one-minus-cos-q0") {
        "one-minus-cos-q0" => |z| 1.0 - z[0].cos(),
        "q0-squared" => |z| z[0] * z[0],
        other => return Err(SpecError::Schedule(other.to_string())),
    };
    Ok(phi)
}

/// Two LQR designs of the arm at `θ₁ₑ = a, b` (degrees), joined by the line in `ρ = 1 − cos θ₁`
/// through both: `K(ρ) = K_a + (ρ − ρ_a)/(ρ_b − ρ_a)·(K_b − K_a)` as coefficients `[K₀, K₁]`.
fn scheduled_lqr(
    plant: &PlantParameters,
    l: &LqrSpec,
    pts: &[f64],
    schedule: Option<&str>,
) -> Result<Vec<Mat>, SpecError> {
    if plant.kind() != PlantKind::Arm {
        return Err(SpecError::DesignPoints {
            detail: ": only the arm's linearisation depends on the drive position".into(),
        });
    }
    if schedule.is_some_and(|s| s != "one-minus-cos-q0") {
        return Err(SpecError::DesignPoints {
            detail: " interpolates in one-minus-cos-q0 only".into(),
        });
    }
    finite("controller.design_points_deg", pts)?;
    let rho = |deg: f64| 1.0 - deg.to_radians().cos();
    if pts.len() != 2 || (rho(pts[0]) - rho(pts[1])).abs() < 1e-6 {
        return Err(SpecError::DesignPoints {
            detail: format!(" = {pts:?}: give two angles with different |θ₁|"),
        });
    }
    let q = diag("controller.lqr.q", &l.q, 4)?;
    let r = check_r("controller.lqr", l.r)?;
    let mut k = Vec::new();
    for &deg in pts {
        let sys = plant
            .linearize_upright(deg.to_radians())
            .map_err(|source| SpecError::Linearisation {
                at: format!("arm at {deg}°"),
                source,
            })?;
        k.push(
            lqr(&sys, &q, &r, None)
                .map_err(|source| SpecError::Design {
                    what: format!("LQR design at θ₁ = {deg}°"),
                    source,
                })?
                .gain,
        );
    }
    let (ra, rb) = (rho(pts[0]), rho(pts[1]));
    let k1 = (&k[1] - &k[0]) / (rb - ra);
    let k0 = &k[0] - &k1 * ra;
    Ok(vec![k0, k1])
}

/// The gain's width: 4 or 5 from the first coefficient's length, the key named otherwise.
fn width(key: &str, first: usize) -> Result<usize, SpecError> {
    if first == NY || first == NZ {
        Ok(first)
    } else {
        Err(SpecError::Length {
            key: key.to_string(),
            entries: "entries (4 for the regulator, 5 for the servo on [y; w])",
            got: first,
            expected: if first < NZ { NY } else { NZ },
        })
    }
}

/// `X(ρ)`'s and `L(ρ)`'s coefficients read and checked: the same width `n` (4 or 5), finite,
/// each `X_i` symmetric (to 1e-9 of its largest entry; symmetrised), and `X(0) ≻ 0`.
pub(super) fn rational_coefficients(
    x: &[Vec<Vec<f64>>],
    l: &[Vec<f64>],
) -> Result<(Vec<Mat>, Vec<Mat>), SpecError> {
    let Some(x0) = x.first().filter(|_| !l.is_empty()) else {
        return Err(SpecError::Keys {
            key: "controller.x_coefficients, controller.l_coefficients".into(),
            expected: "give at least X0 and L0",
        });
    };
    let n = width("controller.x_coefficients[0]", x0.len())?;
    let mut xs = Vec::with_capacity(x.len());
    for (i, rows) in x.iter().enumerate() {
        let key = format!("controller.x_coefficients[{i}]");
        if rows.len() != n {
            return Err(SpecError::Length {
                key,
                entries: "rows",
                got: rows.len(),
                expected: n,
            });
        }
        let mut m = Mat::zeros(n, n);
        for (r, row_v) in rows.iter().enumerate() {
            m.set_row(r, &row(&format!("{key}[{r}]"), row_v, n)?.row(0));
        }
        let scale = m.amax();
        let asym = (&m - m.transpose()).amax();
        if asym > 1e-9 * scale {
            return Err(SpecError::ScheduleMatrix {
                key,
                detail: format!(
                    "must be symmetric (largest |X − Xᵀ| entry {asym:e} against {scale:e})"
                ),
            });
        }
        xs.push((&m + m.transpose()) * 0.5);
    }
    let ls = l
        .iter()
        .enumerate()
        .map(|(i, v)| row(&format!("controller.l_coefficients[{i}]"), v, n))
        .collect::<Result<Vec<_>, _>>()?;
    if xs[0].clone().cholesky().is_none() {
        return Err(SpecError::ScheduleMatrix {
            key: "controller.x_coefficients[0]".into(),
            detail: "X(0) = X0 must be positive definite (the schedule at ρ = 0, where q0 = 0)"
                .into(),
        });
    }
    Ok((xs, ls))
}

/// `K(ρ) = −L(ρ) X(ρ)⁻¹` (`1 × N`) into `k`, on stack matrices (no allocation): `X(ρ)` by
/// Horner's rule, `Kᵀ = −X⁻¹ Lᵀ` by Cholesky; `k = 0` where `X(ρ)` is not positive definite.
fn rational_gain<const N: usize>(
    x: &[Mat],
    l: &[Mat],
) -> impl Fn(f64, &mut [f64]) + Send + Sync + 'static {
    let xs: Vec<SMatrix<f64, N, N>> = x
        .iter()
        .map(|m| SMatrix::from_fn(|i, j| m[(i, j)]))
        .collect();
    let ls: Vec<SMatrix<f64, N, 1>> = l
        .iter()
        .map(|m| SMatrix::from_fn(|i, _| m[(0, i)]))
        .collect();
    move |rho, k| {
        let xm = xs
            .iter()
            .rev()
            .fold(SMatrix::<f64, N, N>::zeros(), |acc, c| acc * rho + c);
        let lt = ls
            .iter()
            .rev()
            .fold(SMatrix::<f64, N, 1>::zeros(), |acc, c| acc * rho + c);
        match xm.cholesky() {
            Some(ch) => {
                let kt = ch.solve(&lt);
                for (ki, v) in k.iter_mut().zip(kt.iter()) {
                    *ki = -v;
                }
            }
            None => k.fill(0.0),
        }
    }
}

/// The gain `K(ρ)` a [`GainScheduledSpec`] describes, as sim's [`GainScheduled`] on `n` = 4 or
/// 5 measurements (the servo's fifth being `w`), scheduled by `φ(z)`.
fn scheduled_law(
    plant: &PlantParameters,
    c: &GainScheduledSpec,
) -> Result<(GainScheduled, usize), SpecError> {
    let phi = schedule_fn(c.schedule.as_deref())?;
    match (
        &c.coefficients,
        &c.lqr,
        &c.design_points_deg,
        &c.x_coefficients,
        &c.l_coefficients,
    ) {
        (Some(coefs), None, None, None, None) => {
            let Some(first) = coefs.first() else {
                return Err(SpecError::Keys {
                    key: "controller.coefficients".into(),
                    expected: "give at least K0",
                });
            };
            let n = width("controller.coefficients[0]", first.len())?;
            let mats = coefs
                .iter()
                .enumerate()
                .map(|(i, k)| row(&format!("controller.coefficients[{i}]"), k, n))
                .collect::<Result<Vec<_>, _>>()?;
            Ok((GainScheduled::polynomial(&mats, phi)?, n))
        }
        (None, Some(l), Some(pts), None, None) => {
            let mats = scheduled_lqr(plant, l, pts, c.schedule.as_deref())?;
            Ok((GainScheduled::polynomial(&mats, phi)?, NY))
        }
        (None, None, None, Some(x), Some(l)) => {
            let (xs, ls) = rational_coefficients(x, l)?;
            let n = xs[0].nrows();
            let g = if n == NZ {
                GainScheduled::from_fn(1, NZ, rational_gain::<NZ>(&xs, &ls), phi)
            } else {
                GainScheduled::from_fn(1, NY, rational_gain::<NY>(&xs, &ls), phi)
            };
            Ok((g, n))
        }
        _ => Err(SpecError::Keys {
            key: "controller (gain-scheduled)".into(),
            expected: "give coefficients; or lqr with design_points_deg (arm); or x_coefficients with l_coefficients",
        }),
    }
}

/// The factory's branch for `kind = "gain-scheduled"` at loop period `ts` \[s\], with the
/// scenario's drive reference `signal` (servo only).
pub(super) fn gain_scheduled(
    plant: &PlantParameters,
    c: &GainScheduledSpec,
    ts: f64,
    signal: Option<Signal>,
) -> Result<Box<dyn Controller>, SpecError> {
    let (law, n) = scheduled_law(plant, c)?;
    if n == NY {
        if c.reference.is_some() || c.step_time.is_some() {
            return Err(SpecError::Keys {
                key: "controller.reference, controller.step_time".into(),
                expected: "a 4-state gain-scheduled regulator tracks no reference; give 5-state gains (the integral servo on [y; w]) to track one",
            });
        }
        if signal.is_some() {
            return Err(SpecError::Reference {
                kind: ControllerSpec::KINDS[2],
                detail: "a 4-state gain-scheduled regulator tracks no reference",
            });
        }
        return Ok(Box::new(law));
    }
    let sig = drive_reference(ControllerSpec::KINDS[2], &c.reference, c.step_time, signal)?;
    // The integrator alone: an `LqIntegralServo` with K₁ = 0, K₂ = −1 commands u = w, the
    // integral its rule gives at this sample.
    let integrator = LqIntegralServo::new(
        &Mat::zeros(1, NY),
        &Mat::from_element(1, 1, -1.0),
        &Mat::from_row_slice(1, NY, &[1.0, 0.0, 0.0, 0.0]),
        vec![sig],
        ts,
        IntegrationRule::ForwardEuler,
    )?;
    Ok(Box::new(ScheduledServo {
        integrator,
        law,
        z: [0.0; NZ],
        w: [0.0],
    }))
}

/// The scheduled integral servo `u = −K(ρ) [y; w]`, `ρ = φ(y)`: `w` from an integrator-only
/// [`LqIntegralServo`], the gain from a [`GainScheduled`] on `z = [y; w]`.
struct ScheduledServo {
    integrator: LqIntegralServo,
    law: GainScheduled,
    z: [f64; NZ],
    w: [f64; 1],
}

impl Controller for ScheduledServo {
    fn ny(&self) -> usize {
        NY
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {
        self.integrator.reset();
        self.law.reset();
    }
    fn sample_time(&self) -> Option<f64> {
        self.integrator.sample_time()
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.integrator.update(t, y, &mut self.w);
        self.z[..NY].copy_from_slice(y);
        self.z[NY] = self.w[0];
        self.law.update(t, &self.z, u);
    }
}
