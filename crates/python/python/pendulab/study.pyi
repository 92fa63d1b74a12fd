import os
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import NDArray

CART_STATES: Tuple[str, str, str, str]
Progress = Callable[[int, int], None]

class Study:
    spec: Dict[str, Any]
    n: int
    def __init__(self, spec: Mapping[str, Any]) -> None: ...
    @property
    def kind(self) -> str: ...
    @property
    def key(self) -> str: ...
    def chunk(self, start: int, count: int, threads: Optional[int] = ...) -> Dict[str, NDArray[Any]]: ...

class StudyResult:
    study: Study
    arrays: Dict[str, NDArray[Any]]
    def __init__(self, study: Study, arrays: Mapping[str, NDArray[Any]]) -> None: ...
    def __getattr__(self, name: str) -> NDArray[Any]: ...
    @property
    def stats(self) -> Dict[str, float]: ...
    def roa_slice(
        self, at: Optional[Mapping[str, int]] = ...
    ) -> Tuple[list, list, NDArray[np.bool_]]: ...
    def save_figure(
        self,
        path: Union[str, os.PathLike],
        field: str = ...,
        bins: int = ...,
        at: Optional[Mapping[str, int]] = ...,
    ) -> None: ...
    def save(
        self, lab_dir: Union[str, os.PathLike], name: Optional[str] = ..., **figure_options: Any
    ) -> str: ...

class ChunkCache:
    dir: str
    def __init__(self, cache_dir: Union[str, os.PathLike], study: Study) -> None: ...
    def load(self, start: int, count: int) -> Optional[Dict[str, NDArray[Any]]]: ...
    def store(self, start: int, count: int, arrays: Mapping[str, NDArray[Any]]) -> None: ...

def roa_initial_states(spec: Mapping[str, Any], start: int, count: int) -> NDArray[np.float64]: ...
def compute_chunk(
    spec: Mapping[str, Any], start: int, count: int, threads: Optional[int] = ...
) -> Dict[str, NDArray[Any]]: ...
def draws(
    parameter_distribution: Mapping[str, Sequence[Any]], n: int, seed: int, start: int = ...
) -> NDArray[np.float64]: ...
def roa(
    plant: Union[str, Mapping[str, float]],
    controller: Sequence[float],
    grid: Mapping[str, Tuple[float, float, int]],
    duration: float,
    *,
    x0: Sequence[float] = ...,
    ts: float = ...,
    substeps: int = ...,
    angle_limit: float = ...,
    angle_tol: float = ...,
    travel: float = ...,
    seed: int = ...,
    **run_options: Any,
) -> StudyResult: ...
def monte_carlo(
    plant: Union[str, Mapping[str, Any]],
    controller: Mapping[str, Any],
    parameter_distribution: Mapping[str, Sequence[Any]],
    imperfections: Optional[Mapping[str, Any]],
    n: int,
    seed: int,
    *,
    x0: Sequence[float] = ...,
    duration: float = ...,
    scenario: Optional[Mapping[str, Any]] = ...,
    **run_options: Any,
) -> StudyResult: ...
def chunk_ranges(n: int, chunk: int) -> list[Tuple[int, int]]: ...
def default_chunk(study: Study) -> int: ...
def assemble(parts: Sequence[Mapping[str, NDArray[Any]]]) -> Dict[str, NDArray[Any]]: ...
def run(
    study: Study,
    backend: str = ...,
    chunk: Optional[int] = ...,
    progress: Optional[Progress] = ...,
    cache_dir: Optional[Union[str, os.PathLike]] = ...,
    threads: Optional[int] = ...,
    **ray_options: Any,
) -> StudyResult: ...
