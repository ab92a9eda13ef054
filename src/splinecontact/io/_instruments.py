"""Every other instrument format, through SurfaceTopography (optional extra).

SurfaceTopography (ContactEngineering, MIT licence) reads some 40 instrument formats (Zygo
MetroPro and DATX, Keyence, Olympus, Bruker/Veeco, Digital Surf, Gwyddion, Park Systems TIFF,
Mitutoyo XLSX, WSxM, BCR-STM, ...). It is an optional dependency:
``pip install "splinecontact[instruments]"``. Without it, such files are refused with a message
saying so.

Untrusted files: the size of the chosen channel (its declared grid) is checked against the
limit of points per file before its data are read, and every exception SurfaceTopography (or
the libraries under it) raises on a damaged or unexpected file becomes an
:class:`InstrumentFileError` naming the file and the original error.

Origin of x: SurfaceTopography gives a grid spacing but not the file's lateral origin, so a
uniform scan read through it starts at x = 0 — the same rule as every built-in reader applies
when a file gives only a spacing (a column of heights with ``spacing=``, an areal ``.npy``);
files with explicit positions (text tables, X3P offsets, non-uniform line scans) keep them.
``metadata["x_origin"]`` says which applies.
"""

from __future__ import annotations

import importlib
import logging
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import (
    FileTooLargeError,
    InstrumentFileError,
    LineSelectionError,
    MissingExtraError,
    MissingUnitsError,
    SplineContactError,
    UnitError,
)
from ..preprocess import RawProfile
from ._limits import DEFAULT_MAX_POINTS, check_points, one_line
from ._units import UNIT_FACTORS, normalize_unit, units_record

__all__ = [
    "AMBIGUOUS_EXTENSIONS",
    "INSTRUMENT_EXTENSIONS",
    "InstrumentFileError",
    "read_with_surfacetopography",
]

#: File extensions of instrument formats left to SurfaceTopography (every extension its readers
#: register, except the formats splinecontact reads itself: text tables, X3P, NumPy).
INSTRUMENT_EXTENSIONS = frozenset(
    {
        ".001", ".002", ".003", ".004", ".005", ".al3d", ".apx", ".bcr", ".bcrf", ".cur",
        ".datx", ".di", ".ezd", ".frt", ".gwy", ".h5", ".hgt", ".ibw", ".jpk", ".lext", ".mat",
        ".mdt", ".mi", ".mnt", ".nc", ".nid", ".nms", ".oir", ".opd", ".opdx", ".os3d", ".plu",
        ".plux", ".poir", ".ps", ".qep", ".sdf", ".spm", ".stp", ".sur", ".tif", ".tiff",
        ".tmd", ".tom", ".top", ".vk3", ".vk4", ".vk6", ".vk7", ".wsxm", ".xlsx",
        ".zmg", ".zon",
    }
)  # fmt: skip

#: Extensions shared by a text table and a binary instrument format (Zygo MetroPro ``.dat``):
#: text goes to the table reader, anything else to SurfaceTopography.
AMBIGUOUS_EXTENSIONS = frozenset({".dat"})

INSTALL_HINT = 'pip install "splinecontact[instruments]"'


def _import_surfacetopography() -> Any:
    try:
        return importlib.import_module("SurfaceTopography")
    except ImportError:
        return None


def _st_unit(unit: str) -> str:
    canonical = normalize_unit(unit)
    return {"µm": "um", "Å": "A"}.get(canonical, canonical)


def read_with_surfacetopography(
    path: Path,
    *,
    unit: str | None = None,
    line: int | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> RawProfile:
    """Read a line scan (or row ``line`` of areal data) with SurfaceTopography.

    Raises
    ------
    MissingExtraError
        SurfaceTopography is not installed.
    InstrumentFileError
        SurfaceTopography cannot read the file.
    FileTooLargeError
        The channel declares more than ``max_points`` points.
    """
    module = _import_surfacetopography()
    if module is None:
        raise MissingExtraError(
            f"{path}: the format {path.suffix or '(no extension)'!s} is read through "
            f"SurfaceTopography, which is not installed; install the optional extra with "
            f"{INSTALL_HINT}, or export the scan as two-column text (x, z with units)"
        )
    quiet = [logging.getLogger(name) for name in ("tifffile", "SurfaceTopography")]
    before = [logger.disabled for logger in quiet]
    try:
        for logger in quiet:  # their warnings would be extra lines besides our one error line
            logger.disabled = True
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return _read(module, path, unit=unit, line=line, max_points=max_points)
    except SplineContactError:
        raise
    except MemoryError:
        raise FileTooLargeError(
            f"{path}: SurfaceTopography ran out of memory reading the file; it is damaged or "
            "larger than this machine can read"
        ) from None
    except Exception as exc:  # foreign code on an untrusted file: any failure is a read error
        raise InstrumentFileError(
            f"{path}: SurfaceTopography cannot read the file ({type(exc).__name__}: "
            f"{one_line(exc)}); check that it is a complete instrument export, or export the "
            "scan as two-column text (x, z with units)"
        ) from None
    finally:
        for logger, disabled in zip(quiet, before, strict=True):
            logger.disabled = disabled


def _read(
    module: Any, path: Path, *, unit: str | None, line: int | None, max_points: int
) -> RawProfile:
    reader = module.open_topography(str(path))
    channel = reader.channels[reader.default_channel.index]
    grid = tuple(int(n) for n in channel.nb_grid_pts)
    check_points(path, math.prod(grid), max_points, f"channel {channel.name!r} {grid}")
    if len(grid) == 2:
        n_lines = grid[1]
        if line is None or not 0 <= line < n_lines:
            which = "choose a line with" if line is None else f"line={line} does not exist;"
            raise LineSelectionError(
                f"{path}: areal data of {grid[0]} × {n_lines} points; {which} line= "
                f"(0 … {n_lines - 1}; CLI --line)"
            )
    elif line not in (None, 0):
        raise LineSelectionError(f"{path}: a line scan has no line {line}; omit line=")
    file_unit = getattr(channel, "unit", None)
    kwargs: dict[str, Any] = {}
    if file_unit is None:
        if unit is None:
            raise MissingUnitsError(
                f"{path}: the file does not give its unit; pass unit= (one of "
                f"{', '.join(UNIT_FACTORS)}; CLI --unit)"
            )
        kwargs["unit"] = _st_unit(unit)
    elif unit is not None and normalize_unit(unit) != normalize_unit(str(file_unit)):
        raise UnitError(f"{path}: the file gives unit {file_unit!r} but unit={unit!r} was passed")
    topography = reader.topography(channel_index=channel.index, **kwargs)
    topo_unit = normalize_unit(str(topography.unit), what=f"{path}: unit")
    factor = UNIT_FACTORS[topo_unit]
    metadata: dict[str, Any] = {
        "source": str(path),
        "format": "surfacetopography",
        "instrument_format": str(reader.format()),
        "channel": str(channel.name),
    }
    if topography.dim == 1:
        x, z = topography.positions_and_heights()
    else:
        x2, _, h2 = topography.positions_and_heights()
        x, z = x2[:, line], h2[:, line]
        metadata["line"] = int(line)  # type: ignore[arg-type]
    uniform = bool(getattr(topography, "is_uniform", True))
    metadata["x_origin"] = (
        "0 (only a grid spacing is given)" if uniform else "file (positions as stated)"
    )
    z = np.ma.filled(np.ma.asarray(z, dtype=np.float64), np.nan)
    origin = "file (SurfaceTopography)" if file_unit else "argument"
    metadata["units"] = units_record(topo_unit, topo_unit, origin, origin, factor, factor)
    with np.errstate(over="ignore", invalid="ignore"):
        x_um = np.asarray(x, dtype=np.float64) * factor
        if uniform and x_um.size:
            x_um = x_um - x_um[0]
        return RawProfile(x_um, z * factor, metadata=metadata)
