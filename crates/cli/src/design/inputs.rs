//! The flags' words read as numbers and poles, and written back: the weights and poles every
//! `pendulab design` method takes (`--q`, `--poles`, `--observer-poles`), checked for count and
//! finiteness, with errors naming the flag.

use anyhow::{Context, Result, bail};
use pendulab_lti::Complex64;

/// Numbers written in the file's and the design record's form: `{x:?}` joined by `, `.
pub(super) fn list(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:?}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Numbers separated by spaces or commas, each finite, `n` of them; errors name `flag`.
pub(super) fn numbers(flag: &str, text: &str, n: usize) -> Result<Vec<f64>> {
    let v = text
        .split([' ', ',', ';'])
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            let x: f64 = s
                .trim()
                .parse()
                .with_context(|| format!("{flag}: '{s}' is not a number"))?;
            if !x.is_finite() {
                bail!("{flag}: {x} is not a finite number");
            }
            Ok(x)
        })
        .collect::<Result<Vec<f64>>>()?;
    if v.len() != n {
        bail!(
            "{flag}: {n} numbers expected, found {} in '{text}'",
            v.len()
        );
    }
    Ok(v)
}

/// Four finite poles in the open left half-plane, written as [`parse_pole`] reads them;
/// errors name `flag`.
pub(super) fn four_poles(flag: &str, text: &str) -> Result<Vec<Complex64>> {
    let p: Vec<Complex64> = text
        .split([' ', ',', ';'])
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            parse_pole(s).with_context(|| {
                format!("{flag}: '{s}' is not a pole (write -3, or -3+2j with -3-2j)")
            })
        })
        .collect::<Result<_>>()?;
    if p.len() != 4 {
        bail!("{flag}: 4 poles expected, found {} in '{text}'", p.len());
    }
    if let Some(bad) = p.iter().find(|z| !(z.re.is_finite() && z.im.is_finite())) {
        bail!("{flag}: {bad} is not finite");
    }
    if let Some(bad) = p.iter().find(|z| z.re >= 0.0) {
        bail!(
            "{flag}: {bad} is not in the open left half-plane: the closed loop would not be stable"
        );
    }
    Ok(p)
}

/// Poles as `[re, im]` rows (the design record's form).
pub(super) fn pole_rows(p: &[Complex64]) -> Vec<Vec<f64>> {
    p.iter().map(|z| vec![z.re, z.im]).collect()
}

/// Poles in words, `[-3+1i, …]`.
pub(super) fn pole_words(p: &[Complex64]) -> String {
    let listed: Vec<String> = p.iter().map(|z| format!("{z}")).collect();
    format!("[{}]", listed.join(", "))
}

/// A pole `re`, `re+imj` or `re-imj` (also `i`).
pub(super) fn parse_pole(s: &str) -> Option<Complex64> {
    let s = s.trim();
    if let Some(body) = s.strip_suffix('j').or_else(|| s.strip_suffix('i')) {
        // The sign of the imaginary part: the last + or − that is not an exponent's.
        let b = body.as_bytes();
        let at = (1..b.len())
            .rev()
            .find(|&i| (b[i] == b'+' || b[i] == b'-') && !matches!(b[i - 1], b'e' | b'E'))?;
        let re: f64 = body[..at].parse().ok()?;
        let im: f64 = body[at..].parse().ok()?;
        return Some(Complex64::new(re, im));
    }
    s.parse().ok().map(|re| Complex64::new(re, 0.0))
}

#[cfg(test)]
mod tests {
    use super::parse_pole;
    use pendulab_lti::Complex64;

    #[test]
    fn poles_parse_in_their_written_forms() {
        assert_eq!(parse_pole("-3"), Some(Complex64::new(-3.0, 0.0)));
        assert_eq!(parse_pole("-3+2j"), Some(Complex64::new(-3.0, 2.0)));
        assert_eq!(parse_pole("-3-2.5i"), Some(Complex64::new(-3.0, -2.5)));
        assert_eq!(parse_pole("-1e-1-2e+0j"), Some(Complex64::new(-0.1, -2.0)));
        assert_eq!(parse_pole("x"), None);
    }
}
