"""The ``splinecontact`` command line (typer).

Each group of commands lives in its own module with a ``register(app)`` function; this module
assembles them and provides :func:`main`, the console-script entry point.
"""

from __future__ import annotations

import sys

import typer

from ..errors import SplineContactError
from . import _analysis, _citation, _compare, _engine, _friction, _measured, _study

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
)

for _module in (_engine, _measured, _study, _analysis, _compare, _friction, _citation):
    _module.register(app)


def main() -> None:
    """Console-script entry point: run the app, turning expected errors into one line."""
    try:
        app()
    except SplineContactError as exc:  # safety net; commands use handle_errors themselves
        typer.secho(f"error: {type(exc).__name__}: {exc}", err=True, fg=typer.colors.RED)
        sys.exit(1)
