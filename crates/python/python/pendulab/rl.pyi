import os
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import NDArray

ENV_ID: str
ENV_KWARGS: Dict[str, Any]
UPRIGHT_WINDOW: float
HOLD_SECONDS: float
FEATURE_SCALE: Tuple[float, float, float]
OMEGA_NP: float
FEATURES: Dict[str, int]

def register_rllib(env_id: str = ...) -> str: ...
def make_vec(num_envs: int, env_id: str = ..., **kwargs: Any) -> Any: ...

class MlpPolicy:
    hidden: Tuple[int, ...]
    sizes: Tuple[int, ...]
    params: NDArray[np.float64]
    u_max: float
    meta: Dict[str, Any]
    features: str
    def __init__(
        self,
        params: Sequence[float],
        hidden: Sequence[int] = ...,
        u_max: float = ...,
        meta: Optional[Mapping[str, Any]] = ...,
        features: str = ...,
    ) -> None: ...
    @classmethod
    def initial(
        cls, hidden: Sequence[int] = ..., seed: int = ..., u_max: float = ..., features: str = ...
    ) -> "MlpPolicy": ...
    def __call__(self, obs: NDArray[Any]) -> Union[float, NDArray[np.float64]]: ...
    def save(self, path: Union[str, os.PathLike], **meta: Any) -> None: ...
    @classmethod
    def load(cls, path: Union[str, os.PathLike]) -> "MlpPolicy": ...

def swingup_success(
    theta: NDArray[Any], terminated: Union[bool, NDArray[np.bool_]], dt: float
) -> NDArray[np.bool_]: ...

def time_to_upright(theta: NDArray[Any], dt: float) -> NDArray[np.float64]: ...

class ESConfig:
    pairs: int
    sigma: float
    learning_rate: float
    weight_decay: float
    episodes: int
    hidden: Tuple[int, ...]
    u_max: float
    env_id: str
    env_kwargs: Mapping[str, Any]
    fitness: str
    anywhere: int
    anywhere_angle: float
    balance_weight: float
    curriculum: int
    seed: int
    def __init__(
        self,
        pairs: int = ...,
        sigma: float = ...,
        learning_rate: float = ...,
        weight_decay: float = ...,
        episodes: int = ...,
        hidden: Tuple[int, ...] = ...,
        u_max: float = ...,
        env_id: str = ...,
        env_kwargs: Mapping[str, Any] = ...,
        fitness: str = ...,
        anywhere: int = ...,
        anywhere_angle: float = ...,
        balance_weight: float = ...,
        curriculum: int = ...,
        seed: int = ...,
    ) -> None: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def check(self) -> None: ...

class CMAConfig:
    popsize: int
    sigma: float
    episodes: int
    hidden: Tuple[int, ...]
    features: str
    u_max: float
    env_id: str
    env_kwargs: Mapping[str, Any]
    bonus: float
    termination_penalty: float
    spread: Tuple[float, float, float, float]
    anywhere: int
    anywhere_angle: float
    balance_weight: float
    seed: int
    def __init__(
        self,
        popsize: int = ...,
        sigma: float = ...,
        episodes: int = ...,
        hidden: Tuple[int, ...] = ...,
        features: str = ...,
        u_max: float = ...,
        env_id: str = ...,
        env_kwargs: Mapping[str, Any] = ...,
        bonus: float = ...,
        termination_penalty: float = ...,
        spread: Tuple[float, float, float, float] = ...,
        anywhere: int = ...,
        anywhere_angle: float = ...,
        balance_weight: float = ...,
        seed: int = ...,
    ) -> None: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def check(self) -> None: ...

class TrainResult:
    policy: MlpPolicy
    config: Union[ESConfig, CMAConfig]
    history: Dict[str, NDArray[np.float64]]
    adam: Dict[str, Any]
    generations: int

def train(
    config: Union[ESConfig, CMAConfig, None] = ...,
    generations: int = ...,
    *,
    backend: str = ...,
    chunk: Optional[int] = ...,
    initial: Optional[MlpPolicy] = ...,
    resume: Optional[TrainResult] = ...,
    progress: Optional[Callable[[int, Dict[str, float]], None]] = ...,
    address: Optional[str] = ...,
    timeout: float = ...,
    num_cpus: float = ...,
    max_retries: int = ...,
    resources: Optional[Dict[str, float]] = ...,
) -> TrainResult: ...
def rollout(policy: MlpPolicy, x0: Sequence[float], env_id: str = ..., **env_kwargs: Any) -> Dict[str, Any]: ...
def evaluate(
    policy: MlpPolicy, states: NDArray[Any], env_id: str = ..., **env_kwargs: Any
) -> Dict[str, NDArray[Any]]: ...
