import os
from typing import Any, Callable, Dict, Optional, Tuple, Union

from .study import Study, StudyResult

def probe(address: str, timeout: float = ...) -> None: ...
def connect(address: Optional[str] = ..., timeout: float = ..., **init_options: Any) -> None: ...
def run(
    study: Study,
    chunk: Optional[int] = ...,
    progress: Optional[Callable[[int, int], None]] = ...,
    cache_dir: Optional[Union[str, os.PathLike]] = ...,
    address: Optional[str] = ...,
    timeout: float = ...,
    num_cpus: float = ...,
    threads: Optional[int] = ...,
    max_retries: int = ...,
    resources: Optional[Dict[str, float]] = ...,
    _fail_once: Optional[Tuple[int, str]] = ...,
) -> StudyResult: ...
