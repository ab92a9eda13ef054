"""Errors of the profile readers: all subclasses of :class:`~splinecontact.ProfileReadError`.

Each message names the file (and the line, column or index where that helps) and says what to
do about it.
"""

from __future__ import annotations

from ..errors import ProfileReadError

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


class EmptyFileError(ProfileReadError):
    """The file is empty (or holds only whitespace)."""


class NoDataError(ProfileReadError):
    """The file has a header (or comments) but no rows of numbers."""


class MalformedRowError(ProfileReadError):
    """A data row cannot be parsed: wrong number of columns, mixed delimiters, bad number."""


class MissingUnitsError(ProfileReadError):
    """Neither the file nor the ``unit=`` argument says in which unit the values are."""


class UnitError(ProfileReadError):
    """A unit is unknown, or the file and the ``unit=`` argument disagree."""


class MissingSpacingError(ProfileReadError):
    """A file of heights only needs the grid spacing (``spacing=`` [µm])."""


class UnknownFormatError(ProfileReadError):
    """The format of the file cannot be recognised."""


class FormatMismatchError(UnknownFormatError):
    """The content of the file contradicts its extension (e.g. binary data in a ``.csv``)."""


class X3PError(ProfileReadError):
    """An X3P file (ISO 5436-2 / ISO 25178-72) is malformed or uses an unsupported feature."""


class LineSelectionError(ProfileReadError):
    """A line of areal data must be chosen, or the chosen line does not exist."""


class MissingExtraError(ProfileReadError):
    """The file needs an optional dependency that is not installed."""


class ReadOptionError(ProfileReadError):
    """A reading option does not fit the file (e.g. ``spacing=`` for a file with an x column)."""


class FileTooLargeError(ProfileReadError):
    """The file (or a member of an archive) is larger than the reader's stated limit.

    The limit is ``max_points`` points per file (default :data:`DEFAULT_MAX_POINTS`, 10⁸) and
    a bound on the length of a text line; it is checked before anything is allocated, so a
    compressed "bomb" or a header declaring 10¹⁰ points is refused at once. Pass a larger
    ``max_points=`` to :func:`~splinecontact.io.read_profile` for a genuine scan that big.
    """


class CorruptFileError(ProfileReadError):
    """The file is damaged or inconsistent: a bad checksum or compressed stream, a member
    shorter or longer than its header declares, stored metadata of the wrong type, ..."""
