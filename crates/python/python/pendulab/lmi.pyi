from typing import Any, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

from .errors import InfeasibleError as InfeasibleError

ArrayLike = npt.ArrayLike
Region = Tuple[Any, ...]

class LmiFeedback:
    K: np.ndarray
    X: np.ndarray
    L: np.ndarray
    poles: list[np.ndarray]
    poles_in_regions: bool
    status: str
    objective: Optional[float]
    iterations: int
    def cost_bound(self, x0: ArrayLike) -> float: ...
    def __iter__(self) -> Any: ...
    def __len__(self) -> int: ...

class Lyapunov:
    P: np.ndarray
    alpha: float
    solves: int
    status: str
    def __array__(self, dtype: Any = ..., copy: Any = ...) -> np.ndarray: ...

class Schedule:
    gamma: float
    gamma_star: Optional[float]
    rho_range: Tuple[float, float]
    status: str
    x_coefficients: Tuple[np.ndarray, np.ndarray, np.ndarray]
    l_coefficients: Tuple[np.ndarray, np.ndarray, np.ndarray]
    optimum: Optional["Schedule"]
    def __call__(self, rho: float) -> np.ndarray: ...
    def X(self, rho: float) -> np.ndarray: ...
    def L(self, rho: float) -> np.ndarray: ...

def alpha_stability(A: ArrayLike, alpha: float, margin: float = ...) -> Lyapunov: ...
def max_decay_rate(A: ArrayLike, margin: float = ..., tol: float = ...) -> Lyapunov: ...
def lq(A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: ArrayLike) -> LmiFeedback: ...
def d_stability(
    A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: ArrayLike, regions: Sequence[Region]
) -> LmiFeedback: ...
def robust(
    vertices: Sequence[Tuple[ArrayLike, ArrayLike]],
    Q: ArrayLike,
    R: ArrayLike,
    regions: Optional[Sequence[Region]] = ...,
) -> LmiFeedback: ...
def saturated(
    A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: ArrayLike, u_max: ArrayLike, x0s: ArrayLike
) -> LmiFeedback: ...
def state_feedback(
    vertices: Sequence[Tuple[ArrayLike, ArrayLike]],
    Q: Optional[ArrayLike] = ...,
    R: Optional[ArrayLike] = ...,
    regions: Optional[Sequence[Region]] = ...,
    u_max: Optional[ArrayLike] = ...,
    x0s: Optional[ArrayLike] = ...,
    refinement: str = ...,
    relax: float = ...,
    margin: float = ...,
) -> LmiFeedback: ...
def gain_scheduled(
    A0: ArrayLike,
    A1: ArrayLike,
    B0: ArrayLike,
    B1: ArrayLike,
    Q: ArrayLike,
    R: ArrayLike,
    rho_range: Tuple[float, float],
    rho0_range: Optional[Tuple[float, float]] = ...,
    rho_dot_bound: float = ...,
    margin: float = ...,
    gamma_relax: float = ...,
    balance: bool = ...,
) -> Schedule: ...
