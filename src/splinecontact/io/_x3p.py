"""ISO 5436-2 / ISO 25178-72 X3P files: a zip of ``main.xml`` and binary point data.

Supported: feature types ``PRF`` (profile) and ``SUR`` (areal, one chosen line), incremental
x (and y) axes, z data types ``I`` (uint16), ``L`` (uint32), ``F`` (float32), ``D`` (float64), with
the z axis increment (scale) and offset applied when given, the optional ``valid.bin`` mask, and
the MD5 checksum of the point data when ``main.xml`` gives one. Positions and heights in X3P
are in metres. Point data are stored with x running fastest, then y.

Untrusted files: ``main.xml`` is refused if it declares a document type or entities (an X3P
never needs them; entity expansion is how "billion laughs" and external-entity attacks work),
so no entity is ever expanded and no external resource is ever opened. Sizes are checked before
anything is decompressed: the zip directory's uncompressed size of every member against what
``main.xml`` declares and against the limit of points per file, then again while streaming.
Only the requested row is kept in memory.
"""

from __future__ import annotations

import hashlib
import math
import zipfile
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any
from xml.etree import ElementTree
from xml.parsers import expat

import numpy as np
from numpy.typing import NDArray

from ..errors import (
    DamagedX3PError,
    FileTooLargeError,
    LineSelectionError,
    ProfileReadError,
    X3PError,
)
from ..preprocess import RawProfile
from ._limits import (
    DEFAULT_MAX_POINTS,
    MAX_XML_BYTES,
    check_points,
    one_line,
    read_chunks,
    read_exact,
)
from ._units import units_record

__all__ = ["ZIP_ERRORS", "DamagedX3PError", "open_zip", "read_x3p"]

_DTYPES = {"I": "<u2", "L": "<u4", "F": "<f4", "D": "<f8"}  # I, L unsigned (openGPS)
_METRE_TO_UM = 1e6
_X3P_UNITS = "X3P standard (metres)"  # where the units of an X3P file come from
#: Errors of the zip and zlib modules on damaged archives (wrapped in DamagedX3PError).
ZIP_ERRORS = (
    zipfile.BadZipFile,
    zipfile.LargeZipFile,
    zlib.error,
    EOFError,
    OSError,
    NotImplementedError,
    RuntimeError,
    ValueError,
    OverflowError,
)


def open_zip(
    path: Path,
    handle: IO[bytes],
    not_zip: Callable[[str], ProfileReadError],
    damaged: type[ProfileReadError],
) -> zipfile.ZipFile:
    """Open a zip archive; a file that is no zip raises ``not_zip(reason)``, a damaged one
    ``damaged`` (both without the zip module's traceback)."""
    try:
        return zipfile.ZipFile(handle)
    except zipfile.BadZipFile as exc:
        raise not_zip(one_line(exc)) from None
    except ZIP_ERRORS as exc:
        raise damaged(f"{path}: the zip archive is damaged ({one_line(exc)})") from None


class _Forbidden(Exception):
    pass


def _refuse(*_args: object) -> None:
    raise _Forbidden


def _refuse_reference(*_args: object) -> int:
    raise _Forbidden


def _parse_xml(path: Path, data: bytes) -> ElementTree.Element:
    """Parse ``main.xml`` with no entity expansion and no external resource.

    A first pass with a bare expat parser refuses any ``<!DOCTYPE``, entity declaration or
    external entity reference (its handlers raise before anything is expanded); only then is
    the document built with :mod:`xml.etree.ElementTree`.
    """
    checker = expat.ParserCreate()
    checker.StartDoctypeDeclHandler = _refuse
    checker.EntityDeclHandler = _refuse
    checker.UnparsedEntityDeclHandler = _refuse
    checker.ExternalEntityRefHandler = _refuse_reference
    checker.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    try:
        checker.Parse(data, True)
    except _Forbidden:
        raise X3PError(
            f"{path}: main.xml declares a document type or entities, which X3P files never "
            "need; refused (entity expansion could exhaust memory or read local files)"
        ) from None
    except (expat.ExpatError, ValueError, RecursionError) as exc:
        raise X3PError(f"{path}: main.xml is not valid XML ({one_line(exc)})") from None
    try:
        return ElementTree.fromstring(data)
    except (ElementTree.ParseError, ValueError, RecursionError) as exc:
        raise X3PError(f"{path}: main.xml is not valid XML ({one_line(exc)})") from None


def _member(path: Path, archive: zipfile.ZipFile, name: str) -> zipfile.ZipInfo:
    try:
        return archive.getinfo(name)
    except KeyError:
        raise X3PError(f"{path}: main.xml points to {name!r}, which the archive lacks") from None


def _read_member(path: Path, archive: zipfile.ZipFile, info: zipfile.ZipInfo, size: int) -> bytes:
    """The whole member, whose directory entry must declare ``size`` bytes (checked first)."""
    if info.file_size != size:
        raise DamagedX3PError(
            f"{path}: {info.filename} is {info.file_size:,} bytes but {size:,} were expected; "
            "the file is damaged"
        )
    try:
        with archive.open(info) as stream:
            return read_exact(path, stream, size, info.filename)
    except ZIP_ERRORS as exc:
        raise DamagedX3PError(f"{path}: {info.filename} cannot be read ({one_line(exc)})") from None


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
    """A finite number from main.xml (``default`` when the element is absent)."""
    text = _text(root, *names)
    if text is None:
        if default is not None:
            return default
        raise X3PError(f"{path}: main.xml has no {'/'.join(names)}; the file is incomplete")
    try:
        value = float(text)
    except ValueError:
        raise X3PError(
            f"{path}: main.xml {'/'.join(names)} = {text[:40]!r} is not a number"
        ) from None
    if not math.isfinite(value):
        raise X3PError(
            f"{path}: main.xml {'/'.join(names)} = {text[:40]!r} is not a finite number; the "
            "file is damaged"
        )
    return value


def _size(path: Path, root: ElementTree.Element, name: str, default: float | None = None) -> int:
    value = _float(path, root, "Record3", "MatrixDimension", name, default=default)
    if value < 1 or value != int(value):
        raise X3PError(
            f"{path}: main.xml MatrixDimension/{name} = {value!r} is not a positive whole "
            "number of points; the file is damaged"
        )
    return int(value)


def _stream_rows(
    path: Path,
    stream: IO[bytes],
    size: int,
    keep: tuple[int, int],
    md5: Any,
    what: str,
) -> bytes:
    """Read a member of ``size`` bytes in chunks, hash all of it, keep bytes ``keep[0]:keep[1]``."""
    kept = bytearray()
    pos = 0
    chunks = read_chunks(
        path, stream, size, what, error=DamagedX3PError, declared="its directory entry declares"
    )
    for chunk in chunks:
        if md5 is not None:
            md5.update(chunk)
        lo, hi = max(keep[0], pos), min(keep[1], pos + len(chunk))
        if lo < hi:
            kept += chunk[lo - pos : hi - pos]
        pos += len(chunk)
    return bytes(kept)


def read_x3p(
    path: Path, *, line: int | None = None, max_points: int = DEFAULT_MAX_POINTS
) -> RawProfile:
    """Read a profile, or row ``line`` of areal data, from an X3P file.

    Parameters
    ----------
    path : Path
        The ``.x3p`` file.
    line : int, optional
        For areal data (``SUR``): index of the row (constant y, 0-based) to read. Required for
        areal data; for a profile it must be ``None`` or ``0``.
    max_points : int, optional
        Largest number of points (SizeX × SizeY × SizeZ) accepted [1].

    Raises
    ------
    X3PError
        The file is not a readable X3P (``DamagedX3PError`` if it is damaged).
    FileTooLargeError
        ``main.xml`` declares more than ``max_points`` points, or is itself too large.
    """
    with open(path, "rb") as handle:  # OSError (missing, unreadable) propagates as such
        archive = open_zip(
            path,
            handle,
            lambda why: X3PError(f"{path}: not a valid X3P file (not a zip archive: {why})"),
            DamagedX3PError,
        )
        with archive:
            return _read_archive(path, archive, line=line, max_points=max_points)


@dataclass(frozen=True)
class _Layout:
    """What ``main.xml`` declares about the point data (lengths in metres, as stored)."""

    feature: str
    dx: float
    x_offset: float
    z_type: str
    z_increment: float
    z_offset: float
    size_x: int
    size_y: int
    size_z: int
    link: str

    @property
    def n(self) -> int:
        """Points in the matrix."""
        return self.size_x * self.size_y * self.size_z

    @property
    def dtype(self) -> np.dtype[Any]:
        """numpy dtype of one stored height."""
        return np.dtype(_DTYPES[self.z_type])


def _main_xml(path: Path, archive: zipfile.ZipFile) -> ElementTree.Element:
    """``main.xml``, size-checked and parsed without entity expansion."""
    names = archive.namelist()
    if "main.xml" not in names:
        shown = ", ".join(repr(n[:60]) for n in names[:5])
        raise X3PError(f"{path}: the archive has no main.xml (it holds {shown}); not an X3P file")
    info = archive.getinfo("main.xml")
    if info.file_size > MAX_XML_BYTES:
        raise FileTooLargeError(
            f"{path}: main.xml declares {info.file_size:,} bytes uncompressed, more than the "
            f"{MAX_XML_BYTES:,} bytes an X3P description can need; the file is damaged or forged"
        )
    return _parse_xml(path, _read_member(path, archive, info, info.file_size))


def _feature(path: Path, root: ElementTree.Element) -> str:
    """The feature type, PRF or SUR."""
    feature = _text(root, "Record1", "FeatureType")
    if feature not in ("PRF", "SUR"):
        feature_shown = feature if feature is None else feature[:40]
        raise X3PError(
            f"{path}: feature type {feature_shown!r} is not supported; only PRF (profile) and "
            "SUR (areal surface) can be read"
        )
    return feature


def _layout(path: Path, root: ElementTree.Element, max_points: int) -> _Layout:
    """Feature type, axes and matrix size of ``main.xml``, each checked."""
    feature = _feature(path, root)
    for axis in ("CX", "CY"):
        axis_type = _text(root, "Record1", "Axes", axis, "AxisType")
        if axis_type not in (None, "I"):
            raise X3PError(
                f"{path}: axis {axis} has type {str(axis_type)[:40]!r} (absolute "
                "coordinates); only incremental (I) lateral axes are supported"
            )
    dx = _float(path, root, "Record1", "Axes", "CX", "Increment")
    if not dx * _METRE_TO_UM >= np.finfo(np.float64).tiny:
        raise X3PError(
            f"{path}: the x increment {dx!r} m is not a positive spacing that floating point "
            "can represent; the file is damaged"
        )
    x_offset = _float(path, root, "Record1", "Axes", "CX", "Offset", default=0.0)
    z_type = _text(root, "Record1", "Axes", "CZ", "DataType")
    if z_type not in _DTYPES:
        type_shown = z_type if z_type is None else z_type[:40]
        raise X3PError(f"{path}: z data type {type_shown!r} is not one of I, L, F, D")
    z_increment = _float(path, root, "Record1", "Axes", "CZ", "Increment", default=1.0)
    z_offset = _float(path, root, "Record1", "Axes", "CZ", "Offset", default=0.0)
    size_x = _size(path, root, "SizeX")
    size_y = _size(path, root, "SizeY")
    size_z = _size(path, root, "SizeZ", default=1.0)
    n = size_x * size_y * size_z
    check_points(path, n, max_points, f"main.xml's matrix ({size_x} × {size_y} × {size_z})")
    link = _text(root, "Record3", "DataLink", "PointDataLink")
    if link is None:
        raise X3PError(
            f"{path}: the point data are inline (DataList), which is not supported; export "
            "with binary point data (bindata/data.bin)"
        )
    return _Layout(
        feature, dx, x_offset, z_type, z_increment, z_offset, size_x, size_y, size_z, link
    )


def _members(
    path: Path, archive: zipfile.ZipFile, root: ElementTree.Element, layout: _Layout
) -> tuple[zipfile.ZipInfo, zipfile.ZipInfo | None]:
    """The point-data member and the optional validity member, their sizes checked."""
    n = layout.n
    data_info = _member(path, archive, layout.link)
    itemsize = layout.dtype.itemsize
    if data_info.file_size != n * itemsize:
        raise DamagedX3PError(
            f"{path}: {layout.link} has {data_info.file_size:,} bytes but "
            f"{layout.size_x}×{layout.size_y}×{layout.size_z} points of type {layout.z_type} "
            f"need {n * itemsize:,}; the file is damaged"
        )
    valid_link = _text(root, "Record3", "ValidPntsLink")
    valid_info = _member(path, archive, valid_link) if valid_link else None
    n_valid_bytes = (n + 7) // 8
    if valid_info is not None and not n_valid_bytes <= valid_info.file_size <= n_valid_bytes + 8:
        raise DamagedX3PError(
            f"{path}: {valid_link} has {valid_info.file_size:,} bytes but {n:,} points need "
            f"{n_valid_bytes:,} bytes of validity bits; the file is damaged"
        )
    return data_info, valid_info


def _row(path: Path, layout: _Layout, line: int | None) -> int:
    """The row to read: 0 for a profile, ``line`` (checked) for areal data."""
    n_lines = layout.size_y * layout.size_z
    if layout.feature == "PRF" or n_lines == 1:
        if line not in (None, 0):
            raise LineSelectionError(
                f"{path}: the file holds a single profile; line={line} does not exist (omit it)"
            )
        return 0
    if line is None:
        raise LineSelectionError(
            f"{path}: areal data of {layout.size_x} × {n_lines} points; choose the row to read "
            f"with line= (0 … {n_lines - 1}; CLI --line)"
        )
    if not 0 <= line < n_lines:
        raise LineSelectionError(
            f"{path}: line={line} does not exist; the areal data have rows 0 … {n_lines - 1}"
        )
    return line


def _read_row(
    path: Path,
    archive: zipfile.ZipFile,
    root: ElementTree.Element,
    layout: _Layout,
    members: tuple[zipfile.ZipInfo, zipfile.ZipInfo | None],
    row: int,
) -> tuple[bytes, bytes | None]:
    """The stored bytes of one row and the validity bits, the MD5 checksum verified."""
    data_info, valid_info = members
    checksum = _text(root, "Record3", "DataLink", "MD5ChecksumPointData")
    md5 = hashlib.md5(usedforsecurity=False) if checksum else None
    itemsize = layout.dtype.itemsize
    row_bytes = layout.size_x * itemsize
    try:
        with archive.open(data_info) as stream:
            data = _stream_rows(
                path,
                stream,
                layout.n * itemsize,
                (row * row_bytes, (row + 1) * row_bytes),
                md5,
                layout.link,
            )
        valid_bytes = (
            _read_member(path, archive, valid_info, valid_info.file_size)
            if valid_info is not None
            else None
        )
    except ZIP_ERRORS as exc:
        raise DamagedX3PError(f"{path}: {layout.link} cannot be read ({one_line(exc)})") from None
    if md5 is not None and md5.hexdigest().lower() != str(checksum).lower():
        raise DamagedX3PError(
            f"{path}: the MD5 checksum of {layout.link} does not match main.xml; the file is "
            "damaged"
        )
    return data, valid_bytes


def _heights(
    layout: _Layout, data: bytes, valid_bytes: bytes | None, row: int
) -> tuple[NDArray[np.float64], NDArray[np.bool_] | None]:
    """Heights [µm] of the row (NaN where the validity bits say invalid) and the bits."""
    with np.errstate(over="ignore", invalid="ignore"):
        z = (
            np.frombuffer(data, dtype=layout.dtype).astype(np.float64) * layout.z_increment
            + layout.z_offset
        ) * (_METRE_TO_UM)
    if valid_bytes is None:
        return z, None
    size_x = layout.size_x
    first = row * size_x
    chunk = np.frombuffer(valid_bytes[first // 8 : (first + size_x + 7) // 8 + 1], np.uint8)
    bits = np.unpackbits(chunk, bitorder="little")
    valid = bits[first % 8 : first % 8 + size_x].astype(bool)
    return np.where(valid, z, np.nan), valid


def _metadata(
    path: Path,
    root: ElementTree.Element,
    layout: _Layout,
    row: int,
    valid: NDArray[np.bool_] | None,
) -> dict[str, Any]:
    """Source, format, matrix, units, flagged points, the row's y and the instrument."""
    dy = _float(path, root, "Record1", "Axes", "CY", "Increment", default=0.0)
    y_offset = _float(path, root, "Record1", "Axes", "CY", "Offset", default=0.0)
    metadata: dict[str, Any] = {
        "source": str(path),
        "format": "x3p",
        "feature_type": layout.feature,
        "matrix": [layout.size_x, layout.size_y, layout.size_z],
        "units": units_record("m", "m", _X3P_UNITS, _X3P_UNITS, _METRE_TO_UM, _METRE_TO_UM),
        "z_data_type": layout.z_type,
        "n_flagged_invalid": int((~valid).sum()) if valid is not None else 0,
    }
    if layout.feature == "SUR":
        metadata["line"] = row
        metadata["line_y_um"] = (y_offset + dy * row) * _METRE_TO_UM
    instrument = {
        key: _text(root, "Record2", "Instrument", key)
        for key in ("Manufacturer", "Model", "Serial", "Version")
    }
    metadata["instrument"] = {k: v[:200] for k, v in instrument.items() if v}
    return metadata


def _read_archive(
    path: Path, archive: zipfile.ZipFile, *, line: int | None, max_points: int
) -> RawProfile:
    root = _main_xml(path, archive)
    layout = _layout(path, root, max_points)
    members = _members(path, archive, root, layout)
    row = _row(path, layout, line)
    data, valid_bytes = _read_row(path, archive, root, layout, members, row)
    z, valid = _heights(layout, data, valid_bytes, row)
    x = (layout.x_offset + layout.dx * np.arange(layout.size_x)) * _METRE_TO_UM
    metadata = _metadata(path, root, layout, row, valid)
    return RawProfile(x, z, x_resolution=0.0, metadata=metadata)
