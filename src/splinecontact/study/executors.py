"""Where a study's batches run: in this process, on a local process pool, or on Dask.

All three are an :class:`Executor`: ``workers`` (how many run at once, after checking they can
run this code), ``run(function, tasks)`` (the outcome of every task, in the order they finish:
the function's result, or :class:`Lost` if the task could not be run) and ``close()``. The
function and the tasks must be picklable for the pool and Dask.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any, TypeVar

from .._version import __version__
from ..errors import StudyConfigError, StudyExecutionError
from .fingerprint import engine_fingerprint
from .store import _one_line

__all__ = ["DaskExecutor", "Executor", "LocalExecutor", "Lost", "make_executor"]

T = TypeVar("T")
R = TypeVar("R")


@dataclass(frozen=True)
class Lost:
    """A task that could not be run (its worker died, ...), with the reason."""

    task: Any
    reason: str


class Executor:
    """Runs tasks somewhere; the interface of every executor."""

    @property
    def workers(self) -> int:
        """How many tasks run at once (a Dask executor first checks its workers' code)."""
        raise NotImplementedError

    def run(self, function: Callable[[T], R], tasks: Sequence[T]) -> Iterator[R | Lost]:
        """The outcome of every task, as they finish (closing the iterator stops the work)."""
        raise NotImplementedError

    def close(self) -> None:
        """Release what the executor holds (a Dask client it opened)."""


def _default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


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


class LocalExecutor(Executor):
    """This process (one worker, or a single task), else a pool of ``workers`` processes."""

    def __init__(self, workers: int | None = None) -> None:
        self._workers = _default_workers() if workers is None else workers

    @property
    def workers(self) -> int:
        return self._workers

    def run(self, function: Callable[[T], R], tasks: Sequence[T]) -> Iterator[R | Lost]:
        if self._workers == 1 or len(tasks) <= 1:
            return (function(task) for task in tasks)
        return self._run_pool(function, tasks, min(self._workers, len(tasks)))

    @staticmethod
    def _run_pool(
        function: Callable[[T], R], tasks: Sequence[T], workers: int
    ) -> Iterator[R | Lost]:
        context = multiprocessing.get_context("spawn")
        pool = ProcessPoolExecutor(
            max_workers=workers,
            mp_context=context,
            initializer=_init_worker,
            initargs=(os.getpid(),),
        )
        finished = False
        try:
            # The workers are started by submit(): started with Ctrl-C ignored, a worker still
            # importing when Ctrl-C comes prints no traceback (the main process handles it).
            with _sigint_ignored():
                pending: dict[Future[R], T] = {pool.submit(function, task): task for task in tasks}
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    task = pending.pop(future)
                    try:
                        yield future.result()
                    except Exception as exc:
                        yield Lost(task, _one_line(exc))
            finished = True
        finally:
            if finished:
                pool.shutdown(wait=True)
            else:
                # Interrupted (Ctrl-C, an error while writing): stop now; running tasks are
                # lost (not stored, so run again) rather than waited for.
                processes = list(getattr(pool, "_processes", {}).values())
                pool.shutdown(wait=False, cancel_futures=True)
                for process in processes:
                    process.terminate()


def _worker_version() -> str:
    return f"{__version__} (engine {engine_fingerprint()})"


class DaskExecutor(Executor):
    """The workers of a Dask distributed scheduler (an address, or a client to use).

    Raises
    ------
    StudyConfigError
        ``scheduler`` is not an address.
    StudyExecutionError
        The distributed package is missing, or the scheduler cannot be reached.
    """

    def __init__(self, scheduler: Any) -> None:
        self.client, self._own = self._connect(scheduler)

    @staticmethod
    def _connect(scheduler: Any) -> tuple[Any, bool]:
        """A distributed Client for ``scheduler`` and whether this executor opened it."""
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
                f"scheduler = {scheduler!r}: not a Dask scheduler address ({_one_line(exc)}); "
                "give one such as tcp://10.0.0.1:8786"
            ) from None
        except (OSError, TimeoutError) as exc:
            raise StudyExecutionError(
                f"cannot connect to the Dask scheduler at {scheduler!r} ({_one_line(exc)}); "
                "start it with `dask scheduler` and workers with `dask worker ADDRESS`"
            ) from None

    def _check_workers(self) -> None:
        """Refuse workers whose splinecontact differs from ours (results would differ)."""
        try:
            versions = self.client.run(_worker_version)
        except Exception as exc:
            raise StudyExecutionError(
                f"the Dask workers cannot run splinecontact ({_one_line(exc)}); install the "
                f"same splinecontact {__version__} on every worker"
            ) from None
        mine = _worker_version()
        wrong = {worker: v for worker, v in versions.items() if v != mine}
        if wrong:
            worker, version = next(iter(wrong.items()))
            raise StudyExecutionError(
                f"Dask worker {worker} has splinecontact {version}, this is {mine}; install "
                "the same code on every worker"
            )

    @property
    def workers(self) -> int:
        self._check_workers()
        return max(1, sum(self.client.nthreads().values()))

    def run(self, function: Callable[[T], R], tasks: Sequence[T]) -> Iterator[R | Lost]:
        from distributed import as_completed

        futures = {self.client.submit(function, task, pure=False): task for task in tasks}
        try:
            for future in as_completed(list(futures)):
                task = futures[future]
                try:
                    yield future.result()
                except Exception as exc:
                    yield Lost(task, _one_line(exc))
                future.release()
        finally:
            self.client.cancel(list(futures))

    def close(self) -> None:
        if self._own:
            self.client.close()


def make_executor(workers: int | None = None, scheduler: Any = None) -> Executor:
    """A :class:`DaskExecutor` for ``scheduler`` if given, else a :class:`LocalExecutor`."""
    return LocalExecutor(workers) if scheduler is None else DaskExecutor(scheduler)
