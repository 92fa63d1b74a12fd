from dataclasses import dataclass
from typing import Any, Callable, Dict, Iterator, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

class Controller:
    ny: int
    nu: int
    sample_time: Optional[float]
    switch_times: list[float]
    def update(self, t: float, y: npt.ArrayLike) -> np.ndarray: ...
    def reset(self) -> None: ...

def sliding_surface(A: npt.ArrayLike, B: npt.ArrayLike, Q: npt.ArrayLike, form: str = ...,
                    weight: str = ...) -> Dict[str, Any]: ...
def sliding_mode(S: npt.ArrayLike, A: npt.ArrayLike, B: npt.ArrayLike, k2: float,
                 delta: float = ...) -> Controller: ...
def energy_pumping(k1: float = ..., params: Optional[Mapping[str, float]] = ...) -> Controller: ...
def energy_shaping(rig: str, params: Optional[Mapping[str, float]] = ...,
                   gains: Optional[Mapping[str, float]] = ...) -> Controller: ...
def nmpc_arm_swing_up(params: Optional[Mapping[str, float]] = ..., u_max: float = ...,
                      ts: float = ...) -> Controller: ...
def odq(A: npt.ArrayLike, B: npt.ArrayLike, C: npt.ArrayLike, dt: float, step: float, method: str = ...,
        horizon: int = ..., max_filter_gain: Optional[float] = ...) -> Dict[str, Any]: ...
def kalman(A: npt.ArrayLike, B: npt.ArrayLike, C: npt.ArrayLike, dt: float, G: npt.ArrayLike,
           Qn: npt.ArrayLike, Rn: npt.ArrayLike) -> Dict[str, Any]: ...
def build(spec: Mapping[str, Any], plant: Union[str, Mapping[str, Any]] = ..., ts: float = ...) -> Controller: ...

_Model = Union[str, Any, Callable[[np.ndarray, np.ndarray], npt.ArrayLike]]

@dataclass
class OperatingPoint:
    x: np.ndarray
    u: np.ndarray
    y: np.ndarray
    dx: np.ndarray
    residual: float
    iterations: int
    status: str
    family_dimension: int
    @property
    def converged(self) -> bool: ...
    def __iter__(self) -> Iterator[np.ndarray]: ...

def find_operating_point(sys: _Model, x0: npt.ArrayLike, u0: Optional[npt.ArrayLike] = ...,
                         y0: Optional[npt.ArrayLike] = ..., t: float = ...,
                         iu: Optional[Sequence[int]] = ..., iy: Optional[Sequence[int]] = ...,
                         ix: Optional[Sequence[int]] = ..., idx: Optional[Sequence[int]] = ..., *,
                         h: Optional[Callable[[np.ndarray, np.ndarray], npt.ArrayLike]] = ...,
                         tol: float = ..., max_iterations: int = ...) -> OperatingPoint: ...

@dataclass
class Innovation:
    residual: np.ndarray
    S: np.ndarray
    K: np.ndarray
    nis: float

class KalmanFilter:
    innovation: Optional[Innovation]
    def __init__(self, x0: npt.ArrayLike, P0: npt.ArrayLike) -> None: ...
    def predict(self, A: npt.ArrayLike, B: Optional[npt.ArrayLike], u: Optional[npt.ArrayLike],
                Q: npt.ArrayLike) -> None: ...
    def update(self, C: npt.ArrayLike, y: npt.ArrayLike, R: npt.ArrayLike, D: Optional[npt.ArrayLike] = ...,
               u: Optional[npt.ArrayLike] = ...) -> Innovation: ...
    @property
    def x(self) -> np.ndarray: ...
    @property
    def P(self) -> np.ndarray: ...

class _NonlinearFilter:
    nx: int
    nu: int
    ny: int
    innovation: Optional[Innovation]
    def predict(self, u: Optional[npt.ArrayLike] = ..., t: float = ...) -> None: ...
    def update(self, y: npt.ArrayLike, u: Optional[npt.ArrayLike] = ..., t: float = ...) -> Innovation: ...
    @property
    def x(self) -> np.ndarray: ...
    @property
    def P(self) -> np.ndarray: ...
    @property
    def ts(self) -> float: ...

class ExtendedKalmanFilter(_NonlinearFilter):
    def __init__(self, sys: _Model, ts: float, x0: npt.ArrayLike, P0: npt.ArrayLike, Q: npt.ArrayLike,
                 R: npt.ArrayLike, *, measured: Optional[Sequence[int]] = ...,
                 h: Optional[Callable[[np.ndarray, np.ndarray], npt.ArrayLike]] = ...,
                 nu: Optional[int] = ..., substeps: int = ...) -> None: ...

class UnscentedKalmanFilter(_NonlinearFilter):
    def __init__(self, sys: _Model, ts: float, x0: npt.ArrayLike, P0: npt.ArrayLike, Q: npt.ArrayLike,
                 R: npt.ArrayLike, *, measured: Optional[Sequence[int]] = ...,
                 h: Optional[Callable[[np.ndarray, np.ndarray], npt.ArrayLike]] = ...,
                 nu: Optional[int] = ..., substeps: int = ..., alpha: float = ..., beta: float = ...,
                 kappa: float = ...) -> None: ...

def read_cart_log(log: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray]: ...
def filter_log(filter: _NonlinearFilter, t: Optional[npt.ArrayLike] = ..., u: Optional[npt.ArrayLike] = ...,
               y: Optional[npt.ArrayLike] = ..., *, log: Any = ...) -> Dict[str, np.ndarray]: ...
def encoder_covariance(q: npt.ArrayLike) -> np.ndarray: ...
def quantization_variance(q: float) -> float: ...
def nees(x_true: npt.ArrayLike, x_hat: npt.ArrayLike, P: npt.ArrayLike) -> float: ...

class LinearMpc:
    nx: int
    nu: int
    horizon: int
    rows_per_stage: int
    def __init__(self, A: npt.ArrayLike, B: npt.ArrayLike, horizon: int, Q: npt.ArrayLike, R: npt.ArrayLike, *,
                 P: Optional[npt.ArrayLike] = ..., u_min: Optional[npt.ArrayLike] = ...,
                 u_max: Optional[npt.ArrayLike] = ..., du_max: Optional[npt.ArrayLike] = ...,
                 state_bounds: Optional[Sequence[Tuple[int, float, float]]] = ...,
                 tolerance: float = ..., max_iterations: int = ...) -> None: ...
    @classmethod
    def sampled(cls, sys: Any, dt: float, horizon: int, Q: npt.ArrayLike, R: npt.ArrayLike,
                **settings: Any) -> "LinearMpc": ...
    def step(self, x: npt.ArrayLike, u_prev: Optional[npt.ArrayLike] = ..., warm: str = ...) -> np.ndarray: ...
    def qp_vectors(self, x: npt.ArrayLike, u_prev: Optional[npt.ArrayLike] = ...) -> Tuple[np.ndarray, np.ndarray]: ...
    def kkt(self) -> Dict[str, float]: ...
    status: str
    iterations: int
    active_set: list[int]
    plan: np.ndarray
    multipliers: np.ndarray
    H: np.ndarray
    G: np.ndarray
    P: np.ndarray
    K: np.ndarray

def solve_qp(H: npt.ArrayLike, g: npt.ArrayLike, A: npt.ArrayLike, w: npt.ArrayLike,
             warm_start: Optional[Sequence[int]] = ..., tolerance: float = ...,
             max_iterations: int = ...) -> Dict[str, Any]: ...
def kkt_residuals(H: npt.ArrayLike, g: npt.ArrayLike, A: npt.ArrayLike, w: npt.ArrayLike, x: npt.ArrayLike,
                  lam: npt.ArrayLike) -> Dict[str, float]: ...
