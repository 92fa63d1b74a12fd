"""Type stubs of pendulab's LTI API (implemented in Rust, ``pendulab._native``).

Gains follow ``u = -K x`` (the book's ``u = +K x`` has ``K_book = -K``). ``dt = 0``:
continuous time; ``dt > 0``: discrete time with that sample time in seconds.
"""

from typing import Any, Iterator, Literal, Optional, Protocol, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]
CArray = npt.NDArray[np.complex128]
ArrayLike = npt.ArrayLike
# A pendulab StateSpace/TransferFunction, a python-control StateSpace (.A .B .C .D .dt) or
# an (A, B, C, D[, dt]) tuple.
SystemLike = Any

class _System(Protocol):
    """What StateSpace and TransferFunction share (a typing protocol of the stubs only)."""

    @property
    def dt(self) -> float: ...
    def poles(self) -> CArray: ...
    def zeros(self) -> CArray: ...
    def dcgain(self) -> Union[float, Array]: ...

class StateSpace(_System):
    """dx/dt = A x + B u, y = C x + D u (dt = 0) or x[k+1] = A x[k] + B u[k] (dt > 0)."""

    def __init__(self, *args: Any, dt: Optional[float] = ...) -> None: ...
    @property
    def A(self) -> Array: ...
    @property
    def B(self) -> Array: ...
    @property
    def C(self) -> Array: ...
    @property
    def D(self) -> Array: ...
    @property
    def nstates(self) -> int: ...
    @property
    def ninputs(self) -> int: ...
    @property
    def noutputs(self) -> int: ...
    def isctime(self) -> bool: ...
    def isdtime(self) -> bool: ...
    def sample(self, Ts: float, method: str = ..., prewarp_frequency: Optional[float] = ...) -> StateSpace: ...

class TransferFunction(_System):
    """SISO num/den, coefficients in descending powers; den normalised to be monic."""

    def __init__(self, num: ArrayLike, den: ArrayLike, dt: Optional[float] = ...) -> None: ...
    @property
    def num(self) -> Array: ...
    @property
    def den(self) -> Array: ...
    def dcgain(self) -> float: ...
    def to_ss(self) -> StateSpace: ...

class TransferMatrix:
    """MIMO transfer function: noutputs x ninputs SISO entries num[i][j]/den[i][j]."""

    def __init__(self, num: Any, den: Optional[Any] = ..., dt: Optional[float] = ...) -> None: ...
    @property
    def num(self) -> list[list[Array]]: ...
    @property
    def den(self) -> list[list[Array]]: ...
    @property
    def dt(self) -> float: ...
    @property
    def ninputs(self) -> int: ...
    @property
    def noutputs(self) -> int: ...
    @property
    def shape(self) -> Tuple[int, int]: ...
    def __call__(self, s: complex) -> CArray: ...
    def __add__(self, other: Any) -> TransferMatrix: ...
    def __radd__(self, other: Any) -> TransferMatrix: ...
    def __sub__(self, other: Any) -> TransferMatrix: ...
    def __rsub__(self, other: Any) -> TransferMatrix: ...
    def __mul__(self, other: Any) -> TransferMatrix: ...
    def __rmul__(self, other: Any) -> TransferMatrix: ...
    def __truediv__(self, other: Any) -> TransferMatrix: ...
    def __neg__(self) -> TransferMatrix: ...
    def feedback(self, other: Any = ..., sign: int = ...) -> TransferMatrix: ...
    def minreal(self) -> TransferMatrix: ...
    def to_ss(self) -> StateSpace: ...
    def zpk(self) -> list[list[Tuple[CArray, CArray, float]]]: ...

class _Result:
    def __iter__(self) -> Iterator[Any]: ...
    def __len__(self) -> int: ...
    def __getitem__(self, index: int) -> Any: ...

class LqrResult(_Result):
    K: Array
    S: Array
    E: CArray
    residual: float

class RiccatiResult(_Result):
    X: Array
    L: CArray
    G: Array
    residual: float
    method: str
    refinement_steps: int

class MatrixEquationResult(_Result):
    X: Array
    residual: float
    def __array__(self, dtype: Any = ..., copy: Optional[bool] = ...) -> Array: ...

class LqeResult(_Result):
    L: Array
    P: Array
    E: CArray
    residual: float

class PlaceResult(_Result):
    K: Array
    poles: CArray
    requested_poles: CArray
    max_relative_error: float
    eigenvector_condition: float
    method: str
    def __array__(self, dtype: Any = ..., copy: Optional[bool] = ...) -> Array: ...

class LqiResult(_Result):
    K: Array
    S: Array
    E: CArray
    state_gain: Array
    integral_gain: Array
    residual: float

class SampledDataLqrResult(_Result):
    K: Array
    S: Array
    E: CArray
    system: StateSpace
    Qd: Array
    Rd: Array
    Nd: Array
    residual: float

class MinimalObserverResult(_Result):
    system: StateSpace
    L: Array
    T: Array
    poles: CArray
    max_relative_error: float

class DampResult(_Result):
    wn: Array
    zeta: Array
    poles: CArray
    time_constants: Array

class LsimResult(_Result):
    y: Array
    t: Array
    x: Array
    u: Array

class LsimSplit(_Result):
    zero_input: LsimResult
    zero_state: LsimResult
    total: LsimResult

class TimeResponse(_Result):
    y: Array
    t: Array
    x: Array

class FrequencyResponse(_Result):
    response: CArray
    omega: Array

class BodeResult(_Result):
    mag_db: Array
    phase_deg: Array
    omega: Array

class NyquistResult(_Result):
    count: int
    response: CArray
    omega: Array
    contour: CArray
    winding: float
    open_loop_unstable: int
    closed_loop_unstable: int
    criterion_holds: bool
    indented_poles: CArray
    min_distance: float

class NicholsResult(_Result):
    mag_db: Array
    phase_deg: Array
    omega: Array

class RootLocusResult(_Result):
    roots: CArray
    gains: Array
    poles: CArray
    zeros: CArray
    centroid: float
    asymptote_angles: Array
    break_points: CArray
    break_gains: Array

class RlocfindResult(_Result):
    gain: float
    poles: CArray
    gain_complex: complex
    distance: float

class DiskMarginResult(_Result):
    alpha: float
    gain_margin_db: float
    phase_margin_deg: float
    gain_interval: Tuple[float, float]
    frequency: float
    closed_loop_stable: bool
    skew: float

class SigmaResult(_Result):
    sv: Array
    omega: Array

def ss(*args: Any, dt: Optional[float] = ...) -> StateSpace: ...
def tf(num: Any, den: Optional[Any] = ..., dt: Optional[float] = ...) -> Union[TransferFunction, TransferMatrix]: ...
def pade(T: float, n: int = ...) -> Tuple[Array, Array]: ...
def thiran(tau: float, Ts: float, order: Optional[int] = ...) -> TransferFunction: ...
def c2d(sys: SystemLike, Ts: float, method: str = ..., prewarp_frequency: Optional[float] = ...) -> Union[StateSpace, TransferFunction]: ...
def d2c(sys: SystemLike, method: str = ..., prewarp_frequency: Optional[float] = ...) -> Union[StateSpace, TransferFunction]: ...
def poles(sys: SystemLike) -> CArray: ...
def zeros(sys: SystemLike) -> CArray: ...
def dcgain(sys: SystemLike) -> Union[float, Array]: ...
def damp(sys: SystemLike) -> DampResult: ...
def ctrb(A: ArrayLike, B: ArrayLike) -> Array: ...
def obsv(A: ArrayLike, C: ArrayLike) -> Array: ...
def gram(sys: SystemLike, type: Literal["c", "o"]) -> MatrixEquationResult: ...
def lyap(A: ArrayLike, Q: ArrayLike, C: Optional[ArrayLike] = ...) -> MatrixEquationResult: ...
def dlyap(A: ArrayLike, Q: ArrayLike) -> MatrixEquationResult: ...
def care(A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: Optional[ArrayLike] = ..., S: Optional[ArrayLike] = ..., E: None = ...) -> RiccatiResult: ...
def dare(A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: Optional[ArrayLike] = ..., S: Optional[ArrayLike] = ..., E: None = ...) -> RiccatiResult: ...
def lqr(*args: Any, N: Optional[ArrayLike] = ...) -> LqrResult: ...
def dlqr(*args: Any, N: Optional[ArrayLike] = ...) -> LqrResult: ...
def lqe(*args: Any) -> LqeResult: ...
def dlqe(*args: Any) -> LqeResult: ...
def place(A: ArrayLike, B: ArrayLike, p: ArrayLike) -> PlaceResult: ...
def acker(A: ArrayLike, B: ArrayLike, p: ArrayLike) -> PlaceResult: ...
def place_observer(A: ArrayLike, C: ArrayLike, p: ArrayLike) -> PlaceResult: ...
def lqi(sys: SystemLike, Q: ArrayLike, R: ArrayLike) -> LqiResult: ...
def lqr_sampled_data(sys: SystemLike, Q: ArrayLike, R: ArrayLike, Ts: float, N: Optional[ArrayLike] = ...) -> SampledDataLqrResult: ...
def reg(sys: SystemLike, K: ArrayLike, L: ArrayLike) -> StateSpace: ...
def minimal_order_observer(sys: SystemLike, p: ArrayLike) -> MinimalObserverResult: ...
def lsim(sys: SystemLike, U: Optional[ArrayLike] = ..., T: Optional[ArrayLike] = ..., X0: Optional[ArrayLike] = ..., hold: Literal["foh", "zoh"] = ..., return_x: bool = ...) -> LsimResult: ...
def lsim_split(sys: SystemLike, U: ArrayLike, T: ArrayLike, X0: ArrayLike, hold: Literal["foh", "zoh"] = ...) -> LsimSplit: ...
def step(sys: SystemLike, T: Optional[ArrayLike] = ...) -> TimeResponse: ...
def impulse(sys: SystemLike, T: Optional[ArrayLike] = ...) -> TimeResponse: ...
def initial(sys: SystemLike, T: Optional[ArrayLike] = ..., X0: Optional[ArrayLike] = ...) -> TimeResponse: ...
def freqresp(sys: SystemLike, omega: Optional[ArrayLike] = ...) -> FrequencyResponse: ...
def bode(sys: SystemLike, omega: Optional[ArrayLike] = ...) -> BodeResult: ...
def nyquist(sys: SystemLike, indent_radius: float = ...) -> NyquistResult: ...
def nichols(sys: SystemLike, omega: Optional[ArrayLike] = ...) -> NicholsResult: ...
def rlocus(sys: SystemLike, gains: Optional[ArrayLike] = ...) -> RootLocusResult: ...
def rlocfind(sys: SystemLike, s0: complex) -> RlocfindResult: ...
def disk_margin(sys: SystemLike, skew: float = ...) -> DiskMarginResult: ...
def sigma(sys: SystemLike, omega: Optional[ArrayLike] = ...) -> SigmaResult: ...

class StabsepResult(_Result):
    """G = G_s + G_u (MATLAB ``GS, GNS = stabsep(G)``); G_u strictly proper."""
    stable: StateSpace
    unstable: StateSpace

class BalrealResult(_Result):
    """MATLAB ``sysb, g, T, Ti = balreal(sys)``: x_b = T x, x = Ti x_b; g descending, inf per unstable state."""
    sysb: StateSpace
    g: Array
    T: Array
    Ti: Array

class HinfnormResult(_Result):
    """MATLAB ``ninf, fpeak = hinfnorm(sys)``; fpeak in rad/s."""
    ninf: float
    fpeak: float
    upper_bound: float

class MuResult(_Result):
    """Bounds on μ(M) for diagonal complex Δ; unpacks as ``upper, lower``."""
    upper: float
    lower: float
    d_scaling: Array

class MimoDiskMarginResult(_Result):
    """MATLAB ``DM, MM = diskmargin(L)``: loop-at-a-time and multi-loop disk margins."""
    loop_at_a_time: list[DiskMarginResult]
    multi_loop: DiskMarginResult
    alpha_bounds: Tuple[float, float]
    mu_peak: MuResult
    peak_frequency: float
    closed_loop_stable: bool

def stabsep(sys: SystemLike) -> StabsepResult: ...
def hsvd(sys: SystemLike) -> Array: ...
def balreal(sys: SystemLike) -> BalrealResult: ...
def balred(sys: SystemLike, orders: Union[int, Sequence[int]], method: Literal["truncate", "matchdc"] = ...) -> Union[StateSpace, list[StateSpace]]: ...
def hinfnorm(sys: SystemLike, tol: float = ...) -> HinfnormResult: ...
def mu_diag_complex(M: ArrayLike) -> MuResult: ...
def disk_margin_mimo(L: SystemLike, skew: float = ...) -> MimoDiskMarginResult: ...

__all__: list[str]

class HinfsynResult(_Result):
    """An H∞ controller; unpacks as python-control's ``K, CL, gam``."""
    K: StateSpace
    CL: StateSpace
    gam: float
    X: Array
    Y: Array
    rho: float
    gamma_infeasible: Optional[float]

class H2synResult(_Result):
    """The H2-optimal controller; unpacks as ``K, CL, norm``."""
    K: StateSpace
    CL: StateSpace
    norm: float
    X: Array
    Y: Array
    Kx: Array
    L: Array

def hinfsyn(P: SystemLike, nmeas: int, ncon: int, gamma: Optional[float] = ..., tol: float = ...) -> HinfsynResult: ...
def h2syn(P: SystemLike, nmeas: int, ncon: int) -> H2synResult: ...
def augw(G: SystemLike, w1: Optional[SystemLike] = ..., w2: Optional[SystemLike] = ..., w3: Optional[SystemLike] = ...) -> StateSpace: ...
