"""Studies: ensembles of SAD simulations over a parameter grid × realizations.

A study (see :mod:`splinecontact.config`) sweeps some simulation parameters over a grid and
repeats every grid point for ``realizations`` independent profile pairs. One realization is

1. profiles: ``lower, upper = weierstrass_mandelbrot_pair(dimension, seed=s_r, ...)`` (eq. 1)
   for rough-on-rough; for rough-on-flat only the lower profile is generated — with the same
   seed as the rough-on-rough lower profile of that realization — and the upper body is
   ``"flat"``;
2. ``simulate(lower, upper, steps=..., e_star=..., ...)`` (eqs. 2–14).

Seeds: realization ``r`` uses ``s_r = numpy.random.SeedSequence(study_seed).spawn(R)[r]``
(entropy ``study_seed``, spawn key ``(r,)``), the same at every grid point: a paired design with
common random numbers across the swept parameters.

Work is batched (a batch is a run of consecutive realizations at one grid point) and executed
in the calling process (``workers=1``), on a local process pool, or on a Dask distributed cluster.
The main process alone writes the Zarr store, batch by batch as they finish: first the data, then
``error``, and ``status`` last, so a batch whose data are not all written is not marked done
(each chunk file is replaced atomically). Re-running continues with the realizations whose
status is still 0. The stored values do not depend on the worker count, the scheduler, the
batch size or the order in which batches finish.

Store schema (``open_study``): dimensions = the swept parameters (named as the parameters, in
study-file order), ``realization``, ``step``; every variable of ``STEP_VARIABLES`` on (grid…,
realization, step) (a study with a ``[[path]]`` also ``PATH_STEP_VARIABLES``: u_T, slipping
contacts, dissipated work, held F_N; see :func:`step_variables`) and of ``SCALAR_VARIABLES`` on
(grid…, realization), float64 (NaN where not
run or failed); ``status`` int8 (0 not run, 1 ok, 2 failed); ``error`` (message, "" if ok);
``seed_spawn_key`` (realization). Attributes: every fixed parameter under its name (parameters
left at the engine default ``None``, e.g. ``g_star``, are absent), ``study_toml``,
``study_seed``, ``splinecontact_version``, ``engine_fingerprint``, ``started``, ``finished``.

Safety: :func:`run_study` prints nothing (progress goes to an optional callback, e.g.
:class:`StudyProgressBar`); the study is validated and checked against :class:`StudyLimits`
before anything is written; ``overwrite`` discards only a recognisable study store of another
study (never another folder, the current directory, its parents, home or root, nor a store
another run holds); an existing store is checked chunk by chunk before a run continues it, and
damage is reported as :class:`~splinecontact.errors.StudyStoreError` naming it.

Testing hook: :func:`run_study` takes ``realization_function`` (default
:func:`simulate_realization`), any picklable module-level callable
``(parameters, seed) -> result`` with ``.curves`` and ``.scalars`` mappings. The tests use it to
inject a failing realization and a fast stand-in engine.
"""

from __future__ import annotations

import ast
import contextlib
import datetime as _dt
import errno
import fcntl
import functools
import hashlib
import itertools
import json
import math
import multiprocessing
import os
import shutil
import signal
import threading
import time
import uuid
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ._version import __version__
from .config import (
    PARAMETERS,
    PATH_REPLACES,
    StudyConfig,
    StudyLimits,
    check_limits,
    load_study,
    parse_study,
)
from .contact import SIMULATION_PARAMETERS
from .errors import (
    OutputError,
    SplineContactError,
    StudyConfigError,
    StudyStoreError,
    UnsafeOutputError,
)
from .generate import GENERATOR_PARAMETERS
from .outputs import atomic_path, check_output_file, is_protected_directory
from .results import PATH_STEP_VARIABLES, SCALAR_VARIABLES, STEP_VARIABLES

__all__ = [
    "STATUS_FAILED",
    "STATUS_NOT_RUN",
    "STATUS_OK",
    "BatchResult",
    "BatchTask",
    "FailedRealization",
    "StudyExecutionError",
    "StudyLimits",
    "StudyProgress",
    "StudyProgressBar",
    "StudySummary",
    "engine_fingerprint",
    "export_netcdf",
    "open_study",
    "parameter_value",
    "print_summary",
    "realization_seed",
    "run_batch",
    "run_study",
    "simulate_realization",
    "step_variables",
]

STATUS_NOT_RUN = 0
STATUS_OK = 1
STATUS_FAILED = 2

#: Target size of one chunk of a per-step variable [bytes].
_CHUNK_BYTES = 2**20
#: Largest automatic batch (realizations per task).
_MAX_AUTO_BATCH = 16

_GENERATOR_KEYS = GENERATOR_PARAMETERS
_SIMULATE_KEYS = SIMULATION_PARAMETERS

RealizationFunction = Callable[[Mapping[str, Any], np.random.SeedSequence], Any]


class StudyExecutionError(SplineContactError):
    """Some batches could not be run (a worker died, the scheduler is unreachable, ...).

    Attributes
    ----------
    summary : StudySummary or None
        The state of the store when the run stopped (None if it never started).
    """

    def __init__(self, message: str, summary: StudySummary | None = None) -> None:
        super().__init__(message)
        self.summary = summary


# --- provenance ---------------------------------------------------------------------------------

#: Modules of the runner itself: not part of the engine fingerprint.
_RUNNER_MODULES = frozenset({"study", "config"})


@functools.cache
def engine_fingerprint() -> str:
    """SHA-256 (16 hex digits) of the source of every package module a realization runs.

    The modules are found by following the package-relative imports of this module (those
    inside functions too), so a new engine module is covered without a list to maintain. The
    runner's own modules (study, config) are excluded. A store records it; resuming with
    another fingerprint is refused, because the store would mix results of two codes.
    """
    root = Path(__file__).resolve().parent
    todo, seen = ["study"], set()
    digest = hashlib.sha256()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        file = root.joinpath(*name.split(".")).with_suffix(".py")
        if not file.is_file():
            file = root.joinpath(*name.split("."), "__init__.py")
            if not file.is_file():
                continue
        seen.add(name)
        source = file.read_bytes()
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                if node.module:
                    todo.append(node.module)
                else:
                    todo.extend(alias.name for alias in node.names)
    for name in sorted(seen - _RUNNER_MODULES):
        file = root.joinpath(*name.split(".")).with_suffix(".py")
        if not file.is_file():
            file = root.joinpath(*name.split("."), "__init__.py")
        digest.update(name.encode() + b"\0" + file.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


# --- one realization ----------------------------------------------------------------------------


def realization_seed(study_seed: int, realization: int) -> np.random.SeedSequence:
    """Seed of realization ``r``: ``SeedSequence(study_seed).spawn(R)[r]`` for any R > r.

    Built directly (entropy ``study_seed``, spawn key ``(r,)``) so it never depends on how
    many children were spawned before.
    """
    return np.random.SeedSequence(study_seed, spawn_key=(realization,))


def simulate_realization(parameters: Mapping[str, Any], seed: np.random.SeedSequence) -> Any:
    """Generate the profiles of one realization and simulate their contact.

    Parameters
    ----------
    parameters : mapping
        One value for every name in :data:`splinecontact.config.PARAMETERS` (units there), and
        optionally ``path``: a sequence of mappings of :class:`splinecontact.Segment` keyword
        arguments (δ_N [µm] or F_N [mN/µm], u_T [µm], steps), which replaces ``steps`` and
        ``final_displacement``.
    seed : numpy.random.SeedSequence
        The realization's seed (:func:`realization_seed`). Rough-on-rough: passed to
        ``weierstrass_mandelbrot_pair``. Rough-on-flat: the lower profile is generated from the
        pair's lower seed (``seed.spawn(2)[0]``), so it equals the rough-on-rough lower profile.

    Returns
    -------
    SimulationResult
    """
    from .contact import simulate
    from .generate import child_seed, weierstrass_mandelbrot, weierstrass_mandelbrot_pair

    dimension = float(parameters["dimension"])
    gen = {k: parameters[k] for k in _GENERATOR_KEYS}
    sim = {k: parameters[k] for k in _SIMULATE_KEYS}
    segments = parameters.get("path")
    if segments is not None:
        from .loadpath import Segment

        for name in PATH_REPLACES:
            sim.pop(name, None)
        sim["path"] = [Segment(**segment) for segment in segments]
    # per-realization diagnostics would repeat once per realization (and from workers)
    sim["diagnostics"] = False
    if parameters["contact_type"] == "rough-on-rough":
        lower, upper = weierstrass_mandelbrot_pair(dimension, seed=seed, **gen)
        return simulate(lower, upper, **sim)
    lower = weierstrass_mandelbrot(dimension, seed=child_seed(seed, 0), **gen)
    return simulate(lower, "flat", **sim)


# --- batches ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class BatchTask:
    """Realizations ``start … stop−1`` at one grid point.

    Attributes
    ----------
    grid_index : tuple of int
        Position in each swept parameter's list (empty if nothing is swept).
    start, stop : int
        Realization range.
    parameters : dict
        The full parameter set of the grid point.
    study_seed : int
        Entropy of the study's SeedSequence.
    n_step_records : int
        Length of the stored step dimension (largest ``steps`` of the study + 1).
    """

    grid_index: tuple[int, ...]
    start: int
    stop: int
    parameters: dict[str, Any]
    study_seed: int
    n_step_records: int


@dataclass(frozen=True, eq=False)
class BatchResult:
    """What a batch sends back: curves (n, n_step_records), scalars (n,), status, messages."""

    task: BatchTask
    curves: dict[str, NDArray[np.float64]]
    scalars: dict[str, NDArray[np.float64]]
    status: NDArray[np.int8]
    errors: tuple[str, ...]


def step_variables(has_path: bool) -> dict[str, tuple[str, str]]:
    """Per-step variables stored by a study: name -> (units, description).

    A study with a load path also stores :data:`~splinecontact.results.PATH_STEP_VARIABLES`
    (u_T, slipping contacts, dissipated work, the held F_N); one without keeps the plain layout.
    """
    return {**STEP_VARIABLES, **PATH_STEP_VARIABLES} if has_path else dict(STEP_VARIABLES)


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def run_batch(
    task: BatchTask, realization_function: RealizationFunction | None = None
) -> BatchResult:
    """Run the realizations of ``task``; an exception in one is recorded, not raised."""
    func = simulate_realization if realization_function is None else realization_function
    n = task.stop - task.start
    width = task.n_step_records
    names = step_variables(task.parameters.get("path") is not None)
    curves = {name: np.full((n, width), np.nan) for name in names}
    scalars = {name: np.full(n, np.nan) for name in SCALAR_VARIABLES}
    status = np.full(n, STATUS_OK, dtype=np.int8)
    errors = [""] * n
    expected = int(task.parameters["steps"]) + 1
    for i, r in enumerate(range(task.start, task.stop)):
        try:
            result = func(task.parameters, realization_seed(task.study_seed, r))
            row_curves = {}
            for name in names:
                values = np.asarray(result.curves[name], dtype=np.float64)
                if values.shape != (expected,):
                    raise ValueError(
                        f"curve {name!r} has shape {values.shape}, expected ({expected},)"
                    )
                row_curves[name] = values
            row_scalars = {name: float(result.scalars[name]) for name in SCALAR_VARIABLES}
        except Exception as exc:
            status[i] = STATUS_FAILED
            errors[i] = _one_line(exc)
            continue
        for name, values in row_curves.items():
            curves[name][i, :expected] = values
        for name, value in row_scalars.items():
            scalars[name][i] = value
    return BatchResult(task, curves, scalars, status, tuple(errors))


def _auto_batch_size(n_pending: int, n_workers: int) -> int:
    return max(1, min(_MAX_AUTO_BATCH, math.ceil(n_pending / (4 * max(1, n_workers)))))


def _make_batches(
    config: StudyConfig, status: NDArray[np.int8], batch_size: int
) -> list[BatchTask]:
    tasks = []
    seed = config.study.seed
    width = config.max_steps + 1
    for grid_index in config.grid_indices():
        params = config.parameters_at(grid_index)
        pending = np.flatnonzero(status[grid_index] == STATUS_NOT_RUN)
        if pending.size == 0:
            continue
        # Runs of consecutive realizations, each cut into batches of at most batch_size.
        breaks = np.flatnonzero(np.diff(pending) != 1) + 1
        for run in np.split(pending, breaks):
            for lo in range(0, run.size, batch_size):
                part = run[lo : lo + batch_size]
                tasks.append(
                    BatchTask(grid_index, int(part[0]), int(part[-1]) + 1, params, seed, width)
                )
    return tasks


# --- the store ----------------------------------------------------------------------------------


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")


def _coord_values(values: Sequence[Any]) -> NDArray[Any]:
    if all(isinstance(v, str) for v in values):
        return np.array(values, dtype=object)
    if all(isinstance(v, int) for v in values):
        return np.array(values, dtype=np.int64)
    return np.array(values, dtype=np.float64)


def _template(config: StudyConfig) -> tuple[xr.Dataset, dict[str, dict[str, Any]]]:
    import dask.array as da

    R = config.study.realizations
    S = config.max_steps + 1
    grid_dims = config.swept_names
    grid_shape = config.grid_shape
    ones = (1,) * len(grid_dims)
    chunk_r = max(1, min(R, _CHUNK_BYTES // (8 * S)))
    step_dims = (*grid_dims, "realization", "step")
    real_dims = (*grid_dims, "realization")
    data_vars: dict[str, Any] = {}
    encoding: dict[str, dict[str, Any]] = {}
    for name, (units, description) in step_variables(config.path is not None).items():
        data = da.full((*grid_shape, R, S), np.nan, chunks=(*ones, chunk_r, S))
        data_vars[name] = (step_dims, data, {"units": units, "long_name": description})
        encoding[name] = {"_FillValue": np.nan, "chunks": (*ones, chunk_r, S)}
    for name, (units, description) in SCALAR_VARIABLES.items():
        data = da.full((*grid_shape, R), np.nan, chunks=(*ones, chunk_r))
        data_vars[name] = (real_dims, data, {"units": units, "long_name": description})
        encoding[name] = {"_FillValue": np.nan, "chunks": (*ones, chunk_r)}
    data_vars["status"] = (
        real_dims,
        np.zeros((*grid_shape, R), dtype=np.int8),
        {"units": "1", "long_name": "0 = not run, 1 = ok, 2 = failed"},
    )
    encoding["status"] = {"_FillValue": None, "chunks": (*ones, chunk_r)}
    data_vars["error"] = (
        real_dims,
        np.full((*grid_shape, R), "", dtype=object),
        {"units": "", "long_name": "exception of a failed realization ('' if ok)"},
    )
    encoding["error"] = {"chunks": (*ones, chunk_r)}
    data_vars["seed_spawn_key"] = (
        ("realization",),
        np.arange(R, dtype=np.int64),
        {
            "units": "1",
            "long_name": "spawn key (r,) of the realization's numpy SeedSequence",
            "entropy": str(config.study.seed),
            "seed_rule": "SeedSequence(entropy=study_seed, spawn_key=(r,)) "
            "= SeedSequence(study_seed).spawn(realizations)[r]",
        },
    )
    coords: dict[str, Any] = {
        "realization": ("realization", np.arange(R, dtype=np.int64), {"units": "1"}),
        "step": ("step", np.arange(S, dtype=np.int64), {"units": "1"}),
    }
    for name, values in config.swept:
        coords[name] = (
            name,
            _coord_values(values),
            {"units": PARAMETERS[name].unit, "long_name": PARAMETERS[name].description},
        )
    attrs: dict[str, Any] = {
        name: value for name, value in config.fixed_parameters.items() if value is not None
    }
    attrs.update(
        {
            "title": f"splinecontact study {config.study.name}",
            "study_name": config.study.name,
            "study_toml": config.to_toml(),
            "study_seed": config.study.seed,
            "splinecontact_version": __version__,
            "engine_fingerprint": engine_fingerprint(),
            "units_convention": (
                "lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness"
            ),
            "started": _now(),
            "finished": "",
        }
    )
    return xr.Dataset(data_vars, coords=coords, attrs=attrs), encoding


def _try_lock(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def _remove_stale_creations(path: Path) -> None:
    """Delete the temporary stores a killed run left beside ``path``.

    A run holds a lock on its temporary store while it builds it, so the temporary store of a
    live concurrent run is never touched: only those nobody holds are removed.
    """
    for stale in path.parent.glob(f".{path.name}.creating-*"):
        if stale.is_symlink() or not stale.is_dir():
            continue
        try:
            fd = os.open(stale, os.O_RDONLY)
        except OSError:
            continue
        try:
            if _try_lock(fd):
                shutil.rmtree(stale, ignore_errors=True)
        finally:
            os.close(fd)


def _create_store(path: Path, config: StudyConfig) -> bool:
    """Create the empty store atomically (built beside ``path``, then renamed).

    Returns False, leaving ``path`` as it is, if another run created the store first.
    """
    if not path.parent.expanduser().resolve().is_dir():
        raise StudyStoreError(
            f"cannot create the store {path}: the folder {path.parent} does not exist"
        )
    _remove_stale_creations(path)
    while True:
        tmp = path.with_name(f".{path.name}.creating-{uuid.uuid4().hex}")
        os.mkdir(tmp)
        fd = os.open(tmp, os.O_RDONLY)
        # Another run's clean-up may have taken it between mkdir and lock: then use a new name.
        if _try_lock(fd) and os.fstat(fd).st_nlink > 0:
            break
        os.close(fd)
    try:
        dataset, encoding = _template(config)
        dataset.to_zarr(tmp, mode="w-", encoding=encoding, consolidated=False, compute=False)
        try:
            os.rename(tmp, path)
        except OSError as exc:
            if exc.errno in (errno.ENOTEMPTY, errno.EEXIST) and path.exists():
                return False  # a concurrent run created it first
            raise
        return True
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
        os.close(fd)


def _root_metadata(path: Path) -> dict[str, Any] | None:
    """The attributes of the store's root group if ``path`` is recognisably a study store.

    Returns None when ``path`` carries no study metadata at all (not a store).

    Raises
    ------
    StudyStoreError
        The root metadata exists but cannot be read (a damaged store).
    """
    meta = path / "zarr.json"
    if not meta.is_file():
        return None
    try:
        data = json.loads(meta.read_bytes())
    except (OSError, ValueError) as exc:
        raise StudyStoreError(
            f"store {path} is damaged: its root metadata zarr.json cannot be read "
            f"({_one_line(exc)}); it cannot be used or replaced: restore it from a copy, or "
            "remove it yourself and run again"
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("attributes"), dict):
        return None
    attrs: dict[str, Any] = data["attributes"]
    return attrs if "study_toml" in attrs else None


def _read_store_attrs(path: Path) -> dict[str, Any] | None:
    try:
        return _root_metadata(path)
    except StudyStoreError:
        return None


def _stored_config(path: Path, attrs: Mapping[str, Any]) -> StudyConfig:
    """The study a store was written for (its ``study_toml`` attribute)."""
    import tomllib

    text = attrs.get("study_toml")
    if not isinstance(text, str):
        raise StudyStoreError(
            f"store {path} is damaged: its attribute study_toml is not text ({text!r:.60})"
        )
    try:
        return parse_study(tomllib.loads(text), source=f"{path} (stored)")
    except (tomllib.TOMLDecodeError, StudyConfigError, RecursionError) as exc:
        raise StudyStoreError(
            f"store {path} is damaged: its attribute study_toml is not a valid study "
            f"({_one_line(exc)})"
        ) from None


def _foreign_entry(path: Path) -> Path | None:
    """The first file or link under ``path`` that is not part of a Zarr store, if any."""
    for root, dirs, files in os.walk(path):
        here = Path(root)
        for name in [*dirs, *files]:
            item = here / name
            rel = item.relative_to(path).parts
            if item.is_symlink():
                return item
            if name in dirs:
                continue
            if rel == ("zarr.json",) or (len(rel) == 2 and rel[1] == "zarr.json"):
                continue
            if len(rel) >= 3 and rel[1] == "c":
                continue  # a chunk file (or a partial one) of an array
            return item
    return None


def _first_difference(a: Any, b: Any, prefix: str = "") -> str | None:
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        for key in list(a) + [k for k in b if k not in a]:
            where = f"{prefix}.{key}" if prefix else str(key)
            if key not in a:
                return f"{where}: absent in the store, {b[key]!r} in the study file"
            if key not in b:
                return f"{where}: {a[key]!r} in the store, absent in the study file"
            diff = _first_difference(a[key], b[key], where)
            if diff:
                return diff
        if list(a) != list(b):
            return f"{prefix}: order {list(a)} in the store, {list(b)} in the study file"
        return None
    if a != b or type(a) is not type(b):
        return f"{prefix}: {a!r} in the store, {b!r} in the study file"
    return None


def _prepare_store(path: Path, config: StudyConfig, *, overwrite: bool) -> bool:
    """Create the store, or check that the existing one holds this study (or discard it).

    Only a directory that is recognisably a study store (its own root metadata, nothing but
    Zarr files in it) is ever discarded, and only with ``overwrite``, never the current
    directory, one of its parents, the home directory or the root, and never while another run
    holds its lock. Anything else is refused and left untouched.

    Returns True if the store was created by this call (it holds no results yet).
    """
    for _ in range(3):
        if not (path.exists() or path.is_symlink()):
            if _create_store(path, config):
                return True
            continue  # a concurrent run created it: check it like any existing store
        attrs = None if not path.is_dir() else _root_metadata(path)
        if attrs is None:
            raise StudyStoreError(
                f"{path} exists and is not a splinecontact study store; choose another "
                "output path (--overwrite replaces only a study store)"
            )
        try:
            stored = _stored_config(path, attrs)
        except StudyStoreError as exc:
            if not overwrite:
                raise StudyStoreError(f"{exc}; --overwrite discards it and starts again") from None
        else:
            diff = _first_difference(stored.identity(), config.identity())
            version = attrs.get("splinecontact_version")
            if diff is None and version != __version__:
                diff = f"splinecontact version {version} wrote the store, this is {__version__}"
            fingerprint = attrs.get("engine_fingerprint")
            if diff is None and fingerprint != engine_fingerprint():
                diff = (
                    "the simulation code changed since the store was started (engine "
                    f"fingerprint {fingerprint} in the store, {engine_fingerprint()} now)"
                )
            if diff is None:
                return False
            if not overwrite:
                raise StudyStoreError(
                    f"store {path} belongs to a different study ({diff}); use another output "
                    "path, or --overwrite to discard the store and start again"
                )
        _discard_store(path)
        overwrite = False
    raise StudyStoreError(f"store {path} keeps changing under this run; is another run using it?")


def _discard_store(path: Path) -> None:
    """Remove the study store ``path`` (already recognised as one), under its lock."""
    if path.is_symlink():
        raise UnsafeOutputError(
            f"-o {path} is a symbolic link; refusing to replace it; give the store's real path"
        )
    if is_protected_directory(path):
        raise UnsafeOutputError(
            f"-o {path} is the current directory, one of its parents or the home directory; "
            "refusing to replace it"
        )
    with _locked(path):  # refuse to discard a store another run is writing
        foreign = _foreign_entry(path)
        if foreign is not None:
            raise UnsafeOutputError(
                f"-o {path} holds {foreign.relative_to(path)}, which is not part of a study "
                "store; refusing to discard it; move your files out or choose another path"
            )
        shutil.rmtree(path)


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    """Hold an exclusive lock on the store directory (released even by kill -9)."""
    fd = os.open(path, os.O_RDONLY)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise StudyStoreError(
                f"store {path} is being written by another running study; wait for it to end"
            ) from None
        yield
    finally:
        os.close(fd)


def _remove_partial_files(path: Path) -> None:
    """Delete chunk files left half-written by an interrupted run (zarr's ``*.partial``)."""
    for partial in path.rglob("*.partial"):
        partial.unlink(missing_ok=True)


_ARRAYS = (*STEP_VARIABLES, *SCALAR_VARIABLES, "error", "status")


def _array_names(config: StudyConfig) -> tuple[str, ...]:
    """The arrays a run of ``config`` writes."""
    steps = step_variables(config.path is not None)
    return (*steps, *SCALAR_VARIABLES, "error", "status")


_STATUS_CODES = (STATUS_NOT_RUN, STATUS_OK, STATUS_FAILED)


def _open_arrays(
    path: Path, mode: str, names: Sequence[str] = _ARRAYS
) -> tuple[Any, dict[str, Any]]:
    """The root group and the arrays a run writes, or a StudyStoreError naming what is missing."""
    import zarr

    try:
        group = zarr.open_group(path, mode=mode)  # type: ignore[arg-type]
    except Exception as exc:
        raise StudyStoreError(
            f"store {path} is damaged: it cannot be opened ({_one_line(exc)})"
        ) from None
    arrays: dict[str, Any] = {}
    for name in names:
        try:
            arrays[name] = group[name]
        except KeyError:
            raise StudyStoreError(
                f"store {path} is damaged: the array {name!r} is missing ({name}/zarr.json)"
            ) from None
        except Exception as exc:
            raise StudyStoreError(
                f"store {path} is damaged: the array {name!r} cannot be opened ({_one_line(exc)})"
            ) from None
    return group, arrays


def _chunk_regions(shape: Sequence[int], chunks: Sequence[int]) -> Iterator[tuple[slice, ...]]:
    ranges = [range(0, n, c) for n, c in zip(shape, chunks, strict=True)]
    for starts in itertools.product(*ranges):
        yield tuple(slice(a, min(a + c, n)) for a, c, n in zip(starts, chunks, shape, strict=True))


def _check_status_codes(path: Path, status: NDArray[Any]) -> None:
    bad = ~np.isin(status, _STATUS_CODES)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        raise StudyStoreError(
            f"store {path} is damaged: status holds the unknown code {int(status[where])} at "
            f"{where} (codes: 0 not run, 1 ok, 2 failed)"
        )


def _verify_store(path: Path, arrays: Mapping[str, Any], config: StudyConfig) -> None:
    """Check shapes, decode every chunk and check the status codes; name the first damage."""
    realizations = config.study.realizations
    shapes = {name: (*config.grid_shape, realizations) for name in _array_names(config)}
    for name in step_variables(config.path is not None):
        shapes[name] = (*config.grid_shape, realizations, config.max_steps + 1)
    for name, array in arrays.items():
        if tuple(array.shape) != shapes[name]:
            raise StudyStoreError(
                f"store {path} is damaged: the array {name!r} has shape {tuple(array.shape)}, "
                f"the study needs {shapes[name]}"
            )
        for region in _chunk_regions(array.shape, array.chunks):
            try:
                block = array[region]
            except MemoryError:
                raise
            except Exception as exc:
                chunk = tuple(r.start // c for r, c in zip(region, array.chunks, strict=True))
                raise StudyStoreError(
                    f"store {path} is damaged: chunk {'/'.join(map(str, chunk))} of {name!r} "
                    f"cannot be read ({_one_line(exc)}); restore the store from a copy, or run "
                    "with --overwrite to start again"
                ) from None
            if name == "status":
                _check_status_codes(path, np.asarray(block))


class _Writer:
    """Writes finished batches into the store: data, then ``error``, then ``status``."""

    def __init__(self, path: Path, names: Sequence[str] = _ARRAYS) -> None:
        self.path = path
        self.names = tuple(names)
        # Read-only until something is written: a run with nothing to do works on a read-only
        # store and changes nothing.
        self.group, self.arrays = _open_arrays(path, "r", self.names)
        self._writable = False

    def _make_writable(self) -> None:
        if not self._writable:
            self.group, self.arrays = _open_arrays(self.path, "r+", self.names)
            self._writable = True

    def status(self) -> NDArray[np.int8]:
        try:
            status = np.asarray(self.arrays["status"][...])
        except MemoryError:
            raise
        except Exception as exc:
            raise StudyStoreError(
                f"store {self.path} is damaged: 'status' cannot be read ({_one_line(exc)})"
            ) from None
        _check_status_codes(self.path, status)
        return status.astype(np.int8)

    def write(self, result: BatchResult) -> None:
        self._make_writable()
        task = result.task
        region = (*task.grid_index, slice(task.start, task.stop))
        for name in result.curves:
            self.arrays[name][(*region, slice(None))] = result.curves[name]
        for name in SCALAR_VARIABLES:
            self.arrays[name][region] = result.scalars[name]
        self.arrays["error"][region] = np.array(result.errors, dtype=object)
        self.arrays["status"][region] = result.status

    def finished(self) -> bool:
        return bool(self.group.attrs.get("finished"))

    def finish(self) -> None:
        self._make_writable()
        self.group.attrs.update({"finished": _now()})


# --- executing ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Lost:
    """A batch that could not be run (its worker died, ...)."""

    task: BatchTask
    reason: str


def _run_serial(
    tasks: Sequence[BatchTask], func: RealizationFunction | None
) -> Iterator[BatchResult | _Lost]:
    for task in tasks:
        yield run_batch(task, func)


def _init_worker(parent: int) -> None:
    """Set up a pool worker: leave Ctrl-C to the main process, and die with it.

    The main process stops its workers when interrupted; if it is killed (``kill -9``) it
    cannot, so a watchdog thread ends the worker once its parent (``parent``, the pid of the
    main process, given explicitly in case it died while this worker was starting) is gone.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # this process is ours: reuse the previous realization's freed arrays without page faults
    from ._memory import retain_freed_memory

    retain_freed_memory()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="splinecontact-parent-watchdog", daemon=True).start()


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """Ignore SIGINT in this block (processes started here inherit it); main thread only."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _run_pool(
    tasks: Sequence[BatchTask], func: RealizationFunction | None, workers: int
) -> Iterator[BatchResult | _Lost]:
    context = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(
        max_workers=workers, mp_context=context, initializer=_init_worker, initargs=(os.getpid(),)
    )
    finished = False
    try:
        # The workers are started by submit(): started with Ctrl-C ignored, a worker still
        # importing when Ctrl-C comes prints no traceback (the main process handles it).
        with _sigint_ignored():
            pending: dict[Future[BatchResult], BatchTask] = {
                pool.submit(run_batch, task, func): task for task in tasks
            }
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                task = pending.pop(future)
                try:
                    yield future.result()
                except Exception as exc:
                    yield _Lost(task, _one_line(exc))
        finished = True
    finally:
        if finished:
            pool.shutdown(wait=True)
        else:
            # Interrupted (Ctrl-C, an error while writing): stop now; running batches are lost
            # (not stored, so run again) rather than waited for.
            processes = list(getattr(pool, "_processes", {}).values())
            pool.shutdown(wait=False, cancel_futures=True)
            for process in processes:
                process.terminate()


def _run_distributed(
    tasks: Sequence[BatchTask], func: RealizationFunction | None, client: Any
) -> Iterator[BatchResult | _Lost]:
    from distributed import as_completed

    futures = {client.submit(run_batch, task, func, pure=False): task for task in tasks}
    try:
        for future in as_completed(list(futures)):
            task = futures[future]
            try:
                yield future.result()
            except Exception as exc:
                yield _Lost(task, _one_line(exc))
            future.release()
    finally:
        client.cancel(list(futures))


def _connect(scheduler: Any) -> tuple[Any, bool]:
    """A distributed Client for ``scheduler`` (an address or a Client) and whether we own it."""
    try:
        from distributed import Client
    except ImportError:
        raise StudyExecutionError(
            "a Dask scheduler needs the distributed package; install it with "
            "`pip install distributed`"
        ) from None

    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise StudyConfigError(
            f"scheduler = {scheduler!r}: not a Dask scheduler address; give one such as "
            "tcp://10.0.0.1:8786"
        )
    try:
        return Client(scheduler, timeout="20s"), True
    except (ValueError, TypeError) as exc:
        raise StudyConfigError(
            f"scheduler = {scheduler!r}: not a Dask scheduler address ({_one_line(exc)}); give "
            "one such as tcp://10.0.0.1:8786"
        ) from None
    except (OSError, TimeoutError) as exc:
        raise StudyExecutionError(
            f"cannot connect to the Dask scheduler at {scheduler!r} ({_one_line(exc)}); start "
            "it with `dask scheduler` and workers with `dask worker ADDRESS`"
        ) from None


def _worker_version() -> str:
    return f"{__version__} (engine {engine_fingerprint()})"


def _check_workers(client: Any) -> None:
    """Refuse workers whose splinecontact differs from ours (results would differ)."""
    try:
        versions = client.run(_worker_version)
    except Exception as exc:
        raise StudyExecutionError(
            f"the Dask workers cannot run splinecontact ({_one_line(exc)}); install the same "
            f"splinecontact {__version__} on every worker"
        ) from None
    mine = _worker_version()
    wrong = {worker: v for worker, v in versions.items() if v != mine}
    if wrong:
        worker, version = next(iter(wrong.items()))
        raise StudyExecutionError(
            f"Dask worker {worker} has splinecontact {version}, this is {mine}; install "
            "the same code on every worker"
        )


def _grid_label(config: StudyConfig, grid_index: Sequence[int]) -> str:
    parts = [
        f"{name}={values[i]}" for (name, values), i in zip(config.swept, grid_index, strict=True)
    ]
    return ", ".join(parts) + ", " if parts else ""


# --- summary ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FailedRealization:
    """A realization that raised: where, which, and the exception's message."""

    grid: dict[str, Any]
    realization: int
    message: str


@dataclass(frozen=True)
class StudySummary:
    """Outcome of :func:`run_study` (counts over the whole store, not only this run).

    Attributes
    ----------
    store : Path
        The Zarr store.
    total, ok, failed, not_run : int
        Realizations in the study, and how many have status ok / failed / not run.
    ran_now : int
        Realizations computed by this call.
    failures : tuple of FailedRealization
        Every failed realization.
    lost : tuple of str
        Batches that could not be run in this call (a worker died, ...), with the reason.
    wall_time : float
        Duration of this call [s].
    """

    store: Path
    total: int
    ok: int
    failed: int
    not_run: int
    ran_now: int
    failures: tuple[FailedRealization, ...] = ()
    lost: tuple[str, ...] = ()
    wall_time: float = 0.0

    @property
    def complete(self) -> bool:
        """Every realization has been run (successfully or not)."""
        return self.not_run == 0


def _summarize(
    path: Path,
    config: StudyConfig,
    writer: _Writer,
    ran_now: int,
    lost: Sequence[str],
    wall_time: float,
) -> StudySummary:
    status = writer.status()
    failures = []
    failed_positions = np.argwhere(status == STATUS_FAILED)
    if failed_positions.size:
        errors = np.asarray(writer.arrays["error"][...], dtype=object)
        for pos in failed_positions:
            *grid_index, r = (int(p) for p in pos)
            grid = {
                name: values[i] for (name, values), i in zip(config.swept, grid_index, strict=True)
            }
            failures.append(FailedRealization(grid, r, str(errors[tuple(pos)])))
    return StudySummary(
        store=path,
        total=int(status.size),
        ok=int(np.count_nonzero(status == STATUS_OK)),
        failed=int(np.count_nonzero(status == STATUS_FAILED)),
        not_run=int(np.count_nonzero(status == STATUS_NOT_RUN)),
        ran_now=ran_now,
        failures=tuple(failures),
        lost=tuple(lost),
        wall_time=wall_time,
    )


def print_summary(summary: StudySummary, console: Any = None, *, max_failures: int = 20) -> None:
    """Print the summary of a study run (counts, failures, wall time) with rich."""
    from rich.console import Console
    from rich.markup import escape

    console = Console() if console is None else console
    state = "complete" if summary.complete else "incomplete"
    console.print(
        f"[bold]study {state}[/bold]: {summary.ok} ok, {summary.failed} failed, "
        f"{summary.not_run} not run, of {summary.total} realizations "
        f"({summary.ran_now} run now, wall time {summary.wall_time:.1f} s) → "
        f"{escape(str(summary.store))}",
        highlight=False,
    )
    for failure in summary.failures[:max_failures]:
        where = ", ".join(f"{k}={v}" for k, v in failure.grid.items())
        where = f"{where}, " if where else ""
        console.print(
            f"  [red]failed[/red] {escape(where)}realization={failure.realization}: "
            f"{escape(failure.message)}",
            highlight=False,
        )
    if len(summary.failures) > max_failures:
        console.print(f"  … and {len(summary.failures) - max_failures} more failures")
    for reason in summary.lost[:max_failures]:
        console.print(f"  [yellow]not run[/yellow] {escape(reason)}", highlight=False)
    if not summary.complete:
        console.print("Run the same command again to continue.", highlight=False)


@dataclass(frozen=True)
class StudyProgress:
    """What :func:`run_study` reports to its ``progress`` callback.

    The callback is called once when the work is planned, after every batch is stored, and
    once at the end with ``summary`` set.

    Attributes
    ----------
    store : Path
        The Zarr store.
    total : int
        Realizations in the study.
    done : int
        Realizations with a result in the store (ok or failed), this call's included.
    ran_now : int
        Realizations computed by this call so far.
    elapsed : float
        Time since the call started [s].
    summary : StudySummary or None
        The outcome, on the last call only.
    """

    store: Path
    total: int
    done: int
    ran_now: int
    elapsed: float
    summary: StudySummary | None = None


class StudyProgressBar:
    """A rich progress bar for :func:`run_study`, drawn on standard error on a terminal only.

    Use it as a context manager and pass it as ``progress``::

        with StudyProgressBar() as bar:
            summary = run_study("study.toml", "out.zarr", progress=bar)
        print_summary(summary)
    """

    def __init__(self, console: Any = None) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            ProgressColumn,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )
        from rich.text import Text

        class _Rate(ProgressColumn):
            def render(self, task: Any) -> Text:
                speed = task.finished_speed or task.speed
                return Text("  –  real./s" if speed is None else f"{speed:6.2f} real./s")

        console = Console(stderr=True) if console is None else console
        self._progress = Progress(
            TextColumn("[bold]study"),
            BarColumn(),
            MofNCompleteColumn(),
            _Rate(),
            TimeElapsedColumn(),
            TextColumn("ETA"),
            TimeRemainingColumn(),
            console=console,
            disable=not console.is_terminal,
            transient=False,
        )
        self._task: Any = None

    def __enter__(self) -> StudyProgressBar:
        self._progress.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._progress.stop()

    def __call__(self, event: StudyProgress) -> None:
        if self._task is None:
            self._task = self._progress.add_task("study", total=event.total, completed=event.done)
        else:
            self._progress.update(self._task, completed=event.done)


# --- the runner ---------------------------------------------------------------------------------


def _default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def _as_config(config_or_path: StudyConfig | str | Path | Mapping[str, Any]) -> StudyConfig:
    if isinstance(config_or_path, StudyConfig):
        return config_or_path
    if isinstance(config_or_path, Mapping):
        return parse_study(config_or_path)
    return load_study(config_or_path)


ProgressCallback = Callable[[StudyProgress], None]


def _check_count(name: str, value: Any) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise StudyConfigError(f"{name} = {value!r}: must be an integer ≥ 1")


def run_study(
    config_or_path: StudyConfig | str | Path | Mapping[str, Any],
    out: str | Path,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    batch_size: int | None = None,
    progress: ProgressCallback | bool | None = None,
    overwrite: bool = False,
    limits: StudyLimits | None = None,
    realization_function: RealizationFunction | None = None,
) -> StudySummary:
    """Run (or continue) a study and store it in the Zarr store ``out``.

    Silent: nothing is printed unless ``progress`` asks for it.

    Parameters
    ----------
    config_or_path : StudyConfig, path or mapping
        The study (a TOML file path, a validated config, or the mapping a TOML file gives).
    out : path
        The Zarr store (a directory). Created if absent; if it holds the same study, the
        realizations not yet run are run; if it holds another study, refused unless
        ``overwrite``.
    workers : int, optional
        Local worker processes (default: the cores available to this process). ``1`` runs in
        this process. Ignored with ``scheduler``.
    scheduler : str or distributed.Client, optional
        Address of a Dask distributed scheduler (e.g. ``"tcp://10.0.0.1:8786"``), or a client.
        Its workers must have the same splinecontact installed.
    batch_size : int, optional
        Realizations per task (default: ``[output] batch_size`` of the study, else automatic:
        about four tasks per worker, at most 16 realizations each). Does not change the results.
    progress : callable, bool or None
        Called with a :class:`StudyProgress` when the work is planned, after every stored batch
        and at the end (e.g. a :class:`StudyProgressBar`). ``None`` or ``False`` (default):
        silent. ``True``: a :class:`StudyProgressBar` and :func:`print_summary` at the end.
    overwrite : bool
        Discard an existing store that belongs to another study. Only a directory that is
        recognisably a study store is discarded (see ``docs/outputs.md``); anything else is
        refused and left untouched.
    limits : StudyLimits, optional
        Ceilings on the size of the study (default :class:`StudyLimits` ()), checked before
        anything is written.
    realization_function : callable, optional
        Replaces :func:`simulate_realization` (testing and extension hook): a picklable
        module-level function ``(parameters, seed) -> result`` with ``.curves``/``.scalars``.

    Returns
    -------
    StudySummary

    Raises
    ------
    StudyConfigError
        Invalid study file, option or scheduler address, or a study above ``limits``; nothing
        is written.
    StudyStoreError
        ``out`` is not a study store, belongs to another study, is damaged, or another run is
        writing it.
    UnsafeOutputError
        ``overwrite`` would discard something that is not a study store.
    StudyExecutionError
        Batches could not be run (a worker died, the scheduler is unreachable); everything
        finished is stored: run again to continue.
    """
    if progress is True:
        with StudyProgressBar() as bar:
            try:
                summary = run_study(
                    config_or_path,
                    out,
                    workers=workers,
                    scheduler=scheduler,
                    batch_size=batch_size,
                    progress=bar,
                    overwrite=overwrite,
                    limits=limits,
                    realization_function=realization_function,
                )
            except StudyExecutionError as exc:
                if exc.summary is not None:
                    bar.__exit__()
                    print_summary(exc.summary)
                raise
        print_summary(summary)
        return summary
    report = progress if callable(progress) else None
    t0 = time.perf_counter()
    config = _as_config(config_or_path)
    path = Path(out)
    _check_count("workers", workers)
    _check_count("batch_size", batch_size)
    check_limits(config, limits)
    client, own_client = (None, False) if scheduler is None else _connect(scheduler)
    try:
        created = _prepare_store(path, config, overwrite=overwrite)
        with _locked(path):
            _remove_partial_files(path)
            writer = _Writer(path, _array_names(config))
            if not created:
                _verify_store(path, writer.arrays, config)
            status = writer.status()
            total = int(status.size)
            n_done = int(np.count_nonzero(status != STATUS_NOT_RUN))
            if client is not None and n_done < total:
                _check_workers(client)
                n_workers = max(1, sum(client.nthreads().values()))
            else:
                n_workers = _default_workers() if workers is None else workers
            size = batch_size or config.output.batch_size
            if size is None:
                size = _auto_batch_size(total - n_done, n_workers)
            tasks = _make_batches(config, status, size)
            if not tasks:
                results: Iterator[BatchResult | _Lost] = iter(())
            elif client is not None:
                results = _run_distributed(tasks, realization_function, client)
            elif n_workers == 1 or len(tasks) <= 1:
                results = _run_serial(tasks, realization_function)
            else:
                results = _run_pool(tasks, realization_function, min(n_workers, len(tasks)))
            ran_now = 0
            lost: list[str] = []
            if report is not None:
                report(StudyProgress(path, total, n_done, 0, time.perf_counter() - t0))
            try:
                for item in results:
                    if isinstance(item, _Lost):
                        t = item.task
                        where = _grid_label(config, t.grid_index)
                        lost.append(f"{where}realizations {t.start}–{t.stop - 1}: {item.reason}")
                        continue
                    writer.write(item)
                    n = item.task.stop - item.task.start
                    ran_now += n
                    n_done += n
                    if report is not None:
                        elapsed = time.perf_counter() - t0
                        report(StudyProgress(path, total, n_done, ran_now, elapsed))
            finally:
                close = getattr(results, "close", None)
                if close is not None:
                    close()
            summary = _summarize(path, config, writer, ran_now, lost, time.perf_counter() - t0)
            # A finished store is left as it is: a no-op run changes nothing.
            if summary.complete and not lost and (ran_now or not writer.finished()):
                writer.finish()
    finally:
        if own_client and client is not None:
            client.close()
    if report is not None:
        report(StudyProgress(path, total, n_done, ran_now, summary.wall_time, summary))
    if lost:
        raise StudyExecutionError(
            f"{len(lost)} batch(es) could not be run ({lost[0]}); everything finished is "
            f"stored in {path}: run the same command again to continue",
            summary,
        )
    return summary


# --- reading ------------------------------------------------------------------------------------


def open_study(path: str | Path) -> xr.Dataset:
    """Load a study store into memory as an :class:`xarray.Dataset` (schema: module docstring).

    Raises
    ------
    StudyStoreError
        If ``path`` is not a study store.
    """
    path = Path(path)
    if not path.exists():
        raise StudyStoreError(f"study store {path}: no such directory")
    attrs = _root_metadata(path) if path.is_dir() else None
    if attrs is None:
        raise StudyStoreError(f"{path} is not a splinecontact study store")
    config = _stored_config(path, attrs)
    names = _array_names(config)
    _open_arrays(path, "r", names)  # names a missing array
    try:
        ds = xr.open_zarr(path, consolidated=False)
    except Exception as exc:
        raise StudyStoreError(
            f"store {path} is damaged: it cannot be opened ({_one_line(exc)})"
        ) from None
    with ds:
        for name, variable in ds.variables.items():
            try:
                variable.load()
            except MemoryError:
                raise
            except Exception as exc:
                raise StudyStoreError(
                    f"store {path} is damaged: {name!r} cannot be read ({_one_line(exc)})"
                ) from None
        loaded = ds.load()
    expected = (*config.grid_shape, config.study.realizations)
    for name in (*names, "seed_spawn_key"):
        if name not in loaded.data_vars:
            raise StudyStoreError(f"store {path} is damaged: the variable {name!r} is missing")
    if loaded["status"].shape != expected or loaded.sizes.get("step") != config.max_steps + 1:
        raise StudyStoreError(
            f"store {path} is damaged: its arrays do not have the shape of its study "
            f"(status {loaded['status'].shape}, the study needs {expected})"
        )
    _check_status_codes(path, loaded["status"].values)
    # Variable-length strings come back as numpy's StringDType: use plain str objects.
    for name in list(loaded.variables):
        var = loaded.variables[name]
        if var.dtype.kind == "T":
            loaded[name] = var.copy(data=np.asarray(var.values, dtype=object))
    order = [
        *step_variables(config.path is not None),
        *SCALAR_VARIABLES,
        "status",
        "error",
        "seed_spawn_key",
    ]
    order += [name for name in loaded.data_vars if name not in order]
    return loaded[order]


def parameter_value(ds: xr.Dataset, name: str, **grid_index: int) -> Any:
    """The value of simulation parameter ``name`` in a study dataset.

    Looks in the coordinates (swept parameters) first, then in the attributes (fixed ones).

    Parameters
    ----------
    ds : xarray.Dataset
        A study (:func:`open_study`), or a selection of one.
    name : str
        A name of :data:`splinecontact.config.PARAMETERS`.
    **grid_index : int
        Positions along swept dimensions, e.g. ``dimension=3``; only ``name``'s is used.

    Returns
    -------
    object
        The value; for a swept parameter without a position, the array of its values (or the
        scalar if ``ds`` was selected at one value); ``None`` for a parameter left at the engine
        default.
    """
    if name in ds.coords:
        coord = ds.coords[name]
        if name in grid_index:
            return coord.values[int(grid_index[name])].item() if coord.ndim else coord.item()
        return coord.item() if coord.ndim == 0 else coord.values
    if name in ds.attrs:
        return ds.attrs[name]
    if name in PARAMETERS:
        return None
    raise StudyStoreError(f"{name!r} is not a study parameter; known: {', '.join(PARAMETERS)}")


def _write_bytes(path: Path, data: memoryview) -> None:
    """Write ``data`` to the new file ``path`` and flush it to disk."""
    with open(path, "xb") as file:
        file.write(data)
        file.flush()
        os.fsync(file.fileno())


def _remove_dead_temporaries(target: Path) -> None:
    """Remove temporary files of earlier exports to ``target`` whose process is gone (kill -9)."""
    for tmp in target.parent.glob(f".{target.stem}.tmp-*-*{target.suffix}"):
        pid_text = tmp.name.removeprefix(f".{target.stem}.tmp-").split("-", 1)[0]
        if not pid_text.isdigit() or int(pid_text) == os.getpid() or not tmp.is_file():
            continue
        try:
            os.kill(int(pid_text), 0)
        except ProcessLookupError:
            tmp.unlink(missing_ok=True)
        except OSError:
            continue


def export_netcdf(store: str | Path, target: str | Path, *, overwrite: bool = False) -> Path:
    """Write a study store as one netCDF-4 file (h5netcdf engine) and return its path.

    The file is written whole to a temporary name beside ``target`` and renamed into place, so
    an interruption or a full disk leaves no partial file and an earlier file intact.

    Parameters
    ----------
    store : path
        The study store (:func:`run_study`).
    target : path
        The netCDF file to write.
    overwrite : bool
        Replace ``target`` if it exists (never a file inside ``store``).

    Raises
    ------
    StudyStoreError
        ``store`` is not a study store, or is damaged.
    OutputExistsError
        ``target`` exists and ``overwrite`` is false.
    UnsafeOutputError
        ``target`` is a folder, lies inside ``store``, or its folder does not exist.
    OutputError
        The file cannot be written (full disk, permissions); nothing is left behind.
    """
    store = Path(store)
    target = Path(target)
    if store.exists():
        resolved, root = target.expanduser().resolve(), store.expanduser().resolve()
        if resolved == root or root in resolved.parents:
            raise UnsafeOutputError(
                f"--netcdf {target} is inside the study store {store}; refusing to write there"
            )
    target = check_output_file(target, overwrite=overwrite, option="--netcdf")
    ds = open_study(store)
    try:
        data = ds.to_netcdf(engine="h5netcdf", invalid_netcdf=False)
    except ImportError as exc:
        raise StudyStoreError(
            f"cannot write {target}: netCDF-4 writing needs h5py ({exc}); install it with "
            "`pip install h5py`"
        ) from None
    _remove_dead_temporaries(target)
    try:
        with atomic_path(target) as tmp:
            _write_bytes(tmp, data)
    except OSError as exc:
        reason = exc.strerror or _one_line(exc)
        raise OutputError(
            f"--netcdf {target}: cannot be written ({reason}); nothing was written"
        ) from None
    return target
