//! Generalised real Schur (QZ) decomposition `A = Q S Zᵀ`, `B = Q T Zᵀ` with reordering.
//!
//! (Implementation follows.)
