//! `pendulab design robust`: one state-feedback gain with the LMI guaranteed LQ cost at every
//! vertex of a box of plant parameters `value · (1 ± P/100)` around the lab's values (book
//! part 2 §1.3, `pendulab_lmi::synthesis::robust_state_feedback`), with optional pole regions
//! `−β < Re λ < −α` at every vertex.

use super::Designed;
use super::inputs::list;
use super::methods::{state_feedback_loop, state_feedback_table, weights};
use anyhow::{Context, Result, bail};
use pendulab_control::spec::DesignInput;
use pendulab_lmi::SolveOptions;
use pendulab_lmi::synthesis::{Region, Vertex, robust_state_feedback};
use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_plants::spec::PlantSpec;

/// The pole regions of `--decay-rate α` (`Re λ < −α`) and `--speed-limit β` (`Re λ > −β`),
/// `0 < α < β`; errors name the flag.
fn regions(decay_rate: Option<f64>, speed_limit: Option<f64>) -> Result<Vec<Region>> {
    let mut regions = Vec::new();
    if let Some(alpha) = decay_rate {
        if !(alpha.is_finite() && alpha > 0.0) {
            bail!("--decay-rate {alpha}: must be a finite number > 0");
        }
        regions.push(Region::DecayRate { alpha });
    }
    if let Some(beta) = speed_limit {
        if !(beta.is_finite() && beta > decay_rate.unwrap_or(0.0)) {
            bail!("--speed-limit {beta}: must be a finite number > 0 and > --decay-rate");
        }
        regions.push(Region::SpeedLimit { beta });
    }
    Ok(regions)
}

/// The `--vary` arguments as `(parameter, fraction)`, 1 to 4 distinct parameters of `plant`;
/// errors name the argument.
fn ranges(vary: &[String], plant: &PlantSpec) -> Result<Vec<(String, f64)>> {
    let nominal = plant.parameters().entries();
    let ranges = vary
        .iter()
        .map(|v| parse_vary(v, &nominal))
        .collect::<Result<Vec<_>>>()?;
    if ranges.len() > 4 {
        bail!(
            "--vary: at most 4 parameters (16 vertices), {} given",
            ranges.len()
        );
    }
    if let Some((i, (name, _))) = ranges
        .iter()
        .enumerate()
        .find(|(i, (n, _))| ranges[..*i].iter().any(|(m, _)| m == n))
    {
        bail!("--vary {}: {name} is given twice", vary[i]);
    }
    Ok(ranges)
}

/// The arguments of `design robust` (module documentation).
pub(super) struct RobustArgs<'a> {
    /// `Q`'s diagonal, four weights.
    pub q: &'a str,
    /// `R` (> 0).
    pub r: f64,
    /// The `NAME=±P%` ranges.
    pub vary: &'a [String],
    /// `α` of `Re λ < −α`.
    pub decay_rate: Option<f64>,
    /// `β` of `Re λ > −β`.
    pub speed_limit: Option<f64>,
}

/// `robust`: the common gain of the box's vertices; the poles given are the lab's nominal
/// plant's. Errors: a bad argument, an unsolved LMI, a vertex's pole outside the region or the
/// open left half-plane.
pub(super) fn robust(
    plant: &PlantSpec,
    ss: &StateSpace<Continuous>,
    args: &RobustArgs<'_>,
) -> Result<Designed> {
    let RobustArgs {
        q,
        r,
        vary,
        decay_rate,
        speed_limit,
    } = *args;
    let regions = regions(decay_rate, speed_limit)?;
    let qv = weights(q, r, 4)?;
    let ranges = ranges(vary, plant)?;
    let vertices = box_vertices(plant.parameters(), &ranges)?;
    let qm = Mat::from_diagonal(&nalgebra::DVector::from_vec(qv.clone()));
    let d = robust_state_feedback(
        &vertices,
        &qm,
        &Mat::from_element(1, 1, r),
        &regions,
        &SolveOptions::default(),
    )
    .with_context(|| format!("robust LQ with Q = diag({}), R = {r}", list(&qv)))?;
    let Some(f) = d.feedback else {
        bail!(
            "robust LQ with Q = diag({}), R = {r}: no common gain found for the {} vertices (status {:?}); nothing written",
            list(&qv),
            vertices.len(),
            d.status
        );
    };
    let worst = f
        .closed_loop_poles
        .iter()
        .flatten()
        .map(|z| z.re)
        .fold(f64::NEG_INFINITY, f64::max);
    if !f.poles_in_regions {
        bail!(
            "robust LQ: a vertex's closed-loop poles are not all inside the requested region; nothing written"
        );
    }
    if worst >= 0.0 {
        bail!(
            "robust LQ: a vertex's closed loop has a pole with real part {worst}; nothing written"
        );
    }
    let k: Vec<f64> = f.gain.row(0).iter().copied().collect();
    let nominal_poles = pendulab_lti::linalg::eigenvalues(&(ss.a() - ss.b() * &f.gain))?;
    let loop_ss = state_feedback_loop(ss, f.gain)?;
    let words: Vec<String> = ranges
        .iter()
        .map(|(n, frac)| format!("{n} ± {}%", frac * 100.0))
        .collect();
    let mut record = vec![
        ("q".to_string(), DesignInput::List(qv.clone())),
        ("r".to_string(), DesignInput::Number(r)),
    ];
    if let Some(alpha) = decay_rate {
        record.push(("decay_rate".to_string(), DesignInput::Number(alpha)));
    }
    if let Some(beta) = speed_limit {
        record.push(("speed_limit".to_string(), DesignInput::Number(beta)));
    }
    for (n, frac) in &ranges {
        record.push((format!("vary_{n}"), DesignInput::Number(*frac)));
    }
    Ok(Designed {
        table: state_feedback_table(&k),
        k,
        poles: nominal_poles,
        loop_ss: Some(loop_ss),
        inputs: format!(
            "Q = diag([{}]), R = {r}, robust over the {} vertices of {} (largest closed-loop real part over the vertices {worst:.4} 1/s; the poles printed are the lab's nominal plant's)",
            list(&qv),
            vertices.len(),
            words.join(", ")
        ),
        note: "",
        record,
        schedule: None,
    })
}

/// `NAME=±P%` (or `NAME=+-P%`): the parameter `NAME` of `nominal` and the fraction `P/100`,
/// `0 < P < 100`; errors name the argument.
fn parse_vary(text: &str, nominal: &[(String, f64)]) -> Result<(String, f64)> {
    let Some((name, range)) = text.split_once('=') else {
        bail!("--vary {text}: write NAME=±P%, e.g. m_p=±10%");
    };
    let name = name.trim();
    if !nominal.iter().any(|(n, _)| n == name) {
        let names: Vec<&str> = nominal.iter().map(|(n, _)| n.as_str()).collect();
        bail!(
            "--vary {text}: '{name}' is not a parameter of the lab's plant ({})",
            names.join(", ")
        );
    }
    let p = range
        .trim()
        .strip_prefix('±')
        .or_else(|| range.trim().strip_prefix("+-"))
        .and_then(|r| r.strip_suffix('%'))
        .and_then(|r| r.trim().parse::<f64>().ok());
    match p {
        Some(p) if p > 0.0 && p < 100.0 => Ok((name.to_string(), p / 100.0)),
        _ => bail!("--vary {text}: the range must be ±P% with 0 < P < 100"),
    }
}

/// The upright linearisations at the `2ⁿ` vertices of the box `value · (1 ± fraction)` of the
/// `n` varied parameters (the others at their lab values), in binary order of the ends
/// (first parameter slowest).
fn box_vertices(
    nominal: &pendulab_plants::spec::PlantParameters,
    ranges: &[(String, f64)],
) -> Result<Vec<Vertex>> {
    let n = ranges.len();
    (0..1usize << n)
        .map(|corner| {
            let entries = nominal.entries().into_iter().map(|(name, v)| {
                match ranges.iter().position(|(r, _)| *r == name) {
                    Some(i) => {
                        let sign = if corner >> (n - 1 - i) & 1 == 1 {
                            1.0
                        } else {
                            -1.0
                        };
                        let value = v * (1.0 + sign * ranges[i].1);
                        (name, value)
                    }
                    None => (name, v),
                }
            });
            let p = pendulab_plants::spec::PlantParameters::from_entries(nominal.kind(), entries)
                .context("a vertex of the --vary box")?;
            p.validate().context("a vertex of the --vary box")?;
            let ss = p
                .linearize_upright(0.0)
                .context("linearising a vertex of the --vary box")?;
            Ok(Vertex {
                a: ss.a().clone(),
                b: ss.b().clone(),
            })
        })
        .collect()
}
