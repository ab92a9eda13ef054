"""Text tables: column tables (x, z[, valid]) and one column of heights.

A table is a block of header lines (titles, units) followed by rows of numbers separated by
one delimiter: semicolon, comma, or white space (tabs and spaces). Units come from the column
titles (``x [mm]``, ``z (nm)``, ``Lateral um``, ``[mm];[mm];[1/0]`` on a line of their own) or
from the caller. Undefined values (``nan``, ``bad``, ``invalid``, empty fields) become NaN; a
column titled ``valid`` flags each point (``1`` valid, ``0`` undefined).

Untrusted files: the file is read line by line (no line may exceed ``MAX_LINE_CHARS``), rows are
stored as packed floats and counted against the limit of points per file as they come, and every
header and unit parser is a single left-to-right scan (no backtracking regular expression), so
the time is linear in the size of the file and the memory bounded by the limit.
"""

from __future__ import annotations

import array
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import (
    EmptyFileError,
    FileTooLargeError,
    LineSelectionError,
    MalformedRowError,
    MissingUnitsError,
    NoDataError,
    ReadOptionError,
    UnitError,
)
from ..preprocess import RawProfile
from ._limits import DEFAULT_MAX_POINTS, check_points, required_spacing
from ._lines import iter_lines
from ._tokens import (
    _delimiter_of,
    _is_comment,
    _is_data_line,
    _number,
    _overflows,
    _resolution,
    _split,
    _split_titles,
)
from ._units import UNIT_FACTORS, normalize_unit, strip_bracketed, unit_in_text, units_record

__all__ = ["METADATA_COMMENT", "read_table"]

#: Comment prefix under which :func:`splinecontact.io.write_profile` stores metadata as JSON.
METADATA_COMMENT = "# splinecontact-metadata:"

_X_NAMES = ("x", "lateral", "position", "distance", "length", "scan position")
_Z_NAMES = ("z", "y", "height", "profile", "total profile", "raw", "altitude", "h", "normal")
_VALID_NAMES = ("valid", "validity", "mask", "valid point", "valid points")
_INVALID_NAMES = ("invalid", "bad")
_DELIMITER_NAMES = {";": "semicolon", ",": "comma", None: "white space"}
#: Header lines (titles, parameters) accepted before the first row of numbers.
_MAX_HEADER_LINES = 10_000


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
    header: list[tuple[int, str]]  # (line number, text) of the last header lines (up to 2)
    n_header: int  # number of header lines
    stored: str | None  # JSON text of the first metadata comment
    column_resolution: list[float]  # finest printed step of each column (file units; 0: none)


def _parse_table(
    path: Path,
    lines: Iterable[tuple[int, str]],
    *,
    delimiter: str | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> _Table:
    """Parse a header block and rows of numbers from ``(line number, text)`` pairs.

    Only the last two header lines and the first metadata comment are kept; rows go into
    packed arrays and are counted against ``max_points`` as they are read.
    """
    header: list[tuple[int, str]] = []
    n_header = 0
    stored: str | None = None
    seen_comment = False
    first: tuple[int, list[str]] | None = None
    iterator = iter(lines)

    def comment(text: str) -> None:
        nonlocal stored
        if stored is None and text.startswith(METADATA_COMMENT):
            stored = text[len(METADATA_COMMENT) :]

    for line_no, line in iterator:
        stripped = line.strip()
        if not stripped:
            continue
        if _is_comment(stripped):
            seen_comment = True
            comment(stripped)
            continue
        delim = delimiter if delimiter is not None else _delimiter_of(stripped)
        tokens = _split(stripped, delim)
        if _is_data_line(tokens, delim):
            first = (line_no, tokens)
            delimiter = delim
            break
        n_header += 1
        header = [*header[-1:], (line_no, stripped)]
        if n_header > _MAX_HEADER_LINES:
            raise NoDataError(
                f"{path}: no rows of numbers in the first {_MAX_HEADER_LINES:,} header lines; "
                "not a table of x, z values"
            )
    if first is None:
        if header:
            last_no, last = header[-1]
            raise NoDataError(
                f"{path}: no rows of numbers after {n_header} header line(s) (last header "
                f"line {last_no}: {last[:60]!r}); the file has a header but no data — export "
                "the scan again with its data"
            )
        if seen_comment:
            raise EmptyFileError(f"{path}: the file has only comments or blank lines, no data")
        raise EmptyFileError(f"{path}: the file is empty; nothing to read — export the scan again")

    start_no, first_tokens = first
    n_columns = len(first_tokens)
    max_values = 3 * max_points
    values = array.array("d")
    rows = array.array("q")
    resolution = [0.0] * n_columns

    def add(line_no: int, stripped: str, tokens: list[str]) -> None:
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
        check_points(path, len(rows) + 1, max_points, "the table")
        if len(values) + n_columns > max_values:
            raise FileTooLargeError(
                f"{path}, line {line_no}: {len(rows) + 1:,} rows of {n_columns} numbers exceed "
                f"{max_values:,} values (3 × max_points); if the table is genuine, pass a "
                "larger max_points= to read_profile"
            )
        for c, token in enumerate(tokens):
            value = _number(token, delimiter)
            if value is None:
                raise MalformedRowError(
                    f"{path}, line {line_no}, column {c + 1}: {token[:40]!r} is not a number "
                    "(undefined points may be written as nan, bad or left empty); fix or "
                    "remove this row"
                )
            if _overflows(token, value):
                raise MalformedRowError(
                    f"{path}, line {line_no}, column {c + 1}: {token[:40]!r} is beyond the "
                    "range of floating-point numbers (magnitude above 1.8e308); fix or remove "
                    "this row"
                )
            values.append(value)
            if value == value and value != 0.0 and not math.isinf(value):
                step = _resolution(token)  # finest printed step of non-zero numbers
                resolution[c] = step if resolution[c] == 0.0 else min(resolution[c], step)
        rows.append(line_no)

    add(start_no, "", first_tokens)
    for line_no, line in iterator:
        stripped = line.strip()
        if not stripped:
            continue
        if _is_comment(stripped):
            comment(stripped)
            continue
        add(line_no, stripped, _split(stripped, delimiter))

    columns = _columns(path, header, n_columns, delimiter)
    return _Table(
        values=np.frombuffer(values, dtype=np.float64).reshape(len(rows), n_columns),
        rows=np.frombuffer(rows, dtype=np.int64).copy(),
        columns=columns,
        delimiter=delimiter,
        header=header,
        n_header=n_header,
        stored=stored,
        column_resolution=resolution,
    )


def _columns(
    path: Path, header: Sequence[tuple[int, str]], n_columns: int, delimiter: str | None
) -> list[_Column]:
    """Titles and units of the columns from the last (up to two) header lines that fit."""
    fitting: list[tuple[int, list[str]]] = []
    for line_no, text in reversed(header):
        titles = _split_titles(text, delimiter, n_columns)
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
            bare = strip_bracketed(titles[c]).strip()
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
                f"{path}, line {column.title_line}: the {what} column's unit "
                f"{column.raw_unit[:40]!r} is not a length unit; use one of "
                f"{', '.join(UNIT_FACTORS)} in the header"
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


def _stored_metadata(path: Path, text: str | None) -> Mapping[str, Any] | None:
    if text is None:
        return None
    from ._stored import parse_stored_metadata

    return parse_stored_metadata(path, text, where=f"the {METADATA_COMMENT!r} comment")


@np.errstate(over="ignore", invalid="ignore")
def _table_to_raw(
    path: Path,
    table: _Table,
    *,
    fmt: str,
    unit: str | None,
    height_unit: str | None,
    spacing: float | None,
    line: int | None = None,
    extra: dict[str, Any] | None = None,
) -> RawProfile:
    """The raw profile of a parsed table (a value overflowing on unit conversion becomes inf,
    an undefined point, without a RuntimeWarning)."""
    columns = table.columns
    n_columns = len(columns)
    n_rows = table.values.shape[0]
    valid_col = _pick(columns, _VALID_NAMES, set())
    invalid_col = _pick(columns, _INVALID_NAMES, set()) if valid_col is None else None
    flag_col = valid_col if valid_col is not None else invalid_col
    used = {flag_col} if flag_col is not None else set()
    data_columns = [c for c in range(n_columns) if c not in used]
    if not data_columns:
        title = columns[flag_col].title if flag_col is not None else ""
        raise NoDataError(
            f"{path}: the only column ({title!r}) is a validity flag, read as such from its "
            "title; the file has no heights — export the scan with its height column"
        )
    picked_x = _pick(columns, _X_NAMES, used)
    matrix = len(data_columns) >= 3 and picked_x is None

    metadata: dict[str, Any] = {"source": str(path), "format": fmt}
    if extra:
        metadata.update(extra)
    if table.n_header:
        metadata["header_lines"] = table.n_header
    metadata["delimiter"] = _DELIMITER_NAMES[table.delimiter]

    if line is not None and not matrix:
        raise ReadOptionError(
            f"{path}: line= is only for areal data (x3p, npy, instrument files, or a text "
            "matrix of heights); this table is a line scan — drop line="
        )
    rows: NDArray[np.int64] | None = table.rows
    if matrix:
        if line is None:
            raise LineSelectionError(
                f"{path}: {n_rows} rows × {len(data_columns)} columns of numbers and no title "
                "naming the x column: an areal matrix of heights (e.g. a Gwyddion ASCII "
                f"export), not a line scan; choose a row with line= (0 … {n_rows - 1}; CLI "
                "--line) and give spacing= [µm], or export the profile as x, z columns"
            )
        if not 0 <= line < n_rows:
            raise LineSelectionError(
                f"{path}: line={line} does not exist; the matrix has rows 0 … {n_rows - 1}"
            )
        spacing = required_spacing(path, spacing, "a row of a height matrix has no positions")
        z_unit, z_from = _resolve_unit(
            path, None, height_unit or unit, "heights", "height_unit" if height_unit else "unit"
        )
        z = table.values[line, data_columns] * UNIT_FACTORS[z_unit]
        x = np.arange(z.size, dtype=np.float64) * spacing
        x_unit, x_from, x_factor, x_resolution = "µm", "argument spacing", 1.0, 0.0
        metadata.update(matrix=[n_rows, len(data_columns)], line=int(line))
        metadata["spacing_um"] = float(spacing)
        rows = None
        flag_col = None
    elif len(data_columns) == 1:  # heights only
        z_col = data_columns[0]
        spacing = required_spacing(path, spacing, "one column of heights and no positions")
        z_unit, z_from = _resolve_unit(
            path,
            columns[z_col],
            height_unit or unit,
            "heights",
            "height_unit" if height_unit else "unit",
        )
        x = np.arange(n_rows, dtype=np.float64) * spacing
        x_unit, x_from, x_factor, x_resolution = "µm", "argument spacing", 1.0, 0.0
        metadata["spacing_um"] = float(spacing)
        metadata["z_column"] = columns[z_col].title or f"column {z_col + 1}"
        z = table.values[:, z_col] * UNIT_FACTORS[z_unit]
    else:
        if spacing is not None:
            raise ReadOptionError(
                f"{path}: spacing= is only for files with one column of heights, but this "
                f"file has {len(data_columns)} data columns (x is the first); drop spacing="
            )
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
        z = table.values[:, z_col] * UNIT_FACTORS[z_unit]
    z_factor = UNIT_FACTORS[z_unit]

    n_flagged = 0
    if flag_col is not None:
        flags = table.values[:, flag_col]
        undefined = (flags == 0) if flag_col == valid_col else (flags != 0)
        undefined |= ~np.isfinite(flags)
        n_flagged = int(undefined.sum())
        z = np.where(undefined, np.nan, z)
        metadata["validity_column"] = columns[flag_col].title
    metadata["n_flagged_invalid"] = n_flagged
    metadata["units"] = units_record(x_unit, z_unit, x_from, z_from, x_factor, z_factor)
    stored = _stored_metadata(path, table.stored)
    if stored is not None:
        metadata["stored_metadata"] = stored.get("profile_metadata", stored)
    return RawProfile(x, z, rows=rows, x_resolution=x_resolution, metadata=metadata)


def read_table(
    path: Path,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> RawProfile:
    """Read a text table (x, z[, valid]), one column of heights, or a row of a height matrix.

    Parameters
    ----------
    path : Path
        The file.
    unit, height_unit : str, optional
        Units of positions and heights when the header gives none (``height_unit`` defaults
        to ``unit``).
    spacing : float, optional
        Grid spacing [µm] for a file of heights only (or a row of a matrix).
    line : int, optional
        Row of a matrix of heights (three or more untitled columns) to read.
    max_points : int, optional
        Largest number of rows accepted [1].
    """
    lines = iter_lines(path)
    try:
        table = _parse_table(path, lines, max_points=max_points)
    finally:
        lines.close()
    return _table_to_raw(
        path, table, fmt="table", unit=unit, height_unit=height_unit, spacing=spacing, line=line
    )
