"""The documented install command works on a fresh virtual environment: ``pip install
./crates/python`` builds the extension (maturin from PyPI as the build backend, the Rust
crates from this checkout) and the installed package imports and computes.

Slow (a release build of the extension) and needs PyPI for the build backend and NumPy:
skipped offline, or when ``PENDULAB_SKIP_INSTALL_TEST`` is set, with the reason shown."""

import os
import pathlib
import socket
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def pypi_reachable() -> bool:
    try:
        socket.create_connection(("pypi.org", 443), timeout=3).close()
        return True
    except OSError:
        return False


@pytest.mark.skipif(bool(os.environ.get("PENDULAB_SKIP_INSTALL_TEST")), reason="PENDULAB_SKIP_INSTALL_TEST is set")
@pytest.mark.skipif(not pypi_reachable(), reason="offline: pip needs PyPI for maturin (the build backend) and NumPy")
def test_pip_install_into_a_fresh_venv(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run(
        [str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", str(ROOT / "crates" / "python")],
        check=True,
        cwd=tmp_path,
        timeout=3600,
    )
    out = subprocess.run(
        [str(py), "-c", "import pendulab as pl, pendulab.lmi, pendulab.book; "
         "print(pl.lqr([[0, 1], [0, 0]], [[0], [1]], [[1, 0], [0, 1]], 1).K.round(6).tolist())"],
        check=True, capture_output=True, text=True, cwd=tmp_path,
    ).stdout
    # The double integrator's LQR gain with Q = I, R = 1 is [1, √3] (closed form).
    assert out.strip() == str([[1.0, round(3 ** 0.5, 6)]])
