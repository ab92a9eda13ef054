"""Exception hierarchy of splinecontact.

Every error the package raises on purpose derives from :class:`SplineContactError`, so a script
(or the command line) can catch one class. Each subclass names one kind of mistake; its message
says what was wrong, with the offending index or value, and what to do about it.

Stage-specific modules may define further subclasses of the classes below (for example the
readers in :mod:`splinecontact.io` subclass :class:`ProfileReadError`).
"""

from __future__ import annotations

__all__ = [
    "BEMError",
    "CohesiveStressError",
    "ContactLawError",
    "GridMismatchError",
    "GridNotIncreasingError",
    "GridNotUniformError",
    "NoConvergenceError",
    "NonFiniteValueError",
    "OutputError",
    "OutputExistsError",
    "ParameterError",
    "PoissonRatioError",
    "ProfileError",
    "ProfileRangeError",
    "ProfileReadError",
    "ProfileShapeError",
    "ProfileTypeError",
    "SplineContactError",
    "StudyConfigError",
    "StudyStoreError",
    "TooFewPointsError",
    "UnknownContactLawError",
    "UnsafeOutputError",
    "WorkOfAdhesionError",
    "YieldStrengthError",
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


# --- outputs ----------------------------------------------------------------------------------


class OutputError(SplineContactError):
    """An output file or folder cannot be written under the package's output rule."""


class OutputExistsError(OutputError):
    """The output exists and ``overwrite`` was not given."""


class UnsafeOutputError(OutputError):
    """Writing there could destroy something splinecontact did not create (or an input)."""


# --- contact laws -----------------------------------------------------------------------------


class ContactLawError(ParameterError):
    """A local contact law (adhesive or elastic–plastic) was given an invalid parameter."""


class UnknownContactLawError(ContactLawError):
    """The name of a contact law is not one the package knows."""


class WorkOfAdhesionError(ContactLawError):
    """The work of adhesion w [J/m²] is negative, not finite or not a number."""


class CohesiveStressError(ContactLawError):
    """The cohesive (Dugdale) stress σ0 [GPa] is not a finite number > 0."""


class YieldStrengthError(ContactLawError):
    """The yield strength or the hardness [GPa] is not a finite number > 0 (or both or neither
    were given)."""


class PoissonRatioError(ContactLawError):
    """Poisson's ratio ν is outside [0, 0.5)."""
