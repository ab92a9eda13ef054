"""Showing a study on a terminal (rich): the progress bar and the summary.

:func:`splinecontact.study.run_study` prints nothing; the command line (or a script) passes a
:class:`StudyProgressBar` as its ``progress`` callback and prints the returned summary with
:func:`print_summary`.
"""

from __future__ import annotations

from typing import Any

from .runner import StudyProgress, StudySummary

__all__ = ["StudyProgressBar", "print_summary"]


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
