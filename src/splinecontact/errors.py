"""Exception hierarchy of splinecontact.

Every error the package raises on purpose derives from :class:`SplineContactError`, so a script
(or the command line) can catch one class. Each subclass names one kind of mistake; its message
says what was wrong, with the offending index or value, and what to do about it.

Every public exception class of the package is defined here (this module imports nothing of
the package, so every stage can import it); the stage modules re-export the ones they raise
(``splinecontact.io.X3PError`` is ``splinecontact.errors.X3PError``).
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "BEMError",
    "BEMGridError",
    "BEMInputError",
    "BEMParameterError",
    "CorruptFileError",
    "CropError",
    "DamagedX3PError",
    "DuplicatePositionError",
    "EmptyFileError",
    "FileTooLargeError",
    "FormatMismatchError",
    "FullContactError",
    "GridMismatchError",
    "GridNotIncreasingError",
    "GridNotUniformError",
    "GridOrderError",
    "InstrumentFileError",
    "LineSelectionError",
    "MalformedRowError",
    "MissingExtraError",
    "MissingSpacingError",
    "MissingUnitsError",
    "NegativeLoadError",
    "NoConvergenceError",
    "NoDataError",
    "NonFiniteValueError",
    "NonPeriodicProfileError",
    "NumpyFileError",
    "OutputError",
    "OutputExistsError",
    "OutputWriteError",
    "ParameterError",
    "PreprocessingOptionError",
    "ProfileError",
    "ProfileRangeError",
    "ProfileReadError",
    "ProfileShapeError",
    "ProfileTypeError",
    "ReadOptionError",
    "ResultSchemaError",
    "SplineContactError",
    "StudyConfigError",
    "StudyStoreError",
    "TooFewPointsError",
    "UndefinedPointsError",
    "UnitError",
    "UnknownFormatError",
    "UnsafeOutputError",
    "X3PError",
]


class SplineContactError(Exception):
    """Base class of every error raised on purpose by splinecontact."""


# --- profiles -------------------------------------------------------------------------------


class ProfileError(SplineContactError, ValueError):
    """A profile's grid or heights are not acceptable."""


class ProfileShapeError(ProfileError):
    """``x`` and ``z`` are not one-dimensional arrays of the same length."""


class ProfileTypeError(ProfileError):
    """``x`` or ``z`` is not an array of real numbers (complex, text, ``None``, objects)."""


class ProfileRangeError(ProfileError):
    """A grid position, grid step or height is finite but outside the range the computation can
    represent without overflow or underflow (see ``splinecontact.profile.LENGTH_LIMIT``)."""


class TooFewPointsError(ProfileError):
    """The profile has fewer points than the method needs."""


class NonFiniteValueError(ProfileError):
    """A grid position or height is NaN or infinite."""


class GridNotIncreasingError(ProfileError):
    """The grid ``x`` is not strictly increasing."""


class GridNotUniformError(ProfileError):
    """The grid ``x`` is not uniformly spaced within the stated tolerance."""


class GridMismatchError(ProfileError):
    """Two profiles that must share a grid (upper and lower body) do not."""


# --- parameters -----------------------------------------------------------------------------


class ParameterError(SplineContactError, ValueError):
    """A numerical parameter is outside its valid range (for example D ∉ [1, 2] or E* ≤ 0)."""


# --- reading measured data ------------------------------------------------------------------


class ProfileReadError(SplineContactError):
    """A profile file could not be read or understood."""


# The readers of :mod:`splinecontact.io`: each message names the file (and the line, column or
# index where that helps) and says what to do about it.


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

    The limit is ``max_points`` points per file (default
    :data:`~splinecontact.io.DEFAULT_MAX_POINTS`, 10⁸) and a bound on the length of a text line;
    it is checked before anything is allocated, so a compressed "bomb" or a header declaring
    10¹⁰ points is refused at once. Pass a larger ``max_points=`` to
    :func:`~splinecontact.io.read_profile` for a genuine scan that big.
    """


class CorruptFileError(ProfileReadError):
    """The file is damaged or inconsistent: a bad checksum or compressed stream, a member
    shorter or longer than its header declares, stored metadata of the wrong type, ..."""


class DamagedX3PError(X3PError, CorruptFileError):
    """An X3P archive is damaged: bad zip structure, checksum, compressed stream or sizes."""


class NumpyFileError(ProfileReadError):
    """A NumPy file does not hold a profile in a form splinecontact understands."""


class InstrumentFileError(ProfileReadError):
    """SurfaceTopography could not read an instrument file (damaged, or unsupported variant)."""


# --- preprocessing measured profiles -----------------------------------------------------------


class UndefinedPointsError(NonFiniteValueError):
    """The scan has undefined points (NaN, or flagged invalid by the instrument)."""


class GridOrderError(GridNotIncreasingError):
    """``x`` steps back somewhere in the scan."""


class DuplicatePositionError(GridNotIncreasingError):
    """Two or more points share the same ``x``."""


class CropError(ProfileError):
    """The crop range leaves too few points or is not a valid range."""


class PreprocessingOptionError(ParameterError):
    """A preprocessing option has an invalid value."""


# --- studies --------------------------------------------------------------------------------


class StudyConfigError(SplineContactError):
    """A study file is invalid (unknown key, wrong type, value out of range)."""


class StudyStoreError(SplineContactError):
    """A study store cannot be used (belongs to another study, is damaged, ...)."""


# --- boundary element reference solver -----------------------------------------------------


class BEMError(SplineContactError):
    """Invalid input to the boundary element reference solver."""


class NoConvergenceError(BEMError):
    """An iterative solver did not reach its tolerance within its iteration limit."""


class BEMInputError(BEMError, ValueError):
    """Bad input to the boundary element solver (base of the specific errors below)."""


class BEMGridError(BEMInputError):
    """The grid cannot be used: too few points, bad spacing, mismatched bodies, NaN heights."""


class NonPeriodicProfileError(BEMGridError):
    """The profile does not wrap around smoothly, so it cannot be one period of a surface."""


class BEMParameterError(BEMInputError):
    """A solver parameter (E*, tolerance, iteration limit) is out of range."""


class NegativeLoadError(BEMInputError):
    """A negative mean pressure or force was requested (the contact is non-adhesive)."""


class FullContactError(BEMInputError):
    """The load or mean gap asked for lies at or beyond full contact."""


# --- results --------------------------------------------------------------------------------


class ResultSchemaError(SplineContactError, ValueError):
    """A result object is built without a variable its schema requires."""


# --- outputs ----------------------------------------------------------------------------------


class OutputError(SplineContactError):
    """An output file or folder cannot be written under the package's output rule."""


class OutputWriteError(OutputError):
    """A result file cannot be written (unknown suffix, or its writer's backend is missing)."""


class OutputExistsError(OutputError):
    """The output exists and ``overwrite`` was not given."""


class UnsafeOutputError(OutputError):
    """Writing there could destroy something splinecontact did not create (or an input)."""


# === contact stage (splinecontact.contact) =======================================================


class LoadPathError(ParameterError):
    """A load path or one of its segments is malformed."""


class ForceControlError(LoadPathError):
    """A force-controlled segment asks for a normal force the contact cannot carry."""


__all__ += ["ForceControlError", "LoadPathError"]


# === analysis stage (splinecontact.analysis, splinecontact.reproduce) =========================

__all__ += ["AnalysisError", "FrictionAnalysisError"]


class AnalysisError(SplineContactError, ValueError):
    """A study Dataset cannot be analysed as asked (missing variable, no successful run, ...)."""


class FrictionAnalysisError(ParameterError):
    """A result cannot give the requested friction quantity (no path, no tangential segment)."""


# === study stage (splinecontact.study) ===========================================================

__all__ += ["StudyExecutionError"]


class StudyExecutionError(SplineContactError):
    """Some batches of a study could not be run (a worker died, the scheduler is unreachable, ...).

    Attributes
    ----------
    summary : splinecontact.study.StudySummary or None
        The state of the store when the run stopped (None if it never started).
    """

    def __init__(self, message: str, summary: Any = None) -> None:
        super().__init__(message)
        self.summary: Any = summary
