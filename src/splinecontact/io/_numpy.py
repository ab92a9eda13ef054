"""NumPy files: ``.npy`` (heights, (N, 2) x–z pairs, or an areal height map) and ``.npz``.

An ``.npz`` written by :func:`splinecontact.io.write_profile` holds arrays ``x`` and ``z`` [µm]
and ``metadata`` (a JSON string with ``units`` and the profile's metadata); it reads back
without any option. Other ``.npz`` files need arrays ``x`` and ``z`` (or ``z`` alone with
``spacing=``) and the ``unit=`` argument.

Untrusted files: ``np.load`` is never called. Each array's header (shape, dtype) is read first
and checked — real numbers only (no object or pickled arrays), at most two dimensions, at most
``max_points`` points, and a data size that matches the file (or the zip member) exactly —
before its data are read, in chunks, to the declared size.
"""

from __future__ import annotations

import math
import os
import tokenize
import warnings
import zipfile
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from ..errors import (
    CorruptFileError,
    LineSelectionError,
    MissingUnitsError,
    NumpyFileError,
    ReadOptionError,
    UnitError,
)
from ..preprocess import RawProfile
from ._limits import DEFAULT_MAX_POINTS, check_points, one_line, read_exact, required_spacing
from ._stored import MAX_STORED_CHARS, parse_stored_metadata
from ._units import UNIT_FACTORS, normalize_unit, units_record
from ._x3p import ZIP_ERRORS, open_zip

__all__ = ["NumpyFileError", "read_npy", "read_npz"]

_HEADER_ERRORS = (
    ValueError,
    SyntaxError,
    TypeError,
    KeyError,
    EOFError,
    OverflowError,
    RecursionError,
    tokenize.TokenError,
    *ZIP_ERRORS,
)


class _Counting:
    """A read-only stream that counts the bytes read (the size of an .npy header)."""

    def __init__(self, stream: IO[bytes]) -> None:
        self.stream = stream
        self.count = 0

    def read(self, size: int = -1) -> bytes:
        data = self.stream.read(size)
        self.count += len(data)
        return data


def _read_array(
    path: Path,
    stream: IO[bytes],
    total: int,
    name: str,
    *,
    max_points: int,
    text: bool = False,
) -> NDArray[Any]:
    """Read one ``.npy`` array of ``total`` bytes from a stream, checking its header first."""
    counting = _Counting(stream)
    what = f"array {name!r}"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numpy's notes on old headers: not our one line
            version = np.lib.format.read_magic(counting)
            if version == (1, 0):
                header = np.lib.format.read_array_header_1_0(counting)
            elif version == (2, 0):
                header = np.lib.format.read_array_header_2_0(counting)
            else:
                raise NumpyFileError(
                    f"{path}: {what} is in .npy format version {version}, which is not "
                    "supported; save it with numpy.save"
                )
        shape, fortran, dtype = header
    except _HEADER_ERRORS as exc:
        raise CorruptFileError(
            f"{path}: {what} has no readable .npy header ({one_line(exc)}); the file is "
            "damaged or not a NumPy file"
        ) from None
    dtype = np.dtype(dtype)
    if dtype.hasobject or dtype.names is not None or dtype.subdtype is not None:
        raise NumpyFileError(
            f"{path}: {what} has dtype {str(dtype)[:60]} (objects, pickles or records); a "
            "profile needs an array of real numbers — save it with numpy.save(float array)"
        )
    if text:
        if dtype.kind not in "US" or shape != ():
            raise NumpyFileError(f"{path}: {what} is not a text string (dtype {dtype})")
        if dtype.itemsize > 4 * MAX_STORED_CHARS:
            raise CorruptFileError(f"{path}: {what} declares {dtype.itemsize:,} bytes of text")
    elif dtype.kind not in "iuf":
        raise NumpyFileError(
            f"{path}: {what} has dtype {dtype}; a profile needs real numbers (integer or float)"
        )
    if not 0 <= len(shape) <= 2 or any(int(n) < 0 for n in shape):
        raise NumpyFileError(
            f"{path}: {what} has shape {tuple(shape)}; expected heights (N,), pairs (N, 2) or "
            "an areal map (ny, nx)"
        )
    n = math.prod(int(k) for k in shape)
    check_points(path, n, max_points, f"{what} (shape {tuple(shape)})")
    size = n * dtype.itemsize
    if total - counting.count != size:
        raise CorruptFileError(
            f"{path}: {what} of shape {tuple(shape)} and dtype {dtype} needs {size:,} bytes but "
            f"the file holds {total - counting.count:,}; the file is truncated or damaged"
        )
    data = read_exact(path, stream, size, what)
    array = np.frombuffer(data, dtype=dtype)
    return array.reshape(shape, order="F" if fortran else "C")


def _units(
    path: Path, unit: str | None, height_unit: str | None, stored: dict[str, str] | None
) -> tuple[str, str, str]:
    if stored:
        x_unit = normalize_unit(stored.get("x", ""), what=f"{path}: stored x unit")
        z_unit = normalize_unit(stored.get("z", ""), what=f"{path}: stored z unit")
        for given, have, what in ((unit, x_unit, "x"), (height_unit or unit, z_unit, "z")):
            if given is not None and normalize_unit(given) != have:
                raise UnitError(
                    f"{path}: the file stores {what} in {have} but {given!r} was passed; drop "
                    "unit=/height_unit= to use the stored units"
                )
        return x_unit, z_unit, "file"
    if unit is None and height_unit is None:
        raise MissingUnitsError(
            f"{path}: a NumPy file does not say in which unit its values are; pass unit= "
            f"(one of {', '.join(UNIT_FACTORS)}; CLI --unit)"
        )
    x_unit = normalize_unit(unit, what="unit=") if unit is not None else "µm"
    z_unit = normalize_unit(height_unit or unit or "µm", what="height_unit=")
    return x_unit, z_unit, "argument"


def _row(path: Path, z: NDArray[Any], line: int | None, extra: str = "") -> NDArray[Any]:
    """Row ``line`` of an areal map (refused without ``line=``)."""
    if line is None:
        raise LineSelectionError(
            f"{path}: areal heights of shape {z.shape}{extra}; choose the row with line= "
            f"(0 … {z.shape[0] - 1}; CLI --line)"
        )
    if not 0 <= line < z.shape[0]:
        raise LineSelectionError(
            f"{path}: line={line} does not exist; rows are 0 … {z.shape[0] - 1}"
        )
    return z[line]


def _heights(
    path: Path,
    z: NDArray[Any],
    *,
    spacing: float | None,
    line: int | None,
) -> tuple[NDArray[np.float64], int | None]:
    if z.ndim == 2:
        z = _row(path, z, line)
    elif z.ndim != 1:
        raise NumpyFileError(f"{path}: heights of shape {z.shape}; expected (N,) or (ny, nx)")
    elif line is not None:
        raise LineSelectionError(f"{path}: line= is only for areal data; this file is a profile")
    required_spacing(path, spacing, "heights without positions")
    return np.asarray(z, dtype=np.float64), line


def _make(
    path: Path,
    x: NDArray[Any] | None,
    z: NDArray[Any],
    *,
    fmt: str,
    unit: str | None,
    height_unit: str | None,
    spacing: float | None,
    line: int | None,
    stored_units: dict[str, str] | None = None,
    stored_metadata: dict[str, Any] | None = None,
) -> RawProfile:
    if x is None:
        z, line = _heights(path, z, spacing=spacing, line=line)
        x_unit, z_unit, origin = _units(path, unit or height_unit, height_unit, stored_units)
        x = np.arange(z.size, dtype=np.float64) * spacing  # type: ignore[operator]
        x_factor = 1.0
        x_unit = "µm"
    else:
        if spacing is not None:
            raise ReadOptionError(f"{path}: the file has positions x; drop spacing=")
        if x.ndim != 1:
            raise NumpyFileError(f"{path}: positions x of shape {x.shape}; expected (N,)")
        if z.ndim == 2:  # an areal map with one x per column: never flattened
            z = _row(path, z, line, extra=f" with x of {x.size} points")
        elif line is not None:
            raise LineSelectionError(f"{path}: line= is only for areal data; this is a profile")
        if z.ndim != 1 or z.size != x.size:
            raise NumpyFileError(
                f"{path}: x has {x.size} points but z has shape {z.shape}; a profile needs "
                "one height per position"
            )
        x_unit, z_unit, origin = _units(path, unit, height_unit, stored_units)
        x_factor = UNIT_FACTORS[x_unit]
        with np.errstate(over="ignore"):
            x = np.asarray(x, dtype=np.float64) * x_factor
    z_factor = UNIT_FACTORS[z_unit]
    metadata: dict[str, Any] = {
        "source": str(path),
        "format": fmt,
        "units": units_record(
            x_unit,
            z_unit,
            origin if spacing is None else "argument spacing",
            origin,
            x_factor,
            z_factor,
        ),
    }
    if spacing is not None:
        metadata["spacing_um"] = float(spacing)
    if line is not None:
        metadata["line"] = int(line)
    if stored_metadata is not None:
        metadata["stored_metadata"] = stored_metadata
    with np.errstate(over="ignore"):
        heights = np.asarray(z, dtype=np.float64) * z_factor
    return RawProfile(x, heights, metadata=metadata)


def read_npy(
    path: Path,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> RawProfile:
    """Read a ``.npy`` array: 1-D heights, (N, 2) or (2, N) x–z pairs, or 2-D areal heights."""
    with open(path, "rb") as handle:
        total = os.fstat(handle.fileno()).st_size
        array = _read_array(path, handle, total, "array", max_points=max_points)
    if array.ndim == 2 and spacing is None and line is None and 2 in array.shape:
        pairs = array if array.shape[1] == 2 else array.T
        return _make(
            path,
            pairs[:, 0],
            pairs[:, 1],
            fmt="npy",
            unit=unit,
            height_unit=height_unit,
            spacing=None,
            line=None,
        )
    if array.ndim in (1, 2):  # heights, or an areal map of which one line is taken
        return _make(
            path,
            None,
            array,
            fmt="npy",
            unit=unit,
            height_unit=height_unit,
            spacing=spacing,
            line=line,
        )
    raise NumpyFileError(
        f"{path}: array of shape {array.shape}; expected heights (N,), pairs (N, 2) or an "
        "areal map (ny, nx)"
    )


def _member(
    path: Path, archive: zipfile.ZipFile, name: str, *, max_points: int, text: bool = False
) -> NDArray[Any]:
    info = archive.getinfo(f"{name}.npy")
    try:
        with archive.open(info) as stream:
            return _read_array(path, stream, info.file_size, name, max_points=max_points, text=text)
    except ZIP_ERRORS as exc:
        raise CorruptFileError(
            f"{path}: array {name!r} cannot be read ({one_line(exc)}); the archive is damaged"
        ) from None


def read_npz(
    path: Path,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> RawProfile:
    """Read an ``.npz`` archive with arrays ``x`` and ``z`` (or ``z`` alone)."""
    with open(path, "rb") as handle:
        archive = open_zip(
            path,
            handle,
            lambda why: NumpyFileError(
                f"{path}: not a readable .npz archive (not a zip of .npy arrays: {why})"
            ),
            CorruptFileError,
        )
        with archive:
            names = {n[:-4] for n in archive.namelist() if n.endswith(".npy")}
            if "z" not in names:
                shown = sorted(n[:40] for n in names)[:10]
                raise NumpyFileError(
                    f"{path}: the archive has arrays {shown} but no 'z' (heights); save the "
                    "profile as arrays x and z"
                )
            z = _member(path, archive, "z", max_points=max_points)
            x = _member(path, archive, "x", max_points=max_points) if "x" in names else None
            stored: dict[str, Any] | None = None
            if "metadata" in names:
                text = _member(path, archive, "metadata", max_points=max_points, text=True)
                value = text.item()
                if isinstance(value, bytes):
                    value = value.decode("utf-8", errors="replace")
                stored = parse_stored_metadata(path, str(value), where="the 'metadata' array")
    stored_units = stored.get("units") if stored else None
    return _make(
        path,
        x,
        z,
        fmt="npz",
        unit=unit,
        height_unit=height_unit,
        spacing=spacing,
        line=line,
        stored_units=stored_units if isinstance(stored_units, dict) else None,
        stored_metadata=stored.get("profile_metadata") if stored else None,
    )
