"""Length units of measured data and their conversion to µm."""

from __future__ import annotations

import re

from ..errors import UnitError

__all__ = [
    "UNIT_FACTORS",
    "bracketed",
    "is_unit_word",
    "normalize_unit",
    "strip_bracketed",
    "unit_in_text",
    "units_record",
]

#: Factor converting one of each unit to µm.
UNIT_FACTORS: dict[str, float] = {
    "m": 1e6,
    "cm": 1e4,
    "mm": 1e3,
    "µm": 1.0,
    "nm": 1e-3,
    "Å": 1e-4,
    "pm": 1e-6,
}

_ALIASES: dict[str, str] = {
    "m": "m",
    "meter": "m",
    "meters": "m",
    "metre": "m",
    "metres": "m",
    "cm": "cm",
    "mm": "mm",
    "millimeter": "mm",
    "millimeters": "mm",
    "millimetre": "mm",
    "millimetres": "mm",
    "µm": "µm",  # micro sign U+00B5
    "μm": "µm",  # greek mu U+03BC
    "um": "µm",
    "micrometer": "µm",
    "micrometers": "µm",
    "micrometre": "µm",
    "micrometres": "µm",
    "micron": "µm",
    "microns": "µm",
    "nm": "nm",
    "nanometer": "nm",
    "nanometers": "nm",
    "nanometre": "nm",
    "nanometres": "nm",
    "å": "Å",  # U+00C5
    "Å": "Å",  # angstrom sign U+212B
    "angstrom": "Å",
    "angstroms": "Å",
    "angstroem": "Å",
    "ang": "Å",
    "pm": "pm",
    "picometer": "pm",
    "picometre": "pm",
}

_OPENERS = "[("
_CLOSERS = "])"


def bracketed(text: str) -> str | None:
    """Content (stripped) of the first bracketed part ``[...]`` or ``(...)`` of a text.

    One left-to-right scan (linear time): the first opening bracket that has a closing bracket
    after it, up to that closing bracket.
    """
    start = -1
    for i, c in enumerate(text):
        if start < 0 and c in _OPENERS:
            start = i
        elif start >= 0 and c in _CLOSERS:
            return text[start + 1 : i].strip()
    return None


def strip_bracketed(text: str) -> str:
    """The text without its bracketed parts (``x [mm]`` -> ``x ``); linear time."""
    out: list[str] = []
    pending: list[str] = []  # an opened bracket whose closing bracket has not come yet
    for c in text:
        if pending:
            if c in _CLOSERS:
                pending = []
            else:
                pending.append(c)
        elif c in _OPENERS:
            pending = [c]
        else:
            out.append(c)
    return "".join(out) + "".join(pending)


def _lookup(word: str) -> str | None:
    word = word.strip()
    if not word:
        return None
    if word == "A":  # a lone capital A is the ångström of many exports; lower-case a is not
        return "Å"
    if word in _ALIASES:
        return _ALIASES[word]
    lowered = word.lower()
    if lowered in ("a",):
        return None
    return _ALIASES.get(lowered)


def is_unit_word(word: str) -> bool:
    """Whether a word is a length unit (``µm``, ``microns``, ``A``...)."""
    return _lookup(word) is not None


def normalize_unit(unit: str, *, what: str = "unit") -> str:
    """Canonical name (``"µm"``, ``"nm"``, ``"mm"``, ``"m"``, ``"Å"``, ...) of a unit string.

    Raises
    ------
    UnitError
        The unit is not a known length unit.
    """
    canonical = _lookup(str(unit))
    if canonical is None:
        raise UnitError(
            f"{what} {unit!r} is not a known length unit; use one of "
            f"{', '.join(UNIT_FACTORS)} (um and A are accepted for µm and Å)"
        )
    return canonical


def unit_in_text(text: str) -> tuple[str | None, str | None]:
    """Find a length unit in a column title.

    Looks for a bracketed unit (``x [mm]``, ``z (nm)``), a slash form (``x/um``), or a unit as
    the last word (``Lateral um``, ``Raw Micrometer``).

    Returns
    -------
    (canonical, raw) : tuple
        The canonical unit and the text it was found in; ``(None, raw)`` when the title has a
        bracketed part that is not a length unit (e.g. ``[1/0]``), ``(None, None)`` when it has
        no unit at all.
    """
    raw = bracketed(text)
    if raw is not None:
        return _lookup(raw), raw
    stripped = text.strip()
    if "/" in stripped:
        raw = stripped.rsplit("/", 1)[1]
        found = _lookup(raw)
        if found is not None:
            return found, raw
    words = re.split(r"[\s_]+", stripped)
    if len(words) >= 2:
        found = _lookup(words[-1])
        if found is not None:
            return found, words[-1]
    return None, None


def units_record(
    x_unit: str, z_unit: str, x_from: str, z_from: str, x_factor: float, z_factor: float
) -> dict[str, str | float]:
    """The ``units`` entry of a read profile's metadata (every reader writes this one form).

    Parameters
    ----------
    x_unit, z_unit : str
        Units of the positions and heights as read (``"µm"`` for positions made from a
        spacing).
    x_from, z_from : str
        Where each unit came from (the file, an argument, a standard).
    x_factor, z_factor : float
        Factors converting them to µm [µm per unit].
    """
    return {
        "x": x_unit,
        "z": z_unit,
        "x_from": x_from,
        "z_from": z_from,
        "x_factor_to_um": x_factor,
        "z_factor_to_um": z_factor,
    }
