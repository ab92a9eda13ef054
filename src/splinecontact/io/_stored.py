"""Metadata stored by :func:`splinecontact.io.write_profile`, checked before it is trusted.

A file written by ``write_profile`` carries a JSON object ``{"units": {...},
"profile_metadata": {...}}``. Anything else found there (a damaged or hostile file) is refused
with :class:`~splinecontact.io.CorruptFileError` naming the key, never passed on.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import CorruptFileError

__all__ = ["MAX_STORED_CHARS", "check_stored_metadata", "parse_stored_metadata"]

#: Longest stored metadata text accepted [characters].
MAX_STORED_CHARS = 4_000_000


def _damaged(path: Path, where: str, what: str) -> CorruptFileError:
    return CorruptFileError(
        f"{path}: the splinecontact metadata in {where} is damaged ({what}); remove it to read "
        "the data alone, or write the file again"
    )


def parse_stored_metadata(path: Path, text: str, *, where: str) -> dict[str, Any]:
    """Parse and check the JSON text of stored metadata."""
    if len(text) > MAX_STORED_CHARS:
        raise _damaged(path, where, f"{len(text):,} characters")
    try:
        loaded = json.loads(text)
    except (ValueError, RecursionError) as exc:  # JSONDecodeError is a ValueError
        raise _damaged(path, where, f"not valid JSON: {str(exc)[:80]}") from None
    return check_stored_metadata(path, loaded, where=where)


def _check_steps(path: Path, steps: object, where: str) -> None:
    if not isinstance(steps, list):
        raise _damaged(path, where, f"'preprocessing' is {str(steps)[:40]!r}, not a list of steps")
    for k, step in enumerate(steps):
        if not isinstance(step, Mapping) or not isinstance(step.get("step"), str):
            raise _damaged(
                path, where, f"preprocessing step {k} is {str(step)[:40]!r}, not a step record"
            )


def check_stored_metadata(path: Path, loaded: object, *, where: str) -> dict[str, Any]:
    """Check the structure of stored metadata (a dict with ``units`` and ``profile_metadata``)."""
    if not isinstance(loaded, dict):
        raise _damaged(path, where, f"a {type(loaded).__name__}, not an object")
    units = loaded.get("units")
    if units is not None and not (
        isinstance(units, dict) and all(isinstance(v, str) for v in units.values())
    ):
        raise _damaged(path, where, f"'units' is {str(units)[:40]!r}")
    inner = loaded.get("profile_metadata", loaded)
    if not isinstance(inner, dict):
        raise _damaged(path, where, f"'profile_metadata' is {str(inner)[:40]!r}, not an object")
    if "preprocessing" in inner:
        _check_steps(path, inner["preprocessing"], where)
    return loaded
