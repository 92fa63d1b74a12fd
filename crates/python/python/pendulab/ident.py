"""Identification of the rigs (book Part 1 §3.2, §3.3) over ``pendulab-ident``.

The methods work on arrays or on a measured record (a CSV path, CSV text or a
:class:`Dataset`); :func:`identify` runs them as ``pendulab identify METHOD --data FILE`` does
(same library calls, same checks, same defaults) and returns the same estimates.

Angles are measured from the hanging rest (``φ = θ − π``) and the arm angle from where the
recording starts, as in ``data/rig/`` (``docs/rig/README.md``).

==================  ======================  ===================================================
method              columns                 estimates
==================  ======================  ===================================================
``cart-ls``         ``t, z, v``             ``ac``, ``bc`` (``z̈ = −a_c ż + b_c v``, eq. 3.31)
``pend-ls``         ``t, z, phi``           ``Jp``, ``mup`` (known ``m_p``, ``l_p``, ``g``)
``arm-ls``          ``t, phi1, v``          ``a1``, ``b1``
``arm-pend-ls``     ``t, phi1, phi2``       ``J2``, ``mu2``, ``alpha2`` (known ``L1, m2, l2, g``)
``cart-step``       ``t, z``                ``ac``, ``bc``, ``Tp``, ``overshoot``, ``omega_n``, ``zeta``
``arm-step``        ``t, theta1``           ``a1``, ``b1``, ``Tp``, ``overshoot``, ``omega_n``, ``zeta``
``pend-free``       ``t, theta``            ``Jp``, ``mup``, ``period``, ``decay_ratio``, …
``arm-pend-free``   ``t, theta2``           ``J2``, ``mu2``, ``period``, ``decay_ratio``, …
==================  ======================  ===================================================

Before an estimate is returned the library's checks run (a time step plausible for the unit,
enough samples for the differentiator and filter, known constants in range, a well-conditioned
regression, plausible and resolved estimates). A failed check raises
:class:`pendulab.InvalidArgumentError` naming the cause; with ``force=True`` the result is
returned anyway with every failed check under ``"warnings"``.
"""

import os
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Union

from . import _native
from ._native import Dataset
from ._native import ident_arm_pendulum_ls as arm_pendulum_ls
from ._native import ident_cart_pendulum_ls as cart_pendulum_ls
from ._native import ident_drive_ls as drive_ls
from ._native import ident_free_oscillation as free_oscillation
from ._native import ident_p_step as p_step

__all__ = [
    "Dataset",
    "read_csv",
    "identify",
    "drive_ls",
    "cart_pendulum_ls",
    "arm_pendulum_ls",
    "p_step",
    "free_oscillation",
    "arx",
    "moesp",
    "ArxResult",
    "MoespResult",
    "METHODS",
]

#: The methods of :func:`identify` (those of ``pendulab identify``).
METHODS = (
    "cart-ls",
    "pend-ls",
    "arm-ls",
    "arm-pend-ls",
    "cart-step",
    "arm-step",
    "pend-free",
    "arm-pend-free",
)

#: The known constants ``pendulab identify`` assumes (book tables 3.5, 3.7).
CONSTANTS = {"mp": 0.107, "lp": 0.230, "g": 9.81, "L1": 0.227, "m2": 0.096, "l2": 0.195}


def read_csv(data: Union[str, os.PathLike], time_unit: Optional[str] = None) -> Dataset:
    """A measured record from a CSV file (a header line naming the columns, ``t`` in seconds
    or, as the header or ``time_unit="ms"`` declares, milliseconds), or from CSV text when
    ``data`` contains a newline."""
    if isinstance(data, str) and "\n" in data:
        return _native.ident_dataset("<text>", data, time_unit)
    path = os.fspath(data)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return _native.ident_dataset(path, text, time_unit)


def _record(data: Any, time_unit: Optional[str]) -> Dataset:
    if isinstance(data, Dataset):
        return data
    if isinstance(data, (str, os.PathLike)):
        return read_csv(data, time_unit)
    raise TypeError(f"data must be a CSV path, CSV text or a pendulab.ident.Dataset, got {type(data).__name__}")


class _Gate:
    """A failed check refuses (``InvalidArgumentError``) or, forced, becomes a warning."""

    def __init__(self, force: bool):
        self.force = force
        self.warnings = []

    def check(self, messages):
        for m in messages:
            if not self.force:
                raise _native.InvalidArgumentError(
                    f"{m}\n(refused; force=True returns the result anyway, with this as a warning)"
                )
            self.warnings.append(m)

    def call(self, f, *args, **kw):
        try:
            f(*args, **kw)
        except _native.Error as e:
            self.check([str(e)])


def identify(
    method: str,
    data: Any,
    *,
    time_unit: Optional[str] = None,
    window: Optional[tuple] = None,
    force: bool = False,
    tf: float = 0.075,
    filter: str = "causal",
    hold: str = "zoh",
    savgol: Optional[int] = None,
    savgol_order: int = 3,
    mp: float = CONSTANTS["mp"],
    lp: float = CONSTANTS["lp"],
    g: float = CONSTANTS["g"],
    L1: float = CONSTANTS["L1"],
    m2: float = CONSTANTS["m2"],
    l2: float = CONSTANTS["l2"],
    kp: Optional[float] = None,
    target: Optional[float] = None,
    step_time: Optional[float] = None,
    column: Optional[str] = None,
    amplitude_correction: bool = False,
    hysteresis: Optional[float] = None,
) -> Dict[str, Any]:
    """``pendulab identify METHOD --data FILE`` from Python: ``method`` one of :data:`METHODS`,
    ``data`` a CSV path, CSV text or :class:`Dataset`; ``window=(t0, t1)`` in seconds (either
    end ``None``). Returns a dict: ``method``, ``data``, ``window``, ``samples``, ``ts``,
    ``estimates`` and ``std_errors`` (name → float), ``condition`` and ``residual_rms``
    (least-squares methods), ``fit`` (the validation), ``warnings`` and ``details`` (the
    method's full result)."""
    if method not in METHODS:
        raise _native.InvalidArgumentError(f"unknown method {method!r} (known: {', '.join(METHODS)})")
    gate = _Gate(force)
    full = _record(data, time_unit)
    gate.call(full.check_time_unit)
    w0, w1 = window if window is not None else (None, None)
    rec = full.window(w0, w1)
    ts = rec.uniform_step()
    t = rec.time()
    ls = dict(filter=filter, tf=tf, hold=hold, savgol=savgol, savgol_order=savgol_order)
    cart = method in ("cart-step", "pend-free")
    est: Dict[str, float] = {}
    se: Dict[str, float] = {}
    out: Dict[str, Any] = {}
    if method in ("cart-ls", "arm-ls"):
        ycol, (a, b) = ("z", ("ac", "bc")) if method == "cart-ls" else ("phi1", ("a1", "b1"))
        r = drive_ls("cart" if method == "cart-ls" else "arm", ts, rec.column(ycol), rec.column("v"), **ls)
        est.update({a: r["a"], b: r["b"]})
        se.update({a: r["std_error"][0], b: r["std_error"][1]})
    elif method == "pend-ls":
        r = cart_pendulum_ls(ts, rec.column("z"), rec.column("phi"), mp=mp, lp=lp, g=g, **ls)
        est.update(Jp=r["Jp"], mup=r["mup"])
        se.update(Jp=r["std_error"][0], mup=r["std_error"][1])
    elif method == "arm-pend-ls":
        r = arm_pendulum_ls(ts, rec.column("phi1"), rec.column("phi2"), L1=L1, m2=m2, l2=l2, g=g, **ls)
        est.update(J2=r["J2"], mu2=r["mu2"], alpha2=r["alpha2"])
        se.update(J2=r["std_error"][0], mu2=r["std_error"][1], alpha2=r["std_error"][0])
    elif method in ("cart-step", "arm-step"):
        col = column or ("z" if cart else "theta1")
        st = step_time if step_time is not None else (w0 if w0 is not None else 1.0)
        r = p_step(
            t,
            rec.column(col),
            st,
            target if target is not None else (0.2 if cart else 1.0),
            kp if kp is not None else (10.0 if cart else 3.0),
        )
        a, b = ("ac", "bc") if cart else ("a1", "b1")
        est.update({a: r["a"], b: r["b"]})
        est.update({k: r[k] for k in ("Tp", "overshoot", "omega_n", "zeta")})
        r["failed_checks"] = []
    else:
        col = column or ("theta" if cart else "theta2")
        m, l = (mp, lp) if cart else (m2, l2)
        r = free_oscillation(
            t, rec.column(col), m, l, g, hysteresis=hysteresis,
            amplitude_correction=amplitude_correction, ts=ts, L1=None if cart else L1,
        )
        jn, mun = ("Jp", "mup") if cart else ("J2", "mu2")
        est.update({jn: r["J"], mun: r["mu"]})
        est.update({k: r[k] for k in ("period", "decay_ratio", "omega_n", "zeta")})
        if r["std_errors"] is not None:
            se.update({jn: r["std_errors"][0], mun: r["std_errors"][1]})
        if r["period_std_error"] is not None:
            se["period"] = r["period_std_error"]
        if r["decay_ratio_std_error"] is not None:
            se["decay_ratio"] = r["decay_ratio_std_error"]
        out["fit_linear"] = r.get("fit_linear")
    gate.check(r["failed_checks"])
    fit = r.get("fit")
    if fit is not None and "error" in fit:
        gate.check([f"validation not run: {fit['error']}"])
    out.update(
        method=method,
        data=full.source,
        window=(float(t[0]), float(t[-1])),
        samples=len(rec),
        ts=ts,
        estimates=est,
        std_errors=se,
        fit=fit,
        warnings=gate.warnings,
        details=r,
    )
    if "condition" in r:
        out["condition"] = r["condition"]
        out["residual_rms"] = r["residual_rms"]
    return out


@dataclass(frozen=True)
class ArxResult:
    """An ARX model ``A(q⁻¹) y(k) = B(q⁻¹) u(k − nk) + e(k)`` (MATLAB's ``[na nb nk]``)."""

    #: ``[1, a₁, …, a_na]``.
    a: Any
    #: ``[b₀, …, b_(nb−1)]`` acting on ``u(k − nk − i)``.
    b: Any
    na: int
    nb: int
    nk: int
    #: Standard errors of ``a₁…a_na`` then ``b₀…``.
    std_error: Any
    #: Residual variance ``‖e‖²/(N − d)``.
    noise_variance: float
    #: Sample time, s.
    ts: float
    #: The discrete :class:`pendulab.StateSpace` of ``z^(−nk) B/A``.
    model: Any
    #: MATLAB ``compare`` fit (percent) on the validation record.
    fit: float
    #: With ``max_order``: every candidate ``{na, nb, nk, loss, aic}`` (``AIC = N ln V + 2d``).
    aic: Optional[List[Dict[str, float]]]


@dataclass(frozen=True)
class MoespResult:
    """A PO-MOESP model ``x(k+1) = A x + B u``, ``y = C x + D u``."""

    A: Any
    B: Any
    C: Any
    D: Any
    order: int
    horizon: int
    #: The cap of the order selection (``None``: ``horizon − 1``).
    max_order: Optional[int]
    #: Singular values of ``L₃₂`` (the order is the number of dominant ones).
    singular_values: Any
    ts: float
    #: The discrete :class:`pendulab.StateSpace`.
    model: Any
    #: MATLAB ``compare`` fit (percent), simulated from the zero state on the validation record.
    fit: float


def arx(u, y, ts: float, na: Optional[int] = None, nb: Optional[int] = None, nk: int = 1,
        max_order: Optional[int] = None, validate: Optional[tuple] = None) -> ArxResult:
    """ARX by least squares (``pendulab identify arx``): orders ``na``, ``nb`` (default 2) and
    delay ``nk``, or with ``max_order`` every ``na, nb ∈ 1…max_order`` ranked by AIC.
    ``validate=(u_val, y_val)`` is the validation record (default ``(u, y)``). Raises
    ``InvalidArgumentError`` (orders < 1, an unexcited regressor), ``ShapeError`` (lengths,
    too few samples for the orders), ``NotFiniteError``."""
    uv, yv = validate if validate is not None else (None, None)
    r = _native.ident_arx(u, y, ts, na=na, nb=nb, nk=nk, max_order=max_order, u_val=uv, y_val=yv)
    return ArxResult(**r)


def moesp(u, y, ts: float, order: Optional[int] = None, horizon: int = 10,
          validate: Optional[tuple] = None, max_order: Optional[int] = None) -> MoespResult:
    """PO-MOESP subspace identification (``pendulab identify moesp``): ``horizon`` block rows,
    ``order`` (default: the largest gap ``σ_n/σ_(n+1)`` of the singular values among
    ``n = 1 … min(max_order, horizon − 1)``; ``max_order=None`` is ``horizon − 1``).
    ``validate=(u_val, y_val)`` as in :func:`arx`. Raises as :func:`arx` (an order above
    ``horizon − 1``, ``max_order`` 0 or given with ``order``, a horizon too long for the
    record)."""
    uv, yv = validate if validate is not None else (None, None)
    r = _native.ident_moesp(u, y, ts, order=order, horizon=horizon, u_val=uv, y_val=yv,
                            max_order=max_order)
    return MoespResult(**r)
