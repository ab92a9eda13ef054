"""Size limits of the readers, checked before any allocation.

Every reader compares what a file *declares* (an X3P matrix size, a NumPy header's shape, a zip
member's uncompressed size) with what it holds and with a limit of points per file before it
allocates, and enforces the declared sizes again while it streams the data. Text files are read
line by line with a bound on the length of a line.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from ..errors import (
    CorruptFileError,
    FileTooLargeError,
    MissingSpacingError,
    ProfileReadError,
    ReadOptionError,
)

__all__ = [
    "DEFAULT_MAX_POINTS",
    "MAX_LINE_CHARS",
    "MAX_XML_BYTES",
    "check_max_points",
    "check_points",
    "one_line",
    "read_chunks",
    "read_exact",
    "required_spacing",
]

#: Points per file the readers accept by default (``max_points=`` raises it): 10⁸, far above
#: any line scan or row of a real areal scan, small enough to refuse bombs before allocating.
DEFAULT_MAX_POINTS = 100_000_000

#: Longest text line the table readers accept [characters] (a metadata comment written by
#: :func:`~splinecontact.io.write_profile` is well below this).
MAX_LINE_CHARS = 4_000_000

#: Largest ``main.xml`` of an X3P file [bytes] (real ones are a few kB).
MAX_XML_BYTES = 16 * 2**20

_CHUNK = 1 << 20


def one_line(exc: BaseException, limit: int = 120) -> str:
    """A library exception's message on one line, shortened (for wrapping it in ours)."""
    text = " ".join(str(exc).split())
    return text if len(text) <= limit else text[: limit - 1] + "…"


def check_max_points(max_points: object) -> int:
    """Validate the ``max_points=`` argument (a positive integer)."""
    if isinstance(max_points, bool) or not isinstance(max_points, numbers.Integral):
        raise ReadOptionError(f"max_points={max_points!r} must be a positive integer")
    value = int(max_points)
    if value < 1:
        raise ReadOptionError(f"max_points={max_points!r} must be a positive integer")
    return int(value)


def check_points(path: Path, n_points: int, max_points: int, what: str) -> None:
    """Refuse ``n_points`` (declared or counted) above ``max_points``."""
    if n_points > max_points:
        raise FileTooLargeError(
            f"{path}: {what} has {n_points:,} points, more than the limit of {max_points:,} "
            "points per file; if the scan is genuine, pass a larger max_points= to read_profile"
        )


def required_spacing(path: Path, spacing: float | None, missing: str) -> float:
    """The grid spacing [µm] that heights without positions need, checked.

    Raises
    ------
    MissingSpacingError
        ``spacing`` is None; the message is ``missing`` (what the file lacks) and the option.
    ReadOptionError
        ``spacing`` is not a positive finite length.
    """
    if spacing is None:
        raise MissingSpacingError(
            f"{path}: {missing}; pass the grid spacing spacing= [µm] (CLI --spacing)"
        )
    if not (math.isfinite(spacing) and spacing > 0):
        raise ReadOptionError(f"{path}: spacing={spacing!r} µm must be positive")
    return spacing


def read_chunks(
    path: Path,
    stream: IO[bytes],
    size: int,
    what: str,
    *,
    error: type[ProfileReadError] = CorruptFileError,
    declared: str = "declared",
) -> Iterator[bytes]:
    """Yield exactly ``size`` bytes of a stream that must end there, in chunks; refuse anything
    else with ``error`` (the excess message says the size was ``declared``).

    A member whose declared size lies (a zip bomb) is refused after at most ``size`` + 1 bytes.
    Reading the end of a zip member also checks its CRC.
    """
    got = 0
    while got < size:
        chunk = stream.read(min(_CHUNK, size - got))
        if not chunk:
            raise error(
                f"{path}: {what} ends after {got:,} bytes but {size:,} were declared; the file "
                "is truncated or damaged"
            )
        yield chunk
        got += len(chunk)
    if stream.read(1):
        raise error(
            f"{path}: {what} holds more than the {size:,} bytes {declared}; the file is damaged "
            "or forged"
        )


def read_exact(path: Path, stream: IO[bytes], size: int, what: str) -> bytes:
    """Read exactly ``size`` bytes from a stream that must end there (:func:`read_chunks`)."""
    return b"".join(read_chunks(path, stream, size, what))
