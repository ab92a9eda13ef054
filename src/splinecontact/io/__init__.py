"""Reading and writing measured line scans.

:func:`read_profile` turns a measurement file into a :class:`~splinecontact.Profile` (x and z
in µm, heights pointing out of the body); :func:`read_raw` stops before the checks and
returns the :class:`~splinecontact.preprocess.RawProfile` arrays; :func:`write_profile`
writes ``.npz`` or ``.csv``/``.txt`` files that read back unchanged.

Formats (``format=``; detected from the extension, else from the content):

``"table"``
    Text columns ``x, z`` (optionally a ``valid`` column, e.g. ``.hfm`` stylus files), with or
    without header, separated by semicolons, commas or white space; or one column of heights
    with ``spacing=``. Units from the header (``x [mm]``, ``z (nm)``, ``Lateral um``, a line
    ``[mm];[mm];[1/0]``), else from ``unit=``; refused when neither gives them.
``"dektak"``
    Bruker Dektak CSV export (parameter block, then a ``Scan Data`` section).
``"x3p"``
    ISO 5436-2 / ISO 25178-72 X3P: a profile, or row ``line=`` of areal data.
``"npy"``, ``"npz"``
    NumPy arrays (units from ``unit=`` unless written by :func:`write_profile`).
``"surfacetopography"``
    Any other instrument format (every extension SurfaceTopography registers, e.g. ``.sur
    .opd .datx .gwy .tiff .xlsx .stp .top .bcrf .nc``, and binary ``.dat`` such as Zygo
    MetroPro), through the optional SurfaceTopography package
    (``pip install "splinecontact[instruments]"``); its errors become
    :class:`InstrumentFileError`.

Origin of x: positions stated by the file are kept (text tables, X3P offsets); a format that
gives only a grid spacing starts at x = 0 (heights with ``spacing=``, areal ``.npy``, every
uniform scan read through SurfaceTopography, which does not report the file's origin).
``Preprocessing(zero_origin=True)`` starts any profile at 0.

Untrusted files: every reader checks what a file declares against what it holds and against
``max_points`` (default :data:`DEFAULT_MAX_POINTS` = 10⁸ points per file) before allocating,
reads text line by line (at most :data:`MAX_LINE_CHARS` characters per line), parses X3P
``main.xml`` without document types or entities, and never unpickles.

Every read error is a :class:`~splinecontact.ProfileReadError` naming the file (and line or
index) and what to do; irregular data are refused by :func:`~splinecontact.preprocess.to_profile`
unless a :class:`~splinecontact.preprocess.Preprocessing` option allows the correction.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from ..errors import (
    CorruptFileError,
    EmptyFileError,
    FileTooLargeError,
    FormatMismatchError,
    LineSelectionError,
    MalformedRowError,
    MissingExtraError,
    MissingSpacingError,
    MissingUnitsError,
    NoDataError,
    ProfileReadError,
    ReadOptionError,
    UnitError,
    UnknownFormatError,
    X3PError,
)
from ..preprocess import Preprocessing, RawProfile, to_profile
from ..profile import Profile
from ..results import jsonable
from ._dektak import is_dektak, read_dektak
from ._instruments import (
    AMBIGUOUS_EXTENSIONS,
    INSTRUMENT_EXTENSIONS,
    InstrumentFileError,
    read_with_surfacetopography,
)
from ._limits import DEFAULT_MAX_POINTS, MAX_LINE_CHARS, check_max_points
from ._lines import has_utf16_bom
from ._numpy import NumpyFileError, read_npy, read_npz
from ._text import METADATA_COMMENT, read_table
from ._units import UNIT_FACTORS, normalize_unit
from ._x3p import ZIP_ERRORS, DamagedX3PError, read_x3p

__all__ = [
    "DEFAULT_MAX_POINTS",
    "FORMATS",
    "MAX_LINE_CHARS",
    "UNIT_FACTORS",
    "CorruptFileError",
    "DamagedX3PError",
    "EmptyFileError",
    "FileTooLargeError",
    "FormatMismatchError",
    "InstrumentFileError",
    "LineSelectionError",
    "MalformedRowError",
    "MissingExtraError",
    "MissingSpacingError",
    "MissingUnitsError",
    "NoDataError",
    "NumpyFileError",
    "ProfileReadError",
    "ReadOptionError",
    "UnitError",
    "UnknownFormatError",
    "X3PError",
    "detect_format",
    "read_profile",
    "read_raw",
    "write_profile",
]

#: Format names accepted by ``format=``.
FORMATS = ("table", "dektak", "x3p", "npy", "npz", "surfacetopography")

_TEXT_EXTENSIONS = frozenset({".csv", ".txt", ".dat", ".hfm", ".tsv", ".xy", ".prf", ".asc"})
_BINARY_SUFFIX_FORMAT = {".x3p": "x3p", ".npy": "npy", ".npz": "npz"}
_ZIP_MAGIC = b"PK\x03\x04"
_NPY_MAGIC = b"\x93NUMPY"


def _content_kind(head: bytes) -> str:
    """``"empty"``, ``"zip"``, ``"npy"``, ``"binary"`` or ``"text"`` from the first bytes."""
    if not head.strip():
        return "empty"
    if has_utf16_bom(head):
        return "text"
    if head.startswith(_ZIP_MAGIC):
        return "zip"
    if head.startswith(_NPY_MAGIC):
        return "npy"
    if b"\x00" in head:
        return "binary"
    control = sum(1 for b in head if b < 9 or 13 < b < 32)
    return "binary" if control > 0.01 * len(head) else "text"


def _zip_kind(path: Path) -> str:
    import zipfile

    try:
        with zipfile.ZipFile(path) as archive:
            names = archive.namelist()
    except ZIP_ERRORS:
        return "binary"
    if "main.xml" in names:
        return "x3p"
    if names and all(name.endswith(".npy") for name in names):
        return "npz"
    return "zip"


def detect_format(path: str | os.PathLike[str]) -> str:
    """Format of a file, from its extension, checked against (or else taken from) its content.

    Raises
    ------
    EmptyFileError
        The file is empty.
    FormatMismatchError
        The content contradicts the extension (e.g. binary data in a ``.csv``).
    UnknownFormatError
        Neither extension nor content identify the format.
    """
    p = Path(path)
    with open(p, "rb") as handle:
        head = handle.read(8192)
    kind = _content_kind(head)
    suffix = p.suffix.lower()
    if kind == "empty":
        raise EmptyFileError(f"{p}: the file is empty; nothing to read — export the scan again")
    if kind == "zip":
        kind = _zip_kind(p)
    names = {
        "x3p": "an X3P archive",
        "npz": "a NumPy .npz archive",
        "npy": "a NumPy .npy array",
        "zip": "a zip archive without main.xml (not X3P)",
        "binary": "binary data",
        "text": "text",
    }

    if suffix in _TEXT_EXTENSIONS:
        if kind != "text" and suffix in AMBIGUOUS_EXTENSIONS:
            return "surfacetopography"  # e.g. a binary Zygo MetroPro .dat
        if kind != "text":
            hint = f"pass format='{kind}' or rename it" if kind in FORMATS else "check the file"
            raise FormatMismatchError(
                f"{p}: the extension {suffix} says text, but the file holds {names[kind]}; {hint}"
            )
        return _text_format(p)
    if suffix in _BINARY_SUFFIX_FORMAT:
        expected = _BINARY_SUFFIX_FORMAT[suffix]
        if kind != expected:
            hint = f"pass format='{kind}' or rename it" if kind in FORMATS else "check the file"
            if kind == "text":
                hint = "rename it (.csv/.txt) or pass format='table'"
            raise FormatMismatchError(
                f"{p}: the extension {suffix} says {names[expected]}, but the file holds "
                f"{names[kind]}; {hint}"
            )
        return expected
    if suffix in INSTRUMENT_EXTENSIONS:
        return "surfacetopography"
    # extension silent: the content decides
    if kind in ("x3p", "npz", "npy"):
        return kind
    if kind == "text":
        return _text_format(p)
    raise UnknownFormatError(
        f"{p}: unrecognised {names[kind]} (extension {suffix or 'none'}); if it is an instrument "
        'file, install the instruments extra (pip install "splinecontact[instruments]") and '
        "pass format='surfacetopography', otherwise export the scan as x, z text with units"
    )


def _text_format(path: Path) -> str:
    return "dektak" if is_dektak(path) else "table"


def read_raw(
    path: str | os.PathLike[str],
    *,
    format: str | None = None,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> RawProfile:
    """Read a measured line scan into raw arrays (µm), without checks or corrections.

    Parameters are those of :func:`read_profile`.
    """
    raw = _read_raw(
        Path(path),
        format=format,
        unit=unit,
        height_unit=height_unit,
        spacing=spacing,
        line=line,
        max_points=check_max_points(max_points),
    )
    return _with_provenance(raw, Path(path))


def _with_provenance(raw: RawProfile, path: Path) -> RawProfile:
    """Add ``file``; for files written by :func:`write_profile`, restore the stored metadata.

    A profile written by :func:`write_profile` reads back with its own metadata (``source``
    stays e.g. ``"weierstrass_mandelbrot"``, earlier preprocessing steps are kept), plus the
    reading record (``file``, ``format``, ``units``).
    """
    metadata = dict(raw.metadata)
    stored = metadata.pop("stored_metadata", None)
    if isinstance(stored, Mapping) and stored:
        merged = {str(k): v for k, v in stored.items()}
        merged.update({k: v for k, v in metadata.items() if k != "source"})
        merged.setdefault("source", str(path))
        metadata = merged
    metadata["file"] = str(path)
    return RawProfile(raw.x, raw.z, rows=raw.rows, x_resolution=raw.x_resolution, metadata=metadata)


def _read_raw(
    p: Path,
    *,
    format: str | None,
    unit: str | None,
    height_unit: str | None,
    spacing: float | None,
    line: int | None,
    max_points: int,
) -> RawProfile:
    if line is not None and (isinstance(line, bool) or not isinstance(line, int | np.integer)):
        raise ReadOptionError(f"line={line!r} must be a whole row number (0, 1, ...)")
    if spacing is not None:
        try:
            spacing = float(spacing)
        except (TypeError, ValueError):
            raise ReadOptionError(f"spacing={spacing!r} must be a number [µm]") from None
    if format is None:
        fmt = detect_format(p)
    else:
        fmt = str(format).lower()
        if fmt not in FORMATS:
            raise ReadOptionError(f"format={format!r} is not one of {', '.join(FORMATS)}")
    if unit is not None:
        normalize_unit(unit, what="unit=")
    if height_unit is not None:
        normalize_unit(height_unit, what="height_unit=")
    if line is not None and fmt == "dektak":
        raise ReadOptionError(f"{p}: line= is only for areal data (x3p, npy, instruments)")
    if fmt in ("table", "dektak"):
        with open(p, "rb") as handle:
            head = handle.read(8192)
        if _content_kind(head) not in ("text", "empty"):
            raise FormatMismatchError(f"{p}: format={fmt!r} was asked for, but the file is binary")
        if fmt == "dektak":
            if not is_dektak(p):
                raise NoDataError(
                    f"{p}: no 'Scan Data' line; not a Dektak CSV export (try format='table')"
                )
            if spacing is not None:
                raise ReadOptionError(f"{p}: a Dektak export has positions; drop spacing=")
            return read_dektak(p, unit=unit, height_unit=height_unit, max_points=max_points)
        return read_table(
            p,
            unit=unit,
            height_unit=height_unit,
            spacing=spacing,
            line=None if line is None else int(line),
            max_points=max_points,
        )
    if fmt == "x3p":
        if unit is not None or height_unit is not None or spacing is not None:
            raise ReadOptionError(
                f"{p}: X3P files state their units (metres) and spacing; drop unit=/spacing="
            )
        return read_x3p(p, line=line, max_points=max_points)
    if fmt in ("npy", "npz"):
        read_numpy = read_npy if fmt == "npy" else read_npz
        return read_numpy(
            p,
            unit=unit,
            height_unit=height_unit,
            spacing=spacing,
            line=line,
            max_points=max_points,
        )
    return read_with_surfacetopography(p, unit=unit, line=line, max_points=max_points)


def read_profile(
    path: str | os.PathLike[str],
    *,
    format: str | None = None,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
    preprocessing: Preprocessing | None = None,
    max_points: int = DEFAULT_MAX_POINTS,
) -> Profile:
    """Read a measured line scan as a :class:`~splinecontact.Profile` (x, z in µm).

    Parameters
    ----------
    path : str or path-like
        The file.
    format : str, optional
        One of ``FORMATS``; by default detected from the extension, else from the content.
    unit : str, optional
        Unit of the values when the file does not state it (``"µm"``/``"um"``, ``"nm"``,
        ``"mm"``, ``"m"``, ``"Å"``/``"A"``). Refused if it contradicts the file.
    height_unit : str, optional
        Unit of the heights if it differs from that of the positions (default: ``unit``).
    spacing : float, optional
        Grid spacing [µm] for files of heights only (one text column, 1-D ``.npy``).
    line : int, optional
        Row (0-based) of areal data (X3P ``SUR``, 2-D ``.npy``, instrument files) to read.
    preprocessing : Preprocessing, optional
        What may be done to irregular data (undefined points, order, duplicates, non-uniform
        grid, cropping, form removal); the default refuses irregular data and changes nothing.
    max_points : int, optional
        Largest number of points [1] a file may hold or declare (an areal file counts all its
        points; a text table its rows). Default ``DEFAULT_MAX_POINTS`` = 10⁸, far above any
        real line scan; checked before anything is allocated, so a compressed "bomb" or a
        forged header is refused at once with ``FileTooLargeError``. Raise it for a genuine
        scan that large.

    Returns
    -------
    Profile
        ``metadata`` records ``file`` and ``source`` (both the file; for a file written by
        :func:`write_profile`, ``source`` and the other stored metadata are restored),
        ``format``, ``units`` (file units, where they came from and the factors to µm) and
        ``preprocessing`` (the steps applied, after any stored ones).

    Raises
    ------
    ProfileReadError
        The file cannot be read (subclasses name the problem: ``EmptyFileError``,
        ``NoDataError``, ``MalformedRowError``, ``MissingUnitsError``, ``UnitError``,
        ``FormatMismatchError``, ``UnknownFormatError``, ``X3PError``, ``MissingExtraError``,
        ``FileTooLargeError`` (beyond ``max_points``, or a text line beyond ``MAX_LINE_CHARS``
        characters), ``CorruptFileError`` (damaged archive, checksum, sizes or stored
        metadata), ...).
    ProfileError
        The data are irregular and ``preprocessing`` does not allow the correction (see
        :func:`splinecontact.preprocess.to_profile`).
    OSError
        The file cannot be opened.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from splinecontact import read_profile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = pathlib.Path(folder) / "scan.csv"
    ...     _ = path.write_text("x [um],z [nm]\\n0,0\\n0.5,100\\n1.0,-100\\n1.5,50\\n2.0,0\\n")
    ...     profile = read_profile(path)
    >>> profile.n_points, profile.dx
    (5, 0.5)
    >>> profile.z  # heights converted from nm to µm
    array([ 0.  ,  0.1 , -0.1 ,  0.05,  0.  ])
    """
    raw = read_raw(
        path,
        format=format,
        unit=unit,
        height_unit=height_unit,
        spacing=spacing,
        line=line,
        max_points=max_points,
    )
    return to_profile(raw, preprocessing)


# --- writing ----------------------------------------------------------------------------------


def write_profile(profile: Profile, path: str | os.PathLike[str]) -> Path:
    """Write a profile so that :func:`read_profile` reads it back unchanged.

    Parameters
    ----------
    profile : Profile
        Positions and heights [µm].
    path : str or path-like
        Target file; the extension chooses the format: ``.npz`` (arrays ``x``, ``z`` [µm] and
        ``metadata``, a JSON string with ``units`` and the profile's metadata) or ``.csv`` /
        ``.txt`` (a comment line with the metadata as JSON, a header ``x [µm], z [µm]``, then
        one ``x, z`` row per point with 17 significant digits, so values read back exactly).

    Returns
    -------
    Path
        The file written. It is written to a temporary name first and renamed, so a failure
        leaves nothing behind.

    Raises
    ------
    ReadOptionError
        The extension is not ``.npz``, ``.csv`` or ``.txt``.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in (".npz", ".csv", ".txt"):
        raise ReadOptionError(
            f"{p}: cannot write {suffix or 'files without extension'}; use .npz, .csv or .txt"
        )
    stored = {
        "units": {"x": "µm", "z": "µm"},
        "profile_metadata": jsonable(dict(profile.metadata)),
    }
    tmp = p.with_name(f".{p.name}.tmp-{os.getpid()}{suffix}")
    try:
        if suffix == ".npz":
            with open(tmp, "wb") as handle:
                np.savez(
                    handle,
                    x=np.asarray(profile.x),
                    z=np.asarray(profile.z),
                    metadata=np.array(json.dumps(stored, ensure_ascii=False)),
                )
        else:
            with open(tmp, "w", encoding="utf-8", newline="\n") as handle:
                handle.write(f"{METADATA_COMMENT} {json.dumps(stored, ensure_ascii=False)}\n")
                handle.write("x [µm], z [µm]\n")
                for xi, zi in zip(profile.x.tolist(), profile.z.tolist(), strict=True):
                    handle.write(f"{xi!r}, {zi!r}\n")
        os.replace(tmp, p)
    finally:
        if tmp.exists():
            tmp.unlink()
    return p
