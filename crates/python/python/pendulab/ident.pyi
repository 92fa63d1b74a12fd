import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

METHODS: Tuple[str, ...]
CONSTANTS: Dict[str, float]

class Dataset:
    names: list[str]
    source: str
    def column(self, name: str) -> np.ndarray: ...
    def time(self) -> np.ndarray: ...
    def uniform_step(self) -> float: ...
    def check_time_unit(self) -> None: ...
    def window(self, t0: Optional[float] = ..., t1: Optional[float] = ...) -> "Dataset": ...
    def __len__(self) -> int: ...

def read_csv(data: Union[str, os.PathLike], time_unit: Optional[str] = ...) -> Dataset: ...
def identify(method: str, data: Any, **options: Any) -> Dict[str, Any]: ...
def drive_ls(rig: str, ts: float, y: npt.ArrayLike, v: npt.ArrayLike, *, filter: str = ..., tf: float = ...,
             hold: str = ..., savgol: Optional[int] = ..., savgol_order: int = ...) -> Dict[str, Any]: ...
def cart_pendulum_ls(ts: float, z: npt.ArrayLike, phi: npt.ArrayLike, mp: float = ..., lp: float = ...,
                     g: float = ..., **options: Any) -> Dict[str, Any]: ...
def arm_pendulum_ls(ts: float, phi1: npt.ArrayLike, phi2: npt.ArrayLike, L1: float = ..., m2: float = ...,
                    l2: float = ..., g: float = ..., **options: Any) -> Dict[str, Any]: ...
def p_step(t: npt.ArrayLike, y: npt.ArrayLike, step_time: float, target: float, kp: float) -> Dict[str, Any]: ...
def free_oscillation(t: npt.ArrayLike, y: npt.ArrayLike, m: float, l: float, g: float = ...,
                     hysteresis: Optional[float] = ..., amplitude_correction: bool = ...,
                     ts: Optional[float] = ..., L1: Optional[float] = ...) -> Dict[str, Any]: ...

class ArxResult:
    a: np.ndarray
    b: np.ndarray
    na: int
    nb: int
    nk: int
    std_error: np.ndarray
    noise_variance: float
    ts: float
    model: Any
    fit: float
    aic: Optional[List[Dict[str, float]]]

class MoespResult:
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    order: int
    horizon: int
    max_order: Optional[int]
    singular_values: np.ndarray
    ts: float
    model: Any
    fit: float

def arx(u: npt.ArrayLike, y: npt.ArrayLike, ts: float, na: Optional[int] = ..., nb: Optional[int] = ...,
        nk: int = ..., max_order: Optional[int] = ...,
        validate: Optional[Tuple[npt.ArrayLike, npt.ArrayLike]] = ...) -> ArxResult: ...
def moesp(u: npt.ArrayLike, y: npt.ArrayLike, ts: float, order: Optional[int] = ..., horizon: int = ...,
          validate: Optional[Tuple[npt.ArrayLike, npt.ArrayLike]] = ...,
          max_order: Optional[int] = ...) -> MoespResult: ...
