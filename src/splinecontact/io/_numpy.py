"""NumPy files: ``.npy`` (heights, (N, 2) x–z pairs, or an areal height map) and ``.npz``.

An ``.npz`` written by :func:`splinecontact.io.write_profile` holds arrays ``x`` and ``z`` [µm]
and ``metadata`` (a JSON string with ``units`` and the profile's metadata); it reads back
without any option. Other ``.npz`` files need arrays ``x`` and ``z`` (or ``z`` alone with
``spacing=``) and the ``unit=`` argument.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..preprocess import RawProfile
from ._errors import (
    LineSelectionError,
    MissingSpacingError,
    MissingUnitsError,
    ProfileReadError,
    ReadOptionError,
    UnitError,
)
from ._units import UNIT_FACTORS, normalize_unit

__all__ = ["read_npy", "read_npz"]


class NumpyFileError(ProfileReadError):
    """A NumPy file does not hold a profile in a form splinecontact understands."""


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


def _heights(
    path: Path,
    z: NDArray[Any],
    *,
    spacing: float | None,
    line: int | None,
) -> tuple[NDArray[np.float64], int | None]:
    if z.ndim == 2:
        if line is None:
            raise LineSelectionError(
                f"{path}: areal heights of shape {z.shape}; choose the row with line= "
                f"(0 … {z.shape[0] - 1}; CLI --line)"
            )
        if not 0 <= line < z.shape[0]:
            raise LineSelectionError(
                f"{path}: line={line} does not exist; rows are 0 … {z.shape[0] - 1}"
            )
        z = z[line]
    elif line is not None:
        raise LineSelectionError(f"{path}: line= is only for areal data; this file is a profile")
    if spacing is None:
        raise MissingSpacingError(
            f"{path}: heights without positions; pass the grid spacing spacing= [µm] "
            "(CLI --spacing)"
        )
    if not (np.isfinite(spacing) and spacing > 0):
        raise ReadOptionError(f"{path}: spacing={spacing!r} µm must be positive")
    return np.asarray(z, dtype=np.float64), line


def _numeric(path: Path, array: NDArray[Any], name: str) -> NDArray[Any]:
    if not np.issubdtype(array.dtype, np.number) or np.iscomplexobj(array):
        raise NumpyFileError(
            f"{path}: array {name!r} has dtype {array.dtype}; a profile needs real numbers"
        )
    return array


def _make(
    path: Path,
    x: NDArray[np.float64] | None,
    z: NDArray[np.float64],
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
        if line is not None:
            raise LineSelectionError(f"{path}: line= is only for areal data; this is a profile")
        x_unit, z_unit, origin = _units(path, unit, height_unit, stored_units)
        x_factor = UNIT_FACTORS[x_unit]
        x = np.asarray(x, dtype=np.float64) * x_factor
    z_factor = UNIT_FACTORS[z_unit]
    metadata: dict[str, Any] = {
        "source": str(path),
        "format": fmt,
        "units": {
            "x": x_unit,
            "z": z_unit,
            "x_from": origin if spacing is None else "argument spacing",
            "z_from": origin,
            "x_factor_to_um": x_factor,
            "z_factor_to_um": z_factor,
        },
    }
    if spacing is not None:
        metadata["spacing_um"] = float(spacing)
    if line is not None:
        metadata["line"] = int(line)
    if stored_metadata is not None:
        metadata["stored_metadata"] = stored_metadata
    return RawProfile(x, np.asarray(z, dtype=np.float64) * z_factor, metadata=metadata)


def read_npy(
    path: Path,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
) -> RawProfile:
    """Read a ``.npy`` array: 1-D heights, (N, 2) or (2, N) x–z pairs, or 2-D areal heights."""
    try:
        array = np.load(path, allow_pickle=False)
    except ValueError as exc:
        raise NumpyFileError(f"{path}: not a readable .npy array without pickles ({exc})") from None
    array = _numeric(path, np.asarray(array), "array")
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


def read_npz(
    path: Path,
    *,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
) -> RawProfile:
    """Read an ``.npz`` archive with arrays ``x`` and ``z`` (or ``z`` alone)."""
    try:
        archive = np.load(path, allow_pickle=False)
    except (ValueError, zipfile.BadZipFile) as exc:
        raise NumpyFileError(f"{path}: not a readable .npz archive ({exc})") from None
    with archive:
        names = set(archive.files)
        if "z" not in names:
            raise NumpyFileError(
                f"{path}: the archive has arrays {sorted(names)} but no 'z' (heights); save the "
                "profile as arrays x and z"
            )
        z = _numeric(path, archive["z"], "z")
        x = _numeric(path, archive["x"], "x") if "x" in names else None
        stored: dict[str, Any] | None = None
        if "metadata" in names:
            try:
                loaded = json.loads(str(archive["metadata"]))
            except (json.JSONDecodeError, ValueError):
                loaded = None
            stored = loaded if isinstance(loaded, dict) else None
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
