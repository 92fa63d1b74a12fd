//! The cart pendulum's right-hand side and RK4 step for `L` states at once (structure of
//! arrays, [`pendulab_sim::fast::lanes`]), with the lane form of the anchored-trig step.
//!
//! Neighbours: `cart.rs` holds the physics and the general `Dynamics` implementation;
//! `anchored.rs` the single-state fixed-size kernel; `tests.rs` checks both against libm.

use super::super::CartPendulum;

/// The right-hand side for `L` states at once (structure of arrays) for
/// [`pendulab_sim::lanes`]: the same operations as [`CartPendulum::derivative_array`], in the
/// same order, per lane, with the sines and cosines from `M`.
impl<const L: usize> pendulab_sim::fast::LaneDynamics<4, L> for CartPendulum {
    #[inline(always)]
    fn derivative_lanes<M: pendulab_sim::fast::SinCos>(
        &self,
        x: &[[f64; L]; 4],
        u: &[f64; L],
    ) -> [[f64; L]; 4] {
        let (s, c) = M::sin_cos(&x[1]);
        let mut ddz = [0.0; L];
        let mut ddtheta = [0.0; L];
        for l in 0..L {
            ddz[l] = self.drive.acceleration(x[2][l], u[l]);
            ddtheta[l] = self.pendulum.acceleration(s[l], c[l], x[3][l], ddz[l]);
        }
        [x[2], x[3], ddz, ddtheta]
    }

    /// With `M::ANCHORED` (`pendulab_sim::fast::AnchoredSinCos`), the lane form of the
    /// [`Trig::Anchored`](pendulab_sim::fast::Trig::Anchored) step (`anchored_step`): the
    /// step's first sines and cosines by `M`, the later stages' from them for the stages'
    /// offsets ([`pendulab_sim::fast::sin_cos_offset_lanes`]), the pendulum's constants
    /// divided by `J` beforehand. If a stage offset of any lane is beyond the series' range,
    /// the whole step is taken by [`pendulab_sim::fast::rk4_lanes`] instead. Other `M`: that
    /// plain step.
    #[inline(always)]
    fn rk4_step_lanes<M: pendulab_sim::fast::SinCos>(
        &self,
        x: &mut [[f64; L]; 4],
        u: &[f64; L],
        h: &[f64; L],
    ) {
        if M::ANCHORED
            && let Some(next) = self.anchored_step_lanes::<M, L>(x, u, h)
        {
            *x = next;
            return;
        }
        pendulab_sim::fast::rk4_lanes::<Self, M, 4, L>(self, x, u, h);
    }
}

impl CartPendulum {
    /// [`CartPendulum::anchored_step`] for `L` lanes; `None` when a stage offset is out of
    /// the series' range in some lane.
    #[inline(always)]
    fn anchored_step_lanes<M: pendulab_sim::fast::SinCos, const L: usize>(
        &self,
        x: &[[f64; L]; 4],
        u: &[f64; L],
        h: &[f64; L],
    ) -> Option<[[f64; L]; 4]> {
        use pendulab_sim::fast::sin_cos_offset_lanes;
        use std::array::from_fn;
        let (s, c) = M::sin_cos(&x[1]);
        let accel = |dz: &[f64; L], dth: &[f64; L], (ss, cc): &([f64; L], [f64; L])| {
            let a: [f64; L] = from_fn(|l| self.drive.acceleration(dz[l], u[l]));
            let b: [f64; L] = from_fn(|l| {
                self.pendulum
                    .acceleration_prescaled(ss[l], cc[l], dth[l], a[l])
            });
            (a, b)
        };
        let half: [f64; L] = from_fn(|l| 0.5 * h[l]);
        let (dz1, dth1) = (x[2], x[3]);
        let (a1, b1) = accel(&dz1, &dth1, &(s, c));
        let dz2: [f64; L] = from_fn(|l| x[2][l] + half[l] * a1[l]);
        let dth2: [f64; L] = from_fn(|l| x[3][l] + half[l] * b1[l]);
        let sc2 = sin_cos_offset_lanes(&from_fn::<f64, L, _>(|l| half[l] * dth1[l]), &s, &c)?;
        let (a2, b2) = accel(&dz2, &dth2, &sc2);
        let dz3: [f64; L] = from_fn(|l| x[2][l] + half[l] * a2[l]);
        let dth3: [f64; L] = from_fn(|l| x[3][l] + half[l] * b2[l]);
        let sc3 = sin_cos_offset_lanes(&from_fn::<f64, L, _>(|l| half[l] * dth2[l]), &s, &c)?;
        let (a3, b3) = accel(&dz3, &dth3, &sc3);
        let dz4: [f64; L] = from_fn(|l| x[2][l] + h[l] * a3[l]);
        let dth4: [f64; L] = from_fn(|l| x[3][l] + h[l] * b3[l]);
        let sc4 = sin_cos_offset_lanes(&from_fn::<f64, L, _>(|l| h[l] * dth3[l]), &s, &c)?;
        let (a4, b4) = accel(&dz4, &dth4, &sc4);
        let sixth: [f64; L] = from_fn(|l| h[l] / 6.0);
        // As in `anchored_step`: the last stage's term added last.
        let step = |x: &[f64; L], k1: &[f64; L], k2: &[f64; L], k3: &[f64; L], k4: &[f64; L]| {
            from_fn::<f64, L, _>(|l| {
                (x[l] + sixth[l] * (k1[l] + 2.0 * k2[l] + 2.0 * k3[l])) + sixth[l] * k4[l]
            })
        };
        Some([
            step(&x[0], &dz1, &dz2, &dz3, &dz4),
            step(&x[1], &dth1, &dth2, &dth3, &dth4),
            step(&x[2], &a1, &a2, &a3, &a4),
            step(&x[3], &b1, &b2, &b3, &b4),
        ])
    }
}
