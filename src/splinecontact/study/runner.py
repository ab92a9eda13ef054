"""Running a study: realizations, batches, progress and the summary; prints nothing.

A study (see :mod:`splinecontact.study.config`) sweeps some simulation parameters over a grid
and repeats every grid point for ``realizations`` independent profile pairs. One realization is

1. profiles: ``lower, upper = weierstrass_mandelbrot_pair(dimension, seed=s_r, ...)`` (eq. 1)
   for rough-on-rough; for rough-on-flat only the lower profile is generated — with the same
   seed as the rough-on-rough lower profile of that realization — and the upper body is
   ``"flat"``;
2. ``simulate(lower, upper, steps=..., e_star=..., ...)`` (eqs. 2–14).

Seeds: realization ``r`` uses ``s_r = numpy.random.SeedSequence(study_seed).spawn(R)[r]``
(entropy ``study_seed``, spawn key ``(r,)``), the same at every grid point: a paired design with
common random numbers across the swept parameters.

Work is batched (a batch is a run of consecutive realizations at one grid point) and executed
by an executor (:mod:`splinecontact.study.executors`): in the calling process
(``workers=1``), on a local process pool, or on a Dask distributed cluster. The main process
alone writes the store (:mod:`splinecontact.study.store`). Re-running continues with the
realizations whose status is still 0. The stored values do not depend on the worker count, the
scheduler, the batch size or the order in which batches finish.

:func:`run_study` prints nothing: progress goes to an optional callback (for example
:class:`splinecontact.study.StudyProgressBar`, which the command line uses); the study is
validated and checked against :class:`~splinecontact.study.StudyLimits` before anything is
written.

Testing hook: :func:`run_study` takes ``realization_function`` (default
:func:`simulate_realization`), any picklable module-level callable
``(parameters, seed) -> result`` with ``.curves`` and ``.scalars`` mappings. The tests use it to
inject a failing realization and a fast stand-in engine.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import StudyConfigError, StudyExecutionError
from ..results import SCALAR_VARIABLES
from .config import PATH_REPLACES, StudyConfig, load_study, parse_study
from .executors import Executor, Lost, make_executor
from .limits import StudyLimits, check_limits
from .store import (
    STATUS_FAILED,
    STATUS_NOT_RUN,
    STATUS_OK,
    BatchResult,
    BatchTask,
    _array_names,
    _locked,
    _one_line,
    _prepare_store,
    _remove_partial_files,
    _verify_store,
    _Writer,
    step_variables,
)
from .warmup import warm_up_workers

__all__ = [
    "FailedRealization",
    "ProgressCallback",
    "RealizationFunction",
    "StudyProgress",
    "StudySummary",
    "realization_seed",
    "run_batch",
    "run_batch_group",
    "run_study",
    "simulate_realization",
]

#: Largest automatic batch (realizations per task).
_MAX_AUTO_BATCH = 16

#: ``(parameters, seed) -> result`` with ``.curves`` and ``.scalars`` mappings.
RealizationFunction = Callable[[Mapping[str, Any], np.random.SeedSequence], Any]


# --- one realization ----------------------------------------------------------------------------


def realization_seed(study_seed: int, realization: int) -> np.random.SeedSequence:
    """Seed of realization ``r``: ``SeedSequence(study_seed).spawn(R)[r]`` for any R > r.

    Built directly (entropy ``study_seed``, spawn key ``(r,)``) so it never depends on how
    many children were spawned before.
    """
    return np.random.SeedSequence(study_seed, spawn_key=(realization,))


def simulate_realization(
    parameters: Mapping[str, Any],
    seed: np.random.SeedSequence,
    *,
    profiles: dict[Any, Any] | None = None,
) -> Any:
    """Generate the profiles of one realization and simulate their contact.

    Parameters
    ----------
    parameters : mapping
        One value for every name in :data:`splinecontact.parameters.PARAMETERS` (units there), and
        optionally ``path``: a sequence of mappings of :class:`splinecontact.Segment` keyword
        arguments (δ_N [µm] or F_N [mN/µm], u_T [µm], steps), which replaces ``steps`` and
        ``final_displacement``, and optionally ``law``: ``name`` and the parameters of a contact
        law (``docs/contact-laws.md``; default Hertz).
    seed : numpy.random.SeedSequence
        The realization's seed (:func:`realization_seed`). Rough-on-rough: passed to
        ``weierstrass_mandelbrot_pair``. Rough-on-flat: the lower profile is generated from the
        pair's lower seed (``seed.spawn(2)[0]``), so it equals the rough-on-rough lower profile.
    profiles : dict, optional
        Profiles already generated for this realization (``seed``), kept by generator
        parameters: a grid point that differs from an earlier one only in the contact type
        (or in a simulation parameter) reuses them instead of generating them again — the
        same arrays, so the same result. Filled in here; give one dict per realization.

    Returns
    -------
    SimulationResult
    """
    from ..contact import SIMULATION_PARAMETERS, simulate
    from ..generate import (
        GENERATOR_PARAMETERS,
        child_seed,
        weierstrass_mandelbrot,
        weierstrass_mandelbrot_pair,
    )

    dimension = float(parameters["dimension"])
    gen = {k: parameters[k] for k in GENERATOR_PARAMETERS}
    sim = {k: parameters[k] for k in SIMULATION_PARAMETERS}
    segments = parameters.get("path")
    if segments is not None:
        from ..contact import Segment

        for name in PATH_REPLACES:
            sim.pop(name, None)
        sim["path"] = [Segment(**segment) for segment in segments]
    law = parameters.get("law")
    if law is not None:
        from ..contact import make_law

        sim["law"] = make_law(**law)
    # per-realization diagnostics would repeat once per realization (and from workers)
    sim["diagnostics"] = False
    from ..contact.streamed import STREAM_MIN_POINTS, simulate_generated

    if (
        int(gen["n_points"]) >= STREAM_MIN_POINTS
        and segments is None
        and not getattr(sim.get("law"), "needs_radius", False)
    ):  # generated, fitted and placed in chunks (the same results, no array of n values)
        flat = parameters["contact_type"] != "rough-on-rough"
        del sim["diagnostics"]
        return simulate_generated(dimension, seed=seed, flat=flat, generator=gen, **sim)
    cache: dict[Any, Any] = {} if profiles is None else profiles
    key = (repr(dimension), tuple((name, repr(value)) for name, value in sorted(gen.items())))
    if parameters["contact_type"] == "rough-on-rough":
        if ("upper", key) not in cache:
            pair = weierstrass_mandelbrot_pair(dimension, seed=seed, **gen)
            cache[("lower", key)], cache[("upper", key)] = pair
        return simulate(cache[("lower", key)], cache[("upper", key)], **sim)
    if ("lower", key) not in cache:
        # the pair's lower profile is generated from the same child seed: the same array
        cache[("lower", key)] = weierstrass_mandelbrot(dimension, seed=child_seed(seed, 0), **gen)
    return simulate(cache[("lower", key)], "flat", **sim)


# --- batches ------------------------------------------------------------------------------------


def run_batch(
    task: BatchTask, realization_function: RealizationFunction | None = None
) -> BatchResult:
    """Run the realizations of ``task``; an exception in one is recorded, not raised."""
    return run_batch_group((task,), realization_function)[0]


def run_batch_group(
    tasks: Sequence[BatchTask], realization_function: RealizationFunction | None = None
) -> tuple[BatchResult, ...]:
    """Run batches of the same realizations at several grid points, realization by realization.

    With the default engine the grid points of one realization share its profiles (see
    :func:`simulate_realization`): a rough-on-flat grid point reuses the lower profile its
    rough-on-rough twin generated. Each result is the one :func:`run_batch` gives alone.
    """
    func = simulate_realization if realization_function is None else realization_function
    share = realization_function is None
    first = tasks[0]
    out = [_BatchRows(task) for task in tasks]
    for i in range(first.stop - first.start):
        profiles: dict[Any, Any] = {}
        for task, rows in zip(tasks, out, strict=True):
            seed = realization_seed(task.study_seed, task.start + i)
            try:
                if share:
                    result = simulate_realization(task.parameters, seed, profiles=profiles)
                else:
                    result = func(task.parameters, seed)
                rows.store(i, result)
            except Exception as exc:
                rows.fail(i, exc)
    return tuple(rows.result() for rows in out)


class _BatchRows:
    """The rows of one batch as its realizations finish (curves, scalars, status, errors)."""

    def __init__(self, task: BatchTask) -> None:
        self.task = task
        n = task.stop - task.start
        width = task.n_step_records
        self.names = step_variables(task.parameters.get("path") is not None)
        self.curves = {name: np.full((n, width), np.nan) for name in self.names}
        self.scalars = {name: np.full(n, np.nan) for name in SCALAR_VARIABLES}
        self.status = np.full(n, STATUS_OK, dtype=np.int8)
        self.errors = [""] * n
        self.expected = int(task.parameters["steps"]) + 1

    def store(self, i: int, result: Any) -> None:
        """Check and keep one realization's result (raises if its curves are malformed)."""
        expected = self.expected
        row_curves = {}
        for name in self.names:
            values = np.asarray(result.curves[name], dtype=np.float64)
            if values.shape != (expected,):
                raise ValueError(f"curve {name!r} has shape {values.shape}, expected ({expected},)")
            row_curves[name] = values
        row_scalars = {name: float(result.scalars[name]) for name in SCALAR_VARIABLES}
        for name, values in row_curves.items():
            self.curves[name][i, :expected] = values
        for name, value in row_scalars.items():
            self.scalars[name][i] = value

    def fail(self, i: int, exc: BaseException) -> None:
        self.status[i] = STATUS_FAILED
        self.errors[i] = _one_line(exc)

    def result(self) -> BatchResult:
        return BatchResult(self.task, self.curves, self.scalars, self.status, tuple(self.errors))


def _group_key(task: BatchTask) -> tuple[Any, ...]:
    """Batches with equal keys generate the same profiles (same realizations, generator inputs)."""
    from ..generate import GENERATOR_PARAMETERS

    params = task.parameters
    gen = tuple((name, repr(params.get(name))) for name in ("dimension", *GENERATOR_PARAMETERS))
    return (task.start, task.stop, task.study_seed, gen)


def _group_batches(tasks: Sequence[BatchTask], share_profiles: bool) -> list[tuple[BatchTask, ...]]:
    """Batches as groups run by one task each: those that share profiles together (rough-on-
    rough first, so that its pair is generated once), else one batch per group; in the order
    of their first batch."""
    if not share_profiles:
        return [(task,) for task in tasks]
    groups: dict[tuple[Any, ...], list[BatchTask]] = {}
    for task in tasks:
        groups.setdefault(_group_key(task), []).append(task)
    return [
        tuple(sorted(group, key=lambda t: t.parameters.get("contact_type") != "rough-on-rough"))
        for group in groups.values()
    ]


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
            # batches of at most batch_size, of equal sizes (10 + 10 rather than 16 + 4): the
            # workers then finish together
            for part in np.array_split(run, math.ceil(run.size / batch_size)):
                tasks.append(
                    BatchTask(grid_index, int(part[0]), int(part[-1]) + 1, params, seed, width)
                )
    return tasks


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


# --- the runner ---------------------------------------------------------------------------------


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
    executor: Executor | None = None,
) -> StudySummary:
    """Run (or continue) a study and store it in the Zarr store ``out``.

    Silent: nothing is printed; progress goes to the ``progress`` callback.

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
    progress : callable or None
        Called with a :class:`StudyProgress` when the work is planned, after every stored batch
        and at the end (e.g. a :class:`splinecontact.study.StudyProgressBar`). ``None`` or
        ``False`` (default): silent. Nothing else is ever printed.
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
    executor : Executor, optional
        Where the batches run (replaces ``workers`` and ``scheduler``); left open, for the
        caller's further work in the same worker processes.

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

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from splinecontact.study import run_study, open_study
    >>> config = {"study": {"name": "tiny", "seed": 1, "realizations": 2},
    ...           "fixed": {"n_points": 2048, "length": 10.0, "steps": 20},
    ...           "sweep": {"dimension": [1.3, 1.7]}}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     summary = run_study(config, pathlib.Path(folder) / "tiny.zarr", workers=1)
    >>> summary.ok, summary.complete
    (4, True)
    """
    if progress is not None and progress is not False and not callable(progress):
        raise StudyConfigError(
            f"progress = {progress!r}: give a callable taking a StudyProgress (for example "
            "splinecontact.study.StudyProgressBar()), or None for a silent run"
        )
    report = progress if callable(progress) else None
    t0 = time.perf_counter()
    config = _as_config(config_or_path)
    path = Path(out)
    _check_count("workers", workers)
    _check_count("batch_size", batch_size)
    check_limits(config, limits)
    own_executor = executor is None
    if executor is None:
        executor = make_executor(workers, scheduler)
    if realization_function is None:
        # the workers start (and compile) while this process prepares the store
        warm_up_workers(executor, config)
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
            # (a Dask executor checks its workers' code here, only if there is work to do)
            n_workers = executor.workers if n_done < total else 1
            size = batch_size or config.output.batch_size
            if size is None:
                size = _auto_batch_size(total - n_done, n_workers)
            groups = _group_batches(
                _make_batches(config, status, size), share_profiles=realization_function is None
            )
            batch = functools.partial(run_batch_group, realization_function=realization_function)
            results: Iterator[tuple[BatchResult, ...] | Lost] = (
                executor.run(batch, groups) if groups else iter(())
            )
            ran_now = 0
            lost: list[str] = []
            if report is not None:
                report(StudyProgress(path, total, n_done, 0, time.perf_counter() - t0))
            try:
                for item in results:
                    if isinstance(item, Lost):
                        for t in item.task:
                            where = _grid_label(config, t.grid_index)
                            lost.append(
                                f"{where}realizations {t.start}–{t.stop - 1}: {item.reason}"
                            )
                        continue
                    for one in item:
                        writer.write(one)
                        n = one.task.stop - one.task.start
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
        if own_executor:
            executor.close()
    if report is not None:
        report(StudyProgress(path, total, n_done, ran_now, summary.wall_time, summary))
    if lost:
        raise StudyExecutionError(
            f"{len(lost)} batch(es) could not be run ({lost[0]}); everything finished is "
            f"stored in {path}: run the same command again to continue",
            summary,
        )
    return summary
