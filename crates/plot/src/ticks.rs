//! Axis scales, limits and tick marks.

/// Ticks of one axis: labelled major positions, unlabelled minor positions, and a common power
/// of ten factored out of the labels (shown once beside the axis).
#[derive(Debug, Clone, Default)]
pub(crate) struct Ticks {
    pub major: Vec<(f64, String)>,
    pub minor: Vec<f64>,
    pub multiplier: Option<String>,
}

/// The "nice" step (1, 2, 2.5 or 5 × 10ᵏ) nearest above `raw`.
pub(crate) fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let e = raw.log10().floor();
    let base = 10f64.powf(e);
    let m = raw / base;
    let nice = if m <= 1.0 + 1e-9 {
        1.0
    } else if m <= 2.0 + 1e-9 {
        2.0
    } else if m <= 2.5 + 1e-9 {
        2.5
    } else if m <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    nice * base
}

/// Limits `[lo, hi]` widened outwards to multiples of a nice step for about `target` intervals.
pub(crate) fn nice_limits(lo: f64, hi: f64, target: usize) -> (f64, f64) {
    let step = nice_step((hi - lo) / target.max(1) as f64);
    snap_limits(lo, hi, step)
}

/// Limits widened outwards to multiples of `step`.
pub(crate) fn snap_limits(lo: f64, hi: f64, step: f64) -> (f64, f64) {
    let a = (lo / step - 1e-9).floor() * step;
    let b = (hi / step + 1e-9).ceil() * step;
    (a, b)
}

/// Decimals needed to print multiples of `step` exactly.
fn decimals(step: f64) -> usize {
    for d in 0..=12 {
        let v = step * 10f64.powi(d as i32);
        if (v - v.round()).abs() < 1e-6 * v.abs().max(1e-12) {
            return d;
        }
    }
    12
}

/// Prints `v` with `d` decimals and a typographic minus sign.
pub(crate) fn format_number(v: f64, d: usize) -> String {
    let s = format!("{:.*}", d, v);
    let s = if s
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    };
    s.replace('-', "\u{2212}")
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// `10ᵏ` with Unicode superscripts.
pub(crate) fn power_of_ten(k: i32) -> String {
    let mut s = String::from("10");
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(SUPERSCRIPTS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// Linear ticks on `[lo, hi]`, about `target` intervals.
pub(crate) fn linear_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    let step = nice_step((hi - lo) / target.max(1) as f64);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let mut values = Vec::new();
    for k in first..=last.min(first.saturating_add(200)) {
        values.push(k as f64 * step);
    }
    let max_abs = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (factor, multiplier) = if max_abs >= 1e5 || (max_abs > 0.0 && max_abs < 1e-3) {
        let k = max_abs.log10().floor() as i32;
        (10f64.powi(k), Some(format!("×{}", power_of_ten(k))))
    } else {
        (1.0, None)
    };
    let d = decimals(step / factor);
    let major = values
        .iter()
        .map(|&v| (v, format_number(v / factor, d)))
        .collect();
    let minor_step = step
        / if (step / 10f64.powf(step.log10().floor()) - 2.0).abs() < 1e-6 {
            4.0
        } else {
            5.0
        };
    let mut minor = Vec::new();
    let mf = (lo / minor_step).ceil() as i64;
    let ml = (hi / minor_step).floor() as i64;
    if ml.saturating_sub(mf) < 400 {
        for k in mf..=ml {
            minor.push(k as f64 * minor_step);
        }
    }
    Ticks {
        major,
        minor,
        multiplier,
    }
}

/// Ticks at the multiples of a given step (at most 200).
pub(crate) fn stepped_ticks(lo: f64, hi: f64, step: f64) -> Ticks {
    let n = ((hi - lo) / step).abs();
    if !(n.is_finite()) || n > 200.0 {
        return linear_ticks(lo, hi, 6);
    }
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let d = decimals(step);
    Ticks {
        major: (first..=last)
            .map(|k| {
                let v = k as f64 * step;
                (v, format_number(v, d))
            })
            .collect(),
        minor: Vec::new(),
        multiplier: None,
    }
}

/// Logarithmic ticks on `[lo, hi]` (both > 0): decades labelled `10ᵏ`, minor ticks at 2…9 × 10ᵏ.
pub(crate) fn log_ticks(lo: f64, hi: f64, max_labels: usize) -> Ticks {
    let k0 = lo.log10().floor() as i32;
    let k1 = hi.log10().ceil() as i32;
    let decades: Vec<i32> = (k0..=k1)
        .filter(|&k| {
            let v = 10f64.powi(k);
            v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9)
        })
        .collect();
    let every = decades.len().div_ceil(max_labels.max(2)).max(1);
    let mut major: Vec<(f64, String)> = decades
        .iter()
        .filter(|k| ((**k - decades[0]) as usize).is_multiple_of(every))
        .map(|&k| (10f64.powi(k), power_of_ten(k)))
        .collect();
    let mut minor = Vec::new();
    for k in k0..=k1 {
        for m in 2..=9 {
            let v = m as f64 * 10f64.powi(k);
            if v >= lo && v <= hi {
                minor.push(v);
            }
        }
    }
    if major.len() < 2 {
        // Less than a decade: label the 1-2-5 positions.
        major.clear();
        for k in k0..=k1 {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(k);
                if v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9) {
                    let d = if k < 0 { (-k) as usize } else { 0 };
                    major.push((v, format_number(v, d)));
                }
            }
        }
    }
    Ticks {
        major,
        minor,
        multiplier: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(0.7), 1.0);
        assert_eq!(nice_step(1.3), 2.0);
        assert_eq!(nice_step(0.23), 0.25);
        assert!((nice_step(0.031) - 0.05).abs() < 1e-15);
        assert_eq!(nice_step(420.0), 500.0);
    }

    #[test]
    fn limits_cover_the_data_on_tick_multiples() {
        // Range 0.2686 over 10 intervals: raw step 0.02686, next nice step 0.05.
        let (a, b) = nice_limits(-0.0312, 0.2374, 10);
        assert!(a <= -0.0312 && b >= 0.2374);
        assert!((a - -0.05).abs() < 1e-12 && (b - 0.25).abs() < 1e-12);
    }

    #[test]
    fn labels_use_common_decimals_and_minus_sign() {
        let t = linear_ticks(-1.0, 1.0, 4);
        let labels: Vec<&str> = t.major.iter().map(|(_, s)| s.as_str()).collect();
        assert_eq!(labels, ["\u{2212}1.0", "\u{2212}0.5", "0.0", "0.5", "1.0"]);
        let t = linear_ticks(0.0, 3000.0, 3);
        assert_eq!(t.major.last().unwrap().1, "3000");
        let t = linear_ticks(0.0, 4e-4, 4);
        assert_eq!(t.multiplier.as_deref(), Some("×10⁻⁴"));
    }

    #[test]
    fn log_ticks_are_decades() {
        let t = log_ticks(0.1, 1000.0, 10);
        let labels: Vec<&str> = t.major.iter().map(|(_, s)| s.as_str()).collect();
        assert_eq!(labels, ["10⁻¹", "10⁰", "10¹", "10²", "10³"]);
        assert_eq!(t.minor.len(), 4 * 8);
    }
}
