"""Checks of the arguments of the public functions, done before anything is allocated.

Every check raises :class:`~splinecontact.errors.ParameterError` with the parameter's name, the
value given and what is accepted, so a wrong type (``None``, a string, ``True``) or a value that
would overflow never reaches numpy or a compiled kernel.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from .errors import ParameterError

__all__ = ["LENGTH_LIMIT", "MAGNITUDE_LIMIT", "check_integer", "check_real", "check_seed"]

#: Largest length or height accepted anywhere [µm] (10⁵⁰ µm; squares and cubes of lengths and
#: of grid slopes then stay far from the floating-point limit of about 1.8·10³⁰⁸).
LENGTH_LIMIT = 1e50

#: Largest modulus [GPa] or friction coefficient [1] accepted (10⁵⁰): a force, modulus × length,
#: then stays far from the floating-point limit.
MAGNITUDE_LIMIT = 1e50


def _unit(unit: str) -> str:
    return f" {unit}" if unit else ""


def check_real(
    name: str,
    value: Any,
    unit: str = "",
    *,
    minimum: float | None = None,
    maximum: float | None = None,
    exclusive_minimum: bool = False,
    note: str = "",
) -> float:
    """``value`` as a finite float within the bounds; :class:`ParameterError` otherwise.

    ``bool``, strings, ``None`` and complex numbers are refused (a real number is expected).
    """
    suffix = f" ({note})" if note else ""
    in_unit = f" in {unit}" if unit else ""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise ParameterError(
            f"{name} = {value!r} is not a real number; give a number{in_unit}{suffix}"
        )
    number = float(value)
    if not math.isfinite(number):
        raise ParameterError(
            f"{name} = {number!r}{_unit(unit)} is not finite; give a finite number"
        )
    if minimum is not None:
        if exclusive_minimum and not number > minimum:
            raise ParameterError(
                f"{name} = {number!r}{_unit(unit)} must be > {minimum:g}{_unit(unit)}{suffix}"
            )
        if not exclusive_minimum and not number >= minimum:
            raise ParameterError(
                f"{name} = {number!r}{_unit(unit)} must be ≥ {minimum:g}{_unit(unit)}{suffix}"
            )
    if maximum is not None and number > maximum:
        raise ParameterError(
            f"{name} = {number!r}{_unit(unit)} must be ≤ {maximum:g}{_unit(unit)}{suffix}"
        )
    return number


def check_integer(
    name: str,
    value: Any,
    *,
    minimum: int,
    maximum: int | None = None,
    note: str = "",
    raise_with: str = "",
) -> int:
    """``value`` as an int within the bounds; :class:`ParameterError` otherwise.

    Integers (Python or numpy) and floats with an integral value (``1e6``) are accepted; ``bool``,
    fractions, NaN, infinities, strings and ``None`` are refused. ``raise_with`` names the keyword
    that raises ``maximum``.
    """
    suffix = f" ({note})" if note else ""
    number: int | None = None
    if isinstance(value, bool | np.bool_):
        number = None
    elif isinstance(value, numbers.Integral):
        number = int(value)
    elif isinstance(value, numbers.Real):
        as_float = float(value)
        if math.isfinite(as_float) and as_float.is_integer():
            number = int(as_float)
    if number is None:
        raise ParameterError(f"{name} = {value!r} must be an integer ≥ {minimum}{suffix}")
    if number < minimum:
        raise ParameterError(f"{name} = {number} must be an integer ≥ {minimum}{suffix}")
    if maximum is not None and number > maximum:
        how = f"; pass {raise_with}= to allow more" if raise_with else ""
        ceiling = f"{maximum:_}".replace("_", " ")
        raise ParameterError(f"{name} = {number} is above the ceiling {ceiling}{suffix}{how}")
    return number


def check_seed(seed: Any, name: str = "seed") -> None:
    """Refuse a seed that is not ``None``, a non-negative int, a SeedSequence or a Generator."""
    if seed is None or isinstance(seed, np.random.SeedSequence | np.random.Generator):
        return
    if isinstance(seed, bool | np.bool_) or not isinstance(seed, numbers.Integral):
        raise ParameterError(
            f"{name} = {seed!r} is not a seed; give a non-negative integer, a "
            "numpy.random.SeedSequence, a numpy.random.Generator or None (fresh entropy)"
        )
    if int(seed) < 0:
        raise ParameterError(f"{name} = {int(seed)} is negative; give a non-negative integer")
