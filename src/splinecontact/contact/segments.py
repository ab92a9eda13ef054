"""Load-path descriptions: :class:`Segment`, their validation and their text form.

A path is a sequence of :class:`Segment`. It starts at zero minimum gap and no tangential shift
(δ_N = 0, u_T = 0, step 0); each segment moves linearly, in ``steps`` equal increments, from the
end of the previous one to its targets:

* ``Segment(normal=δ_N, tangential=u_T, steps=n)`` — displacement control [µm];
* ``Segment(normal_force=F_N, tangential=u_T, steps=n)`` — F_N [mN/µm] is held at every step of
  the segment while u_T moves.

The driver that follows a path is :mod:`splinecontact.contact.loadpath`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import LoadPathError

__all__ = ["Segment", "parse_path", "validate_path"]


def _finite(name: str, value: Any, unit: str, index: int | None) -> float:
    where = "" if index is None else f"segment {index}: "
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise LoadPathError(f"{where}{name} = {value!r} must be a number{unit}")
    value = float(value)
    if not math.isfinite(value):
        raise LoadPathError(f"{where}{name} = {value!r}{unit} must be finite")
    return value


@dataclass(frozen=True, kw_only=True)
class Segment:
    """One straight piece of a load path of the upper body.

    Give at most one of ``normal`` (displacement control) or ``normal_force`` (force control);
    with neither, δ_N stays where the previous segment left it (displacement control).

    Parameters
    ----------
    normal : float, optional
        Target normal displacement δ_N [µm] at the segment's end (positive presses the bodies
        together; 0 is zero minimum gap at u_T = 0; negative values separate them). Default:
        keep the current δ_N (unless ``normal_force`` is given).
    normal_force : float, optional
        Normal force F_N [mN/µm] held at every step of the segment (> 0).
    tangential : float, optional
        Target tangential displacement u_T [µm] of the upper body, positive along +x. Default:
        keep the current shift.
    steps : int
        Number of equal increments [1] (≥ 1).
    """

    normal: float | None = None
    normal_force: float | None = None
    tangential: float | None = None
    steps: int

    def __post_init__(self) -> None:
        if self.normal is not None and self.normal_force is not None:
            raise LoadPathError(
                f"Segment(normal={self.normal!r}, normal_force={self.normal_force!r}): give "
                "at most one of normal (δ_N [µm], displacement control) or normal_force "
                "(F_N [mN/µm], force control)"
            )
        if self.normal is not None:
            object.__setattr__(self, "normal", _finite("normal", self.normal, " µm", None))
        if self.normal_force is not None:
            force = _finite("normal_force", self.normal_force, " mN/µm", None)
            if not force > 0:
                raise LoadPathError(
                    f"normal_force = {force!r} mN/µm must be > 0 (to separate the bodies use "
                    "a displacement segment, normal=...)"
                )
            object.__setattr__(self, "normal_force", force)
        if self.tangential is not None:
            object.__setattr__(
                self, "tangential", _finite("tangential", self.tangential, " µm", None)
            )
        steps = self.steps
        if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or int(steps) < 1:
            raise LoadPathError(f"steps = {steps!r} must be an integer ≥ 1")
        object.__setattr__(self, "steps", int(steps))

    @property
    def force_controlled(self) -> bool:
        """True when the segment holds F_N instead of prescribing δ_N."""
        return self.normal_force is not None


def validate_path(path: Iterable[Segment]) -> tuple[Segment, ...]:
    """Check a load path and return it as a tuple.

    Raises
    ------
    LoadPathError
        The path is empty, or an element is not a :class:`Segment`.
    """
    if isinstance(path, Segment | str | bytes):
        raise LoadPathError(
            f"path = {path!r}: give a sequence of Segment, e.g. path=[Segment(normal=0.001, "
            "steps=100)]"
        )
    try:
        items = tuple(path)
    except TypeError:
        raise LoadPathError(f"path = {path!r} is not a sequence of Segment") from None
    if not items:
        raise LoadPathError("path is empty: give at least one Segment")
    for index, item in enumerate(items):
        if not isinstance(item, Segment):
            raise LoadPathError(
                f"path[{index}] = {item!r} is not a Segment; build it with "
                "splinecontact.Segment(normal=..., tangential=..., steps=...)"
            )
    return items


_SPEC_KEYS = {"normal": "normal", "force": "normal_force", "normal_force": "normal_force",
              "tangential": "tangential", "steps": "steps"}  # fmt: skip


def parse_path(text: str) -> tuple[Segment, ...]:
    """A load path from text: segments separated by ``;``, each ``key=value`` pairs by ``,``.

    Keys: ``normal`` (δ_N [µm]), ``force`` or ``normal_force`` (F_N [mN/µm]), ``tangential``
    (u_T [µm]) and ``steps`` [1], e.g. ``"normal=0.001,steps=200; tangential=0.02,steps=400"``.

    Raises
    ------
    LoadPathError
        Empty text, an unknown key, a repeated key, a value that is not a number, or a bad
        segment (see :class:`Segment`).
    """
    parts = [p.strip() for p in text.split(";")]
    if not any(parts):
        raise LoadPathError(f"path {text!r} is empty: give e.g. 'normal=0.001,steps=200'")
    segments = []
    for index, part in enumerate(parts):
        if not part:
            raise LoadPathError(f"path {text!r}: segment {index} is empty (stray ';')")
        kwargs: dict[str, Any] = {}
        for item in part.split(","):
            key, sep, value = item.partition("=")
            key = key.strip().lower()
            if not sep or key not in _SPEC_KEYS:
                raise LoadPathError(
                    f"path segment {index} {part!r}: {item.strip()!r} is not key=value with key "
                    "normal, force, tangential or steps"
                )
            name = _SPEC_KEYS[key]
            if name in kwargs:
                raise LoadPathError(f"path segment {index} {part!r}: {key} given twice")
            try:
                kwargs[name] = int(value) if name == "steps" else float(value)
            except ValueError:
                raise LoadPathError(
                    f"path segment {index} {part!r}: {key} = {value.strip()!r} is not "
                    + ("an integer" if name == "steps" else "a number")
                ) from None
        if "steps" not in kwargs:
            raise LoadPathError(f"path segment {index} {part!r}: give steps=N")
        try:
            segments.append(Segment(**kwargs))
        except LoadPathError as exc:
            raise LoadPathError(f"path segment {index} {part!r}: {exc}") from None
    return tuple(segments)
