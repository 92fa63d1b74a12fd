//! Reordering a real Schur form: moving one block along the diagonal (LAPACK `dtrexc`) and
//! bringing selected eigenvalues to the leading positions (`dtrsen`'s reordering loop), by
//! repeated adjacent swaps.
//!
//! Neighbours: [`super`] holds the public API (`RealSchur::reorder`, `ordered_schur`);
//! `swap.rs` holds the adjacent swap; `hessenberg.rs` and `francis.rs` compute the Schur form.

use super::block_eigenvalues;
use super::swap::{SwapRejected, exchange};
use crate::linalg::{Complex64, Mat};

/// Block size at row `k` of the quasi-triangular `t`.
fn bsize(t: &Mat, k: usize) -> usize {
    if k + 1 < t.nrows() && t[(k + 1, k)] != 0.0 {
        2
    } else {
        1
    }
}

/// Moves the block starting at (or containing) row `ifst` to row `ilst` (LAPACK `dtrexc`),
/// returning the final starting row. A 2×2 block that splits into two real eigenvalues during
/// the moves is moved as a pair of 1×1 blocks.
pub(crate) fn trexc(
    t: &mut Mat,
    mut z: Option<&mut Mat>,
    ifst: usize,
    ilst: usize,
) -> std::result::Result<usize, SwapRejected> {
    let n = t.nrows();
    if n <= 1 {
        return Ok(ilst);
    }
    let mut ifst = ifst;
    let mut ilst = ilst;
    if ifst > 0 && t[(ifst, ifst - 1)] != 0.0 {
        ifst -= 1;
    }
    let mut nbf = bsize(t, ifst);
    if ilst > 0 && t[(ilst, ilst - 1)] != 0.0 {
        ilst -= 1;
    }
    let nbl = bsize(t, ilst);
    if ifst == ilst {
        return Ok(ilst);
    }
    let mut here = ifst;
    if ifst < ilst {
        // Move down.
        if nbf == 2 && nbl == 1 {
            ilst -= 1;
        }
        if nbf == 1 && nbl == 2 {
            ilst += 1;
        }
        loop {
            if nbf == 1 || nbf == 2 {
                let nbnext = if here + nbf + 1 < n {
                    bsize(t, here + nbf)
                } else {
                    1
                };
                if here + nbf >= n {
                    break;
                }
                exchange(t, z.as_deref_mut(), here, nbf, nbnext)?;
                here += nbnext;
                if nbf == 2 && t[(here + 1, here)] == 0.0 {
                    nbf = 3;
                }
            } else {
                // Two 1×1 blocks, swapped individually.
                if here + 2 >= n {
                    break;
                }
                let nbnext = if here + 3 < n { bsize(t, here + 2) } else { 1 };
                exchange(t, z.as_deref_mut(), here + 1, 1, nbnext)?;
                if nbnext == 1 {
                    exchange(t, z.as_deref_mut(), here, 1, 1)?;
                    here += 1;
                } else {
                    let nbnext = if t[(here + 2, here + 1)] == 0.0 { 1 } else { 2 };
                    if nbnext == 2 {
                        exchange(t, z.as_deref_mut(), here, 1, 2)?;
                        here += 2;
                    } else {
                        exchange(t, z.as_deref_mut(), here, 1, 1)?;
                        exchange(t, z.as_deref_mut(), here + 1, 1, 1)?;
                        here += 2;
                    }
                }
            }
            if here >= ilst {
                break;
            }
        }
    } else {
        // Move up.
        loop {
            if nbf == 1 || nbf == 2 {
                let nbnext = if here >= 2 && t[(here - 1, here - 2)] != 0.0 {
                    2
                } else {
                    1
                };
                exchange(t, z.as_deref_mut(), here - nbnext, nbnext, nbf)?;
                here -= nbnext;
                if nbf == 2 && t[(here + 1, here)] == 0.0 {
                    nbf = 3;
                }
            } else {
                let nbnext = if here >= 2 && t[(here - 1, here - 2)] != 0.0 {
                    2
                } else {
                    1
                };
                exchange(t, z.as_deref_mut(), here - nbnext, nbnext, 1)?;
                if nbnext == 1 {
                    exchange(t, z.as_deref_mut(), here, 1, 1)?;
                    here -= 1;
                } else {
                    let nbnext = if t[(here, here - 1)] == 0.0 { 1 } else { 2 };
                    if nbnext == 2 {
                        exchange(t, z.as_deref_mut(), here - 1, 2, 1)?;
                        here -= 2;
                    } else {
                        exchange(t, z.as_deref_mut(), here, 1, 1)?;
                        exchange(t, z.as_deref_mut(), here - 1, 1, 1)?;
                        here -= 2;
                    }
                }
            }
            if here <= ilst {
                break;
            }
        }
    }
    Ok(here)
}

/// Reorders the standard-form quasi-triangular `t` (and `z`) so the blocks selected by
/// `select` (evaluated once per block, on the original eigenvalues) lead; returns their total
/// order (LAPACK `dtrsen`'s reordering loop).
pub(crate) fn reorder_quasi_triangular<F: FnMut(Complex64) -> bool>(
    t: &mut Mat,
    mut z: Option<&mut Mat>,
    mut select: F,
) -> std::result::Result<usize, SwapRejected> {
    let n = t.nrows();
    let mut flags = vec![false; n];
    let mut k = 0;
    while k < n {
        let size = bsize(t, k);
        let s = select(block_eigenvalues(t, k, size)[0]);
        flags[k] = s;
        if size == 2 {
            flags[k + 1] = s;
        }
        k += size;
    }
    let mut ks = 0;
    let mut k = 0;
    while k < n {
        let size = bsize(t, k);
        if flags[k] {
            if k != ks {
                trexc(t, z.as_deref_mut(), k, ks)?;
            }
            ks += size;
        }
        k += size;
    }
    Ok(ks)
}
