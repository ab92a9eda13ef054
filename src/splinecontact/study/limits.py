"""Ceilings on the size of a study, checked before anything is allocated or written."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import StudyConfigError
from .config import StudyConfig

__all__ = ["StudyLimits", "check_limits"]


@dataclass(frozen=True)
class StudyLimits:
    """Ceilings on the size of a study, checked before anything is allocated or written.

    A valid study file can still describe a run that would exhaust memory or disk, or run for
    months. :func:`check_limits` refuses such a study with one line that names the ceiling and
    how to raise it (``--limit NAME=VALUE`` on the command line, ``limits=StudyLimits(...)`` in
    Python). The defaults are far above the paper's study (4000 realizations of 10⁶ points and
    1000 steps).

    Attributes
    ----------
    steps : int
        Most displacement increments of one simulation [1] (default 10⁶).
    points_terms : int
        Most ``n_points × directions × (n_max + 1)`` of one generated profile [1]: the
        generator's work, one cosine per point and term (default 10¹⁰; the paper: 4.2·10⁸).
    grid_points : int
        Most points of the sweep grid (the product of the swept lists' lengths) [1]
        (default 10⁴).
    realizations : int
        Most realizations in the whole study, ``realizations × grid points`` [1] (default 10⁶).
    realization_points : int
        Most profile points simulated in the whole study, ``realizations × grid points ×
        n_points`` [1] (default 10¹¹; the paper: 4·10⁹).
    stored_values : int
        Most values of one per-step variable in the store, ``realizations × grid points ×
        (steps + 1)`` [1] (default 10⁸, 800 MB per variable in memory; the paper: 4·10⁶).
    """

    steps: int = 1_000_000
    points_terms: int = 10**10
    grid_points: int = 10_000
    realizations: int = 1_000_000
    realization_points: int = 10**11
    stored_values: int = 10**8

    @classmethod
    def parse(cls, items: Sequence[str], base: StudyLimits | None = None) -> StudyLimits:
        """Apply ``NAME=VALUE`` items (the CLI's ``--limit``) to ``base`` (default: defaults).

        Raises
        ------
        StudyConfigError
            Unknown name, or a value that is not a positive integer.
        """
        import dataclasses

        names = [f.name for f in dataclasses.fields(cls)]
        values = dataclasses.asdict(base or cls())
        for item in items:
            name, sep, text = item.partition("=")
            name = name.strip().replace("-", "_")
            if not sep or name not in names:
                raise StudyConfigError(
                    f"--limit {item!r}: give NAME=VALUE with NAME one of {', '.join(names)}"
                )
            try:
                number = float(text.replace("_", ""))
            except ValueError:
                number = math.nan
            if not (math.isfinite(number) and number >= 1 and number == int(number)):
                raise StudyConfigError(
                    f"--limit {item!r}: {text.strip()!r} is not a positive integer"
                )
            values[name] = int(number)
        return cls(**values)


def check_limits(config: StudyConfig, limits: StudyLimits | None = None) -> None:
    """Refuse a study above one of the ceilings of ``limits`` (see :class:`StudyLimits`).

    Parameters
    ----------
    config : StudyConfig
        The validated study.
    limits : StudyLimits, optional
        The ceilings (default: :class:`StudyLimits` ()).

    Raises
    ------
    StudyConfigError
        With one line naming the quantity, its value, the ceiling and how to raise it.
    """
    limits = StudyLimits() if limits is None else limits
    grid = config.n_grid_points
    total = grid * config.study.realizations
    n_points = max(config.parameter_values("n_points"))
    terms = max(config.parameter_values("directions")) * (max(config.parameter_values("n_max")) + 1)
    checks = [
        ("steps", config.max_steps, "steps of one simulation"),
        ("points_terms", n_points * terms, "n_points × directions × (n_max + 1) of one profile"),
        ("grid_points", grid, "points of the sweep grid"),
        ("realizations", total, "realizations × grid points"),
        ("realization_points", total * n_points, "realizations × grid points × n_points"),
        (
            "stored_values",
            total * (config.max_steps + 1),
            "realizations × grid points × (steps + 1)",
        ),
    ]
    for name, value, what in checks:
        ceiling = getattr(limits, name)
        if value > ceiling:
            raise StudyConfigError(
                f"study {config.study.name!r}: {what} = {value:,} is above the ceiling "
                f"{name} = {ceiling:,}; make the study smaller, or raise the ceiling with "
                f"--limit {name}={value} (Python: limits=StudyLimits({name}={value}))"
            )
