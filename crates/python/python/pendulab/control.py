"""Controllers beyond a static gain (book Part 2 §2–§3), over ``pendulab-control``.

Designs return their results as dicts of arrays; run-time controllers come back as
:class:`Controller` objects with ``update(t, y) -> u`` (the measurement ``y`` at time ``t`` in
seconds to the command ``u``, as the sampled-data loop calls them), ``reset()``, ``ny``,
``nu``, ``sample_time``. Library sign: ``u = −K x`` (the book's ``u = +K x`` has
``K_book = −K``).

- :func:`sliding_surface`, :func:`sliding_mode` — the LQ-optimal switching surface and the
  sliding-mode law ``u = −(SᵀA x + K₂ σ/(|σ| + δ)) / (SᵀB)``, ``σ = Sᵀx`` (Part 2 §3.2.3);
- :func:`energy_pumping`, :func:`energy_shaping` — swing-up from the hanging rest (Part 2
  §3.2.3; the energy-shaping gains are tuned for the rigs, not from the book);
- :func:`nmpc_arm_swing_up` — the C/GMRES NMPC swing-up of the arm pendulum (Part 2 §3.3);
- :func:`odq` — the optimal dynamic quantizer, closed form or LP (Part 2 §2.3.4);
- :func:`kalman` — the steady-state Kalman filter (MATLAB ``kalman``);
- :func:`build` — the controller a ``ControllerSpec`` describes (``docs/model.md`` §6), from the
  factory the CLI and :func:`pendulab.plants.simulate` use;
- :func:`find_operating_point` — trim (equilibria and operating points, MATLAB ``findop``) of a
  plant or of your own model given as callables ``f(x, u)``, ``h(x, u)``;
- :class:`KalmanFilter`, :class:`ExtendedKalmanFilter`, :class:`UnscentedKalmanFilter`,
  :func:`filter_log`, :func:`encoder_covariance`, :func:`quantization_variance`, :func:`nees` —
  recursive state estimation;
- :class:`LinearMpc`, :func:`solve_qp`, :func:`kkt_residuals` — constrained linear MPC and its
  dual active-set QP method (closed loop on the nonlinear plants: the spec kind ``"mpc"`` in
  :func:`pendulab.plants.simulate`).

Callables: ``f(x, u)`` and ``h(x, u)`` receive two 1-d ``float64`` arrays and return a
sequence or array (``len(x)`` values for ``f``). They are called from the library with the GIL
held; an exception they raise propagates unchanged, a result of the wrong length raises
:class:`pendulab.ShapeError` and NaN/±Inf :class:`pendulab.NotFiniteError`, each naming the
function and the point ``(x, u)``.
"""

import json
import os
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import Controller
from ._native import control_energy_pumping as energy_pumping
from ._native import control_energy_shaping as energy_shaping
from ._native import control_kalman as kalman
from ._native import control_nmpc_arm_swing_up as nmpc_arm_swing_up
from ._native import control_odq as odq
from ._native import control_sliding_mode as sliding_mode
from ._native import control_sliding_surface as sliding_surface

__all__ = [
    "Controller",
    "sliding_surface",
    "sliding_mode",
    "energy_pumping",
    "energy_shaping",
    "nmpc_arm_swing_up",
    "odq",
    "kalman",
    "build",
    "OperatingPoint",
    "find_operating_point",
    "Innovation",
    "KalmanFilter",
    "ExtendedKalmanFilter",
    "UnscentedKalmanFilter",
    "filter_log",
    "read_cart_log",
    "encoder_covariance",
    "quantization_variance",
    "nees",
    "LinearMpc",
    "solve_qp",
    "kkt_residuals",
]


def build(spec: Mapping[str, Any], plant: Union[str, Mapping[str, Any]] = "cart", ts: float = 1e-3) -> Controller:
    """The controller ``spec`` (a ``ControllerSpec`` dict such as ``{"kind": "state-feedback",
    "k_book": [...]}``) describes for ``plant`` (``"cart"``, ``"arm"`` or a ``PlantSpec`` dict),
    running at loop period ``ts`` (s)."""
    p = plant if isinstance(plant, str) else json.dumps(plant)
    return _native.control_build(json.dumps(spec), p, float(ts))


# --- operating points --------------------------------------------------------------------


@dataclass
class OperatingPoint:
    """An operating point found by :func:`find_operating_point`: state ``x``, input ``u``,
    output ``y`` (empty without an output map), ``dx = f(x, u)`` (``dx0``, zero unless given,
    to the tolerance but for the derivatives left free by ``idx``), ``residual`` (``‖r‖_∞`` of the equations, in
    the units of ``ẋ`` and ``y``; ≤ ``tol``), ``iterations`` (Levenberg–Marquardt), ``status``:
    ``"isolated"`` or ``"family"`` (the equations leave ``family_dimension`` unknowns free,
    e.g. the cart's position along the rail). Unpacks as python-control's result:
    ``x, u = find_operating_point(...)``."""

    x: np.ndarray
    u: np.ndarray
    y: np.ndarray
    dx: np.ndarray
    residual: float
    iterations: int
    status: str
    family_dimension: int

    @property
    def converged(self) -> bool:
        """Always ``True``: a search that does not meet ``tol`` raises
        :class:`pendulab.LinAlgError` (``variant == "NoConvergence"``) instead."""
        return True

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.x, self.u))


def find_operating_point(
    sys: Any,
    x0: Any,
    u0: Any = None,
    y0: Any = None,
    t: float = 0.0,
    iu: Optional[Sequence[int]] = None,
    iy: Optional[Sequence[int]] = None,
    ix: Optional[Sequence[int]] = None,
    idx: Optional[Sequence[int]] = None,
    dx0: Any = None,
    *,
    h: Optional[Callable[[np.ndarray, np.ndarray], Any]] = None,
    tol: float = 1e-10,
    max_iterations: int = 100,
) -> OperatingPoint:
    """An operating point ``(x, u)`` of ``sys`` with ``f(x, u) = 0`` (and outputs held), by
    Levenberg–Marquardt on the remaining unknowns (``pendulab_control::trim``).

    ``sys``: a :class:`pendulab.plants.CartPendulum` / ``ArmPendulum`` (its parameters; state
    ``[z, θ, ż, θ̇]`` / ``[θ₁, θ₂, θ̇₁, θ̇₂]`` in m, rad, m/s, rad/s, input the voltage in V, no
    output map), ``"cart"`` / ``"arm"`` (the book's rigs), or your own model: a callable
    ``f(x, u) -> dx/dt`` with ``nx = len(x0)`` states, ``nu = len(u0)`` inputs (none without
    ``u0``) and optionally ``h(x, u) -> y``.

    Keywords follow python-control 0.10's ``find_operating_point`` and MATLAB's ``operspec``:

    - ``x0``: the initial guess of the state; ``ix`` lists states *held* at their ``x0`` value
      (``operspec`` ``States.Known``);
    - ``u0``: the input (default zeros). Without ``y0`` every input is held at ``u0``; with
      ``y0`` it is a guess; ``iu`` lists the inputs held (``Inputs.Known``);
    - ``y0``: the output values (one per output of ``h``); ``iy`` selects those held (default
      all; ``Outputs.Known``);
    - ``idx``: the states whose derivative is held (default all; the others are free,
      ``States.SteadyState = false``);
    - ``dx0``: the values the held derivatives take (one per state; default zeros: an
      equilibrium; ``States.dx``), e.g. a steady acceleration;
    - ``t``: the evaluation time (s); ``tol``: accept ``‖r‖_∞ ≤ tol``; ``max_iterations``.

    Raises :class:`pendulab.ShapeError` for lengths that do not fit the model,
    :class:`pendulab.NotFiniteError` for NaN/±Inf (also when ``f`` or ``h`` returns them),
    :class:`pendulab.InvalidArgumentError` for an index out of range or listed twice, ``h``
    with a plant, or everything held at a point that is not an operating point,
    :class:`pendulab.LinAlgError` (``variant == "NoConvergence"``) when the search stalls
    above ``tol`` (no operating point near ``x0``); an exception raised by ``f`` or ``h``
    propagates.
    """
    d = _native.control_find_operating_point(
        sys, x0, u0, y0, float(t), _ints(iu), _ints(iy), _ints(ix), _ints(idx), h, float(tol),
        int(max_iterations), dx0)
    return OperatingPoint(**d)


def _ints(v: Optional[Sequence[int]]) -> Optional[list]:
    return None if v is None else [int(i) for i in np.atleast_1d(np.asarray(v)).reshape(-1)]


# --- Kalman filters ----------------------------------------------------------------------


@dataclass
class Innovation:
    """What one measurement update did: ``residual`` ``ν = y − ŷ``, its covariance ``S =
    P_yy + R``, the gain ``K = P_xy S⁻¹`` (``nx × ny``), ``nis = νᵀ S⁻¹ ν`` (χ² with ``ny``
    degrees of freedom for a consistent filter)."""

    residual: np.ndarray
    S: np.ndarray
    K: np.ndarray
    nis: float


class _Estimator:
    """The estimate ``x`` and its error covariance ``P`` of a filter held in ``_f``."""

    _f: Any

    @property
    def x(self) -> np.ndarray:
        """The current estimate ``x̂``."""
        return self._f.x

    @property
    def P(self) -> np.ndarray:
        """The current error covariance ``P``."""
        return self._f.P


class KalmanFilter(_Estimator):
    """The time-varying linear Kalman filter (``pendulab_control::kalman::KalmanFilter``) of
    ``x_{k+1} = A_k x_k + B_k u_k + w_k``, ``y_k = C_k x_k + D_k u_k + v_k``, ``w ~ N(0, Q_k)``,
    ``v ~ N(0, R_k)`` (per-sample covariances), started from ``x0`` with the covariance
    ``P0`` (positive definite). The matrices may change at every call.

    - ``predict(A, B, u, Q)``: ``x̄ = A x̂ + B u``, ``P̄ = A P Aᵀ + Q`` (``B = u = None``: no
      input);
    - ``update(C, y, R, D=None, u=None)``: ``K = P̄Cᵀ S⁻¹``, ``S = C P̄ Cᵀ + R``, ``x̂ = x̄ + K ν``,
      ``P = P̄ − K S Kᵀ``; returns the :class:`Innovation` (also kept in ``innovation``);
    - ``x``, ``P``: the current estimate and covariance.

    Raises :class:`pendulab.ShapeError` for sizes that do not fit, ``NotFiniteError`` for
    NaN/±Inf, :class:`pendulab.LinAlgError` (``variant == "Singular"``) if ``P0`` or ``S`` is
    not positive definite."""

    def __init__(self, x0: Any, P0: Any):
        self._f = _native.KalmanFilter(x0, P0)
        self.innovation: Optional[Innovation] = None

    def predict(self, A: Any, B: Any, u: Any, Q: Any) -> None:
        self._f.predict(A, B, u, Q)

    def update(self, C: Any, y: Any, R: Any, D: Any = None, u: Any = None) -> Innovation:
        self.innovation = Innovation(**self._f.update(C, y, R, D, u))
        return self.innovation

    def __repr__(self) -> str:
        return f"KalmanFilter(nx={len(self.x)})"


class _NonlinearFilter(_Estimator):
    """The filters of a model sampled at ``ts`` (s): the state one sample later is RK4 over
    ``ts`` in ``substeps`` steps with the input held; the measurement is the states listed in
    ``measured`` (default for the plants: the encoders ``[0, 1]``) or ``h(x, u)``.

    ``sys``: a :class:`pendulab.plants.CartPendulum` / ``ArmPendulum``, ``"cart"`` /
    ``"arm"``, or a callable ``f(x, u) -> dx/dt`` with ``nu`` inputs (default 0) and
    ``nx = len(x0)`` states. ``Q`` (``nx × nx``) and ``R`` (measured × measured) are the
    per-sample process and measurement noise covariances, ``P0`` the initial covariance
    (positive definite).

    - ``predict(u=None, t=0.0)``: one sample ahead from ``t`` with ``u`` (default zeros);
    - ``update(y, u=None, t=0.0)``: the update with ``y`` taken at ``t``; returns the
      :class:`Innovation` (also in ``innovation``);
    - ``x``, ``P``, ``ts``, ``nx``, ``nu``, ``ny``.

    Raises as :class:`KalmanFilter`; ``InvalidArgumentError`` for a measured state out of
    range, nothing measured, ``ts ≤ 0``; an exception raised by ``f`` or ``h`` propagates."""

    _kind = ""

    def __init__(self, sys, ts, x0, P0, Q, R, measured=None, h=None, nu=None, substeps=1, **sigma):
        self._f = _native.NonlinearFilter(
            self._kind, sys, float(ts), x0, P0, Q, R, _ints(measured), h, nu, int(substeps), **sigma)
        self.nx, self.nu, self.ny = self._f.dims
        self.innovation: Optional[Innovation] = None

    def _u(self, u: Any) -> Any:
        return np.zeros(self.nu) if u is None else u

    def predict(self, u: Any = None, t: float = 0.0) -> None:
        self._f.predict(float(t), self._u(u))

    def update(self, y: Any, u: Any = None, t: float = 0.0) -> Innovation:
        self.innovation = Innovation(**self._f.update(float(t), self._u(u), y))
        return self.innovation

    @property
    def ts(self) -> float:
        return self._f.ts

    def __repr__(self) -> str:
        return f"{type(self).__name__}(nx={self.nx}, nu={self.nu}, ny={self.ny}, ts={self.ts})"


class ExtendedKalmanFilter(_NonlinearFilter):
    __doc__ = ("The extended Kalman filter (``pendulab_control::kalman``): ``F = ∂Φ/∂x``, "
               "``H = ∂h/∂x`` at the estimate by Richardson-extrapolated central differences. "
               + _NonlinearFilter.__doc__)
    _kind = "ekf"

    def __init__(self, sys, ts, x0, P0, Q, R, *, measured=None, h=None, nu=None, substeps=1):
        super().__init__(sys, ts, x0, P0, Q, R, measured, h, nu, substeps)


class UnscentedKalmanFilter(_NonlinearFilter):
    __doc__ = ("The unscented Kalman filter (``pendulab_control::kalman``): ``2n + 1`` sigma points "
               "``m ± (√((n + λ) P))_i``, ``λ = α²(n + κ) − n``, weights ``W₀ᵐ = λ/(n + λ)``, "
               "``W₀ᶜ = W₀ᵐ + 1 − α² + β``, ``Wᵢ = 1/(2(n + λ))`` (``α > 0``, ``β ≥ 0``, "
               "``n + κ > 0``; defaults 1, 2, 0). " + _NonlinearFilter.__doc__)
    _kind = "ukf"

    def __init__(self, sys, ts, x0, P0, Q, R, *, measured=None, h=None, nu=None, substeps=1,
                 alpha=1.0, beta=2.0, kappa=0.0):
        super().__init__(sys, ts, x0, P0, Q, R, measured, h, nu, substeps,
                         alpha=float(alpha), beta=float(beta), kappa=float(kappa))


def read_cart_log(log: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(t, u, y)`` of a cart log as ``pendulab estimate --log`` reads it: CSV with a header
    (read by :func:`pendulab.ident.read_csv`, uniform ``t`` in s), the cart position ``z``
    (m), the angle ``phi`` (or ``theta``) from the hanging rest (rad) and the voltage ``v``
    (V). Returns ``t`` (N,), ``u = v`` (N, 1) and ``y = [z, φ + π]`` (N, 2: the angle from the
    upright, the cart model's convention). ``log``: a path or a ``pendulab.ident.Dataset``.
    Raises :class:`pendulab.InvalidArgumentError` naming a missing column."""
    from .ident import Dataset, read_csv
    from .errors import InvalidArgumentError

    data = log if isinstance(log, Dataset) else read_csv(os.fspath(log))
    data.uniform_step()

    def column(*names: str) -> np.ndarray:
        for n in names:
            if n in data.names:
                return np.asarray(data.column(n))
        raise InvalidArgumentError(
            f"{data.source}: no column {' or '.join(names)} (columns: {', '.join(data.names)})")

    z, phi, v = column("z"), column("phi", "theta"), column("v")
    return np.asarray(data.time()), v[:, None], np.column_stack([z, phi + np.pi])


def filter_log(filter: _NonlinearFilter, t: Any = None, u: Any = None, y: Any = None, *,
               log: Any = None) -> dict:
    """Runs an :class:`ExtendedKalmanFilter` or :class:`UnscentedKalmanFilter` over a record
    sampled at its ``ts``: sample ``k`` at ``t[k]``, ``u[k]`` applied from ``t[k]`` to
    ``t[k+1]``, ``y[k]`` measured at ``t[k]``; the first sample is an update only, every later
    one a prediction then the update (``pendulab_control::kalman::filter_log``). ``u``:
    (N, nu) (or (N,) for one input), ``y``: (N, ny). With ``log`` (a cart log's path or
    ``Dataset``) the signals are :func:`read_cart_log`'s, as ``pendulab estimate --log`` runs
    them. Returns a dict: ``states`` (N, nx) after each update, ``variances`` (N, nx, the
    diagonal of ``P``), ``nis`` (N,). Raises :class:`pendulab.ShapeError` if the lengths
    differ."""
    if log is not None:
        t, u, y = read_cart_log(log)
    if not isinstance(filter, _NonlinearFilter):
        raise TypeError(f"filter must be an ExtendedKalmanFilter or UnscentedKalmanFilter, "
                        f"got {type(filter).__name__}")
    return _native.control_filter_log(filter._f, t, u, y)


from ._native import control_encoder_covariance as encoder_covariance  # noqa: E402
from ._native import control_nees as nees  # noqa: E402
from ._native import control_quantization_variance as quantization_variance  # noqa: E402


# --- constrained linear MPC ----------------------------------------------------------------


class LinearMpc:
    """Constrained linear MPC (``pendulab_control::mpc::LinearMpc``) of ``x_{k+1} = A x_k +
    B u_k``: from the state ``x₀`` and the previous input ``u₋₁`` it minimises
    ``Σ_{k<N} (x_kᵀQx_k + u_kᵀRu_k) + x_NᵀPx_N`` subject to ``u_min ≤ u_k ≤ u_max``,
    ``|u_k − u_{k−1}| ≤ du_max`` and, for each ``(i, lo, hi)`` in ``state_bounds``,
    ``lo ≤ x_{k,i} ≤ hi`` (``k = 1 … N``), as the condensed QP ``min ½UᵀHU + gᵀU s.t.
    GU ≤ w`` solved by the warm-started dual active-set method.

    ``horizon`` ``N`` (1–1000 steps); ``Q`` (``nx × nx``), ``R`` (``nu × nu``, positive
    definite); ``P = None``: the DARE solution, so that without active constraints the first
    move is the discrete LQR law ``u₀ = −K x₀`` (``K``); ``u_max`` alone also sets ``u_min =
    −u_max``; scalars apply to every input; ``±inf`` means no bound. Units are the model's
    (for the rigs: m, rad, m/s, rad/s; V). :meth:`sampled` builds it from a continuous
    :class:`pendulab.StateSpace` sampled by ZOH at ``dt`` (s).

    ``step(x, u_prev=None, warm="shifted")`` returns the first move ``u₀`` (``u_prev``
    defaults to the last step's move, zeros at first; ``warm``: ``"cold"``, ``"same"``,
    ``"shifted"`` working set); afterwards ``status``, ``iterations``, ``active_set``,
    ``plan``, ``multipliers`` and ``kkt()`` describe that QP. Closed loop on the nonlinear
    plants: the spec kind ``"mpc"`` in :func:`pendulab.plants.simulate`.

    Raises :class:`pendulab.ShapeError`/``NotFiniteError`` for bad data,
    ``InvalidArgumentError`` for a bad horizon or bounds, ``NotStabilizableError`` if the DARE
    has no stabilising solution, ``LinAlgError`` if ``R`` is not positive definite; ``step``
    raises :class:`pendulab.InfeasibleError` (``certificate``, ``certificate_valid``) for an
    infeasible QP and ``LinAlgError`` (``variant == "MaxIterations"``) at the iteration
    limit."""

    def __init__(self, A: Any, B: Any, horizon: int, Q: Any, R: Any, *, P: Any = None,
                 u_min: Any = None, u_max: Any = None, du_max: Any = None,
                 state_bounds: Optional[Sequence[Tuple[int, float, float]]] = None,
                 tolerance: float = 1e-9, max_iterations: int = 0, _sys: Any = None,
                 _dt: Optional[float] = None):
        sb = None if state_bounds is None else [(int(i), float(lo), float(hi)) for i, lo, hi in state_bounds]
        self._m = _native.control_linear_mpc(
            A, B, int(horizon), Q, R, P, u_min, u_max, du_max, sb, float(tolerance),
            int(max_iterations), _sys, None if _dt is None else float(_dt))
        self.nx, self.nu, self.horizon, self.rows_per_stage = self._m.dims

    @classmethod
    def sampled(cls, sys: Any, dt: float, horizon: int, Q: Any, R: Any, **settings: Any) -> "LinearMpc":
        """The MPC of the continuous ``sys`` (a :class:`pendulab.StateSpace`; only ``A``,
        ``B`` are used) sampled by ZOH at the prediction step ``dt`` (s); ``settings`` as the
        constructor's keywords."""
        return cls(None, None, horizon, Q, R, _sys=sys, _dt=dt, **settings)

    def step(self, x: Any, u_prev: Any = None, warm: str = "shifted") -> np.ndarray:
        return self._m.step(x, u_prev, warm)

    def qp_vectors(self, x: Any, u_prev: Any = None) -> Tuple[np.ndarray, np.ndarray]:
        """The QP's ``(g, w)`` at ``x`` and ``u_prev`` (default zeros)."""
        return self._m.qp_vectors(x, np.zeros(self.nu) if u_prev is None else u_prev)

    def kkt(self) -> dict:
        """The KKT residuals of the last step's answer (see :func:`kkt_residuals`)."""
        return self._m.kkt()

    status = property(lambda self: self._m.status, doc="The last step's QP status.")
    iterations = property(lambda self: self._m.iterations, doc="Active-set iterations of the last step.")
    active_set = property(lambda self: self._m.active_set, doc="Active rows of G U ≤ w at the last step.")
    plan = property(lambda self: self._m.plan, doc="The last plan U = [u₀; …; u_{N−1}].")
    multipliers = property(lambda self: self._m.multipliers, doc="The last step's multipliers λ ≥ 0.")
    H = property(lambda self: self._m.H, doc="The condensed Hessian H (N·nu × N·nu).")
    G = property(lambda self: self._m.G, doc="The constraint matrix G (m × N·nu).")
    P = property(lambda self: self._m.P, doc="The terminal weight in use.")
    K = property(lambda self: self._m.K, doc="K = (R + BᵀPB)⁻¹BᵀPA: the unconstrained first move is −K x.")

    def __repr__(self) -> str:
        return f"LinearMpc(nx={self.nx}, nu={self.nu}, horizon={self.horizon})"


def solve_qp(H: Any, g: Any, A: Any, w: Any, warm_start: Optional[Sequence[int]] = None,
             tolerance: float = 1e-9, max_iterations: int = 0) -> dict:
    """``minimise ½xᵀHx + gᵀx  s.t.  A x ≤ w`` (``H`` symmetric positive definite, no zero row
    in ``A``) by the dual active-set method of Goldfarb–Idnani in DAQP's least-distance form
    (``pendulab_control::mpc::DualActiveSetQp``), from the working set ``warm_start``.
    ``tolerance``: largest accepted constraint violation (rows scaled to unit norm in the
    metric of ``H``); ``max_iterations = 0``: ``4(n + m)``.

    Returns a dict: ``x``, ``multipliers`` (``λ ≥ 0``, zero off the active set),
    ``active_set``, ``iterations``, ``status`` (``"solved"``) and ``kkt`` (the residuals of
    :func:`kkt_residuals`). Raises :class:`pendulab.InfeasibleError` when ``A x ≤ w`` has no
    point (``status == "infeasible"``, ``certificate`` ``y ≥ 0`` with ``yᵀA = 0``,
    ``yᵀw < 0``, ``certificate_valid``), :class:`pendulab.LinAlgError` at the iteration
    limit (``variant == "MaxIterations"``) or for ``H`` not positive definite or a zero row
    (``variant == "Singular"``), ``ShapeError``/``NotFiniteError`` for bad data."""
    return _native.control_solve_qp(H, g, A, w, _ints(warm_start), float(tolerance), int(max_iterations))


def kkt_residuals(H: Any, g: Any, A: Any, w: Any, x: Any, lam: Any) -> dict:
    """The KKT residuals of ``(x, λ)`` for ``minimise ½xᵀHx + gᵀx s.t. A x ≤ w``, each a largest
    absolute entry: ``stationarity`` ``‖Hx + g + Aᵀλ‖_∞``, ``primal`` ``max(0, max(Ax − w))``,
    ``dual`` ``max(0, max(−λ))``, ``complementarity`` ``max|λᵢ (Ax − w)ᵢ|``."""
    return _native.control_kkt_residuals(H, g, A, w, x, lam)
