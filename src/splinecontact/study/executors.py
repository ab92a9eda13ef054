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


def _init_worker(parent: int, barrier: Any = None) -> None:
    """Set up a pool worker: leave Ctrl-C to the main process, and die with it.

    The main process stops its workers when interrupted; if it is killed (``kill -9``) it
    cannot, so a watchdog thread ends the worker once its parent (``parent``, the pid of the
    main process, given explicitly in case it died while this worker was starting) is gone.
    ``barrier`` (a ``multiprocessing.Barrier`` of the pool's size, or None) is where the
    warm-up tasks of :meth:`LocalExecutor.warm_up` meet.
    """
    global _WARM_UP_BARRIER
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # this process is ours: reuse the previous realization's freed arrays without page faults
    from .._memory import retain_freed_memory

    retain_freed_memory()
    _WARM_UP_BARRIER = barrier

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="splinecontact-parent-watchdog", daemon=True).start()


#: In a pool worker: the barrier its warm-up task waits at (set by :func:`_init_worker`; a
#: per-process handle, never shared state within one process).
_WARM_UP_BARRIER: Any = None

#: Longest wait of a warm-up task for the other workers' [s]; past it each goes on alone.
_WARM_UP_TIMEOUT = 300.0


def _warm_up_task(function: Callable[[Any], Any], part: Any) -> None:
    """Run one part of a warm-up in a pool worker, then wait until every worker has run its part.

    Each worker takes exactly one warm-up task (a worker blocked here takes no other), so no
    worker starts real work before all the parts are done. A part that raises is ignored: a
    warm-up only saves time (what it prepares is otherwise prepared on first use).
    """
    with contextlib.suppress(Exception):  # an optimisation only: real work reports its errors
        if part is not None:
            function(part)
    barrier = _WARM_UP_BARRIER
    if barrier is not None:
        with contextlib.suppress(threading.BrokenBarrierError, RuntimeError):
            barrier.wait(_WARM_UP_TIMEOUT)


@contextlib.contextmanager
def _sigint_held() -> Iterator[None]:
    """Hold SIGINT back from the processes started in this block; main thread only.

    The main thread blocks SIGINT here (it is not ignored: a Ctrl-C that comes in the block is
    handled by another thread of this process or delivered when the block ends, never lost);
    a worker started here inherits the blocked signal, so one still importing prints no
    traceback, and ignores it from its initializer on. Where signals cannot be blocked (not
    POSIX) SIGINT is ignored in the block instead, as processes inherit that too.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            yield
        finally:
            signal.signal(signal.SIGINT, previous)
        return
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)


class LocalExecutor(Executor):
    """This process (one worker, or a single task), else a pool of ``workers`` processes.

    The pool is started by the first task (or :meth:`warm_up`) and kept for later calls of
    :meth:`run` and :meth:`submit` until :meth:`close`, so that work done after a study (its
    figures) runs in the processes the study has already started.
    """

    def __init__(self, workers: int | None = None) -> None:
        self._workers = _default_workers() if workers is None else workers
        self._pool: ProcessPoolExecutor | None = None
        self._barrier: Any = None

    @property
    def workers(self) -> int:
        return self._workers

    def _get_pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            context = multiprocessing.get_context("spawn")
            self._pool = ProcessPoolExecutor(
                max_workers=self._workers,
                mp_context=context,
                initializer=_init_worker,
                initargs=(os.getpid(), self._barrier),
            )
        return self._pool

    def warm_up(self, function: Callable[[T], Any], parts: Sequence[T]) -> bool:
        """Start the pool now and run ``function(part)`` once per part, each in its own worker.

        The workers wait for each other after their part (at most ``len(parts)`` parts, one
        per worker; workers beyond them wait without a part), so tasks submitted afterwards
        start only once every part is done. Used to share out the compilation of the numba
        kernels: each worker compiles some into the on-disk cache and loads the others from it,
        instead of every worker compiling all of them at once. Returns immediately; a part that
        fails is ignored. Does nothing (returns False) in this process or once the pool runs.
        """
        if self._workers < 2 or self._pool is not None or len(parts) > self._workers:
            return False
        context = multiprocessing.get_context("spawn")
        self._barrier = context.Barrier(self._workers)
        pool = self._get_pool()
        padded: list[Any] = [*parts, *([None] * (self._workers - len(parts)))]
        with _sigint_held():
            for part in padded:
                pool.submit(_warm_up_task, function, part)
        return True

    def submit(self, function: Callable[[T], R], task: T) -> Future[R]:
        """Run ``function(task)`` in a worker of the pool (in this process with one worker)."""
        if self._workers == 1:
            future: Future[R] = Future()
            try:
                future.set_result(function(task))
            except Exception as exc:
                future.set_exception(exc)
            return future
        with _sigint_held():
            return self._get_pool().submit(function, task)

    def run(self, function: Callable[[T], R], tasks: Sequence[T]) -> Iterator[R | Lost]:
        if self._workers == 1 or (len(tasks) <= 1 and self._pool is None):
            return (function(task) for task in tasks)
        return self._run_pool(function, tasks)

    def _run_pool(self, function: Callable[[T], R], tasks: Sequence[T]) -> Iterator[R | Lost]:
        pool = self._get_pool()
        finished = False
        try:
            # The workers are started by submit(): started with Ctrl-C held back, a worker still
            # importing when Ctrl-C comes prints no traceback (the main process handles it).
            with _sigint_held():
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
            if not finished:
                # Interrupted (Ctrl-C, an error while writing): stop now; running tasks are
                # lost (not stored, so run again) rather than waited for.
                self._terminate()

    def _terminate(self) -> None:
        pool, self._pool = self._pool, None
        if pool is None:
            return
        processes = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()

    def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=True)


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
