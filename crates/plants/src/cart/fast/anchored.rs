//! The anchored-trig RK4 step of [`FastCart`](super::FastCart) with [`Trig::Anchored`](pendulab_sim::fast::Trig::Anchored) on one
//! state: series sines and cosines near upright and the stages' angles by the addition
//! theorem, for short (1 ms) and long (20 ms) steps. Two variants, by the step length:
//!
//! - steps of at most 2⁻⁸ s (the 1 ms loops): `narrow_anchored_step`, written once for both
//!   multiply–adds of
//!   [`FixedDynamics::rk4_step_fixed_with`](pendulab_sim::fast::FixedDynamics::rk4_step_fixed_with)
//!   (the kernel's FMA-compiled loop takes it with fused multiply–adds): series sines and
//!   cosines at three angles fixed by the step's start, the third and fourth stages'
//!   accelerations by a rotation through the small offsets their angles add, and every
//!   stage's θ̇-dependence folded into one multiply–add; each sine and cosine within
//!   1.5 ulp + 2.5·10⁻¹⁷ of libm's at its angle, the rotations within 1.5 ulp of theirs
//!   (see there);
//! - longer steps (e.g. the 20 ms of the CartPole-v1 environment,
//!   `pendulab_sim::env::FixedEnv`, whose angles up to 12° and stage offsets `(h/2)·θ̇`,
//!   `h·θ̇` mostly exceed 1/32): `anchored_step`, the first angle's sine and cosine by one
//!   series within [`FastCart::ANCHORED_ANGLE_LIMIT`](super::FastCart::ANCHORED_ANGLE_LIMIT)
//!   of upright (`wide_angle_series`) and the later stages' from them by the addition theorem
//!   with `wide_shift_series` for offsets up to
//!   [`FastCart::ANCHORED_SHIFT_LIMIT`](super::FastCart::ANCHORED_SHIFT_LIMIT) (libm beyond),
//!   within 2 ulp + 6·10⁻¹⁷ and 2 ulp + 1.1·10⁻¹⁶ of libm's. One series rather than tiers,
//!   because an episode's random angles would mispredict the choice between tiers about
//!   every third step. This variant always uses separate multiplications and additions.

use super::super::CartPendulum;
use super::FastCart;
use pendulab_sim::fast::{
    COS_TAYLOR, MulAdd, ROTATE_LIMIT, SIN_TAYLOR, rotate_small, sin_cos_near_zero, sin_cos_offset,
};

/// One anchored RK4 step of `h` with `u` held, in place: the narrow step with the
/// multiply–adds of `F` for `h ≤ 2⁻⁸ s`, the wide step otherwise.
#[inline(always)]
pub(super) fn step<F: MulAdd>(plant: &CartPendulum, x: &mut [f64; 4], u: f64, h: f64) {
    if h <= NARROW_STEP_LIMIT {
        *x = plant.narrow_anchored_step::<F>(x, u, h);
    } else {
        let theta = x[1];
        let (s, c) = anchor_sin_cos(theta);
        *x = plant.anchored_step(x, u, h, (s, c), |d| stage_sin_cos(theta, d, s, c));
    }
}

/// Steps up to this length (s) take `narrow_anchored_step` (its stage offsets stay within
/// the rotation's range for accelerations up to `2⁻¹⁴/(h²/2)`, 122 rad/s² at 1 ms); longer
/// ones `anchored_step` with the wide series (see the module docs).
const NARROW_STEP_LIMIT: f64 = 1.0 / 256.0;

pub(super) const WIDE_ANGLE_LIMIT: f64 = FastCart::ANCHORED_ANGLE_LIMIT;
pub(super) const WIDE_SHIFT_LIMIT: f64 = FastCart::ANCHORED_SHIFT_LIMIT;

/// The sine and cosine of an anchored RK4 step's first angle for steps longer than 2⁻⁸ s:
/// [`wide_angle_series`] for `|θ| ≤` [`WIDE_ANGLE_LIMIT`], libm beyond (and for NaN); within
/// 2 ulp + 6·10⁻¹⁷ of libm (checked in this module's tests over the whole range). One series
/// for the whole range: the random angles of an environment's episodes would mispredict the
/// choice between narrower series about every third step.
#[inline(always)]
pub(super) fn anchor_sin_cos(theta: f64) -> (f64, f64) {
    if theta.abs() <= WIDE_ANGLE_LIMIT {
        wide_angle_series(theta)
    } else {
        theta.sin_cos()
    }
}

/// `(sin(θ + d), cos(θ + d))` of an RK4 stage angle from `(s, c) = (sin θ, cos θ)` for steps
/// longer than 2⁻⁸ s: the addition theorem of [`sin_cos_offset`] with
/// [`wide_shift_series`] for `|d| ≤` [`WIDE_SHIFT_LIMIT`] (one series for the whole range,
/// as [`anchor_sin_cos`]), libm's `(θ + d).sin_cos()` beyond (and for NaN).
#[inline(always)]
pub(super) fn stage_sin_cos(theta: f64, d: f64, s: f64, c: f64) -> (f64, f64) {
    if d.abs() <= WIDE_SHIFT_LIMIT {
        let (sd, cm1) = wide_shift_series(d);
        (s + (s * cm1 + c * sd), c + (c * cm1 - s * sd))
    } else {
        (theta + d).sin_cos()
    }
}

/// `(sin x, cos x)` for `|x| ≤ 1/4` by their Taylor series to `x¹¹` and `x¹²` (the first
/// omitted terms, `x¹³/13! < 2.5·10⁻¹⁸` and `x¹⁴/14! < 5·10⁻²⁰`, are far below half an ulp),
/// the polynomials in `z = x²` evaluated in Estrin's pairing: `sin x = x + x·z·P(z)`,
/// `cos x = 1 + z·Q(z)`. The correction terms are at most `x³/6 < 2.7·10⁻³` and
/// `x²/2 ≤ 1/32`, so their few roundings cost ≲ 2·10⁻¹⁷ and the final addition half an ulp.
#[inline(always)]
fn wide_angle_series(x: f64) -> (f64, f64) {
    const S: [f64; 5] = SIN_TAYLOR;
    const C: [f64; 6] = COS_TAYLOR;
    let z = x * x;
    let z2 = z * z;
    let p = (S[0] + S[1] * z) + z2 * ((S[2] + S[3] * z) + S[4] * z2);
    let q = (C[0] + C[1] * z) + z2 * ((C[2] + C[3] * z) + z2 * (C[4] + C[5] * z));
    (x + (x * z) * p, 1.0 + z * q)
}

/// `(sin d, cos d − 1)` for `|d| ≤ 1/8` by their Taylor series to `d⁹` and `d¹⁰` (the first
/// omitted terms, `d¹¹/11! < 3·10⁻¹⁸` and `d¹²/12! < 2·10⁻²⁰`), Estrin's pairing in `z = d²`;
/// as the series of `pendulab_sim::fast::sin_cos_offset` with two more terms each.
#[inline(always)]
fn wide_shift_series(d: f64) -> (f64, f64) {
    // The first four and five coefficients.
    const S: [f64; 5] = SIN_TAYLOR;
    const C: [f64; 6] = COS_TAYLOR;
    let z = d * d;
    let z2 = z * z;
    let p = (S[0] + S[1] * z) + z2 * (S[2] + S[3] * z);
    let q = (C[0] + C[1] * z) + z2 * ((C[2] + C[3] * z) + C[4] * z2);
    (d + (d * z) * p, z * q)
}

impl CartPendulum {
    /// One classic RK4 step of [`Trig::Anchored`](pendulab_sim::fast::Trig::Anchored) for steps of at most 2⁻⁸ s, with the
    /// multiply–adds `a·b + c` of `F`. With `x = [z, θ, v, ω]` (`v = ż`, `ω = θ̇`),
    /// `G = m_p g l_p/J`, `M = μ_p/J`, `L = m_p l_p/J`, `α = a_c`, `β = b_c` and the stage
    /// values of RK4 (`v_k`, `ω_k`, `θ_k` the stage states, `a_k = z̈`, `b_k = θ̈` their
    /// derivatives), the stages substituted into one another give
    ///
    /// ```text
    /// a₁ = βu − αv,        a₂ = a₁ − α(h/2)a₁,   a₃ = a₁ − α(h/2)a₂,   a₄ = a₁ − αh·a₃
    /// b₁ = G sin θ − Mω − L cos θ · a₁
    /// b₂ = (G sin θ₂ − Mω − L cos θ₂ · a₂) − M(h/2)·b₁,               θ₂ = θ + (h/2)ω
    /// b₃ = (G sin θ₃ − Mω − L cos θ₃ · a₃) − M(h/2)·b₂,   θ₃ = θ₂ + e₃,  e₃ = (h²/4)·b₁
    /// b₄ = (G sin θ₄ − Mω − L cos θ₄ · a₄) − Mh·b₃,       θ₄ = θ₄' + e₄, e₄ = (h²/2)·b₂,
    ///                                                      θ₄' = θ + hω
    /// z' = (z + hv) + (h²/6)·(a₁ + a₂ + a₃),   θ' = θ₄' + (h²/6)·(b₁ + b₂ + b₃)
    /// v' = v + (h/6)·((a₁ + a₄) + 2(a₂ + a₃)),  ω' = (ω + (h/6)·(b₁ + 2b₂ + 2b₃)) + (h/6)·b₄
    /// ```
    ///
    /// (the damping `−Mω_k = −Mω − M·c_k h·b_{k−1}` folded into one multiply–add per stage;
    /// `v_k`, `ω_k` never formed). The sines and cosines of the three angles fixed by the
    /// step's start, `θ`, `θ₂` and `θ₄'` (each rounded once with [`Fused`](pendulab_sim::fast::Fused), twice
    /// with [`Separate`](pendulab_sim::fast::Separate) — as the general loop rounds `θ₂`), come from
    /// [`sin_cos_near_zero`] (series within 1/4 rad of upright, libm beyond), each within
    /// 1.5 ulp + 2.5·10⁻¹⁷ of libm's, off the chain that runs through `u` and `θ̈`. The third
    /// and fourth stages' angles add `e = e₃, e₄` (|e| ~ 10⁻⁵ at 1 ms), and by the addition
    /// theorem `G sin(θ_b + e) − L a cos(θ_b + e) = P cos e + Q sin e` with
    /// `P = G sin θ_b − L a cos θ_b`, `Q = G cos θ_b + L a sin θ_b`, so their accelerations are
    /// [`rotate_small`]`(P, Q, e, −Mω)`: three operations after `e` instead of a stage sine
    /// and cosine and the products after them. It is within 1.5 ulp + 6·10⁻¹⁹·(|P| + |Q|) of
    /// the exact rotation for `|e| ≤` [`ROTATE_LIMIT`] (2⁻¹⁴); larger offsets (|θ̈| above
    /// 244 or 122 rad/s² at 1 ms) and NaN take the stage sine and cosine from
    /// [`sin_cos_offset`] instead. Every stage's acceleration is thus that of sines and
    /// cosines within 1.5 ulp + 2.5·10⁻¹⁷ of libm's at the stage angle (up to the rounding of
    /// the base angle, half an ulp of `θ` or two), plus a few roundings of its terms.
    #[inline(always)]
    fn narrow_anchored_step<F: MulAdd>(&self, x: &[f64; 4], u: f64, h: f64) -> [f64; 4] {
        let ma = F::mul_add;
        let [z, theta, v, w] = *x;
        let (alpha, beta) = (self.drive.a(), self.drive.b());
        let (g, m, l) = (self.pendulum.mgl_j, self.pendulum.mu_j, self.pendulum.ml_j);
        let h2 = 0.5 * h;
        let hq = h2 * h2;
        let hh = hq + hq;
        let h6 = h * (1.0 / 6.0);
        let hs = h * h6;
        let (ah2, mh2) = (alpha * h2, m * h2);
        // The three angles fixed by the step's start (off the chain through `u`).
        let (s1, c1) = sin_cos_near_zero::<F>(theta);
        let theta2 = ma(h2, w, theta);
        let (s2, c2) = sin_cos_near_zero::<F>(theta2);
        let theta4 = ma(h, w, theta);
        let (s4, c4) = sin_cos_near_zero::<F>(theta4);
        let mw = m * w;
        // Stages 1 and 2.
        let a1 = ma(beta, u, -(alpha * v));
        let b1 = ma(-(l * c1), a1, ma(g, s1, -mw));
        let a2 = ma(-ah2, a1, a1);
        let (gs2, lc2) = (g * s2, l * c2);
        let b2 = ma(-mh2, b1, ma(-lc2, a2, gs2 - mw));
        // Stage 3: the acceleration at θ₂ rotated by e₃.
        let a3 = ma(-ah2, a2, a1);
        let e3 = hq * b1;
        let k3 = if e3.abs() <= ROTATE_LIMIT {
            let p = ma(-lc2, a3, gs2);
            let q = ma(l * s2, a3, g * c2);
            rotate_small::<F>(p, q, e3, -mw)
        } else {
            let (s3, c3) = sin_cos_offset(theta2, e3, s2, c2);
            ma(-(l * c3), a3, ma(g, s3, -mw))
        };
        let b3 = ma(-mh2, b2, k3);
        // Stage 4: the acceleration at θ + hω rotated by e₄.
        let a4 = ma(-(ah2 + ah2), a3, a1);
        let e4 = hh * b2;
        let k4 = if e4.abs() <= ROTATE_LIMIT {
            let p = ma(-(l * c4), a4, g * s4);
            let q = ma(l * s4, a4, g * c4);
            rotate_small::<F>(p, q, e4, -mw)
        } else {
            let (s4e, c4e) = sin_cos_offset(theta4, e4, s4, c4);
            ma(-(l * c4e), a4, ma(g, s4e, -mw))
        };
        let b4 = ma(-(mh2 + mh2), b3, k4);
        // The four updates in different shapes: alike ones would be paired into vector
        // registers, which makes z wait for θ (measured: the controller's sum, which starts
        // with z, then sits on the chain).
        [
            ma(h, v, z) + hs * ((a1 + a2) + a3),
            ma(hs, (b1 + b2) + b3, theta4),
            ma(h6, (a1 + a4) + 2.0 * (a2 + a3), v),
            ma(h6, b4, ma(h6, (b1 + 2.0 * b2) + 2.0 * b3, w)),
        ]
    }

    /// One RK4 step of [`Trig::Anchored`](pendulab_sim::fast::Trig::Anchored) for steps longer than 2⁻⁸ s (the operations of
    /// [`pendulab_sim::fast::rk4_fixed`] with the pendulum's constants divided by `J`
    /// beforehand and the last stage's term added last), given `(s, c)`, the sine and cosine
    /// of the step's first angle `θ` ([`anchor_sin_cos`]: a series near upright, libm
    /// beyond); `shift(d)` returns those of a stage angle `θ + d` ([`stage_sin_cos`]) for the
    /// offsets
    /// themselves, `d = (h/2)·θ̇₁, (h/2)·θ̇₂, h·θ̇₃` — never recovered from a rounded angle,
    /// which keeps the round trip `(θ + d) − θ` off the step's dependency chain. The later
    /// offsets are formed as `(h/2)·x₃ + (h/2)²·k₁` and `h·x₃ + (h²/2)·k₂` (`k` the stages'
    /// `θ̈`) rather than from the stage's `θ̇`: one operation less on the chain, the same offset to
    /// an ulp of it.
    #[inline(always)]
    fn anchored_step(
        &self,
        x: &[f64; 4],
        u: f64,
        h: f64,
        (s, c): (f64, f64),
        shift: impl Fn(f64) -> (f64, f64),
    ) -> [f64; 4] {
        let f = |dz: f64, dth: f64, (s, c): (f64, f64)| {
            let ddz = self.drive.acceleration(dz, u);
            (ddz, self.pendulum.acceleration_prescaled(s, c, dth, ddz))
        };
        let half = 0.5 * h;
        let (quarter, hh) = (half * half, h * half);
        let (dz1, dth1) = (x[2], x[3]);
        let (hx, hhx) = (half * dth1, h * dth1);
        let (a1, b1) = f(dz1, dth1, (s, c));
        let (dz2, dth2) = (x[2] + half * a1, x[3] + half * b1);
        let (a2, b2) = f(dz2, dth2, shift(hx));
        let (dz3, dth3) = (x[2] + half * a2, x[3] + half * b2);
        let (a3, b3) = f(dz3, dth3, shift(hx + quarter * b1));
        let (dz4, dth4) = (x[2] + h * a3, x[3] + h * b3);
        let (a4, b4) = f(dz4, dth4, shift(hhx + hh * b2));
        let sixth = h / 6.0;
        // The last stage's term added last and on its own (one operation less after it).
        [
            (x[0] + sixth * (dz1 + 2.0 * dz2 + 2.0 * dz3)) + sixth * dz4,
            (x[1] + sixth * (dth1 + 2.0 * dth2 + 2.0 * dth3)) + sixth * dth4,
            (x[2] + sixth * (a1 + 2.0 * a2 + 2.0 * a3)) + sixth * a4,
            (x[3] + sixth * (b1 + 2.0 * b2 + 2.0 * b3)) + sixth * b4,
        ]
    }
}
