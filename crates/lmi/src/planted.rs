//! Semidefinite programs with an optimum known by construction, for tests and benchmarks of
//! the interior-point methods.

use crate::error::Result;
use crate::expr::Expr;
use crate::problem::Problem;
use pendulab_lti::Mat;
use pendulab_lti::random::SplitMix64;

/// A problem of [`planted_sdp`] and its optimal value.
#[derive(Debug, Clone)]
pub struct PlantedSdp {
    /// `maximise bᵀy  s.t.  C_k − Σ_i y_i A_{k,i} ⪰ 0, k = 1..blocks`.
    pub problem: Problem,
    /// The vector variable `y` (`variables × 1`).
    pub y: Expr,
    /// The optimal value `Σ_k ⟨C_k, X_k*⟩`.
    pub optimum: f64,
}

/// Uniform in `[lo, hi)` from `rng` (53 random bits): SplitMix64, so that a seed gives the
/// same problem on every platform.
fn uniform(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.unit()
}

/// `maximise bᵀy  s.t.  C_k − Σ_i y_i A_{k,i} ⪰ 0` (`blocks` LMIs of side `side`, `variables`
/// scalars `y_i`) with an optimum known by construction. For each block, a strictly
/// complementary pair `X_k* ⪰ 0` (rank `rank`) and `Z_k* ⪰ 0` (rank `side − rank`) with
/// `X_k* Z_k* = 0` is drawn on one random orthogonal basis (eigenvalues uniform in
/// `[0.1, 10)`), the `A_{k,i}` are random symmetric (entries uniform in `[−1, 1)`), `y*` is
/// random, `C_k = Z_k* + Σ_i y*_i A_{k,i}` and `b_i = Σ_k ⟨A_{k,i}, X_k*⟩`. Then `y*` is
/// feasible (`C_k − Σ_i y*_i A_{k,i} = Z_k*`), the `X_k*` are feasible for the dual
/// `min Σ_k ⟨C_k, X_k⟩ s.t. Σ_k ⟨A_{k,i}, X_k⟩ = b_i, X_k ⪰ 0`, and the duality gap
/// `Σ_k ⟨Z_k*, X_k*⟩` is zero: both are optimal, and the optimal value is `Σ_k ⟨C_k, X_k*⟩`.
/// The coefficient matrices are dense (every variable enters every entry).
///
/// # Errors
/// [`crate::LmiError::InvalidArgument`] unless `0 < side`, `rank ≤ side` and
/// `variables ≥ 1`.
pub fn planted_sdp(
    seed: u64,
    side: usize,
    variables: usize,
    rank: usize,
    blocks: usize,
) -> Result<PlantedSdp> {
    if side == 0 || rank > side || variables == 0 {
        return Err(crate::LmiError::InvalidArgument {
            what: "planted_sdp".into(),
            reason: format!(
                "needs side ≥ 1, rank ≤ side and variables ≥ 1, got side {side}, rank {rank}, \
                 variables {variables}"
            ),
        });
    }
    let mut rng = SplitMix64::new(seed);
    let y_star: Vec<f64> = (0..variables)
        .map(|_| uniform(&mut rng, -1.0, 1.0))
        .collect();
    let mut b = vec![0.0; variables];
    let mut optimum = 0.0;
    let mut problem = Problem::new();
    let y = problem.matrix("y", variables, 1);
    for k in 0..blocks {
        let q = Mat::from_fn(side, side, |_, _| uniform(&mut rng, -1.0, 1.0))
            .qr()
            .q();
        let mut x_star = Mat::zeros(side, side);
        let mut z_star = Mat::zeros(side, side);
        for j in 0..side {
            let v = q.column(j);
            let w = uniform(&mut rng, 0.1, 10.0);
            if j < rank {
                x_star += (v * v.transpose()) * w;
            } else {
                z_star += (v * v.transpose()) * w;
            }
        }
        let mut c = z_star;
        let mut lmi = Expr::zeros(side, side);
        for (i, yi_star) in y_star.iter().enumerate() {
            let m = Mat::from_fn(side, side, |_, _| uniform(&mut rng, -1.0, 1.0));
            let a = (&m + m.transpose()) * 0.5;
            c += &a * *yi_star;
            b[i] += a.component_mul(&x_star).sum();
            lmi = &lmi - &Expr::kron(&y.sub_block(i, 0, 1, 1), &Expr::constant(&a));
        }
        optimum += c.component_mul(&x_star).sum();
        let lmi = &Expr::constant(&c) + &lmi;
        problem.positive_semidefinite(&format!("block {k}"), &lmi)?;
    }
    let objective = &Expr::constant(&Mat::from_row_slice(1, variables, &b)) * &y;
    problem.maximize(&objective)?;
    Ok(PlantedSdp {
        problem,
        y,
        optimum,
    })
}
