//! `kind = "observer"`: observer-based output feedback from the encoder positions (book part 1
//! ch. 7, §7.4, example 7.1).
//!
//! The design model is the plant's upright linearisation (the arm at `θ₁ₑ = 0`) with the
//! measured outputs the two encoder positions, `y_m = [q₀, q₁]` (`C = [I₂ 0]`). The state
//! feedback `u = −K x̂` (library sign; `k_book` is the book's `u = +K_book x`, `K = −K_book`)
//! is given as `k`, `k_book`, designed by `lqr = {q, r}` or placed at `poles`; the full-order
//! observer `x̂̇ = A x̂ + B u + L (y_m − C x̂)` (library sign `A − LC`; the book writes
//! `A + L_book C`, `L = −L_book`) has its gain `l` given or placed at `observer_poles`. The
//! controller `(A − BK − LC, L, −K)` (`pendulab_lti::design::observer_controller`) is
//! discretised at the loop period by Tustin (default, the book's stand-in for the continuous
//! controller at 1 ms) or ZOH, and runs as [`output_feedback_controller`] does. It reads the
//! positions `y[0]`, `y[1]` of the rig's 4-entry measurement and ignores the velocity
//! estimates. (`pendulab-control` has no minimal-order observer; the kind is full order.)
//!
//! Poles are written as `[re, im]` pairs in rad/s, a complex pole with its conjugate.

use super::{LqrSpec, SpecError, gain, row};
use crate::estimation::output_feedback_controller;
use pendulab_lti::design::{StateFeedback, observer_controller, place, place_observer};
use pendulab_lti::linalg::{eigenvalues, sort_eigenvalues};
use pendulab_lti::{Complex64, Continuous, Discretization, Mat, StateSpace};
use pendulab_plants::spec::PlantParameters;
use pendulab_sim::Controller;

kind_keys! {
    /// Keys of `kind = "observer"` (module documentation of [`crate::spec::observer`]).
    pub struct ObserverSpec {
        /// Library state-feedback gain `K` (`u = −K x̂`), 4 entries.
        pub k: Option<Vec<f64>>,
        /// The book's gain `K_book` (`u = +K_book x̂`), 4 entries.
        pub k_book: Option<Vec<f64>>,
        /// An LQR design of `K` (`q` of length 4).
        pub lqr: Option<LqrSpec>,
        /// Closed-loop poles of `A − BK` \[rad/s\], 4 `[re, im]` pairs (pole placement).
        pub poles: Option<Vec<[f64; 2]>>,
        /// Library observer gain `L` (`A − LC`), 4 rows of 2 entries (columns `q₀`, `q₁`).
        pub l: Option<Vec<Vec<f64>>>,
        /// Observer poles, eigenvalues of `A − LC` \[rad/s\], 4 `[re, im]` pairs.
        pub observer_poles: Option<Vec<[f64; 2]>>,
        /// `"tustin"` (default) or `"zoh"`.
        pub discretization: Option<String>,
    }
}

/// An observer-based design on a plant: its model, gains and closed-loop poles.
#[derive(Debug, Clone, PartialEq)]
pub struct ObserverDesign {
    /// The design model: the upright linearisation with outputs `[q₀, q₁]`.
    pub model: StateSpace<Continuous>,
    /// State-feedback gain `K` (1 × 4, `u = −K x̂`).
    pub k: Mat,
    /// Observer gain `L` (4 × 2, `A − LC`).
    pub l: Mat,
    /// The continuous closed loop's eigenvalues: of the plant `(A, B, C)` in feedback with the
    /// controller `(A_c, B_c, C_c) = (A − BK − LC, L, −K)`, i.e. of
    /// `[[A, B C_c], [B_c C, A_c]]` (8 values, sorted as `pendulab_lti::linalg::sort_eigenvalues`).
    pub closed_loop_poles: Vec<Complex64>,
}

fn poles(key: &str, p: &[[f64; 2]]) -> Result<Vec<Complex64>, SpecError> {
    if p.len() != 4 {
        return Err(SpecError::Length {
            key: key.to_string(),
            entries: "poles",
            got: p.len(),
            expected: 4,
        });
    }
    let flat: Vec<f64> = p.iter().flatten().copied().collect();
    super::finite(key, &flat)?;
    Ok(p.iter().map(|&[re, im]| Complex64::new(re, im)).collect())
}

/// Designs the observer-based controller `c` describes on `plant` (module documentation).
///
/// # Errors
/// [`SpecError`] naming the key: gains or poles missing, given twice, of the wrong length or
/// not finite; a failed placement or LQR design; a model that cannot be formed.
pub fn observer_design(
    plant: &PlantParameters,
    c: &ObserverSpec,
) -> Result<ObserverDesign, SpecError> {
    let full = super::upright(plant)?;
    let cm = Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let model = StateSpace::continuous(full.a().clone(), full.b().clone(), cm, Mat::zeros(2, 1))
        .map_err(SpecError::ServoModel)?;
    let design = |what: &str| {
        let what = what.to_string();
        move |source| SpecError::Design { what, source }
    };
    let given = [
        c.k.is_some(),
        c.k_book.is_some(),
        c.lqr.is_some(),
        c.poles.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err(SpecError::Keys {
            key: "controller (observer)".into(),
            expected: "give exactly one of k, k_book, lqr, poles",
        });
    }
    let k = match &c.poles {
        Some(p) => {
            place(model.a(), model.b(), &poles("controller.poles", p)?)
                .map_err(design("controller: pole placement"))?
                .gain
        }
        None => gain(plant, &c.k, &c.k_book, &c.lqr, "controller")?,
    };
    let l = match (&c.l, &c.observer_poles) {
        (Some(rows), None) => {
            if rows.len() != 4 {
                return Err(SpecError::Length {
                    key: "controller.l".into(),
                    entries: "rows",
                    got: rows.len(),
                    expected: 4,
                });
            }
            let mut l = Mat::zeros(4, 2);
            for (i, r) in rows.iter().enumerate() {
                l.set_row(i, &row(&format!("controller.l[{i}]"), r, 2)?.row(0));
            }
            l
        }
        (None, Some(p)) => {
            place_observer(
                model.a(),
                model.c(),
                &poles("controller.observer_poles", p)?,
            )
            .map_err(design("controller: observer pole placement"))?
            .gain
        }
        _ => {
            return Err(SpecError::Keys {
                key: "controller (observer)".into(),
                expected: "give exactly one of l, observer_poles",
            });
        }
    };
    let ctrl = observer_controller(&model, &k, &l).map_err(design("controller: observer"))?;
    let (a, b, cc) = (model.a(), model.b(), model.c());
    let mut acl = Mat::zeros(8, 8);
    acl.view_mut((0, 0), (4, 4)).copy_from(a);
    acl.view_mut((0, 4), (4, 4)).copy_from(&(b * ctrl.c()));
    acl.view_mut((4, 0), (4, 4)).copy_from(&(ctrl.b() * cc));
    acl.view_mut((4, 4), (4, 4)).copy_from(ctrl.a());
    let mut closed_loop_poles =
        eigenvalues(&acl).map_err(design("controller: closed-loop eigenvalues"))?;
    sort_eigenvalues(&mut closed_loop_poles);
    Ok(ObserverDesign {
        model,
        k,
        l,
        closed_loop_poles,
    })
}

/// The running controller of `c` on `plant` at loop period `ts`.
pub(super) fn observer(
    plant: &PlantParameters,
    c: &ObserverSpec,
    ts: f64,
) -> Result<Box<dyn Controller>, SpecError> {
    let method = match c.discretization.as_deref() {
        None | Some("tustin") => Discretization::Tustin { prewarp: None },
        Some("zoh") => Discretization::Zoh,
        Some(other) => {
            return Err(SpecError::Keys {
                key: format!("controller.discretization = \"{other}\""),
                expected: "must be \"tustin\" or \"zoh\"",
            });
        }
    };
    let d = observer_design(plant, c)?;
    let fb = StateFeedback::new(d.k.clone()).map_err(|source| SpecError::Design {
        what: "controller: state feedback".into(),
        source,
    })?;
    let inner = output_feedback_controller(&d.model, &fb, &d.l, ts, method)?;
    Ok(Box::new(Positions {
        inner,
        positions: [0.0; 2],
    }))
}

/// A controller of the two encoder positions run on the rig's 4-entry measurement
/// `[q₀, q₁, q̇₀, q̇₁]`: it passes `[q₀, q₁]` on and ignores the velocity estimates.
struct Positions<C> {
    inner: C,
    positions: [f64; 2],
}

impl<C: Controller> Controller for Positions<C> {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        self.inner.nu()
    }
    fn reset(&mut self) {
        self.inner.reset()
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.positions = [y[0], y[1]];
        self.inner.update(t, &self.positions, u)
    }
    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }
}
