from typing import Any, Optional, Tuple

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

class RigEnv(gymnasium.Env):
    def __init__(
        self,
        rig: str = ...,
        task: str = ...,
        dt: float = ...,
        substeps: int = ...,
        max_steps: int = ...,
        travel: Optional[float] = ...,
        quantize: bool = ...,
        params: Optional[dict[str, float]] = ...,
        render_mode: Optional[str] = ...,
    ) -> None: ...
    @property
    def state(self) -> npt.NDArray[np.float64]: ...

class RigVectorEnv(VectorEnv):
    def __init__(
        self,
        num_envs: int = ...,
        rig: str = ...,
        task: str = ...,
        dt: float = ...,
        substeps: int = ...,
        max_steps: int = ...,
        travel: Optional[float] = ...,
        quantize: bool = ...,
        params: Optional[dict[str, float]] = ...,
        render_mode: Optional[str] = ...,
        threads: Optional[int] = ...,
    ) -> None: ...
    @property
    def state(self) -> npt.NDArray[np.float64]: ...

__all__: list[str]
