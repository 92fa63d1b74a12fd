"""pendulab — the inverted-pendulum control laboratory, from Python.

The numerics are pendulab's Rust crates (``pendulab._native``); this package gives them
python-control's and MATLAB's names.
"""

from ._native import __version__

__all__ = ["__version__"]
