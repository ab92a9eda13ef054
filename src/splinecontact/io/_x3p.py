"""ISO 5436-2 / ISO 25178-72 X3P files: a zip of ``main.xml`` and binary point data.

Supported: feature types ``PRF`` (profile) and ``SUR`` (areal, one chosen line), incremental
x (and y) axes, z data types ``I`` (uint16), ``L`` (uint32), ``F`` (float32), ``D`` (float64), with
the z axis increment (scale) and offset applied when given, the optional ``valid.bin`` mask, and
the MD5 checksum of the point data when ``main.xml`` gives one. Positions and heights in X3P
are in metres. Point data are stored with x running fastest, then y.
"""

from __future__ import annotations

import hashlib
import zipfile
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np

from ..preprocess import RawProfile
from ._errors import LineSelectionError, X3PError

__all__ = ["read_x3p"]

_DTYPES = {"I": "<u2", "L": "<u4", "F": "<f4", "D": "<f8"}  # I, L unsigned (openGPS)
_METRE_TO_UM = 1e6


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _find(root: ElementTree.Element, *names: str) -> ElementTree.Element | None:
    node: ElementTree.Element | None = root
    for name in names:
        if node is None:
            return None
        node = next((child for child in node if _local(child.tag) == name), None)
    return node


def _text(root: ElementTree.Element, *names: str) -> str | None:
    node = _find(root, *names)
    return None if node is None or node.text is None else node.text.strip()


def _float(
    path: Path, root: ElementTree.Element, *names: str, default: float | None = None
) -> float:
    text = _text(root, *names)
    if text is None:
        if default is not None:
            return default
        raise X3PError(f"{path}: main.xml has no {'/'.join(names)}; the file is incomplete")
    try:
        return float(text)
    except ValueError:
        raise X3PError(f"{path}: main.xml {'/'.join(names)} = {text!r} is not a number") from None


def read_x3p(path: Path, *, line: int | None = None) -> RawProfile:
    """Read a profile, or row ``line`` of areal data, from an X3P file.

    Parameters
    ----------
    path : Path
        The ``.x3p`` file.
    line : int, optional
        For areal data (``SUR``): index of the row (constant y, 0-based) to read. Required for
        areal data; for a profile it must be ``None`` or ``0``.
    """
    try:
        archive = zipfile.ZipFile(path)
    except zipfile.BadZipFile as exc:
        raise X3PError(f"{path}: not a valid X3P file (not a zip archive: {exc})") from None
    with archive:
        names = archive.namelist()
        if "main.xml" not in names:
            raise X3PError(
                f"{path}: the archive has no main.xml (it holds {', '.join(names[:5])}); "
                "not an X3P file"
            )
        try:
            root = ElementTree.fromstring(archive.read("main.xml"))
        except ElementTree.ParseError as exc:
            raise X3PError(f"{path}: main.xml is not valid XML ({exc})") from None
        feature = _text(root, "Record1", "FeatureType")
        if feature not in ("PRF", "SUR"):
            raise X3PError(
                f"{path}: feature type {feature!r} is not supported; only PRF (profile) and "
                "SUR (areal surface) can be read"
            )
        axes = {}
        for axis in ("CX", "CY", "CZ"):
            axes[axis] = {
                "type": _text(root, "Record1", "Axes", axis, "AxisType"),
                "data_type": _text(root, "Record1", "Axes", axis, "DataType"),
            }
        for axis in ("CX", "CY"):
            if axes[axis]["type"] not in (None, "I"):
                raise X3PError(
                    f"{path}: axis {axis} has type {axes[axis]['type']!r} (absolute "
                    "coordinates); only incremental (I) lateral axes are supported"
                )
        dx = _float(path, root, "Record1", "Axes", "CX", "Increment")
        x_offset = _float(path, root, "Record1", "Axes", "CX", "Offset", default=0.0)
        z_type = axes["CZ"]["data_type"]
        if z_type not in _DTYPES:
            raise X3PError(f"{path}: z data type {z_type!r} is not one of I, L, F, D")
        z_increment = _float(path, root, "Record1", "Axes", "CZ", "Increment", default=1.0)
        z_offset = _float(path, root, "Record1", "Axes", "CZ", "Offset", default=0.0)
        size_x = int(_float(path, root, "Record3", "MatrixDimension", "SizeX"))
        size_y = int(_float(path, root, "Record3", "MatrixDimension", "SizeY"))
        size_z = int(_float(path, root, "Record3", "MatrixDimension", "SizeZ", default=1.0))
        link = _text(root, "Record3", "DataLink", "PointDataLink")
        if link is None:
            raise X3PError(
                f"{path}: the point data are inline (DataList), which is not supported; export "
                "with binary point data (bindata/data.bin)"
            )
        if link not in names:
            raise X3PError(f"{path}: main.xml points to {link!r}, which the archive lacks")
        data = archive.read(link)
        checksum = _text(root, "Record3", "DataLink", "MD5ChecksumPointData")
        if checksum and hashlib.md5(data).hexdigest().lower() != checksum.lower():
            raise X3PError(
                f"{path}: the MD5 checksum of {link} does not match main.xml; the file is damaged"
            )
        valid_link = _text(root, "Record3", "ValidPntsLink")
        valid_bytes = archive.read(valid_link) if valid_link and valid_link in names else None

    n = size_x * size_y * size_z
    dtype = np.dtype(_DTYPES[z_type])
    if len(data) != n * dtype.itemsize:
        raise X3PError(
            f"{path}: {link} has {len(data)} bytes but {size_x}×{size_y}×{size_z} points of "
            f"type {z_type} need {n * dtype.itemsize}; the file is damaged"
        )
    values = np.frombuffer(data, dtype=dtype).astype(np.float64)
    values = values * z_increment + z_offset  # increment 1 and offset 0 when absent
    grid = values.reshape(size_z * size_y, size_x)  # x runs fastest
    valid = None
    if valid_bytes is not None:
        bits = np.unpackbits(np.frombuffer(valid_bytes, dtype=np.uint8), bitorder="little")
        valid = bits[:n].astype(bool).reshape(size_z * size_y, size_x)

    n_lines = grid.shape[0]
    if feature == "PRF" or n_lines == 1:
        if line not in (None, 0):
            raise LineSelectionError(
                f"{path}: the file holds a single profile; line={line} does not exist (omit it)"
            )
        row = 0
    else:
        if line is None:
            raise LineSelectionError(
                f"{path}: areal data of {size_x} × {n_lines} points; choose the row to read "
                f"with line= (0 … {n_lines - 1}; CLI --line)"
            )
        if not 0 <= line < n_lines:
            raise LineSelectionError(
                f"{path}: line={line} does not exist; the areal data have rows 0 … {n_lines - 1}"
            )
        row = line
    z = grid[row] * _METRE_TO_UM
    if valid is not None:
        z = np.where(valid[row], z, np.nan)
    x = (x_offset + dx * np.arange(size_x)) * _METRE_TO_UM
    dy = _float(path, root, "Record1", "Axes", "CY", "Increment", default=0.0)
    y_offset = _float(path, root, "Record1", "Axes", "CY", "Offset", default=0.0)

    metadata: dict[str, Any] = {
        "source": str(path),
        "format": "x3p",
        "feature_type": feature,
        "matrix": [size_x, size_y, size_z],
        "units": {
            "x": "m",
            "z": "m",
            "x_from": "X3P standard (metres)",
            "z_from": "X3P standard (metres)",
            "x_factor_to_um": _METRE_TO_UM,
            "z_factor_to_um": _METRE_TO_UM,
        },
        "z_data_type": z_type,
        "n_flagged_invalid": int((~valid[row]).sum()) if valid is not None else 0,
    }
    if feature == "SUR":
        metadata["line"] = row
        metadata["line_y_um"] = (y_offset + dy * row) * _METRE_TO_UM
    instrument = {
        key: _text(root, "Record2", "Instrument", key)
        for key in ("Manufacturer", "Model", "Serial", "Version")
    }
    metadata["instrument"] = {k: v for k, v in instrument.items() if v}
    return RawProfile(x, z, x_resolution=0.0, metadata=metadata)
