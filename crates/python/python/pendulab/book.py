"""The examples of 「倒立振子で学ぶ制御工学」 (``pendulab-book``), as ``pendulab book`` and
``pendulab report`` run them (``docs/report.md``).

- :func:`list` — every example: ``id`` (the book's M-file stem), ``title``, ``section``
  (e.g. ``"Part 1 §4.1"``), ``parameters``, ``needs_data``;
- :func:`run` — one example: its ``values`` (name → bool, float or NumPy array), the book's
  printed ``references`` beside them, ``notes``, ``status`` and the ``figures`` written into
  ``out`` (SVG and PNG, GIF for animations);
- :func:`report` — the lab report (``index.html``, ``figures/<id>/``, ``status.md``) in ``out``.

An unknown id raises :class:`pendulab.InvalidArgumentError`; a failing example
:class:`pendulab.Error` with the Rust message.
"""

import builtins
import os
from typing import Any, Dict, List, Optional, Sequence, Union

from . import _native

__all__ = ["list", "run", "report", "ids"]

PathLike = Union[str, os.PathLike]


def list() -> List[Dict[str, Any]]:  # noqa: A001 - the book's verb, as `pendulab book list`
    """Every example in book order (dicts: ``id``, ``title``, ``section``, ``parameters``,
    ``needs_data``)."""
    return _native.book_list()


def ids() -> List[str]:
    """The examples' ids in book order."""
    return [e["id"] for e in _native.book_list()]


def run(id: str, out: Optional[PathLike] = None, data: Optional[PathLike] = None) -> Dict[str, Any]:
    """Runs the example ``id`` (figures drawn and written into the directory ``out`` when
    given); ``data`` is a measured-data CSV file for an example that takes one."""
    text = None
    if data is not None:
        with builtins.open(os.fspath(data), encoding="utf-8") as f:
            text = f.read()
    return _native.book_run(id, None if out is None else os.fspath(out), text)


def report(out: PathLike, only: Optional[Sequence[str]] = None) -> Dict[str, Any]:
    """Runs the examples (``only``: these ids) in parallel and writes the lab report into
    ``out``; returns the page's path and the counts per status (``failing_ids`` lists the
    examples that failed)."""
    return _native.book_report(os.fspath(out), None if only is None else builtins.list(only))
