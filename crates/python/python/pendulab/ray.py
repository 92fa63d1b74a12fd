"""Studies on a Ray cluster (``docs/studies.md``): :func:`run` computes a
:class:`pendulab.study.Study` as one Ray task per chunk and gathers the results in index
order, bit-identical to the local backend.

What is shipped: the study's specification (a small JSON-able dict, ``ray.put`` once and
passed by reference to every task) and each task's ``(start, count)``; each task returns
its chunk's NumPy arrays. Workers import ``pendulab`` themselves, so the package must be
installed in the workers' Python environment (the same wheel; a ``runtime_env`` with
``pip: ["pendulab"]`` does it on a cluster).

:func:`connect` joins a cluster at ``address`` after checking, within ``timeout`` seconds,
that a gRPC server answers there (:func:`probe`), so an unreachable address raises
``ConnectionError`` instead of waiting.
"""

import os
import socket
import time
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np

from .errors import InvalidArgumentError
from .study import ChunkCache, Study, StudyResult, assemble, chunk_ranges, compute_chunk, default_chunk

__all__ = ["connect", "probe", "run"]


def _ray():
    try:
        import ray
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("pendulab.ray needs Ray: pip install 'ray[tune]'") from e
    return ray


def _host_port(address: str) -> Tuple[str, int]:
    a = address.split("://", 1)[-1]
    host, sep, port = a.rpartition(":")
    if not sep or not port.isdigit():
        raise InvalidArgumentError(f"pendulab.ray: address {address!r} must be host:port (or ray://host:port)")
    return host.strip("[]"), int(port)


#: The HTTP/2 client preface and an empty SETTINGS frame (RFC 9113 §3.4, §6.5).
_H2_HELLO = b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n" + b"\x00\x00\x00\x04\x00\x00\x00\x00\x00"


def probe(address: str, timeout: float = 10.0) -> None:
    """Checks within ``timeout`` seconds that a gRPC server (Ray's GCS and Ray Client are
    gRPC over HTTP/2) answers at ``address``: it opens a TCP connection, sends the HTTP/2
    client preface and expects the server's SETTINGS frame back. Raises ``ConnectionError``
    naming the address otherwise (a closed port, no route, or a port that accepts but does
    not speak HTTP/2)."""
    host, port = _host_port(address)
    deadline = time.monotonic() + timeout
    try:
        with socket.create_connection((host, port), timeout=timeout) as s:
            s.sendall(_H2_HELLO)
            head = b""
            while len(head) < 9:
                s.settimeout(max(1e-3, deadline - time.monotonic()))
                more = s.recv(9 - len(head))
                if not more:
                    raise OSError("the connection was closed without an HTTP/2 answer")
                head += more
    except OSError as e:
        raise ConnectionError(
            f"pendulab.ray: no Ray cluster answers at {address} within {timeout} s ({e or type(e).__name__})") from None
    if head[3] != 0x04:
        raise ConnectionError(f"pendulab.ray: {address} answers, but not as a Ray (gRPC) server")


def connect(address: Optional[str] = None, timeout: float = 10.0, **init_options: Any) -> None:
    """Joins the Ray cluster at ``address`` (``host:port`` of the head's GCS, or
    ``ray://host:port`` for Ray Client) unless this process has joined one already;
    ``None``: the cluster already joined, else ``ray.init(**init_options)`` (a local one).
    Raises ``ConnectionError`` naming the address when no gRPC server answers there within
    ``timeout`` seconds (:func:`probe`, checked first, whether or not a cluster is joined)."""
    ray = _ray()
    if address is not None:
        probe(address, timeout)
    if ray.is_initialized():
        return
    if address is None:
        ray.init(**init_options)
    else:
        ray.init(address=address, **init_options)


def _chunk_task(spec: Dict[str, Any], start: int, count: int, threads: int,
                fail_once: Optional[Tuple[int, str]]) -> Dict[str, np.ndarray]:
    """What a worker runs: samples ``start .. start + count`` of ``spec``. ``fail_once =
    (start, marker)`` is a test hook: the first attempt at that chunk creates the file
    ``marker`` and kills its worker process (``os._exit``), as a crashed node would."""
    if fail_once is not None and fail_once[0] == start:
        try:
            fd = os.open(fail_once[1], os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            pass
        else:
            os.close(fd)
            os._exit(1)
    return compute_chunk(spec, start, count, threads)


def run(
    study: Study,
    chunk: Optional[int] = None,
    progress=None,
    cache_dir: Optional[Union[str, os.PathLike]] = None,
    address: Optional[str] = None,
    timeout: float = 10.0,
    num_cpus: float = 1,
    threads: Optional[int] = None,
    max_retries: int = 3,
    resources: Optional[Dict[str, float]] = None,
    _fail_once: Optional[Tuple[int, str]] = None,
) -> StudyResult:
    """``study`` on Ray: one task per chunk of ``chunk`` samples (each task asks for
    ``num_cpus`` CPUs and ``resources``, runs on ``threads`` threads — default
    ``num_cpus`` — and is retried up to ``max_retries`` times if its worker dies), after
    :func:`connect` to ``address``. Chunks already in ``cache_dir`` are not submitted; each
    finished chunk is written there as it arrives, so a study whose driver or workers died
    resumes where it stopped. ``progress(done, total)`` is called as chunks finish (in
    completion order); the result is assembled in index order."""
    ray = _ray()
    connect(address, timeout=timeout)
    ranges = chunk_ranges(study.n, chunk or default_chunk(study))
    cache = ChunkCache(cache_dir, study) if cache_dir is not None else None
    parts: Dict[int, Dict[str, np.ndarray]] = {}
    done = 0
    for start, count in ranges:
        part = cache.load(start, count) if cache else None
        if part is not None:
            parts[start] = part
            done += count
    if progress and done:
        progress(done, study.n)
    todo = [(s, c) for s, c in ranges if s not in parts]
    if todo:
        task = ray.remote(_chunk_task).options(
            num_cpus=num_cpus, resources=resources or {}, max_retries=int(max_retries))
        spec_ref = ray.put(study.spec)
        nthreads = int(threads or max(1, int(num_cpus)))
        pending = {task.remote(spec_ref, s, c, nthreads, _fail_once): (s, c) for s, c in todo}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                s, c = pending.pop(ref)
                part = ray.get(ref)
                parts[s] = part
                if cache:
                    cache.store(s, c, part)
                done += c
                if progress:
                    progress(done, study.n)
    return StudyResult(study, assemble([parts[s] for s, _ in ranges]))
