"""Shared fixtures and analytic profile builders for the tests."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

ANGSTROM = 1e-4  # [µm]


def circle_cap(x: NDArray[np.float64], radius: float, centre: float = 0.0) -> NDArray[np.float64]:
    """Heights [µm] of a circular peak of the given radius [µm], apex 0 at ``centre``.

    Written as −s²/(R + √(R² − s²)) so that it stays exact for radii up to 1e12 µm.
    """
    s = x - centre
    return -(s * s) / (radius + np.sqrt(radius * radius - s * s))


def circle_cup(x: NDArray[np.float64], radius: float, centre: float = 0.0) -> NDArray[np.float64]:
    """Heights [µm] of a circular valley (cup) of the given radius [µm], bottom 0 at ``centre``."""
    return -circle_cap(x, radius, centre)
