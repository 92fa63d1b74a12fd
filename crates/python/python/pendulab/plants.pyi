from typing import Mapping, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

_F = npt.NDArray[np.float64]
_State = Sequence[float] | npt.ArrayLike

class CartPendulum:
    """The cart-type pendulum (book table 3.5); state [z, θ, ż, θ̇], input v (V)."""
    def __init__(self, params: Optional[Mapping[str, float]] = ...) -> None: ...
    @property
    def params(self) -> dict[str, float]: ...
    @property
    def inertia_about_pivot(self) -> float: ...
    @property
    def upright_energy(self) -> float: ...
    def derivative(self, x: _State, u: float) -> _F: ...
    def jacobian(self, x: _State, u: float) -> Tuple[_F, _F]: ...
    def linearize(
        self, posture: str = ..., z: float = ..., measured: bool = ...
    ) -> Tuple[_F, _F, _F, _F]: ...
    def energy(self, x: _State) -> float: ...

class ArmPendulum:
    """The arm-type pendulum (book table 3.7); state [θ₁, θ₂, θ̇₁, θ̇₂], input v (V)."""
    def __init__(self, params: Optional[Mapping[str, float]] = ...) -> None: ...
    @property
    def params(self) -> dict[str, float]: ...
    @property
    def alphas(self) -> Tuple[float, float, float]: ...
    @property
    def upright_energy(self) -> float: ...
    def derivative(self, x: _State, u: float) -> _F: ...
    def jacobian(self, x: _State, u: float) -> Tuple[_F, _F]: ...
    def linearize(
        self, posture: str = ..., theta1: float = ..., measured: bool = ...
    ) -> Tuple[_F, _F, _F, _F]: ...
    def lpv(self) -> Tuple[_F, _F, _F, _F]: ...
    def energy(self, x: _State) -> float: ...

class Trajectory:
    t: _F
    x: _F
    u: _F
    command: _F
    y: _F
    reference: _F
    ts: float
    switch_times: list[float]
    summary: dict[str, object]
    def to_pandas(self) -> object: ...

def simulate(
    plant: str | Mapping[str, object],
    controller: Mapping[str, object],
    x0: _State,
    t_final: float,
    imperfections: Optional[Mapping[str, object]] = ...,
    **scenario: object,
) -> Trajectory: ...
def simulate_batch(
    plant: str | Mapping[str, object],
    controller: Mapping[str, object],
    x0s: Sequence[_State],
    t_final: float,
    imperfections: Optional[Mapping[str, object]] = ...,
    workers: Optional[int] = ...,
    **scenario: object,
) -> list[Trajectory]: ...
def feedback_batch(
    K: npt.ArrayLike,
    x0s: npt.ArrayLike,
    t_final: float,
    params: Optional[Mapping[str, float]] = ...,
    ts: float = ...,
    substeps: int = ...,
    stay_within: Optional[Tuple[int, float]] = ...,
    threads: Optional[int] = ...,
) -> dict[str, _F]: ...

__all__: list[str]
