"""Text readers: column tables (x, z[, valid]), one column of heights, Bruker Dektak CSV.

A table is a block of header lines (titles, units) followed by rows of numbers separated by
one delimiter: semicolon, comma, or white space (tabs and spaces). Units come from the column
titles (``x [mm]``, ``z (nm)``, ``Lateral um``, ``[mm];[mm];[1/0]`` on a line of their own) or
from the caller. Undefined values (``nan``, ``bad``, ``invalid``, empty fields) become NaN; a
column titled ``valid`` flags each point (``1`` valid, ``0`` undefined).
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..preprocess import RawProfile
from ._errors import (
    EmptyFileError,
    MalformedRowError,
    MissingSpacingError,
    MissingUnitsError,
    NoDataError,
    ReadOptionError,
    UnitError,
)
from ._units import UNIT_FACTORS, normalize_unit, unit_in_text

__all__ = ["METADATA_COMMENT", "decode_text", "is_dektak", "read_dektak", "read_table"]

#: Comment prefix under which :func:`splinecontact.io.write_profile` stores metadata as JSON.
METADATA_COMMENT = "# splinecontact-metadata:"

_MISSING = {
    "",
    "nan",
    "-nan",
    "+nan",
    "bad",
    "invalid",
    "na",
    "n/a",
    "-",
    "--",
    "*",
    "none",
    "null",
}
_COMMENT_PREFIXES = ("#", "%", "//", "!")
_X_NAMES = ("x", "lateral", "position", "distance", "length", "scan position")
_Z_NAMES = ("z", "y", "height", "profile", "total profile", "raw", "altitude", "h", "normal")
_VALID_NAMES = ("valid", "validity", "mask", "valid point", "valid points")
_INVALID_NAMES = ("invalid", "bad")
_DELIMITER_NAMES = {";": "semicolon", ",": "comma", None: "white space"}


def decode_text(data: bytes) -> str:
    """Decode a text file: UTF-8 (with or without BOM), else Windows-1252 (old exports)."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1252", errors="replace")


def _is_comment(stripped: str) -> bool:
    return stripped.startswith(_COMMENT_PREFIXES)


def _delimiter_of(line: str) -> str | None:
    """Semicolon, else white space if the line has a tab, else comma, else white space."""
    if ";" in line:
        return ";"
    if "\t" in line:
        return None
    if "," in line:
        return ","
    return None


def _split(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    parts = [p.strip() for p in line.split(delimiter)]
    while parts and parts[-1] == "":  # trailing delimiters (Dektak exports end rows with ",,")
        parts.pop()
    return parts


def _split_titles(line: str, delimiter: str | None) -> list[str]:
    """Split a title line; with white space, keep ``x [mm]`` or ``z (nm)`` together."""
    if delimiter is not None:
        return _split(line, delimiter)
    return re.findall(r"[^\s\[(]+(?:\s*[\[(][^\])]*[\])])?|[\[(][^\])]*[\])]", line)


def _number(token: str, delimiter: str | None) -> float | None:
    """Value of a data token; NaN for an undefined marker; None if it is not a number."""
    if delimiter != "," and "," in token and "." not in token:
        token = token.replace(",", ".")  # decimal comma
    try:
        return float(token)
    except ValueError:
        if token.strip().lower() in _MISSING:
            return float("nan")
        return None


def _resolution(token: str) -> float:
    """One unit of the last printed decimal of a number token (``0.0125`` -> 1e-4)."""
    mantissa, _, exponent = token.strip().lower().lstrip("+-").partition("e")
    try:
        power = int(exponent) if exponent else 0
    except ValueError:
        return 0.0
    decimals = len(mantissa.split(".", 1)[1]) if "." in mantissa else 0
    return float(10.0 ** (power - decimals))


def _is_data_line(tokens: Sequence[str], delimiter: str | None) -> bool:
    if not tokens:
        return False
    values = [_number(t, delimiter) for t in tokens]
    if any(v is None for v in values):
        return False
    return any(_plain_float(t, delimiter) for t in tokens)


def _plain_float(token: str, delimiter: str | None) -> bool:
    if delimiter != "," and "," in token and "." not in token:
        token = token.replace(",", ".")
    try:
        float(token)
    except ValueError:
        return False
    return True


@dataclass(frozen=True)
class _Column:
    title: str
    name: str
    unit: str | None
    raw_unit: str | None
    title_line: int | None


@dataclass(frozen=True)
class _Table:
    values: NDArray[np.float64]  # (n_rows, n_columns)
    rows: NDArray[np.int64]  # 1-based line number of each row
    columns: list[_Column]
    delimiter: str | None
    header: list[tuple[int, str]]  # (line number, text) of the header block
    comments: list[str]
    column_resolution: list[float]  # finest printed step of each column (file units; 0: none)


def _parse_table(
    path: Path, lines: Sequence[str], first_line: int = 1, *, delimiter: str | None = None
) -> _Table:
    """Parse a header block and rows of numbers. ``first_line`` numbers ``lines[0]``."""
    header: list[tuple[int, str]] = []
    comments: list[str] = []
    start = None
    for k, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if _is_comment(stripped):
            comments.append(stripped)
            continue
        delim = delimiter if delimiter is not None else _delimiter_of(stripped)
        if _is_data_line(_split(stripped, delim), delim):
            start = k
            delimiter = delim
            break
        header.append((first_line + k, stripped))
    if start is None:
        if header:
            last_no, last = header[-1]
            raise NoDataError(
                f"{path}: no rows of numbers after {len(header)} header line(s) (last header "
                f"line {last_no}: {last[:60]!r}); the file has a header but no data — export "
                "the scan again with its data"
            )
        raise EmptyFileError(f"{path}: the file has only comments or blank lines, no data")

    first_tokens = _split(lines[start].strip(), delimiter)
    n_columns = len(first_tokens)
    values: list[list[float]] = []
    rows: list[int] = []
    resolution = [0.0] * n_columns
    start_no = first_line + start
    for k in range(start, len(lines)):
        stripped = lines[k].strip()
        if not stripped or _is_comment(stripped):
            if stripped:
                comments.append(stripped)
            continue
        line_no = first_line + k
        tokens = _split(stripped, delimiter)
        if len(tokens) != n_columns:
            other = [d for d in (";", ",", "\t") if d in stripped and d != delimiter]
            if other and (delimiter is not None or other != ["\t"]):
                used = "tab" if other[0] == "\t" else repr(other[0])
                raise MalformedRowError(
                    f"{path}, line {line_no}: the row uses {used} but the data starting on "
                    f"line {start_no} is separated by {_DELIMITER_NAMES[delimiter]}; the file "
                    "mixes delimiters — use one delimiter throughout"
                )
            raise MalformedRowError(
                f"{path}, line {line_no}: {len(tokens)} column(s) but the data starting on "
                f"line {start_no} has {n_columns} ({stripped[:60]!r}); fix or remove this row"
            )
        row: list[float] = []
        for c, token in enumerate(tokens):
            value = _number(token, delimiter)
            if value is None:
                raise MalformedRowError(
                    f"{path}, line {line_no}, column {c + 1}: {token[:40]!r} is not a number "
                    "(undefined points may be written as nan, bad or left empty); fix or "
                    "remove this row"
                )
            row.append(value)
            if value == value and value != 0.0:  # finest printed step of non-zero numbers
                step = _resolution(token)
                resolution[c] = step if resolution[c] == 0.0 else min(resolution[c], step)
        values.append(row)
        rows.append(line_no)

    columns = _columns(path, header, n_columns, delimiter)
    return _Table(
        values=np.asarray(values, dtype=np.float64).reshape(len(values), n_columns),
        rows=np.asarray(rows, dtype=np.int64),
        columns=columns,
        delimiter=delimiter,
        header=header,
        comments=comments,
        column_resolution=resolution,
    )


def _columns(
    path: Path, header: Sequence[tuple[int, str]], n_columns: int, delimiter: str | None
) -> list[_Column]:
    """Titles and units of the columns from the last (up to two) header lines that fit."""
    fitting: list[tuple[int, list[str]]] = []
    for line_no, text in reversed(header):
        titles = _split_titles(text, delimiter)
        if len(titles) != n_columns:
            break
        fitting.insert(0, (line_no, titles))
        if len(fitting) == 2:
            break
    columns = []
    for c in range(n_columns):
        name, unit, raw_unit, title, title_line = "", None, None, "", None
        for line_no, titles in fitting:
            found, raw = unit_in_text(titles[c])
            if raw is not None and raw_unit is None:
                unit, raw_unit, title_line = found, raw, line_no
            bare = re.sub(r"[\[(][^\])]*[\])]", "", titles[c]).strip()
            if found is not None and raw is not None and bare.endswith(raw):
                bare = bare[: -len(raw)].rstrip(" /_")
            if bare and not name:
                name = bare
            title = f"{title} {titles[c]}".strip()
        columns.append(_Column(title, name.strip(" ,;:").lower(), unit, raw_unit, title_line))
    return columns


def _pick(columns: Sequence[_Column], names: Sequence[str], exclude: set[int]) -> int | None:
    for wanted in names:
        for c, column in enumerate(columns):
            if c not in exclude and (column.name == wanted or column.name.startswith(wanted + " ")):
                return c
    return None


def _resolve_unit(
    path: Path,
    column: _Column | None,
    given: str | None,
    what: str,
    option: str,
) -> tuple[str, str]:
    """Unit of one column: the header's, else the caller's; refuse conflicts and absence."""
    header_unit = None
    if column is not None and column.raw_unit is not None:
        if column.unit is None:
            raise UnitError(
                f"{path}, line {column.title_line}: the {what} column's unit {column.raw_unit!r} "
                f"is not a length unit; use one of {', '.join(UNIT_FACTORS)} in the header"
            )
        header_unit = column.unit
    given_unit = normalize_unit(given, what=f"{option}=") if given is not None else None
    if header_unit is not None and given_unit is not None and header_unit != given_unit:
        raise UnitError(
            f"{path}: the header gives the {what} in {header_unit} but {option}={given!r} was "
            f"passed; drop {option}= to use the header's unit (or correct the header)"
        )
    if header_unit is not None:
        return header_unit, "header"
    if given_unit is not None:
        return given_unit, "argument"
    raise MissingUnitsError(
        f"{path}: the file does not say in which unit the {what} are; pass {option}= "
        f"(one of {', '.join(UNIT_FACTORS)}; CLI --{option.replace('_', '-')})"
    )


def _stored_metadata(comments: Sequence[str]) -> dict[str, Any] | None:
    for comment in comments:
        if comment.startswith(METADATA_COMMENT):
            try:
                loaded = json.loads(comment[len(METADATA_COMMENT) :])
            except json.JSONDecodeError:
                return None
            return loaded if isinstance(loaded, dict) else None
    return None


def _table_to_raw(
    path: Path,
    table: _Table,
    *,
    fmt: str,
    unit: str | None,
    height_unit: str | None,
    spacing: float | None,
    extra: dict[str, Any] | None = None,
) -> RawProfile:
    columns = table.columns
    n_columns = len(columns)
    valid_col = _pick(columns, _VALID_NAMES, set())
    invalid_col = _pick(columns, _INVALID_NAMES, set()) if valid_col is None else None
    flag_col = valid_col if valid_col is not None else invalid_col
    used = {flag_col} if flag_col is not None else set()
    data_columns = [c for c in range(n_columns) if c not in used]

    metadata: dict[str, Any] = {"source": str(path), "format": fmt}
    if extra:
        metadata.update(extra)
    if table.header:
        metadata["header_lines"] = len(table.header)
    metadata["delimiter"] = _DELIMITER_NAMES[table.delimiter]

    if len(data_columns) == 1:  # heights only
        z_col = data_columns[0]
        if spacing is None:
            raise MissingSpacingError(
                f"{path}: one column of heights and no positions; pass the grid spacing "
                "spacing= [µm] (CLI --spacing)"
            )
        if not (np.isfinite(spacing) and spacing > 0):
            raise ReadOptionError(f"{path}: spacing={spacing!r} µm must be positive")
        z_unit, z_from = _resolve_unit(
            path,
            columns[z_col],
            height_unit or unit,
            "heights",
            "height_unit" if height_unit else "unit",
        )
        x = np.arange(table.values.shape[0], dtype=np.float64) * spacing
        x_unit, x_from, x_factor, x_resolution = "µm", "argument spacing", 1.0, 0.0
        metadata["spacing_um"] = float(spacing)
    else:
        if spacing is not None:
            raise ReadOptionError(
                f"{path}: spacing= is only for files with one column of heights, but this "
                f"file has {len(data_columns)} data columns (x is the first); drop spacing="
            )
        picked_x = _pick(columns, _X_NAMES, used)
        x_col = data_columns[0] if picked_x is None else picked_x
        picked_z = _pick(columns, _Z_NAMES, used | {x_col})
        z_col = next(c for c in data_columns if c != x_col) if picked_z is None else picked_z
        x_unit, x_from = _resolve_unit(path, columns[x_col], unit, "positions (x)", "unit")
        z_unit, z_from = _resolve_unit(
            path,
            columns[z_col],
            height_unit if height_unit is not None else unit,
            "heights (z)",
            "height_unit" if height_unit is not None else "unit",
        )
        x_factor = UNIT_FACTORS[x_unit]
        x = table.values[:, x_col] * x_factor
        x_resolution = table.column_resolution[x_col] * x_factor
        ignored = [
            columns[c].title or f"column {c + 1}" for c in data_columns if c not in (x_col, z_col)
        ]
        if ignored:
            metadata["ignored_columns"] = ignored
        metadata["x_column"] = columns[x_col].title or f"column {x_col + 1}"
    metadata["z_column"] = columns[z_col].title or f"column {z_col + 1}"
    z_factor = UNIT_FACTORS[z_unit]
    z = table.values[:, z_col] * z_factor

    n_flagged = 0
    if flag_col is not None:
        flags = table.values[:, flag_col]
        undefined = (flags == 0) if flag_col == valid_col else (flags != 0)
        undefined |= ~np.isfinite(flags)
        n_flagged = int(undefined.sum())
        z = np.where(undefined, np.nan, z)
        metadata["validity_column"] = columns[flag_col].title
    metadata["n_flagged_invalid"] = n_flagged
    metadata["units"] = {
        "x": x_unit,
        "z": z_unit,
        "x_from": x_from,
        "z_from": z_from,
        "x_factor_to_um": x_factor,
        "z_factor_to_um": z_factor,
    }
    stored = _stored_metadata(table.comments)
    if stored is not None:
        metadata["stored_metadata"] = stored.get("profile_metadata", stored)
    return RawProfile(x, z, rows=table.rows, x_resolution=x_resolution, metadata=metadata)


def _lines_or_empty(path: Path, text: str) -> list[str]:
    lines = text.splitlines()
    if not any(line.strip() for line in lines):
        raise EmptyFileError(f"{path}: the file is empty; nothing to read — export the scan again")
    return lines


def read_table(
    path: Path,
    text: str,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    fmt: str = "table",
) -> RawProfile:
    """Read a text table (x, z[, valid]) or one column of heights.

    Parameters
    ----------
    path : Path
        The file (for messages and metadata).
    text : str
        Its decoded content.
    unit, height_unit : str, optional
        Units of positions and heights when the header gives none (``height_unit`` defaults
        to ``unit``).
    spacing : float, optional
        Grid spacing [µm] for a file of heights only.
    """
    lines = _lines_or_empty(path, text)
    table = _parse_table(path, lines)
    return _table_to_raw(path, table, fmt=fmt, unit=unit, height_unit=height_unit, spacing=spacing)


def is_dektak(text: str) -> bool:
    """Whether a text has the "Scan Data" section of a Bruker Dektak CSV export."""
    return _scan_data_line(text.splitlines()) is not None


def _scan_data_line(lines: Sequence[str]) -> int | None:
    for k, line in enumerate(lines):
        if line.split(",", 1)[0].strip().lower() == "scan data":
            return k
    return None


def read_dektak(
    path: Path,
    text: str,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
) -> RawProfile:
    """Read a Bruker Dektak CSV export.

    The file has blocks of ``key,value[,unit]`` lines (scan parameters, analytical results),
    then a line ``Scan Data``, a title line such as ``Lateral um,Total Profile Å`` and rows of
    comma-separated numbers (trailing empty fields are ignored). The lateral column is ``x``;
    the first other column is the height. The scan parameters are kept in the metadata under
    ``instrument_parameters``.
    """
    lines = _lines_or_empty(path, text)
    k = _scan_data_line(lines)
    if k is None:  # pragma: no cover - callers check is_dektak first
        raise NoDataError(f"{path}: no 'Scan Data' section; not a Dektak CSV export")
    parameters: dict[str, str] = {}
    for line in lines[:k]:
        parts = [p.strip() for p in line.split(",")]
        parts = [p for p in parts if p]
        if len(parts) >= 2 and len(parameters) < 200:
            parameters.setdefault(parts[0], " ".join(parts[1:]))
    table = _parse_table(path, lines[k + 1 :], first_line=k + 2, delimiter=",")
    return _table_to_raw(
        path,
        table,
        fmt="dektak",
        unit=unit,
        height_unit=height_unit,
        spacing=None,
        extra={"instrument_parameters": parameters} if parameters else None,
    )
