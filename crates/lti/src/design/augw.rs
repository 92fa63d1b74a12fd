//! The augmented plant of mixed-sensitivity design (MATLAB `augw`, python-control `augw`).

use super::standard_plant::StandardPlant;
use crate::domain::Continuous;
use crate::error::{LtiError, Result};
use crate::linalg::Mat;
use crate::state_space::StateSpace;

/// The mixed-sensitivity standard plant of `G` (`ny × nu`) with the weights `W₁` on the
/// error, `W₂` on the control and `W₃` on the output (MATLAB `augw(G, W1, W2, W3)`; a
/// `None` weight is absent, as MATLAB's `[]`):
///
/// ```text
///       ⎡ z₁ ⎤   ⎡ W₁   −W₁G ⎤
///       ⎢ z₂ ⎥ = ⎢ 0     W₂  ⎥ ⎡ w ⎤
///       ⎢ z₃ ⎥   ⎢ 0    W₃G  ⎥ ⎣ u ⎦
///       ⎣ y  ⎦   ⎣ I    −G   ⎦
/// ```
///
/// so that with `u = K y` (`y = e = w − G u`, the [`StandardPlant`] convention) the closed
/// loop is `T_zw = [W₁S; W₂KS; W₃T]`, `S = (I + GK)⁻¹`, `T = GKS`. `W₁` and `W₃` take `ny`
/// inputs and `W₂` takes `nu` (a SISO weight of another plant is not expanded: use
/// [`append`](crate::interconnect::append) to make it diagonal).
///
/// The realisation has the states `[x_G; x_W₁; x_W₂; x_W₃]`, the inputs `[w (ny); u (nu)]`
/// and the outputs `[z₁; z₂; z₃; y (ny)]`; `nmeas = ny`, `ncon = nu`. With `W₁ = (A₁, B₁,
/// C₁, D₁)` and so on:
/// `ẋ_G = A_G x_G + B_G u`, `e = w − C_G x_G − D_G u`, `ẋ₁ = A₁x₁ + B₁e`, `z₁ = C₁x₁ + D₁e`,
/// `ẋ₂ = A₂x₂ + B₂u`, `z₂ = C₂x₂ + D₂u`, `ẋ₃ = A₃x₃ + B₃(C_G x_G + D_G u)`,
/// `z₃ = C₃x₃ + D₃(C_G x_G + D_G u)`, `y = e`.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] for a weight with the wrong number of inputs.
pub fn augw(
    g: &StateSpace<Continuous>,
    w1: Option<&StateSpace<Continuous>>,
    w2: Option<&StateSpace<Continuous>>,
    w3: Option<&StateSpace<Continuous>>,
) -> Result<StandardPlant> {
    let (ny, nu, ng) = (g.ny(), g.nu(), g.nx());
    let check = |what: &str, w: Option<&StateSpace<Continuous>>, inputs: usize| -> Result<()> {
        if let Some(w) = w
            && w.nu() != inputs
        {
            return Err(LtiError::DimensionMismatch {
                what: format!("{what} (outputs x inputs)"),
                expected: (w.ny(), inputs),
                found: (w.ny(), w.nu()),
            });
        }
        Ok(())
    };
    check("W1", w1, ny)?;
    check("W2", w2, nu)?;
    check("W3", w3, ny)?;
    let dims = |w: Option<&StateSpace<Continuous>>| w.map_or((0, 0), |w| (w.nx(), w.ny()));
    let ((n1, z1), (n2, z2), (n3, z3)) = (dims(w1), dims(w2), dims(w3));
    let n = ng + n1 + n2 + n3;
    let (nin, nout) = (ny + nu, z1 + z2 + z3 + ny);
    let (o1, o2, o3) = (ng, ng + n1, ng + n1 + n2);
    let (r2, r3, ry) = (z1, z1 + z2, z1 + z2 + z3);
    let mut a = Mat::zeros(n, n);
    let mut b = Mat::zeros(n, nin);
    let mut c = Mat::zeros(nout, n);
    let mut d = Mat::zeros(nout, nin);
    let (ag, bg, cg, dg) = (g.a(), g.b(), g.c(), g.d());
    a.view_mut((0, 0), (ng, ng)).copy_from(ag);
    b.view_mut((0, ny), (ng, nu)).copy_from(bg);
    c.view_mut((ry, 0), (ny, ng)).copy_from(&(-cg));
    d.view_mut((ry, 0), (ny, ny))
        .copy_from(&Mat::identity(ny, ny));
    d.view_mut((ry, ny), (ny, nu)).copy_from(&(-dg));
    if let Some(w) = w1 {
        a.view_mut((o1, o1), (n1, n1)).copy_from(w.a());
        a.view_mut((o1, 0), (n1, ng)).copy_from(&(-(w.b() * cg)));
        b.view_mut((o1, 0), (n1, ny)).copy_from(w.b());
        b.view_mut((o1, ny), (n1, nu)).copy_from(&(-(w.b() * dg)));
        c.view_mut((0, o1), (z1, n1)).copy_from(w.c());
        c.view_mut((0, 0), (z1, ng)).copy_from(&(-(w.d() * cg)));
        d.view_mut((0, 0), (z1, ny)).copy_from(w.d());
        d.view_mut((0, ny), (z1, nu)).copy_from(&(-(w.d() * dg)));
    }
    if let Some(w) = w2 {
        a.view_mut((o2, o2), (n2, n2)).copy_from(w.a());
        b.view_mut((o2, ny), (n2, nu)).copy_from(w.b());
        c.view_mut((r2, o2), (z2, n2)).copy_from(w.c());
        d.view_mut((r2, ny), (z2, nu)).copy_from(w.d());
    }
    if let Some(w) = w3 {
        a.view_mut((o3, o3), (n3, n3)).copy_from(w.a());
        a.view_mut((o3, 0), (n3, ng)).copy_from(&(w.b() * cg));
        b.view_mut((o3, ny), (n3, nu)).copy_from(&(w.b() * dg));
        c.view_mut((r3, o3), (z3, n3)).copy_from(w.c());
        c.view_mut((r3, 0), (z3, ng)).copy_from(&(w.d() * cg));
        d.view_mut((r3, ny), (z3, nu)).copy_from(&(w.d() * dg));
    }
    StandardPlant::new(StateSpace::continuous(a, b, c, d)?, ny, nu)
}
