"""Errors of the profile readers (defined in :mod:`splinecontact.errors`, re-exported here).

All are subclasses of :class:`~splinecontact.ProfileReadError`. Each message names the file
(and the line, column or index where that helps) and says what to do about it.
"""

from __future__ import annotations

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
    ReadOptionError,
    UnitError,
    UnknownFormatError,
    X3PError,
)

__all__ = [
    "CorruptFileError",
    "EmptyFileError",
    "FileTooLargeError",
    "FormatMismatchError",
    "LineSelectionError",
    "MalformedRowError",
    "MissingExtraError",
    "MissingSpacingError",
    "MissingUnitsError",
    "NoDataError",
    "ReadOptionError",
    "UnitError",
    "UnknownFormatError",
    "X3PError",
]
