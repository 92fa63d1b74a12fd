//! Open-loop commands through the sampled-data loop.

use crate::controller::Controller;
use crate::signal::Signal;

/// An open-loop "controller" `u_k = s(t_k)`: a preset command sequence sampled and held like
/// any controller's (e.g. the voltage steps of an identification experiment). It ignores the
/// measurement, whose length it declares as `ny`.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenLoop {
    signals: Vec<Signal>,
    ny: usize,
}

impl OpenLoop {
    /// Commands `u_i(t_k) = signals[i](t_k)` for a loop whose measurement has `ny` entries.
    pub fn new(signals: Vec<Signal>, ny: usize) -> Self {
        Self { signals, ny }
    }
}

impl Controller for OpenLoop {
    fn ny(&self) -> usize {
        self.ny
    }
    fn nu(&self) -> usize {
        self.signals.len()
    }
    fn reset(&mut self) {}
    #[inline]
    fn update(&mut self, t: f64, _y: &[f64], u: &mut [f64]) {
        for (ui, s) in u.iter_mut().zip(&self.signals) {
            *ui = s.value(t);
        }
    }
}
