"""Every other instrument format, through SurfaceTopography (optional extra).

SurfaceTopography (ContactEngineering, MIT licence) reads some 35 instrument formats (Zygo,
Keyence, Olympus, Bruker AFM, Digital Surf, ...). It is an optional dependency:
``pip install "splinecontact[instruments]"``. Without it, such files are refused with a
message saying so.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Any

import numpy as np

from ..preprocess import RawProfile
from ._errors import LineSelectionError, MissingExtraError, MissingUnitsError, UnitError
from ._units import UNIT_FACTORS, normalize_unit

__all__ = ["INSTRUMENT_EXTENSIONS", "read_with_surfacetopography"]

#: File extensions of instrument formats left to SurfaceTopography.
INSTRUMENT_EXTENSIONS = frozenset(
    {
        ".al3d", ".bcr", ".datx", ".di", ".spm", ".001", ".ezd", ".nid", ".frt", ".gwy",
        ".h5", ".ibw", ".jpk", ".lext", ".mat", ".mi", ".mnt", ".nc", ".nms", ".opd", ".opdx",
        ".os3d", ".plu", ".plux", ".ps", ".sdf", ".sur", ".tmd", ".vk3", ".vk4", ".vk6", ".vk7",
        ".wsxm", ".zmg", ".zon", ".oir", ".poir", ".mdt",
    }
)  # fmt: skip

INSTALL_HINT = 'pip install "splinecontact[instruments]"'


def _import_surfacetopography() -> Any:
    try:
        return importlib.import_module("SurfaceTopography")
    except ImportError:
        return None


def read_with_surfacetopography(
    path: Path, *, unit: str | None = None, line: int | None = None, max_points: int = 10**8
) -> RawProfile:
    """Read a line scan (or row ``line`` of areal data) with SurfaceTopography.

    Raises
    ------
    MissingExtraError
        SurfaceTopography is not installed.
    """
    module = _import_surfacetopography()
    if module is None:
        raise MissingExtraError(
            f"{path}: the format {path.suffix or '(no extension)'!s} is read through "
            f"SurfaceTopography, which is not installed; install the optional extra with "
            f"{INSTALL_HINT}, or export the scan as two-column text (x, z with units)"
        )
    reader = module.open_topography(str(path))
    channel = reader.channels[reader.default_channel.index]
    file_unit = getattr(channel, "unit", None)
    kwargs: dict[str, Any] = {}
    if file_unit is None:
        if unit is None:
            raise MissingUnitsError(
                f"{path}: the file does not give its unit; pass unit= (one of "
                f"{', '.join(UNIT_FACTORS)}; CLI --unit)"
            )
        kwargs["unit"] = {"µm": "um", "Å": "A"}.get(normalize_unit(unit), normalize_unit(unit))
    elif unit is not None and normalize_unit(unit) != normalize_unit(str(file_unit)):
        raise UnitError(f"{path}: the file gives unit {file_unit!r} but unit={unit!r} was passed")
    topography = reader.topography(**kwargs)
    topo_unit = normalize_unit(str(topography.unit), what=f"{path}: unit")
    factor = UNIT_FACTORS[topo_unit]
    metadata: dict[str, Any] = {"source": str(path), "format": "surfacetopography"}
    if topography.dim == 1:
        if line not in (None, 0):
            raise LineSelectionError(f"{path}: a line scan has no line {line}; omit line=")
        x, z = topography.positions_and_heights()
    else:
        x2, _, h2 = topography.positions_and_heights()
        n_lines = h2.shape[1]
        if line is None or not 0 <= line < n_lines:
            raise LineSelectionError(
                f"{path}: areal data of {h2.shape[0]} × {n_lines} points; choose a line with "
                f"line= (0 … {n_lines - 1}; CLI --line)"
            )
        x, z = x2[:, line], h2[:, line]
        metadata["line"] = int(line)
    z = np.ma.filled(np.ma.asarray(z, dtype=np.float64), np.nan)
    metadata["units"] = {
        "x": topo_unit,
        "z": topo_unit,
        "x_from": "file (SurfaceTopography)" if file_unit else "argument",
        "z_from": "file (SurfaceTopography)" if file_unit else "argument",
        "x_factor_to_um": factor,
        "z_factor_to_um": factor,
    }
    return RawProfile(np.asarray(x, dtype=np.float64) * factor, z * factor, metadata=metadata)
