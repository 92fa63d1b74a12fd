"""The package imports and reports the workspace's version (crates/python/Cargo.toml)."""

import re
from pathlib import Path

import pendulab


def test_version_is_the_workspace_version():
    cargo = (Path(__file__).resolve().parents[3] / "Cargo.toml").read_text()
    version = re.search(r'^version = "([^"]+)"', cargo, re.M).group(1)
    assert pendulab.__version__ == version
