"""Length units of measured data and their conversion to µm."""

from __future__ import annotations

import re

from ._errors import UnitError

__all__ = ["UNIT_FACTORS", "normalize_unit", "unit_in_text"]

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

_BRACKETED = re.compile(r"[\[(]\s*([^\])]*?)\s*[\])]")


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
    match = _BRACKETED.search(text)
    if match:
        raw = match.group(1)
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
