"""``splinecontact study``: run ensembles of simulations from a TOML study file, export them."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import typer

from ._common import fail, handle_errors

__all__ = ["register"]

study_app = typer.Typer(
    name="study",
    help="Ensembles over parameters × realizations (parallel, resumable, on Dask).",
    no_args_is_help=True,
)


@contextlib.contextmanager
def _dask_logs_quiet(active: bool = True) -> Iterator[None]:
    """Hold Dask's own log lines below ERROR while a study runs on the command line.

    A worker lost during a run that then completes makes ``distributed`` log "Couldn't gather N
    keys, rescheduling": the run's progress and summary (and the store) already say everything
    the user needs, and the command promises no other line. Errors still show.
    """
    import logging

    if not active:
        yield
        return
    import distributed  # noqa: F401  (configures its loggers on import: set ours after it)

    # distributed gives several of its loggers their own level and handler (no propagation),
    # so each one is held back, not only the parents
    names = [
        name
        for name in list(logging.root.manager.loggerDict)
        if name.split(".")[0] in ("distributed", "dask")
    ]
    loggers = [logging.getLogger(name) for name in sorted({"distributed", "dask", *names})]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(max(logger.getEffectiveLevel(), logging.ERROR))
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels, strict=True):
            logger.setLevel(level)


@study_app.command("run")
@handle_errors
def run(
    study_file: Annotated[Path, typer.Argument(help="Study file (TOML).")],
    out: Annotated[Path, typer.Option("-o", "--out", help="Zarr store to write (a directory).")],
    workers: Annotated[
        int | None,
        typer.Option(
            "--workers", min=1, help="Local worker processes (default: the cores available)."
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="Address of a Dask distributed scheduler, e.g. tcp://10.0.0.1:8786.",
        ),
    ] = None,
    batch_size: Annotated[
        int | None,
        typer.Option("--batch-size", min=1, help="Realizations per task (default: automatic)."),
    ] = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No progress bar, no summary.")
    ] = False,
    overwrite: Annotated[
        bool,
        typer.Option(
            "--overwrite",
            help="Discard an existing study store of a different study (only a study store; "
            "see docs/outputs.md).",
        ),
    ] = False,
    limit: Annotated[
        list[str] | None,
        typer.Option(
            "--limit",
            metavar="NAME=VALUE",
            help="Raise a size ceiling (steps, points_terms, grid_points, realizations, "
            "realization_points, stored_values); repeatable.",
        ),
    ] = None,
) -> None:
    """Run a study, or continue it where it stopped (same command, same store).

    Exit status: 0 when every realization has run (failed realizations are results, listed
    in the summary and recorded in the store), 1 on an error, 130 when interrupted.
    """
    from ..study import StudyExecutionError, StudyLimits, StudyProgressBar, print_summary, run_study

    if scheduler is not None and workers is not None:
        raise fail(
            "--workers sets the local worker processes, --scheduler sends the work to a Dask "
            "cluster's workers instead; give one of them"
        )
    limits = StudyLimits.parse(limit or [])
    bar = None if quiet else StudyProgressBar()
    try:
        with (
            _dask_logs_quiet(scheduler is not None),
            bar if bar is not None else contextlib.nullcontext(),
        ):
            summary = run_study(
                study_file,
                out,
                workers=workers,
                scheduler=scheduler,
                batch_size=batch_size,
                progress=bar,
                overwrite=overwrite,
                limits=limits,
            )
    except StudyExecutionError as exc:
        if bar is not None and exc.summary is not None:
            print_summary(exc.summary)
        raise
    except KeyboardInterrupt:
        raise fail(
            f"interrupted; everything finished is stored in {out}: run the same command "
            "again to continue",
            code=130,
        ) from None
    if bar is not None:
        print_summary(summary)


@study_app.command("export")
@handle_errors
def export(
    store: Annotated[Path, typer.Argument(help="Study store written by `study run`.")],
    netcdf: Annotated[Path, typer.Option("--netcdf", help="netCDF-4 file to write.")],
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="Replace the netCDF file if it exists.")
    ] = False,
) -> None:
    """Write a study store as one netCDF-4 file (written whole, then renamed into place)."""
    from ..study import export_netcdf

    export_netcdf(store, netcdf, overwrite=overwrite)


def register(app: typer.Typer) -> None:
    """Add the ``study`` command group to ``app``."""
    app.add_typer(study_app, name="study")
