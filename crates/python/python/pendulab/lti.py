"""Linear time-invariant systems: python-control's and MATLAB's names over pendulab-lti.

Every function here is implemented in Rust (``pendulab._native``): arguments are converted
to float64 matrices (any real dtype, memory order, nested lists; shapes and NaN/Inf
checked), the GIL is released around the computation, and results come back as NumPy
arrays or small result classes that unpack like python-control's tuples::

    K, S, E = pendulab.lqr(A, B, Q, R)     # u = -K x
    res = pendulab.lqr(A, B, Q, R)
    res.residual                           # relative residual of the Riccati equation

Sign convention: every state-feedback gain is for ``u = -K x`` (closed loop ``A - B K``),
observer gains for ``A - L C``. The book 「倒立振子で学ぶ制御工学」 writes ``u = +K x``;
its gain is ``K_book = -K``.

Systems are ``StateSpace`` / ``TransferFunction`` objects, python-control ``StateSpace``
objects (anything with ``.A .B .C .D .dt``) or SISO ``TransferFunction`` objects, or
``(A, B, C, D[, dt])`` tuples; ``dt = 0``
is continuous time, ``dt > 0`` discrete time with that sample time in seconds.

Errors are ``pendulab.Error`` subclasses (see ``pendulab.errors``) carrying the Rust
message; all but the base class are also ``ValueError``.
"""

from ._native import (
    H2synResult,
    HinfsynResult,
    augw,
    h2syn,
    hinfsyn,
    BodeResult,
    DampResult,
    FrequencyResponse,
    LqeResult,
    LqiResult,
    LqrResult,
    LsimResult,
    LsimSplit,
    MatrixEquationResult,
    MinimalObserverResult,
    PlaceResult,
    RiccatiResult,
    SampledDataLqrResult,
    StateSpace,
    TimeResponse,
    TransferFunction,
    acker,
    bode,
    c2d,
    care,
    ctrb,
    d2c,
    damp,
    dare,
    dcgain,
    dlqe,
    dlqr,
    dlyap,
    freqresp,
    gram,
    impulse,
    initial,
    lqe,
    lqi,
    lqr,
    lqr_sampled_data,
    lsim,
    lsim_split,
    lyap,
    minimal_order_observer,
    obsv,
    place,
    place_observer,
    poles,
    reg,
    ss,
    step,
    tf,
    zeros,
)

__all__ = [
    "hinfsyn",
    "h2syn",
    "augw",
    "HinfsynResult",
    "H2synResult",
    "StateSpace",
    "TransferFunction",
    "ss",
    "tf",
    "c2d",
    "d2c",
    "poles",
    "zeros",
    "dcgain",
    "damp",
    "ctrb",
    "obsv",
    "gram",
    "lyap",
    "dlyap",
    "care",
    "dare",
    "lqr",
    "dlqr",
    "lqe",
    "dlqe",
    "place",
    "acker",
    "place_observer",
    "lqi",
    "lqr_sampled_data",
    "reg",
    "minimal_order_observer",
    "lsim",
    "lsim_split",
    "step",
    "impulse",
    "initial",
    "freqresp",
    "bode",
    "LqrResult",
    "RiccatiResult",
    "MatrixEquationResult",
    "LqeResult",
    "PlaceResult",
    "LqiResult",
    "SampledDataLqrResult",
    "MinimalObserverResult",
    "DampResult",
    "LsimResult",
    "LsimSplit",
    "TimeResponse",
    "FrequencyResponse",
    "BodeResult",
]
