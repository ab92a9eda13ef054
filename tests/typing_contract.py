"""Type-checker contract (checked by mypy with the package, never imported by pytest).

mypy runs with ``warn_unused_ignores``: each ``type: ignore[...]`` below must be needed, so mypy
fails if a misspelt result attribute were ever accepted (for example through a ``__getattr__``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from splinecontact import SimulationResult
from splinecontact.bem import BEMPath
from splinecontact.compare import Comparison


def declared_fields(result: SimulationResult) -> tuple[NDArray[np.float64], float]:
    """The schema's variables are declared, typed attributes."""
    force: NDArray[np.float64] = result.normal_force
    slope: float = result.rsq_gap
    return force, slope


def misspelt_field_is_an_error(result: SimulationResult) -> object:
    """A typo is a type error, not a runtime lookup."""
    return result.normal_forse  # type: ignore[attr-defined]


def optional_path_field_needs_a_check(result: SimulationResult) -> float:
    """Load-path variables are Optional: using one unchecked is a type error."""
    return float(result.n_slipping[-1])  # type: ignore[index]


def datasets(path: BEMPath, comparison: Comparison) -> tuple[object, object]:
    """Both have ``to_xarray``."""
    return path.to_xarray(), comparison.to_xarray()
