//! Wrapping angles: the one home of the workspace's angle wrapping.
//!
//! A pendulum angle read from an incremental encoder is **multi-turn**: raising the pendulum to
//! the top the other way round from its hanging rest reads one turn (`2π`) more than raising
//! it directly. Every controller that stabilises an equilibrium must act on the angle wrapped
//! to that equilibrium, or it sees an error of `2π` and saturates. The rig runtime, the
//! simulators, the swing-up switch and the safety checks all wrap with the functions here, so
//! they agree on the convention:
//!
//! - [`wrap_angle`]`(θ)` ∈ `(−π, π]`, the representative of `θ` modulo `2π` nearest to `0`
//!   (upright), ties (`θ ≡ π`) going to `+π`;
//! - [`wrap_about`]`(θ, c) = c + wrap_angle(θ − c)` ∈ `(c − π, c + π]`, the representative nearest
//!   to the centre `c` (e.g. `c = π` for a controller of the hanging rest).
//!
//! Only **pendulum** angles wrap. The drive position `q₀` — the cart position, or the arm
//! angle `θ₁` whose turns count (the arm's cable and its travel limit see every turn) — is
//! never wrapped.
//!
//! Both functions are exact up to the rounding of `θ − c` and of the one subtraction of `2π`
//! that `rem_euclid` makes (absolute error below `|θ|·2⁻⁵²` or so); NaN and ±∞ give NaN.
//!
//! ```
//! use pendulab_plants::{wrap_about, wrap_angle};
//! use std::f64::consts::PI;
//! assert!((wrap_angle(2.0 * PI + 0.1) - 0.1).abs() < 1e-15);
//! assert_eq!(wrap_angle(-PI), PI);
//! // The hanging rest read one turn on, wrapped about the hanging equilibrium.
//! assert!((wrap_about(3.0 * PI + 0.2, PI) - (PI + 0.2)).abs() < 1e-14);
//! ```

use std::f64::consts::PI;

/// `θ` wrapped to `(−π, π]` \[rad\]: `θ − 2πn` with the integer `n` that lands it there
/// (the closed form `n = ⌈(θ − π)/2π⌉`). `−π` maps to `+π`; NaN and ±∞ give NaN.
#[inline]
pub fn wrap_angle(theta: f64) -> f64 {
    let w = (theta + PI).rem_euclid(2.0 * PI) - PI;
    // rem_euclid lies in [0, 2π], so w ∈ [−π, π]: move the closed end.
    if w <= -PI { PI } else { w }
}

/// `θ` wrapped to `(c − π, c + π]` about the centre `c` \[rad\]: `c + wrap_angle(θ − c)`, the
/// representative of `θ` modulo `2π` nearest to `c`. NaN in either argument gives NaN.
#[inline]
pub fn wrap_about(theta: f64, centre: f64) -> f64 {
    centre + wrap_angle(theta - centre)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form `θ − 2π⌈(θ − π)/2π⌉`, evaluated independently of `rem_euclid`.
    fn closed_form(theta: f64) -> f64 {
        theta - 2.0 * PI * ((theta - PI) / (2.0 * PI)).ceil()
    }

    #[test]
    fn matches_the_closed_form_and_atan2() {
        // Angles a + 2πn with a away from the ends ±π, n up to 1000 turns.
        for n in [-1000i32, -7, -2, -1, 0, 1, 2, 3, 1000] {
            for i in -99..=99 {
                let a = i as f64 * 0.0313; // |a| ≤ 3.099 < π
                let theta = a + 2.0 * PI * n as f64;
                let got = wrap_angle(theta);
                // Rounding of θ (|θ| ≤ 6.3e3, ulp 9e-13) and of the closed form's subtraction.
                let tol = 4.0 * f64::EPSILON * theta.abs().max(1.0);
                assert!((got - a).abs() <= tol, "wrap({theta}) = {got}, a = {a}");
                assert!((got - closed_form(theta)).abs() <= tol);
                // A second independent algorithm: atan2 of the sine and cosine.
                assert!((got - theta.sin().atan2(theta.cos())).abs() <= 1e-9 + tol);
                assert!(got > -PI && got <= PI);
            }
        }
    }

    #[test]
    fn the_ends_go_to_plus_pi() {
        for theta in [PI, -PI, 3.0 * PI, -3.0 * PI] {
            let got = wrap_angle(theta);
            // ±π, ±3π are not exact multiples in floating point: the result is π up to the
            // rounding of 3π, on the closed side (never −π).
            assert!((got - PI).abs() < 1e-14, "wrap({theta}) = {got}");
            assert!(got > -PI && got <= PI, "wrap({theta}) = {got}");
        }
        // Just past the ends: the other side.
        assert!((wrap_angle(PI + 1e-3) - (-PI + 1e-3)).abs() < 1e-14);
        assert!((wrap_angle(-PI - 1e-3) - (PI - 1e-3)).abs() < 1e-14);
    }

    #[test]
    fn non_finite_gives_nan() {
        assert!(wrap_angle(f64::NAN).is_nan());
        assert!(wrap_angle(f64::INFINITY).is_nan());
        assert!(wrap_angle(f64::NEG_INFINITY).is_nan());
        assert!(wrap_about(0.1, f64::NAN).is_nan());
        assert!(wrap_about(f64::NAN, PI).is_nan());
    }

    #[test]
    fn about_a_centre_is_the_nearest_representative() {
        for centre in [0.0, PI, -PI / 2.0, 10.0] {
            for i in -40..=40 {
                let theta = i as f64 * 0.37;
                let got = wrap_about(theta, centre);
                // Same angle: a whole number of turns away.
                let turns = (got - theta) / (2.0 * PI);
                assert!((turns - turns.round()).abs() < 1e-12);
                // Nearest to the centre: within half a turn, on the half-open interval.
                assert!(got > centre - PI - 1e-12 && got <= centre + PI + 1e-12);
            }
        }
    }
}
