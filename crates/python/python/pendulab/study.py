"""Studies: which initial states a controller catches (region of attraction) and how its
runs spread over the plant's parameter uncertainty (Monte Carlo), on local cores or a Ray
cluster (``docs/studies.md``).

A study is cut into chunks of consecutive sample indices. Every sample's result depends only
on the study's specification and its index (a region-of-attraction sample's initial state is
its grid point; a Monte Carlo sample's parameters and noise seed come from counter-based
streams of ``(seed, index)`` in Rust), so the result is bit-identical whatever the chunking,
the backend or the worker. ``run`` computes the chunks on local cores (the native batch path,
GIL released, Ctrl-C honoured between chunks) or on Ray (``backend="ray"``, see
``pendulab.ray``); with ``cache_dir`` each finished chunk is kept on disk under the study's
hash and a rerun computes only the missing ones.

- :func:`roa`: the book's cart pendulum (table 3.5, parameters overridable) under
  ``u = −K x`` from every point of a grid of initial states, by the lane kernel of
  ``pendulab bench sim-batch``; per sample ``caught`` / ``held`` / ``time_to_fall`` /
  ``steps`` (RK4 steps integrated) / ``final_state``.
- :func:`monte_carlo`: any plant spec and controller spec through the one simulate path with
  the rig's imperfections, plant parameters drawn per sample; per sample ``caught``,
  ``settling_time``, ``peak_input``, ``max_angle_deviation``, ``params``.
"""

import hashlib
import json
import math
import os
import tempfile
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from ._native import (
    __version__,
    batch_feedback,
    study_draws,
    study_histogram_figure,
    study_monte_carlo_chunk,
    study_roa_figure,
)
from .errors import InvalidArgumentError, NotFiniteError

__all__ = ["Study", "StudyResult", "roa", "monte_carlo", "run", "draws"]

#: The cart's state names, in the order of ``[z, θ, ż, θ̇]`` (``docs/model.md``).
CART_STATES = ("z", "theta", "dz", "dtheta")

Progress = Callable[[int, int], None]


class Study:
    """A study's specification (a JSON-able dict, what is shipped to workers) and its size.

    ``chunk(start, count, threads=None)`` computes samples ``start .. start + count`` and
    returns their per-sample arrays; ``key`` is the SHA-256 of the specification and the
    package version (the cache directory's name)."""

    def __init__(self, spec: Mapping[str, Any]):
        self.spec = dict(spec)
        self.n = int(self.spec["n"])

    @property
    def kind(self) -> str:
        return self.spec["kind"]

    @property
    def key(self) -> str:
        text = json.dumps(self.spec, sort_keys=True) + "|" + __version__
        return hashlib.sha256(text.encode()).hexdigest()[:24]

    def chunk(self, start: int, count: int, threads: Optional[int] = None) -> Dict[str, np.ndarray]:
        return compute_chunk(self.spec, start, count, threads)

    def __repr__(self) -> str:
        return f"Study({self.kind}, n={self.n}, key={self.key})"


def _grid_axes(spec: Mapping[str, Any]):
    return [(CART_STATES.index(name), lo, hi, n) for name, lo, hi, n in spec["axes"]]


def roa_initial_states(spec: Mapping[str, Any], start: int, count: int) -> np.ndarray:
    """The initial states ``[z, θ, ż, θ̇]`` of samples ``start .. start + count`` of a
    region-of-attraction study: sample ``k`` is the grid point whose axis indices are
    ``numpy.unravel_index(k, shape)`` (C order, the last axis fastest); axis value ``i`` is
    ``lo + (hi − lo)·i/(n − 1)`` (``lo`` for ``n = 1``); the other states are ``x0``'s."""
    axes = _grid_axes(spec)
    shape = tuple(a[3] for a in axes)
    idx = np.unravel_index(np.arange(start, start + count), shape)
    x = np.tile(np.asarray(spec["x0"], dtype=float), (count, 1))
    for (col, lo, hi, n), i in zip(axes, idx):
        x[:, col] = lo + (hi - lo) * i / (n - 1) if n > 1 else lo
    return x


def compute_chunk(spec: Mapping[str, Any], start: int, count: int,
                  threads: Optional[int] = None) -> Dict[str, np.ndarray]:
    """Samples ``start .. start + count`` of the study ``spec`` (what a worker runs)."""
    if spec["kind"] == "roa":
        x0s = roa_initial_states(spec, start, count)
        out = batch_feedback(spec["K"], x0s, spec["duration"], params=spec["params"], ts=spec["ts"],
                             substeps=spec["substeps"], stay_within=(1, spec["angle_limit"]),
                             threads=threads)
        fs = out["final_state"]
        theta = np.mod(fs[:, 1] + np.pi, 2 * np.pi) - np.pi
        caught = out["held"] & (np.abs(theta) <= spec["angle_tol"]) & (np.abs(fs[:, 0]) <= spec["travel"])
        fall = np.where(out["held"], np.nan, out["steps"] / spec["substeps"] * spec["ts"])
        return {"caught": caught, "held": out["held"], "time_to_fall": fall, "steps": out["steps"],
                "final_state": fs}
    if spec["kind"] == "monte_carlo":
        return dict(study_monte_carlo_chunk(
            spec["plant"], spec["controller"], spec["scenario"], spec["names"], spec["kinds"],
            spec["a"], spec["b"], spec["seed"], start, count, threads=threads))
    raise InvalidArgumentError(f"study: unknown kind {spec['kind']!r}")


def draws(parameter_distribution: Mapping[str, Sequence[Any]], n: int, seed: int, start: int = 0) -> np.ndarray:
    """The parameter draws of samples ``start .. start + n`` (``n × p``, columns in the
    mapping's order) as :func:`monte_carlo` makes them."""
    names, kinds, a, b = _distribution(parameter_distribution)
    return study_draws(_seed(seed), start, n, kinds, a, b)


def _seed(seed: Any) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= int(seed) < 2**64:
        raise InvalidArgumentError(f"study: seed must be an integer in [0, 2⁶⁴), got {seed!r}")
    return int(seed)


def _finite(name: str, v: Any) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise InvalidArgumentError(f"study: {name} must be a number, got {v!r}") from None
    if not math.isfinite(x):
        raise NotFiniteError(f"study: {name} is {x}; it must be finite")
    return x


def _distribution(pd: Mapping[str, Sequence[Any]]):
    names, kinds, a, b = [], [], [], []
    for name, d in pd.items():
        if isinstance(d, str) or len(d) != 3:
            raise InvalidArgumentError(
                f"study: parameter_distribution[{name!r}] must be (\"uniform\", low, high) or "
                f"(\"normal\", mean, std), got {d!r}")
        names.append(str(name))
        kinds.append(str(d[0]))
        a.append(_finite(f"parameter_distribution[{name!r}][1]", d[1]))
        b.append(_finite(f"parameter_distribution[{name!r}][2]", d[2]))
    return names, kinds, a, b


def roa(
    plant: Union[str, Mapping[str, float]],
    controller: Sequence[float],
    grid: Mapping[str, Tuple[float, float, int]],
    duration: float,
    *,
    x0: Sequence[float] = (0.0, 0.0, 0.0, 0.0),
    ts: float = 1e-3,
    substeps: int = 1,
    angle_limit: float = math.pi / 2,
    angle_tol: float = 0.05,
    travel: float = math.inf,
    seed: int = 0,
    **run_options: Any,
) -> "StudyResult":
    """The region of attraction of ``u = −K x`` (``controller``: the gain ``K``, 4 entries, V
    per SI state unit) on the book's cart pendulum (``plant``: ``"cart"`` or a dict
    overriding parameters of table 3.5) over ``grid``: ``{state: (low, high, points)}`` for
    states among ``z, theta, dz, dtheta`` (m, rad, m/s, rad/s; the others from ``x0``), every
    run ``duration`` s at sample time ``ts`` (RK4, ``substeps`` per sample).

    A sample is ``held`` when ``|θ| ≤ angle_limit`` at every sample (the run stops at the
    first one past it, ``time_to_fall`` s, after ``steps`` RK4 steps), and ``caught`` when held and ending with
    ``|θ| ≤ angle_tol`` and ``|z| ≤ travel``. ``seed`` enters the hash only (the grid has no
    randomness). ``run_options`` go to :func:`run` (``backend``, ``chunk``, ``progress``,
    ``cache_dir``, ``threads``, Ray options).

    Raises ``InvalidArgumentError`` for an empty grid, an unknown state or a non-cart plant,
    ``NotFiniteError`` for NaN/±Inf bounds.
    """
    if plant == "cart":
        params = None
    elif isinstance(plant, Mapping):
        params = {str(k): _finite(f"plant[{k!r}]", v) for k, v in plant.items()}
    else:
        raise InvalidArgumentError(
            f"study.roa: plant must be \"cart\" or a dict of table 3.5 parameters, got {plant!r} "
            "(the grid kernel models the cart pendulum)")
    try:
        gain = np.asarray(controller, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidArgumentError(
            f"study.roa: controller must be the gain K (4 numbers, u = −K x), got {controller!r}") from None
    K = [_finite(f"K[{i}]", v) for i, v in enumerate(gain)]
    if len(K) != 4:
        raise InvalidArgumentError(f"study.roa: controller must be the gain K with 4 entries, got {len(K)}")
    if not grid:
        raise InvalidArgumentError("study.roa: the grid is empty (give {state: (low, high, points)})")
    axes = []
    for name, ax in grid.items():
        if name not in CART_STATES:
            raise InvalidArgumentError(f"study.roa: unknown state {name!r}; expected one of {CART_STATES}")
        if len(ax) != 3:
            raise InvalidArgumentError(f"study.roa: grid[{name!r}] must be (low, high, points), got {ax!r}")
        lo, hi = _finite(f"grid[{name!r}] low", ax[0]), _finite(f"grid[{name!r}] high", ax[1])
        pts = int(ax[2])
        if pts < 1:
            raise InvalidArgumentError(f"study.roa: grid[{name!r}] has {pts} points; the grid is empty")
        if hi < lo:
            raise InvalidArgumentError(f"study.roa: grid[{name!r}] has low {lo} > high {hi}")
        axes.append([name, lo, hi, pts])
    x0v = [_finite(f"x0[{i}]", v) for i, v in enumerate(x0)]
    if len(x0v) != 4:
        raise InvalidArgumentError(f"study.roa: x0 must have 4 entries [z, θ, ż, θ̇], got {len(x0v)}")
    spec = {
        "kind": "roa", "K": K, "params": params, "axes": axes, "x0": x0v,
        "duration": _finite("duration", duration), "ts": _finite("ts", ts), "substeps": int(substeps),
        "angle_limit": _finite("angle_limit", angle_limit), "angle_tol": _finite("angle_tol", angle_tol),
        "travel": float(travel), "seed": _seed(seed), "n": int(np.prod([a[3] for a in axes])),
    }
    if spec["duration"] <= 0 or spec["ts"] <= 0 or spec["substeps"] < 1:
        raise InvalidArgumentError("study.roa: duration and ts must be positive, substeps at least 1")
    return run(Study(spec), **run_options)


def monte_carlo(
    plant: Union[str, Mapping[str, Any]],
    controller: Mapping[str, Any],
    parameter_distribution: Mapping[str, Sequence[Any]],
    imperfections: Optional[Mapping[str, Any]],
    n: int,
    seed: int,
    *,
    x0: Sequence[float] = (0.0, 0.1, 0.0, 0.0),
    duration: float = 5.0,
    scenario: Optional[Mapping[str, Any]] = None,
    **run_options: Any,
) -> "StudyResult":
    """``n`` runs of ``controller`` (a ``ControllerSpec`` dict) on ``plant`` (``"cart"``,
    ``"arm"`` or a ``PlantSpec`` dict) from ``x0`` for ``duration`` s with ``imperfections``
    (the ``ScenarioSpec`` imperfections, as :func:`pendulab.plants.simulate`; further scenario
    keys in ``scenario``), sample ``i`` with the plant parameters of
    ``parameter_distribution``: ``{name: ("uniform", low, high) | ("normal", mean, std)}``
    (names as in the plant spec, e.g. ``m_p``, ``a_c``; SI units) drawn from the
    counter-based streams of ``(seed, i)``, and with a measurement-noise seed of its own.

    Per sample: ``caught`` (stayed in the rig's angle window and on the track),
    ``settling_time`` (s, NaN if it did not settle), ``peak_input`` (V),
    ``max_angle_deviation`` (rad), ``params`` (``n × p``). ``run_options`` go to :func:`run`.
    """
    if int(n) < 1:
        raise InvalidArgumentError(f"study.monte_carlo: n = {n}; needs at least one sample")
    names, kinds, a, b = _distribution(parameter_distribution)
    sc = dict(scenario or {})
    sc["initial_state"] = [_finite(f"x0[{i}]", v) for i, v in enumerate(x0)]
    sc["duration"] = _finite("duration", duration)
    if imperfections is not None:
        sc["imperfections"] = dict(imperfections)
    spec = {
        "kind": "monte_carlo",
        "plant": plant if isinstance(plant, str) else json.dumps(plant, sort_keys=True),
        "controller": json.dumps(controller, sort_keys=True),
        "scenario": json.dumps(sc, sort_keys=True),
        "names": names, "kinds": kinds, "a": a, "b": b, "seed": _seed(seed), "n": int(n),
    }
    # Validate everything on one sample before the study starts.
    compute_chunk(spec, 0, 1, threads=1)
    return run(Study(spec), **run_options)


def chunk_ranges(n: int, chunk: int):
    """The ``(start, count)`` of each chunk of ``n`` samples in chunks of ``chunk``."""
    if int(chunk) < 1:
        raise InvalidArgumentError(f"study: chunk = {chunk}; needs at least 1")
    return [(s, min(chunk, n - s)) for s in range(0, n, chunk)]


def default_chunk(study: Study) -> int:
    """1024 grid runs (the native batch's chunk) or 64 Monte Carlo runs."""
    return 1024 if study.kind == "roa" else 64


class ChunkCache:
    """Finished chunks of one study on disk: ``<dir>/<study key>/<start>-<count>.npz`` (and
    ``spec.json``), each written to a temporary file and renamed, so a killed run leaves
    only whole chunks."""

    def __init__(self, cache_dir: Union[str, os.PathLike], study: Study):
        self.dir = os.path.join(os.fspath(cache_dir), study.key)
        os.makedirs(self.dir, exist_ok=True)
        spec_path = os.path.join(self.dir, "spec.json")
        if not os.path.exists(spec_path):
            with open(spec_path, "w") as f:
                json.dump(study.spec, f, sort_keys=True, indent=1)

    def _path(self, start: int, count: int) -> str:
        return os.path.join(self.dir, f"{start}-{count}.npz")

    def load(self, start: int, count: int) -> Optional[Dict[str, np.ndarray]]:
        p = self._path(start, count)
        if not os.path.exists(p):
            return None
        with np.load(p) as z:
            return {k: z[k] for k in z.files}

    def store(self, start: int, count: int, arrays: Mapping[str, np.ndarray]) -> None:
        fd, tmp = tempfile.mkstemp(dir=self.dir, suffix=".tmp")
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, self._path(start, count))


def run(
    study: Study,
    backend: str = "local",
    chunk: Optional[int] = None,
    progress: Optional[Progress] = None,
    cache_dir: Optional[Union[str, os.PathLike]] = None,
    threads: Optional[int] = None,
    **ray_options: Any,
) -> "StudyResult":
    """Computes ``study`` in chunks of ``chunk`` samples on ``backend``: ``"local"`` (the
    native batch path on ``threads`` cores, default all) or ``"ray"``
    (:func:`pendulab.ray.run`, which takes ``ray_options``). ``progress(done, total)`` is
    called after each chunk with the samples finished so far; with ``cache_dir`` finished
    chunks are read from and written to ``cache_dir/<study.key>/``."""
    if backend == "ray":
        from . import ray as pray

        return pray.run(study, chunk=chunk, progress=progress, cache_dir=cache_dir, threads=threads,
                        **ray_options)
    if backend != "local":
        raise InvalidArgumentError(f"study: backend {backend!r}; expected \"local\" or \"ray\"")
    if ray_options:
        raise InvalidArgumentError(f"study: options {sorted(ray_options)} are for backend=\"ray\"")
    ranges = chunk_ranges(study.n, chunk or default_chunk(study))
    cache = ChunkCache(cache_dir, study) if cache_dir is not None else None
    parts, done = [], 0
    for start, count in ranges:
        part = cache.load(start, count) if cache else None
        if part is None:
            part = study.chunk(start, count, threads)
            if cache:
                cache.store(start, count, part)
        parts.append(part)
        done += count
        if progress:
            progress(done, study.n)
    return StudyResult(study, assemble(parts))


def assemble(parts: Sequence[Mapping[str, np.ndarray]]) -> Dict[str, np.ndarray]:
    """The chunks' arrays joined in index order."""
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def _json_safe(v: Any) -> Any:
    """``v`` with every non-finite float replaced by ``"inf"``, ``"-inf"`` or ``"nan"``
    (strict JSON has no such numbers)."""
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, Mapping):
        return {k: _json_safe(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_json_safe(x) for x in v]
    return v


class StudyResult:
    """A finished study: ``study`` (its specification), ``arrays`` (per-sample outcomes, also
    as attributes: ``result.caught``), ``stats`` (a dict of summary statistics) and
    ``save_figure(path)`` (SVG or PNG by the extension)."""

    def __init__(self, study: Study, arrays: Mapping[str, np.ndarray]):
        self.study = study
        self.arrays = dict(arrays)

    def __getattr__(self, name: str) -> np.ndarray:
        arrays = self.__dict__.get("arrays", {})
        if name in arrays:
            return arrays[name]
        raise AttributeError(name)

    @property
    def stats(self) -> Dict[str, float]:
        """``n``, ``caught`` (count) and ``caught_fraction``; for Monte Carlo also the
        settling time's mean, median and 95th percentile over the runs that settled (s) and
        the peak input's mean, 95th percentile and maximum (V)."""
        c = self.arrays["caught"]
        s: Dict[str, float] = {"n": int(c.size), "caught": int(c.sum()), "caught_fraction": float(c.mean())}
        if self.study.kind == "monte_carlo":
            st = self.arrays["settling_time"]
            st = st[np.isfinite(st)]
            pk = self.arrays["peak_input"]
            s.update(
                settled=int(st.size),
                settling_time_mean=float(st.mean()) if st.size else math.nan,
                settling_time_median=float(np.median(st)) if st.size else math.nan,
                settling_time_p95=float(np.percentile(st, 95)) if st.size else math.nan,
                peak_input_mean=float(pk.mean()), peak_input_p95=float(np.percentile(pk, 95)),
                peak_input_max=float(pk.max()))
        return s

    def roa_slice(self, at: Optional[Mapping[str, int]] = None):
        """The caught map over the grid's two axes with more than one point (the others at
        index ``at[state]``, default 0): ``(x_axis, y_axis, cells)`` with ``cells[j, i]``
        for point ``i`` of the first axis and ``j`` of the second."""
        if self.study.kind != "roa":
            raise InvalidArgumentError("study: roa_slice needs a region-of-attraction study")
        axes = self.study.spec["axes"]
        shape = tuple(a[3] for a in axes)
        free = [i for i, a in enumerate(axes) if a[3] > 1]
        if len(free) != 2:
            raise InvalidArgumentError(f"study: a slice needs two axes with several points, the grid has {len(free)}")
        cube = self.arrays["caught"].reshape(shape)
        index = []
        for i, a in enumerate(axes):
            index.append(slice(None) if i in free else int((at or {}).get(a[0], 0)))
        plane = cube[tuple(index)]
        return axes[free[0]], axes[free[1]], plane.T

    def save_figure(self, path: Union[str, os.PathLike], field: str = "settling_time",
                    bins: int = 30, at: Optional[Mapping[str, int]] = None) -> None:
        """A region-of-attraction study: ``pendulab-plot``'s map of :meth:`roa_slice`; a Monte
        Carlo study: the histogram of ``field`` over its finite values in ``bins`` bins.
        Saved as SVG or PNG by the extension of ``path``."""
        path = os.fspath(path)
        if self.study.kind == "roa":
            (xn, xlo, xhi, nx), (yn, ylo, yhi, ny), cells = self.roa_slice(at)
            units = {"z": "m", "theta": "rad", "dz": "m/s", "dtheta": "rad/s"}
            frac = cells.mean()
            study_roa_figure(path, (xlo, xhi), (ylo, yhi), nx, ny, [bool(c) for c in cells.reshape(-1)],
                             f"{xn}(0) [{units[xn]}]", f"{yn}(0) [{units[yn]}]",
                             f"region of attraction ({100 * frac:.1f} % caught)")
            return
        v = np.asarray(self.arrays[field], dtype=float).reshape(-1)
        v = v[np.isfinite(v)]
        if v.size == 0:
            raise InvalidArgumentError(f"study: {field} has no finite value to draw")
        counts, edges = np.histogram(v, bins=int(bins))
        units = {"settling_time": "s", "peak_input": "V", "max_angle_deviation": "rad"}
        study_histogram_figure(path, edges.tolist(), counts.astype(float).tolist(),
                               f"{field} [{units.get(field, '')}]",
                               f"Monte Carlo, {v.size} of {self.arrays[field].size} runs")

    def save(self, lab_dir: Union[str, os.PathLike], name: Optional[str] = None, **figure_options: Any) -> str:
        """Writes the study into a lab directory for ``pendulab report --lab`` (``docs/lab.md``):
        ``lab_dir/studies/<name>/summary.json`` (``kind``, ``stats``, ``spec``, ``key``,
        ``pendulab_version``, ``figure``; NaN statistics written as ``null``, a non-finite
        number of the spec as the string ``"inf"``, ``"-inf"`` or ``"nan"``) and
        ``figure.svg`` (:meth:`save_figure` with ``figure_options``), both written whole
        (a temporary file renamed). ``name`` defaults to ``<kind>-<key>``; it must be a plain
        file name. Returns the study's folder."""
        name = name or f"{self.study.kind}-{self.study.key}"
        if not name or os.sep in name or (os.altsep and os.altsep in name) or name.startswith("."):
            raise InvalidArgumentError(f"study: name {name!r} must be a plain folder name")
        folder = os.path.join(os.fspath(lab_dir), "studies", name)
        os.makedirs(folder, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".svg")
        os.close(fd)
        try:
            self.save_figure(tmp, **figure_options)
            os.replace(tmp, os.path.join(folder, "figure.svg"))
        finally:
            if os.path.exists(tmp):
                os.remove(tmp)
        stats = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in self.stats.items()}
        summary = {"kind": self.study.kind, "stats": stats, "spec": _json_safe(self.study.spec), "key": self.study.key,
                   "pendulab_version": __version__, "figure": "figure.svg"}
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".json")
        with os.fdopen(fd, "w") as f:
            json.dump(summary, f, indent=1, sort_keys=True, allow_nan=False)
        os.replace(tmp, os.path.join(folder, "summary.json"))
        return folder

    def __repr__(self) -> str:
        return f"StudyResult({self.study.kind}, {self.stats})"
