//! Uniform quantisers: the D/A converter of the drive and the encoders of the rigs.

use crate::error::{Result, check_positive};

/// How a value is mapped to the quantisation grid `{k·q}`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rounding {
    /// To the nearest level, ties away from zero: `q·round(v/q)` — Simulink's Quantizer block
    /// (the book's "with quantizer" library block), and a D/A converter.
    #[default]
    Nearest,
    /// Down to the level below: `q·⌊v/q⌋` — the count of an incremental encoder started at
    /// zero when the motion is positive.
    Floor,
}

/// A uniform quantiser with step `q` (in the units of the signal).
///
/// ```
/// use pendulab_sim::Quantizer;
/// // The rig's 16-bit D/A converter over ±5 V: q = 10/2¹⁶ V.
/// let dac = Quantizer::from_bits(16, 10.0).unwrap();
/// assert_eq!(dac.step(), 10.0 / 65536.0);
/// assert_eq!(dac.apply(1.0e-4), 10.0 / 65536.0 * (1.0e-4f64 * 6553.6).round());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantizer {
    step: f64,
    rounding: Rounding,
}

impl Quantizer {
    /// A round-to-nearest quantiser with step `q > 0`.
    ///
    /// # Errors
    /// [`crate::SimError::InvalidParameter`] unless `q` is finite and positive.
    pub fn new(q: f64) -> Result<Self> {
        check_positive("quantisation step", q)?;
        Ok(Self {
            step: q,
            rounding: Rounding::Nearest,
        })
    }

    /// A quantiser of `bits` bits over a full range `span` (e.g. 10 V for ±5 V):
    /// `q = span / 2^bits`, rounding to nearest.
    ///
    /// # Errors
    /// [`crate::SimError::InvalidParameter`] unless `1 ≤ bits ≤ 52` and `span > 0`.
    pub fn from_bits(bits: u32, span: f64) -> Result<Self> {
        if !(1..=52).contains(&bits) {
            return Err(crate::SimError::InvalidParameter {
                what: "converter bits".into(),
                value: bits as f64,
                requirement: "must be between 1 and 52",
            });
        }
        check_positive("converter span", span)?;
        Self::new(span / f64::powi(2.0, bits as i32))
    }

    /// The same step with another rounding rule.
    pub fn with_rounding(mut self, rounding: Rounding) -> Self {
        self.rounding = rounding;
        self
    }

    /// The step `q`.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// The rounding rule.
    pub fn rounding(&self) -> Rounding {
        self.rounding
    }

    /// The quantised value.
    #[inline]
    pub fn apply(&self, v: f64) -> f64 {
        match self.rounding {
            Rounding::Nearest => self.step * (v / self.step).round(),
            Rounding::Floor => self.step * (v / self.step).floor(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_and_error_bounds() {
        let q = Quantizer::new(0.25).unwrap();
        // Closed forms: nearest level, ties away from zero.
        assert_eq!(q.apply(0.3), 0.25);
        assert_eq!(q.apply(0.375), 0.5);
        assert_eq!(q.apply(-0.375), -0.5);
        assert_eq!(q.apply(-0.1), 0.0);
        let f = q.with_rounding(Rounding::Floor);
        assert_eq!(f.apply(0.49), 0.25);
        assert_eq!(f.apply(-0.01), -0.25);
        // Defining property over a sweep: |Q(v) − v| ≤ q/2 (nearest), 0 ≤ v − Q(v) < q (floor),
        // and Q(v) is a level (an integer multiple of q, here exactly representable).
        let enc = Quantizer::new(2.0 * std::f64::consts::PI / 14400.0).unwrap();
        for i in 0..10_000 {
            let v = -3.0 + 6e-4 * i as f64 + 1e-7;
            let e = enc.apply(v) - v;
            assert!(e.abs() <= 0.5 * enc.step() * (1.0 + 1e-12));
            let n = enc.apply(v) / enc.step();
            assert!((n - n.round()).abs() < 1e-9);
            let d = v - f.apply(v);
            assert!((0.0..0.25).contains(&d));
        }
        assert!(Quantizer::new(0.0).is_err());
        assert!(Quantizer::new(f64::NAN).is_err());
        assert!(Quantizer::from_bits(0, 10.0).is_err());
        assert_eq!(
            Quantizer::from_bits(16, 10.0).unwrap().step(),
            10.0 / 65536.0
        );
    }
}
