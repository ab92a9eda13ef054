"""Shared helpers of the command-line interface: one clear error line instead of a traceback."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import ParamSpec, TypeVar

import typer

from ..errors import SplineContactError

P = ParamSpec("P")
T = TypeVar("T")

__all__ = ["fail", "handle_errors"]


def fail(message: str, code: int = 1) -> typer.Exit:
    """Print ``error: message`` on standard error and return the ``typer.Exit`` to raise."""
    typer.secho(f"error: {message}", err=True, fg=typer.colors.RED)
    return typer.Exit(code)


def handle_errors(func: Callable[P, T]) -> Callable[P, T]:
    """Decorate a command: expected errors become one line on stderr and exit code 1.

    Expected errors are :class:`SplineContactError` and the operating-system errors of file
    handling (missing file, permission denied, ...). Anything else is a bug and keeps its
    traceback.
    """

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> T:
        try:
            return func(*args, **kwargs)
        except SplineContactError as exc:
            raise fail(f"{type(exc).__name__}: {exc}") from None
        except OSError as exc:
            raise fail(f"{type(exc).__name__}: {exc}") from None

    return wrapper
