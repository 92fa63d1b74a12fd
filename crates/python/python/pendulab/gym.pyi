from typing import Any, Optional, Tuple, TypedDict

from typing_extensions import Unpack

import gymnasium
import numpy as np
import numpy.typing as npt
from gymnasium.vector import VectorEnv

class CartPoleEnv(gymnasium.Env):
    state: Optional[npt.NDArray[np.float64]]
    def __init__(self, sutton_barto_reward: bool = ..., render_mode: Optional[str] = ...) -> None: ...
    def reset(self, *, seed: Optional[int] = ..., options: Optional[dict] = ...) -> Tuple[npt.NDArray[np.float32], dict]: ...
    def step(self, action: int) -> Tuple[npt.NDArray[np.float32], float, bool, bool, dict]: ...

class CartPoleVectorEnv(VectorEnv):
    def __init__(
        self,
        num_envs: int = ...,
        max_episode_steps: int = ...,
        render_mode: Optional[str] = ...,
        sutton_barto_reward: bool = ...,
        threads: Optional[int] = ...,
    ) -> None: ...
    @property
    def state(self) -> npt.NDArray[np.float64]: ...

class RigOptions(TypedDict, total=False):
    """The rig's keyword options (``RigEnv``'s docstring)."""

    dt: float
    substeps: int
    max_steps: int
    travel: Optional[float]
    quantize: bool
    dac: bool
    params: Optional[dict[str, float]]

class RigEnv(gymnasium.Env):
    travel: float
    def __init__(
        self,
        rig: str = ...,
        task: str = ...,
        render_mode: Optional[str] = ...,
        **options: Unpack[RigOptions],
    ) -> None: ...
    @property
    def state(self) -> npt.NDArray[np.float64]: ...

class RigVectorEnv(VectorEnv):
    travel: float
    def __init__(
        self,
        num_envs: int = ...,
        rig: str = ...,
        task: str = ...,
        render_mode: Optional[str] = ...,
        threads: Optional[int] = ...,
        **options: Unpack[RigOptions],
    ) -> None: ...
    @property
    def state(self) -> npt.NDArray[np.float64]: ...

__all__: list[str]
