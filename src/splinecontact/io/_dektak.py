"""Bruker Dektak CSV exports: a block of scan parameters, a ``Scan Data`` line, then a table."""

from __future__ import annotations

from pathlib import Path

from ..errors import NoDataError
from ..preprocess import RawProfile
from ._limits import DEFAULT_MAX_POINTS
from ._lines import iter_lines
from ._text import _parse_table, _table_to_raw

__all__ = ["is_dektak", "read_dektak"]

#: Lines searched for the "Scan Data" line of a Dektak export.
_DEKTAK_SCAN_LINES = 10_000


def _is_scan_data(line: str) -> bool:
    return line.split(",", 1)[0].strip().lower() == "scan data"


def is_dektak(path: Path) -> bool:
    """Whether a text file has the "Scan Data" line of a Bruker Dektak CSV export.

    Only the first lines are searched (the parameter block of an export is short).
    """
    lines = iter_lines(path)
    try:
        for line_no, line in lines:
            if _is_scan_data(line):
                return True
            if line_no >= _DEKTAK_SCAN_LINES:
                return False
    finally:
        lines.close()
    return False


def read_dektak(
    path: Path,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> RawProfile:
    """Read a Bruker Dektak CSV export.

    The file has blocks of ``key,value[,unit]`` lines (scan parameters, analytical results),
    then a line ``Scan Data``, a title line such as ``Lateral um,Total Profile Å`` and rows of
    comma-separated numbers (trailing empty fields are ignored). The lateral column is ``x``;
    the first other column is the height. The scan parameters are kept in the metadata under
    ``instrument_parameters``.
    """
    lines = iter_lines(path)
    try:
        parameters: dict[str, str] = {}
        found = False
        for line_no, line in lines:
            if _is_scan_data(line):
                found = True
                break
            if line_no >= _DEKTAK_SCAN_LINES:
                break
            parts = [p.strip() for p in line.split(",")]
            parts = [p for p in parts if p]
            if len(parts) >= 2 and len(parameters) < 200:
                parameters.setdefault(parts[0][:200], " ".join(parts[1:])[:200])
        if not found:
            raise NoDataError(
                f"{path}: no 'Scan Data' line; not a Dektak CSV export (try format='table')"
            )
        table = _parse_table(path, lines, delimiter=",", max_points=max_points)
    finally:
        lines.close()
    return _table_to_raw(
        path,
        table,
        fmt="dektak",
        unit=unit,
        height_unit=height_unit,
        spacing=None,
        extra={"instrument_parameters": parameters} if parameters else None,
    )
