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
realization, step) and of ``SCALAR_VARIABLES`` on (grid…, realization), float64 (NaN where not
run or failed); ``status`` int8 (0 not run, 1 ok, 2 failed); ``error`` (message, "" if ok);
``seed_spawn_key`` (realization). Attributes: every fixed parameter under its name (parameters
left at the engine default ``None``, e.g. ``g_star``, are absent), ``study_toml``,
``study_seed``, ``splinecontact_version``, ``engine_fingerprint``, ``started``, ``finished``.

Testing hook: :func:`run_study` takes ``realization_function`` (default
:func:`simulate_realization`), any picklable module-level callable
``(parameters, seed) -> result`` with ``.curves`` and ``.scalars`` mappings. The tests use it to
inject a failing realization and a fast stand-in engine.
"""

from __future__ import annotations

import ast
import contextlib
import datetime as _dt
import fcntl
import functools
import hashlib
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
from .config import PARAMETERS, StudyConfig, load_study, parse_study
from .contact import SIMULATION_PARAMETERS
from .errors import SplineContactError, StudyConfigError, StudyStoreError
from .generate import GENERATOR_PARAMETERS
from .results import SCALAR_VARIABLES, STEP_VARIABLES

__all__ = [
    "STATUS_FAILED",
    "STATUS_NOT_RUN",
    "STATUS_OK",
    "BatchResult",
    "BatchTask",
    "FailedRealization",
    "StudyExecutionError",
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
    """Some batches could not be run (a worker died, the scheduler is unreachable, ...)."""


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
        One value for every name in :data:`splinecontact.config.PARAMETERS` (units there).
    seed : numpy.random.SeedSequence
        The realization's seed (:func:`realization_seed`). Rough-on-rough: passed to
        ``weierstrass_mandelbrot_pair``. Rough-on-flat: the lower profile is generated from the
        pair's lower seed (``seed.spawn(2)[0]``), so it equals the rough-on-rough lower profile.

    Returns
    -------
    SimulationResult
    """
    import warnings

    from .contact import simulate
    from .diagnostics import SimulationWarning
    from .generate import child_seed, weierstrass_mandelbrot, weierstrass_mandelbrot_pair

    dimension = float(parameters["dimension"])
    gen = {k: parameters[k] for k in _GENERATOR_KEYS}
    sim = {k: parameters[k] for k in _SIMULATE_KEYS}
    with warnings.catch_warnings():
        # per-realization diagnostics would repeat once per realization (and from workers)
        warnings.simplefilter("ignore", SimulationWarning)
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
    curves = {name: np.full((n, width), np.nan) for name in STEP_VARIABLES}
    scalars = {name: np.full(n, np.nan) for name in SCALAR_VARIABLES}
    status = np.full(n, STATUS_OK, dtype=np.int8)
    errors = [""] * n
    expected = int(task.parameters["steps"]) + 1
    for i, r in enumerate(range(task.start, task.stop)):
        try:
            result = func(task.parameters, realization_seed(task.study_seed, r))
            row_curves = {}
            for name in STEP_VARIABLES:
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
    for name, (units, description) in STEP_VARIABLES.items():
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


def _create_store(path: Path, config: StudyConfig) -> None:
    """Create the empty store atomically (built beside ``path``, then renamed)."""
    for stale in path.parent.glob(f".{path.name}.creating-*"):  # left by a killed creation
        shutil.rmtree(stale, ignore_errors=True)
    tmp = path.with_name(f".{path.name}.creating-{uuid.uuid4().hex}")
    try:
        dataset, encoding = _template(config)
        dataset.to_zarr(tmp, mode="w-", encoding=encoding, consolidated=False, compute=False)
        os.rename(tmp, path)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


def _read_store_attrs(path: Path) -> dict[str, Any] | None:
    import zarr

    try:
        group = zarr.open_group(path, mode="r")
    except Exception:
        return None
    attrs = dict(group.attrs)
    return attrs if "study_toml" in attrs else None


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


def _prepare_store(path: Path, config: StudyConfig, *, overwrite: bool) -> None:
    if path.exists():
        attrs = _read_store_attrs(path)
        if attrs is None:
            if not overwrite:
                raise StudyStoreError(
                    f"{path} exists and is not a splinecontact study store; choose another "
                    "output path (or --overwrite to replace it)"
                )
        else:
            import tomllib

            stored = parse_study(tomllib.loads(attrs["study_toml"]), source=f"{path} (stored)")
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
                return
            if not overwrite:
                raise StudyStoreError(
                    f"store {path} belongs to a different study ({diff}); use another output "
                    "path, or --overwrite to discard the store and start again"
                )
        if path.is_dir():
            with _locked(path):  # refuse to discard a store another run is writing
                shutil.rmtree(path)
        else:
            path.unlink()
    _create_store(path, config)


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


class _Writer:
    """Writes finished batches into the store: data, then ``error``, then ``status``."""

    def __init__(self, path: Path) -> None:
        import zarr

        self.group = zarr.open_group(path, mode="r+")
        names = [*STEP_VARIABLES, *SCALAR_VARIABLES, "error", "status"]
        self.arrays: dict[str, Any] = {name: self.group[name] for name in names}

    def status(self) -> NDArray[np.int8]:
        return np.asarray(self.arrays["status"][...], dtype=np.int8)

    def write(self, result: BatchResult) -> None:
        task = result.task
        region = (*task.grid_index, slice(task.start, task.stop))
        for name in STEP_VARIABLES:
            self.arrays[name][(*region, slice(None))] = result.curves[name]
        for name in SCALAR_VARIABLES:
            self.arrays[name][region] = result.scalars[name]
        self.arrays["error"][region] = np.array(result.errors, dtype=object)
        self.arrays["status"][region] = result.status

    def finish(self) -> None:
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

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="splinecontact-parent-watchdog", daemon=True).start()


def _run_pool(
    tasks: Sequence[BatchTask], func: RealizationFunction | None, workers: int
) -> Iterator[BatchResult | _Lost]:
    context = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(
        max_workers=workers, mp_context=context, initializer=_init_worker, initargs=(os.getpid(),)
    )
    finished = False
    try:
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
    from distributed import Client

    if isinstance(scheduler, Client):
        return scheduler, False
    try:
        return Client(scheduler, timeout="20s"), True
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


def _progress(enabled: bool) -> Any:
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

    console = Console(stderr=True)
    progress = Progress(
        TextColumn("[bold]study"),
        BarColumn(),
        MofNCompleteColumn(),
        _Rate(),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
        console=console,
        disable=not (enabled and console.is_terminal),
        transient=False,
    )
    return progress


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


def run_study(
    config_or_path: StudyConfig | str | Path | Mapping[str, Any],
    out: str | Path,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    batch_size: int | None = None,
    progress: bool = True,
    overwrite: bool = False,
    realization_function: RealizationFunction | None = None,
) -> StudySummary:
    """Run (or continue) a study and store it in the Zarr store ``out``.

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
    progress : bool
        Show a progress bar (on a terminal) and print the summary at the end.
    overwrite : bool
        Discard an existing store that belongs to another study.
    realization_function : callable, optional
        Replaces :func:`simulate_realization` (testing and extension hook): a picklable
        module-level function ``(parameters, seed) -> result`` with ``.curves``/``.scalars``.

    Returns
    -------
    StudySummary

    Raises
    ------
    StudyConfigError
        Invalid study file.
    StudyStoreError
        ``out`` belongs to another study, or another run is writing it.
    StudyExecutionError
        Batches could not be run (a worker died, the scheduler is unreachable); everything
        finished is stored: run again to continue.
    """
    t0 = time.perf_counter()
    config = _as_config(config_or_path)
    path = Path(out)
    if workers is not None and workers < 1:
        raise StudyConfigError(f"workers = {workers}: must be ≥ 1")
    if batch_size is not None and batch_size < 1:
        raise StudyConfigError(f"batch_size = {batch_size}: must be ≥ 1")
    client, own_client = (None, False) if scheduler is None else _connect(scheduler)
    try:
        _prepare_store(path, config, overwrite=overwrite)
        with _locked(path):
            _remove_partial_files(path)
            writer = _Writer(path)
            status = writer.status()
            n_done = int(np.count_nonzero(status != STATUS_NOT_RUN))
            if client is not None:
                _check_workers(client)
                n_workers = max(1, sum(client.nthreads().values()))
            else:
                n_workers = _default_workers() if workers is None else workers
            size = batch_size or config.output.batch_size
            if size is None:
                size = _auto_batch_size(int(status.size) - n_done, n_workers)
            tasks = _make_batches(config, status, size)
            if client is not None:
                results = _run_distributed(tasks, realization_function, client)
            elif n_workers == 1 or len(tasks) <= 1:
                results = _run_serial(tasks, realization_function)
            else:
                results = _run_pool(tasks, realization_function, min(n_workers, len(tasks)))
            ran_now = 0
            lost: list[str] = []
            bar = _progress(progress)
            with bar:
                task_id = bar.add_task("study", total=int(status.size), completed=n_done)
                try:
                    for item in results:
                        if isinstance(item, _Lost):
                            t = item.task
                            where = _grid_label(config, t.grid_index)
                            lost.append(
                                f"{where}realizations {t.start}–{t.stop - 1}: {item.reason}"
                            )
                            continue
                        writer.write(item)
                        ran_now += item.task.stop - item.task.start
                        bar.advance(task_id, item.task.stop - item.task.start)
                finally:
                    close = getattr(results, "close", None)
                    if close is not None:
                        close()
            summary = _summarize(path, config, writer, ran_now, lost, time.perf_counter() - t0)
            if summary.complete and not lost:
                writer.finish()
    finally:
        if own_client and client is not None:
            client.close()
    if progress:
        print_summary(summary)
    if lost:
        raise StudyExecutionError(
            f"{len(lost)} batch(es) could not be run ({lost[0]}); everything finished is "
            f"stored in {path}: run the same command again to continue"
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
    if _read_store_attrs(path) is None:
        raise StudyStoreError(f"{path} is not a splinecontact study store")
    with xr.open_zarr(path, consolidated=False) as ds:
        loaded = ds.load()
    # Variable-length strings come back as numpy's StringDType: use plain str objects.
    for name in list(loaded.variables):
        var = loaded.variables[name]
        if var.dtype.kind == "T":
            loaded[name] = var.copy(data=np.asarray(var.values, dtype=object))
    order = [*STEP_VARIABLES, *SCALAR_VARIABLES, "status", "error", "seed_spawn_key"]
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


def export_netcdf(store: str | Path, target: str | Path) -> Path:
    """Write a study store as one netCDF-4 file (h5netcdf engine) and return its path."""
    ds = open_study(store)
    target = Path(target)
    try:
        ds.to_netcdf(target, engine="h5netcdf", invalid_netcdf=False)
    except ImportError as exc:
        raise StudyStoreError(
            f"cannot write {target}: netCDF-4 writing needs h5py ({exc}); install it with "
            "`pip install h5py`"
        ) from None
    return target
