"""The command line's one error line: :func:`fail`, :func:`warn`, :func:`handle_errors`.

It is imported by ``splinecontact --help``, so it must stay light: numpy, the readers, the
generator (numba) and the solvers are imported inside the functions that use them.
"""

from __future__ import annotations

import contextlib
import functools
import io
import os
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from typing import ParamSpec, TypeVar

import typer

from ..errors import SplineContactError

P = ParamSpec("P")
T = TypeVar("T")

__all__ = ["fail", "handle_errors", "note", "warn"]


def fail(message: str, code: int = 1) -> typer.Exit:
    """Print ``error: message`` on standard error and return the ``typer.Exit`` to raise."""
    typer.secho(f"error: {message}", err=True, fg=typer.colors.RED)
    return typer.Exit(code)


def warn(message: str) -> None:
    """Print ``warning: message`` on standard error."""
    typer.secho(f"warning: {message}", err=True, fg=typer.colors.YELLOW)


def note(*messages: str) -> None:
    """Print ``note: message`` on standard error, one line each (seeds drawn, bodies made)."""
    for message in messages:
        typer.echo(f"note: {message}", err=True)


@contextlib.contextmanager
def _native_stderr_held() -> Iterator[list[bytes]]:
    """Send what native code (LAPACK, numba) writes to file descriptor 2 to a temporary file.

    Python's own ``sys.stderr`` keeps writing to the terminal (through a duplicate of the
    descriptor), so progress lines still appear at once. The held bytes are put in the yielded
    list when the block ends; the caller decides whether to show them (success) or not (an
    error, which must be one line). Does nothing when ``sys.stderr`` is not descriptor 2 (tests).
    """
    held: list[bytes] = []
    try:
        if sys.stderr is None or sys.stderr.fileno() != 2:
            raise ValueError
    except (AttributeError, ValueError, OSError, io.UnsupportedOperation):
        yield held
        return
    sys.stderr.flush()
    saved = os.dup(2)
    spool = tempfile.TemporaryFile()
    old_stderr = sys.stderr
    replacement = io.TextIOWrapper(
        open(os.dup(saved), "wb", buffering=0),  # closed with it in the finally below
        encoding=old_stderr.encoding or "utf-8",
        errors="backslashreplace",
        line_buffering=True,
        write_through=True,
    )
    os.dup2(spool.fileno(), 2)
    sys.stderr = replacement
    try:
        yield held
    finally:
        with contextlib.suppress(OSError, ValueError):
            replacement.flush()
        sys.stderr = old_stderr
        os.dup2(saved, 2)
        os.close(saved)
        replacement.close()
        spool.seek(0)
        held.append(spool.read())
        spool.close()


# The library's errors name its keyword arguments; on the command line the same ceilings are
# raised with options.
_CLI_HINTS = (
    ("pass a larger max_points= to read_profile", "pass a larger --max-points"),
    ("pass max_points= to allow more", "pass --max-points to allow more"),
    ("raise Preprocessing.max_points", "raise it with --max-points"),
    ("pass max_steps= to allow more", "pass --max-steps to allow more"),
)


def _cli_hints(text: str) -> str:
    for api, cli in _CLI_HINTS:
        text = text.replace(api, cli)
    return text


def handle_errors(func: Callable[P, T]) -> Callable[P, T]:
    """Decorate a command: expected errors become exactly one line on stderr and exit code 1.

    Expected errors are :class:`SplineContactError`, operating-system errors of file handling
    (missing file, permission denied, disk full) and running out of memory. Warnings and native
    library chatter raised before such an error are dropped, so the error line is the only
    line; on success they are shown (warnings as ``warning: ...`` lines). Anything else is a
    bug and keeps its traceback.
    """

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> T:
        message: str | None = None
        with (
            _native_stderr_held() as native,
            warnings.catch_warnings(record=True) as caught,
        ):
            warnings.simplefilter("default")
            try:
                result = func(*args, **kwargs)
            except SplineContactError as exc:
                message = f"{type(exc).__name__}: {_cli_hints(str(exc))}"
            except MemoryError:
                message = (
                    "MemoryError: out of memory; use fewer points (n_points=, --crop, "
                    "--resample-spacing) or fewer --steps; nothing was written"
                )
            except OSError as exc:
                message = f"{type(exc).__name__}: {exc}"
        if message is not None:
            raise fail(" ".join(message.split())) from None
        if native and native[0]:
            sys.stderr.write(native[0].decode("utf-8", "backslashreplace"))
        seen: set[tuple[type, str]] = set()
        for item in caught:
            key = (item.category, str(item.message))
            if key in seen:
                continue
            seen.add(key)
            from ..diagnostics import SimulationWarning

            text = str(item.message)
            if not issubclass(item.category, SimulationWarning):
                text = f"{item.category.__name__}: {text}"
            warn(text)
        return result

    return wrapper
