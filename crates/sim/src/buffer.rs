//! State storage for the hot loops: fixed-size arrays when the state size is known at compile
//! time, vectors otherwise. One generic kernel serves both; with arrays every slice length is
//! a compile-time constant after inlining, so the loops unroll and nothing is allocated.

/// A state-sized scratch vector.
pub(crate) trait Buf: Clone + Send + std::fmt::Debug {
    /// A zero vector of length `n` (for arrays, `n` equals the array length).
    fn zeros(n: usize) -> Self;
    /// The entries.
    fn s(&self) -> &[f64];
    /// The entries, mutably.
    fn m(&mut self) -> &mut [f64];
}

impl<const N: usize> Buf for [f64; N] {
    #[inline(always)]
    fn zeros(n: usize) -> Self {
        debug_assert_eq!(n, N);
        [0.0; N]
    }
    #[inline(always)]
    fn s(&self) -> &[f64] {
        self
    }
    #[inline(always)]
    fn m(&mut self) -> &mut [f64] {
        self
    }
}

impl Buf for Vec<f64> {
    #[inline]
    fn zeros(n: usize) -> Self {
        vec![0.0; n]
    }
    #[inline(always)]
    fn s(&self) -> &[f64] {
        self
    }
    #[inline(always)]
    fn m(&mut self) -> &mut [f64] {
        self
    }
}

/// Calls `$body` with the type alias `$B` bound to `[f64; n]` for `n ≤ 8` and to `Vec<f64>`
/// otherwise: the dispatch from a run-time state size to a monomorphised kernel.
macro_rules! with_buffer {
    ($n:expr, $B:ident => $body:expr) => {
        $crate::buffer::with_buffer!(@sizes $n, $B => $body; 1 2 3 4 5 6 7 8)
    };
    (@sizes $n:expr, $B:ident => $body:expr; $($size:literal)+) => {
        match $n {
            $(
                $size => {
                    type $B = [f64; $size];
                    $body
                }
            )+
            _ => {
                type $B = Vec<f64>;
                $body
            }
        }
    };
}
pub(crate) use with_buffer;
