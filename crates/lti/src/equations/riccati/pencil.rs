//! Extended-pencil (QZ) solvers for the CARE and DARE.

use crate::error::{LtiError, Result};
use crate::linalg::Mat;

/// Stabilising CARE solution from the ordered generalised Schur form of the extended pencil
/// (unrefined; the caller computes diagnostics).
pub(crate) fn care_pencil(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    scaling: bool,
) -> Result<Mat> {
    let _ = (a, b, q, r, n, scaling);
    Err(LtiError::InvalidArgument(
        "the extended-pencil Riccati method is not available yet".into(),
    ))
}

/// Stabilising DARE solution from the ordered generalised Schur form of the extended
/// symplectic pencil (unrefined; the caller computes diagnostics).
pub(crate) fn dare_pencil(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    scaling: bool,
) -> Result<Mat> {
    let _ = (a, b, q, r, n, scaling);
    Err(LtiError::InvalidArgument(
        "the extended-pencil Riccati method is not available yet".into(),
    ))
}
