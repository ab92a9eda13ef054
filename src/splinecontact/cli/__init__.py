"""The ``splinecontact`` command line (typer).

Each group of commands lives in its own module with a ``register(app)`` function; this module
assembles them and provides :func:`main`, the console-script entry point. The command modules
import numpy, numba, scipy, xarray and matplotlib only inside the commands, so ``--help``,
``--version`` and option errors answer at once.
"""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from ..errors import SplineContactError
from . import _analysis, _citation, _compare, _engine, _friction, _law, _measured, _study
from ._citation import version_text

__all__ = ["app", "main"]

#: The typer application holding every ``splinecontact`` command (``main`` runs it).
app = typer.Typer(
    name="splinecontact",
    help=(
        "Contact mechanics of rough surfaces by spline assisted discretization (SAD). "
        "Units: lengths µm, moduli GPa, forces mN per µm of thickness."
    ),
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
    rich_markup_mode=None,  # plain help: rich formatting alone costs 0.15 s per call
)


def _print_version(value: bool) -> None:
    if value:
        typer.echo(version_text())
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            callback=_print_version,
            is_eager=True,
            help="Print the package version and exit.",
        ),
    ] = False,
) -> None:
    """Contact mechanics of rough surfaces by spline assisted discretization (SAD).

    Units: lengths µm, moduli GPa, forces mN per µm of thickness.
    """


for _module in (_engine, _measured, _study, _analysis, _compare, _friction, _law, _citation):
    _module.register(app)


def main() -> None:
    """Console-script entry point: run the app, turning expected errors into one line."""
    try:
        app()
    except SplineContactError as exc:  # safety net; commands use handle_errors themselves
        typer.secho(f"error: {type(exc).__name__}: {exc}", err=True, fg=typer.colors.RED)
        sys.exit(1)
    except MemoryError:
        typer.secho("error: MemoryError: out of memory; nothing was written", err=True,
                    fg=typer.colors.RED)  # fmt: skip
        sys.exit(1)
    except OSError as exc:
        typer.secho(f"error: {type(exc).__name__}: {exc}", err=True, fg=typer.colors.RED)
        sys.exit(1)
