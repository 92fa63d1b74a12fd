"""Studies on a local Ray cluster (``pendulab.ray``, ``docs/studies.md``): the same study on
Ray and locally, bit for bit, for two chunkings; a worker killed in the middle of a study
(the ``_fail_once`` hook) with the task retried; resume from chunks a local run cached; an
unreachable cluster address failing fast. Skipped when Ray is not installed
(``requirements-test.txt`` pins it)."""

import os
import socket
import threading
import time

import numpy as np
import pytest

ray = pytest.importorskip("ray")

import pendulab as pl  # noqa: E402
from pendulab import plants, study  # noqa: E402
from pendulab import ray as pray  # noqa: E402
from test_batch import lqr_gain  # noqa: E402  (the LQR gain of pendulab bench sim-batch)

BOOK_K = {"kind": "state-feedback", "k_book": [3.16228, 13.47175, 4.48137, 2.26289]}
GRID = {"theta": (-1.2, 1.2, 15), "dtheta": (-3.0, 3.0, 11)}


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def assert_same(a, b):
    assert a.arrays.keys() == b.arrays.keys()
    for k in a.arrays:
        np.testing.assert_array_equal(a.arrays[k], b.arrays[k])
        assert a.arrays[k].dtype == b.arrays[k].dtype


def test_ray_equals_local_for_two_chunkings(cluster):
    k = lqr_gain()
    local = study.roa("cart", k, GRID, 3.0)
    for chunk in (16, 50):
        seen = []
        on_ray = study.roa("cart", k, GRID, 3.0, backend="ray", chunk=chunk,
                           progress=lambda d, t: seen.append(d))
        assert_same(local, on_ray)
        assert sorted(seen) == seen and seen[-1] == 165
    dist = {"m_p": ("uniform", 0.07, 0.11), "a_c": ("normal", 8.0, 0.5)}
    imp = {"quantization": True, "noise": {"std": [1e-4, 1e-3, 1e-3, 1e-2], "seed": 0}}
    mc_local = study.monte_carlo("cart", BOOK_K, dist, imp, 12, seed=5, duration=1.0)
    for chunk in (5, 12):
        assert_same(mc_local, study.monte_carlo("cart", BOOK_K, dist, imp, 12, seed=5, duration=1.0,
                                                backend="ray", chunk=chunk))


def test_a_killed_worker_is_retried_and_the_result_unchanged(cluster, tmp_path):
    k = lqr_gain()
    local = study.roa("cart", k, GRID, 3.0)
    marker = str(tmp_path / "killed")
    again = study.roa("cart", k, GRID, 3.0, backend="ray", chunk=40, max_retries=2,
                      _fail_once=(40, marker))
    assert os.path.exists(marker)  # the first attempt at chunk 40.. did die
    assert_same(local, again)
    # Without retries the death surfaces as Ray's error instead of a hang.
    with pytest.raises(ray.exceptions.RayError):
        study.roa("cart", k, GRID, 3.0, backend="ray", chunk=40, max_retries=0,
                  _fail_once=(80, str(tmp_path / "killed2")))


def test_ray_resumes_the_chunks_a_local_run_left(cluster, tmp_path):
    k = lqr_gain()
    local = study.roa("cart", k, GRID, 2.0, chunk=30, cache_dir=tmp_path)
    d = tmp_path / local.study.key
    for name in ("30-30.npz", "150-15.npz"):
        os.remove(d / name)
    seen = []
    resumed = study.roa("cart", k, GRID, 2.0, backend="ray", chunk=30, cache_dir=tmp_path,
                        progress=lambda done, total: seen.append(done))
    assert seen[0] == 165 - 45  # the cached chunks, reported before any task runs
    assert len(seen) == 3 and seen[-1] == 165
    assert_same(local, resumed)


def test_an_unreachable_address_fails_fast(cluster):
    # The running cluster's GCS passes the probe; a closed port, a port that accepts and
    # stays silent, one that answers but not in HTTP/2, and a malformed address do not, each
    # within its timeout (local sockets: the test does not depend on the network).
    pray.probe(ray.get_runtime_context().gcs_address, timeout=5.0)
    t0 = time.monotonic()
    with pytest.raises(ConnectionError, match="127.0.0.1:1"):
        pray.connect("127.0.0.1:1", timeout=2.0)
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen(1)
        addr = f"127.0.0.1:{silent.getsockname()[1]}"
        with pytest.raises(ConnectionError, match=addr):
            pray.connect(addr, timeout=1.0)
    with socket.socket() as chatty:
        chatty.bind(("127.0.0.1", 0))
        chatty.listen(1)
        addr = f"127.0.0.1:{chatty.getsockname()[1]}"

        def answer():
            conn, _ = chatty.accept()
            conn.sendall(b"-ERR this is not gRPC\r\n")
            conn.close()

        t = threading.Thread(target=answer, daemon=True)
        t.start()
        with pytest.raises(ConnectionError, match="not as a Ray"):
            pray.connect(addr, timeout=2.0)
        t.join(2.0)
    with pytest.raises(pl.InvalidArgumentError, match="host:port"):
        pray.connect("no-port", timeout=1.0)
    assert time.monotonic() - t0 < 6.0
