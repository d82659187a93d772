"""Batch fits on a Dask ``distributed`` cluster: many files, or the texels of a map.

Needs Debian's ``python3-dask`` and ``python3-distributed`` (imported when a
function here is called, so ``import brdffit`` never needs them).

The work is split into tasks of ``per_task`` fits each, so scheduling costs
are paid per task, not per fit. The geometry of a texel map is scattered to
every worker once and shared by all of its tasks; each task fits its texels
in one :func:`brdffit.fit_many` call (``brdffit_fit_many()``: one geometry
grid per worker thread, no grid or fit per texel; files, and models written
in Python, are fitted one :class:`~brdffit.Fit` per item). Every task is a pure function of its inputs: when a worker
dies, the scheduler runs its unfinished (or finished but not yet gathered)
tasks again elsewhere, and every item is in the result exactly once, at its
place. A failing item (an unreadable file, a fit that fails) is reported in
its row of the result, never fatal. The same task function runs locally in
:func:`fit_files_local` and :func:`fit_texels_local`, which give identical
results without a cluster.

Example::

    from distributed import Client, LocalCluster
    import brdffit.dask as bd

    with LocalCluster(n_workers=4, threads_per_worker=1) as cluster, Client(cluster) as c:
        table = bd.fit_files(c, paths, "ashikhmin-shirley", progress=True)
    print(table.params, table.rms, table.failed())
"""

import os
import threading
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

import numpy as np

from .fit import Fit
from .grid import Grid
from .many import fit_many
from .model import Model

__all__ = ["Geometry", "FitTable", "BatchJob", "fit_files", "fit_texels", "submit_files",
           "submit_texels", "submit_texel_file", "fit_files_local", "fit_texels_local"]

ModelSpec = Union[str, Callable[[], Model]]


class Geometry:
    """The shared geometry of a texel map: regular axes ``(theta_i, theta_o,
    phi_o)`` or scattered directions ``(theta_i, phi_i, theta_o, phi_o)``
    (with optional sample ``weights``), radians. One object, scattered once
    per worker."""

    def __init__(self, regular=None, scattered=None, weights=None):
        if (regular is None) == (scattered is None):
            raise ValueError("give regular axes or scattered directions")
        arrays = regular if regular is not None else scattered
        self.kind = "regular" if regular is not None else "scattered"
        self.arrays = tuple(np.ascontiguousarray(a, dtype=np.float64) for a in arrays)
        if len(self.arrays) != (3 if self.kind == "regular" else 4):
            raise ValueError("%s geometry needs %d arrays"
                             % (self.kind, 3 if self.kind == "regular" else 4))
        self.weights = None if weights is None else np.ascontiguousarray(weights, np.float64)

    def __getstate__(self):
        state = dict(self.__dict__)
        state.pop("_local", None)  # per-process grids are not sent
        return state

    def shared_grid(self, n_channels: int) -> Grid:
        """A grid of this geometry with ``n_channels`` channels of zeros,
        made once per thread of a process and kept: the geometry of the
        batch fits of :func:`texels_task`."""
        local = self.__dict__.setdefault("_local", threading.local())
        grids = local.__dict__.setdefault("grids", {})
        if n_channels not in grids:
            grids[n_channels] = self.grid(np.zeros((self.sample_count, n_channels)))
        return grids[n_channels]

    @property
    def sample_count(self) -> int:
        """Samples per texel."""
        if self.kind == "regular":
            return int(np.prod([a.size for a in self.arrays]))
        return self.arrays[0].size

    def grid(self, values) -> Grid:
        """The grid of one texel's values, ``(n_samples, n_channels)``; NaN
        values are missing."""
        values = np.asarray(values, dtype=np.float64).reshape(self.sample_count, -1)
        missing = np.isnan(values)
        missing = missing if missing.any() else None
        values = np.where(np.isnan(values), 0.0, values)
        # Arrays unpickled on a worker may lie at any byte offset of the
        # message; the library reads doubles, so hand it aligned copies.
        arrays = [_aligned(a) for a in self.arrays]
        if self.kind == "regular":
            return Grid.from_regular(*arrays, values, missing=missing)
        weights = None if self.weights is None else _aligned(self.weights)
        return Grid.from_scattered(*arrays, values, missing=missing, weights=weights)


def _aligned(a: np.ndarray) -> np.ndarray:
    """``a`` as an aligned, C-contiguous float64 array (a copy only if needed)."""
    return np.require(a, dtype=np.float64, requirements=["C", "A"])


def _model(spec: ModelSpec) -> Model:
    return Model.builtin(spec) if isinstance(spec, str) else spec()


def _load(path: str) -> Grid:
    ext = os.path.splitext(path)[1].lower()
    return Grid.load_csv(path) if ext == ".csv" else Grid.load_merl(path)


def _fit_row(grid: Grid, model: Model, options: Dict[str, Any]) -> Dict[str, Any]:
    opts = dict(options)
    damping = opts.pop("damping", None)
    with Fit(grid, model, **opts) as fit:
        if damping is not None:
            fit.set_damping(damping)
        fit.run()
        return {"params": fit.params, "std_errors": fit.std_errors, "rms": fit.error("rms"),
                "cost": fit.error("cost"), "iterations": fit.iterations,
                "stop_reason": fit.stop_reason, "error": None}


def _failed_row(exc: BaseException) -> Dict[str, Any]:
    return {"params": None, "std_errors": None, "rms": np.nan, "cost": np.nan,
            "iterations": -1, "stop_reason": "failed",
            "error": "%s: %s" % (type(exc).__name__, exc)}


def _fit_items(items: Sequence, make_grid: Callable, model: ModelSpec,
               options: Dict[str, Any]) -> List[Dict[str, Any]]:
    """Fit every item; a failing one gives a row with its error."""
    m = _model(model)
    rows = []
    try:
        for item in items:
            try:
                with make_grid(item) as grid:
                    rows.append(_fit_row(grid, m, options))
            except Exception as exc:  # reported in the row, not fatal
                rows.append(_failed_row(exc))
    finally:
        m.close()
    return rows


def _many_rows(result) -> List[Dict[str, Any]]:
    """The rows of a :class:`~brdffit.ManyResult`, as :func:`_fit_row` makes them."""
    rows = []
    ok, stops = result.ok.tolist(), result.stop_reasons()
    rms, cost, iterations = result.rms.tolist(), result.cost.tolist(), result.iterations.tolist()
    for k in range(len(result)):
        if ok[k]:
            rows.append({"params": result.params[k].copy(),
                         "std_errors": result.std_errors[k].copy(),
                         "rms": rms[k], "cost": cost[k], "iterations": int(iterations[k]),
                         "stop_reason": stops[k], "error": None})
        else:
            rows.append({"params": None, "std_errors": None, "rms": np.nan, "cost": np.nan,
                         "iterations": -1, "stop_reason": "failed",
                         "error": "BrdffitError: %s" % result.error(k)})
    return rows


def _fit_texels(values: np.ndarray, geometry: "Geometry", model: ModelSpec,
                options: Dict[str, Any]) -> List[Dict[str, Any]]:
    """Fit texels ``values`` (n, n_samples, n_channels) in one batch call
    (a Python model: one fit per texel)."""
    m = _model(model)
    try:
        if m._python_eval is not None:
            return [_fit_one(geometry.grid, v, m, options) for v in values]
        opts = dict(options)
        damping = opts.pop("damping", None)
        with Fit(geometry.shared_grid(values.shape[2]), m, **opts) as fit:
            if damping is not None:
                fit.set_damping(damping)
            return _many_rows(fit_many(fit, values))
    finally:
        m.close()


def _fit_one(make_grid: Callable, item, m: Model, options: Dict[str, Any]) -> Dict[str, Any]:
    try:
        with make_grid(item) as grid:
            return _fit_row(grid, m, options)
    except Exception as exc:  # reported in the row, not fatal
        return _failed_row(exc)


def files_task(paths: Sequence[str], model: ModelSpec, options: Dict[str, Any]):
    """One task: fit the files ``paths`` (read where the task runs)."""
    return _fit_items(paths, _load, model, options)


def texels_task(values: np.ndarray, geometry: Geometry, model: ModelSpec,
                options: Dict[str, Any]):
    """One task: fit the texels ``values[k]`` over the shared ``geometry``."""
    return _fit_texels(_texel_values(geometry, values), geometry, model, options)


def texel_file_task(path: str, start: int, stop: int, geometry: Geometry, model: ModelSpec,
                    options: Dict[str, Any]):
    """One task: fit texels ``start .. stop - 1`` of the ``.npy`` map at
    ``path``, read (memory-mapped) where the task runs."""
    values = np.load(path, mmap_mode="r")
    return _fit_texels(_texel_values(geometry, values[start:stop]), geometry, model, options)


class FitTable:
    """Results of a batch, one row per item in input order.

    Attributes:
        names: the items (file paths, or texel indices).
        rows: per item a dict with ``params``, ``std_errors`` (arrays, None
            on failure), ``rms``, ``cost``, ``iterations``, ``stop_reason``
            and ``error`` (None, or the reason the item failed).
    """

    def __init__(self, names: Sequence, rows: Sequence[Dict[str, Any]]):
        if len(names) != len(rows):
            raise ValueError("%d names for %d rows" % (len(names), len(rows)))
        self.names = list(names)
        self.rows = list(rows)

    def __len__(self):
        return len(self.rows)

    @property
    def ok(self) -> np.ndarray:
        """True where the fit succeeded."""
        return np.array([r["error"] is None for r in self.rows], dtype=bool)

    def _stack(self, key):
        sizes = {r[key].size for r in self.rows if r[key] is not None}
        if len(sizes) > 1:
            raise ValueError("the items have parameter vectors of different lengths %s; "
                             "read rows instead" % sorted(sizes))
        p = sizes.pop() if sizes else 0
        return np.array([r[key] if r[key] is not None else np.full(p, np.nan)
                         for r in self.rows]).reshape(len(self.rows), p)

    @property
    def params(self) -> np.ndarray:
        """``(n_items, n_params)`` fitted parameters; NaN rows for failures."""
        return self._stack("params")

    @property
    def std_errors(self) -> np.ndarray:
        """``(n_items, n_params)`` standard errors; NaN rows for failures."""
        return self._stack("std_errors")

    @property
    def rms(self) -> np.ndarray:
        """RMS error per item (NaN for failures)."""
        return np.array([r["rms"] for r in self.rows], dtype=np.float64)

    @property
    def iterations(self) -> np.ndarray:
        """Iterations of the final LM run per item (-1 for failures)."""
        return np.array([r["iterations"] for r in self.rows], dtype=np.int64)

    def failed(self) -> List[tuple]:
        """``(name, error)`` of every failed item."""
        return [(n, r["error"]) for n, r in zip(self.names, self.rows) if r["error"]]

    def __repr__(self):
        return "<brdffit.dask.FitTable %d items, %d failed>" % (len(self), len(self.failed()))


def _chunks(n: int, per_task: int) -> List[range]:
    if per_task < 1:
        raise ValueError("per_task must be >= 1")
    return [range(i, min(i + per_task, n)) for i in range(0, n, per_task)]


class BatchJob:
    """Tasks submitted to a cluster; :meth:`result` gathers them into a
    :class:`FitTable`. ``futures`` holds one future per task, in order."""

    def __init__(self, client, names: Sequence, futures: Sequence):
        self.client = client
        self.names = list(names)
        self.futures = list(futures)

    def progress(self) -> None:
        """Show distributed's progress bar until every task is done."""
        from distributed import progress
        progress(self.futures)

    def result(self) -> FitTable:
        """Wait for every task and return the table (rows in input order)."""
        parts = self.client.gather(self.futures)
        rows = [row for part in parts for row in part]
        return FitTable(self.names, rows)


#: The options a batch passes to every Fit (``damping``: a built-in name).
FIT_OPTIONS = ("pipeline", "objective", "cap", "weighting", "clearcoat", "threads",
               "max_iterations", "plausible", "start", "fixed", "damping")


def _options(options: Optional[Dict[str, Any]]) -> Dict[str, Any]:
    """Check the options here, so a mistake fails at once, not in every row."""
    options = dict(options or {})
    unknown = sorted(set(options) - set(FIT_OPTIONS))
    if unknown:
        raise ValueError("unknown batch fit options %s (known: %s)"
                         % (", ".join(unknown), ", ".join(FIT_OPTIONS)))
    return options


def submit_files(client, paths: Sequence[str], model: ModelSpec = "ashikhmin-shirley",
                 options: Optional[Dict[str, Any]] = None, per_task: int = 8,
                 retries: int = 2) -> BatchJob:
    """Submit fits of files (CSV by extension ``.csv``, else MERL binary):
    ``per_task`` files per task, read by the worker (the paths must be
    readable there). ``model`` is a built-in name or a function returning a
    :class:`~brdffit.Model` (run on the worker); ``options`` are
    :class:`~brdffit.Fit` keyword arguments plus ``damping`` (a name).
    ``retries``: how often a task that raised is run again (a worker's death
    is handled by the scheduler in any case)."""
    paths = [os.fspath(p) for p in paths]
    options = _options(options)
    futures = [client.submit(files_task, paths[r.start:r.stop], model, options,
                             pure=True, retries=retries)
               for r in _chunks(len(paths), per_task)]
    return BatchJob(client, paths, futures)


def _texel_values(geometry: Geometry, values) -> np.ndarray:
    v = np.ascontiguousarray(values, dtype=np.float64)
    return v.reshape(v.shape[0], geometry.sample_count, -1)


def submit_texels(client, geometry: Geometry, values, model: ModelSpec = "ashikhmin-shirley",
                  options: Optional[Dict[str, Any]] = None, per_task: int = 64,
                  retries: int = 2) -> BatchJob:
    """Submit fits of the texels of a map: ``values`` has shape
    ``(n_texels, n_samples, n_channels)`` (or ``(n_texels, n_theta_i,
    n_theta_o, n_phi_o, n_channels)`` for a regular geometry), NaN for a
    missing value. The geometry is scattered to every worker once; each task
    carries only its ``per_task`` texels' values, which travel with the task
    through the scheduler (so a task lost with a worker can run again; for
    large maps :func:`submit_texel_file` avoids that traffic)."""
    v = _texel_values(geometry, values)
    options = _options(options)
    shared = client.scatter(geometry, broadcast=True)
    futures = [client.submit(texels_task, v[r.start:r.stop], shared, model, options,
                             pure=True, retries=retries)
               for r in _chunks(v.shape[0], per_task)]
    return BatchJob(client, list(range(v.shape[0])), futures)


def submit_texel_file(client, geometry: Geometry, path: str,
                      model: ModelSpec = "ashikhmin-shirley",
                      options: Optional[Dict[str, Any]] = None, per_task: int = 64,
                      retries: int = 2) -> BatchJob:
    """As :func:`submit_texels` for a map stored as a ``.npy`` file (shape
    as the ``values`` of :func:`submit_texels`) that the workers can read:
    each task reads its own tile, so only a path and a range travel through
    the scheduler, and a task lost with a worker is simply read again."""
    path = os.fspath(path)
    n = np.load(path, mmap_mode="r").shape[0]
    options = _options(options)
    shared = client.scatter(geometry, broadcast=True)
    futures = [client.submit(texel_file_task, path, r.start, r.stop, shared, model, options,
                             pure=True, retries=retries)
               for r in _chunks(n, per_task)]
    return BatchJob(client, list(range(n)), futures)


def fit_files(client, paths: Sequence[str], model: ModelSpec = "ashikhmin-shirley",
              options: Optional[Dict[str, Any]] = None, per_task: int = 8, retries: int = 2,
              progress: bool = False) -> FitTable:
    """Fit files on the cluster of ``client`` and gather a :class:`FitTable`
    (see :func:`submit_files`); ``progress`` shows a progress bar."""
    job = submit_files(client, paths, model, options, per_task, retries)
    if progress:
        job.progress()
    return job.result()


def fit_texels(client, geometry: Geometry, values, model: ModelSpec = "ashikhmin-shirley",
               options: Optional[Dict[str, Any]] = None, per_task: int = 64, retries: int = 2,
               progress: bool = False) -> FitTable:
    """Fit the texels of a map on the cluster: ``values`` is an array (see
    :func:`submit_texels`) or the path of a ``.npy`` file the workers read
    (see :func:`submit_texel_file`)."""
    submit = submit_texel_file if isinstance(values, (str, os.PathLike)) else submit_texels
    job = submit(client, geometry, values, model, options, per_task, retries)
    if progress:
        job.progress()
    return job.result()


def fit_files_local(paths: Sequence[str], model: ModelSpec = "ashikhmin-shirley",
                    options: Optional[Dict[str, Any]] = None) -> FitTable:
    """The same fits as :func:`fit_files`, in this process (no dask needed)."""
    paths = [os.fspath(p) for p in paths]
    return FitTable(paths, files_task(paths, model, _options(options)))


def fit_texels_local(geometry: Geometry, values, model: ModelSpec = "ashikhmin-shirley",
                     options: Optional[Dict[str, Any]] = None) -> FitTable:
    """The same fits as :func:`fit_texels`, in this process (no dask needed)."""
    if isinstance(values, (str, os.PathLike)):
        values = np.load(os.fspath(values), mmap_mode="r")
    v = _texel_values(geometry, values)
    return FitTable(list(range(v.shape[0])), texels_task(v, geometry, model, _options(options)))
