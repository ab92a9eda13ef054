"""What the adhesive and elastic–plastic laws change on a load–unload path of a rough pair.

Each function reads the per-step curves of one :class:`~splinecontact.results.SimulationResult`
of a load path (``simulate(..., path=..., law=...)``): δ_N [µm] and F_N [mN/µm] on the ``step``
dimension. Energies are per unit thickness [mN·µm/µm].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ParameterError

__all__ = ["CycleEnergy", "Unloading", "cycle_energy", "unloading"]


def _curves(result: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    curves = result.curves if hasattr(result, "curves") else result
    return (
        np.asarray(curves["displacement"], dtype=float),
        np.asarray(curves["normal_force"], dtype=float),
    )


def _check_range(start: int, stop: int, n: int) -> None:
    if not (0 <= start < stop < n):
        raise ParameterError(
            f"steps {start}..{stop} are not a range of the result's {n} steps; give "
            "0 ≤ start < stop < number of steps"
        )


@dataclass(frozen=True)
class CycleEnergy:
    """Energy exchanged over steps ``start..stop`` (trapezoidal rule in δ_N).

    Attributes
    ----------
    work : float
        ∫ F_N dδ_N [mN·µm/µm]: over a closed cycle (same δ_N at both ends), the energy the
        contact dissipated (≥ 0; 0 for a history-free law without jumps).
    """

    work: float


def cycle_energy(result: Any, start: int, stop: int) -> CycleEnergy:
    """∫ F_N dδ_N over the steps ``start..stop`` [mN·µm/µm] (a hysteresis loop when closed)."""
    d, f = _curves(result)
    _check_range(start, stop, d.size)
    seg = slice(start, stop + 1)
    return CycleEnergy(float(np.trapezoid(f[seg], d[seg])))


@dataclass(frozen=True)
class Unloading:
    """The unloading branch of a load path, steps ``start..stop`` (δ_N decreasing).

    Attributes
    ----------
    pull_off_force : float
        Most tensile F_N on the branch [mN/µm] (≤ 0 with adhesion; 0 without).
    pull_off_displacement : float
        δ_N where it occurs [µm].
    work_of_separation : float
        Work done against the adhesive (tensile) force while separating,
        −∫ min(F_N, 0) dδ_N over the branch with δ_N decreasing [mN·µm/µm] (≥ 0).
    residual_displacement : float
        δ_N where the compressive force first returns to 0 on unloading [µm], extrapolated along
        the last two compressive steps (exact for an elastic unloading line): the residual
        approach of a plastically flattened pair (NaN if F_N never drops to 0 on the branch).
    """

    pull_off_force: float
    pull_off_displacement: float
    work_of_separation: float
    residual_displacement: float


def unloading(result: Any, start: int, stop: int) -> Unloading:
    """Pull-off force, work of separation and residual approach of the unloading branch.

    Parameters
    ----------
    result : SimulationResult
        A load-path result (or a mapping of its curves).
    start, stop : int
        First and last step of the unloading branch (δ_N non-increasing) [1].

    Raises
    ------
    ParameterError
        The steps are not a range of the result, or δ_N increases on it.
    """
    d, f = _curves(result)
    _check_range(start, stop, d.size)
    seg = slice(start, stop + 1)
    ds, fs = d[seg], f[seg]
    if np.any(np.diff(ds) > 0):
        raise ParameterError(
            f"steps {start}..{stop}: δ_N increases there; give an unloading branch"
        )
    k = int(np.argmin(fs))
    tensile = np.minimum(fs, 0.0)
    work = float(np.trapezoid(tensile, ds))  # δ_N decreasing: ∫ (negative) dδ (negative) ≥ 0
    residual = float("nan")
    for i in range(fs.size - 1):
        if fs[i] > 0.0 >= fs[i + 1]:
            # Along the last two compressive steps (the elastic unloading line) when there are
            # two, else between the last compressive step and the first one without force.
            j = i - 1 if i >= 1 and fs[i - 1] > fs[i] else i + 1
            t = fs[i] / (fs[i] - fs[j])
            residual = float(ds[i] + t * (ds[j] - ds[i]))
            break
    return Unloading(
        pull_off_force=min(float(fs[k]), 0.0),
        pull_off_displacement=float(ds[k]),
        work_of_separation=work,
        residual_displacement=residual,
    )
