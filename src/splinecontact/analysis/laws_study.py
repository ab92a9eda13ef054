"""Adhesion and plasticity of rough pairs against D over an ensemble, with confidence bands.

:func:`laws_study` runs one load–unload cycle per realization under a contact law and reads it
with :mod:`splinecontact.analysis.laws` (pull-off force, work of separation, residual approach,
dissipated energy) and with the κ of eq. 15 generalized to an adhesive pair
(:func:`adhesive_kappa`). Energies are per unit thickness [mN·µm/µm].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..errors import ParameterError
from ._defaults import _MODEL_DEFAULTS
from .ensemble import confidence_halfwidth
from .laws import cycle_energy, unloading

__all__ = ["LAWS_STUDY_VARIABLES", "adhesive_kappa", "laws_study"]

#: Variables of :func:`laws_study` and their units.
LAWS_STUDY_VARIABLES: dict[str, str] = {
    "pull_off_force": "mN/µm",
    "work_of_separation": "mN·µm/µm",
    "residual_displacement": "µm",
    "residual_fraction": "1",
    "dissipated_energy": "mN·µm/µm",
    "kappa": "1",
    "zero_area_force": "mN/µm",
}


def adhesive_kappa(
    normal_force: ArrayLike,
    area: ArrayLike,
    rsq: float,
    e_star: float,
    *,
    fit_fraction: float = 0.3,
) -> tuple[float, float]:
    """κ of eq. 15 for a loading curve that may start in tension: (κ [1], F_0 [mN/µm]).

    With adhesion F_N is negative when the first contacts form, so A_S is not proportional to
    F_N; it is to F_N − F_0, where F_0 ≤ 0 is the force at vanishing area. A straight line
    A_S = s (F_N − F_0) is fitted by least squares over the loading steps with A_S > 0 and
    F_N ≤ F_0 + ``fit_fraction`` (F_max − F_0), and κ = R_Sq E* s. Without adhesion F_0 ≈ 0 and
    κ is the eq. 15 value.

    Parameters
    ----------
    normal_force, area : array_like
        F_N [mN/µm] and A_S [µm] on the loading steps (δ_N increasing).
    rsq : float
        R_Sq [1] (of the rough profile, or of the gap for rough-on-rough).
    e_star : float
        E* [GPa] (= mN/µm²).
    fit_fraction : float
        Fitted part of the load range above F_0, in (0, 1] [1].

    Returns
    -------
    (kappa, zero_area_force)
        NaN for both with fewer than 3 fitted steps.
    """
    if not 0.0 < fit_fraction <= 1.0:
        raise ParameterError(f"fit_fraction = {fit_fraction!r} must lie in (0, 1]")
    f = np.asarray(normal_force, dtype=float)
    a = np.asarray(area, dtype=float)
    touching = np.isfinite(f) & np.isfinite(a) & (a > 0.0)
    if np.count_nonzero(touching) < 3:
        return math.nan, math.nan
    f0_guess = float(np.min(f[touching]))
    top = f0_guess + fit_fraction * (float(np.max(f[touching])) - f0_guess)
    sel = touching & (f <= top)
    if np.count_nonzero(sel) < 3:
        return math.nan, math.nan
    slope, intercept = np.polyfit(f[sel], a[sel], 1)
    if not slope > 0.0:
        return math.nan, math.nan
    return float(rsq * e_star * slope), float(-intercept / slope)


def laws_study(
    dimensions: Any,
    seeds: Any,
    *,
    law: Any = None,
    flat: bool = True,
    n_points: int = 20_000,
    length: float = 2.0,
    load_fraction: float = 0.1,
    steps: int = 150,
    e_star: float = _MODEL_DEFAULTS["e_star"],
    fit_fraction: float = 0.3,
    confidence: float = 0.95,
    progress: Callable[[int, int], None] | None = None,
) -> xr.Dataset:
    """Pull-off, work of separation, residual approach, dissipation and κ against D.

    Each realization (``weierstrass_mandelbrot_pair(D, seed=s)``; the lower profile on a flat
    when ``flat``) starts apart at δ_N = −0.2 δ_max, is pressed to δ_max = ``load_fraction`` ×
    the lower peak-to-valley height in ``steps`` steps and pulled back to −0.2 δ_max in ``steps``
    steps (a closed cycle; the pair separates when the law's reach is below 0.2 δ_max), under
    ``law`` (displacement control).

    Parameters
    ----------
    dimensions : sequence of float
        Fractal dimensions D [1].
    seeds : sequence of int
        One realization per seed [1].
    law : contact law, optional
        From :func:`splinecontact.contact.make_law` (Hertz when omitted).
    flat : bool
        Rough-on-flat (default) instead of rough-on-rough.
    n_points : int
        Grid points [1].
    length : float
        Profile length [µm].
    load_fraction : float
        δ_max as a fraction of the lower peak-to-valley height [1].
    steps : int
        Steps of the loading and of the unloading [1].
    e_star : float
        E* [GPa].
    fit_fraction : float
        Load range of the κ fit (:func:`adhesive_kappa`) [1].
    confidence : float
        Level of the Student-t confidence interval of the ensemble mean [1].
    progress : callable, optional
        Called as ``progress(done, total)`` after each realization [1] (nothing is printed).

    Returns
    -------
    xarray.Dataset
        Every :data:`LAWS_STUDY_VARIABLES` name on (dimension, realization) — ``pull_off_force``
        (−min F_N on unloading, ≥ 0), ``work_of_separation``, ``residual_displacement`` and
        ``residual_fraction`` (= residual / δ_max; NaN when the force never returns to 0 while
        compressive, e.g. with adhesion), ``dissipated_energy`` (∫ F_N dδ_N over the cycle),
        ``kappa`` and ``zero_area_force`` (:func:`adhesive_kappa`) — plus ``<name>_mean`` and
        ``<name>_ci`` (half-width) on (dimension); units in attributes.
    """
    from ..contact import Segment, simulate
    from ..generate import weierstrass_mandelbrot_pair

    dims = [float(d) for d in dimensions]
    seed_list = [int(s) for s in seeds]
    if not dims or not seed_list:
        raise ParameterError("give at least one dimension and one seed")
    if steps < 3:
        raise ParameterError(f"steps = {steps!r} must be at least 3")
    values = {name: np.full((len(dims), len(seed_list)), np.nan) for name in LAWS_STUDY_VARIABLES}
    for i, dimension in enumerate(dims):
        for j, seed in enumerate(seed_list):
            lower, upper = weierstrass_mandelbrot_pair(
                dimension, seed=seed, n_points=n_points, length=length
            )
            depth = load_fraction * lower.peak_to_valley
            path = [  # δ_N targets [µm]: apart, pressed, pulled apart again (a closed cycle)
                Segment(normal=-0.2 * depth, steps=1),
                Segment(normal=depth, steps=steps),
                Segment(normal=-0.2 * depth, steps=steps),
            ]
            result = simulate(
                lower,
                "flat" if flat else upper,
                path=path,
                law=law,
                e_star=e_star,
                mu0=0.0,
                diagnostics=False,
            )
            top = steps + 1
            u = unloading(result, top, top + steps)
            kappa_value, zero_area = adhesive_kappa(
                np.asarray(result.curves["normal_force"])[1 : top + 1],
                np.asarray(result.curves["contact_area"])[1 : top + 1],
                float(result.rsq_lower if flat else result.rsq_gap),
                e_star,
                fit_fraction=fit_fraction,
            )
            row = {
                "pull_off_force": -u.pull_off_force,
                "work_of_separation": u.work_of_separation,
                "residual_displacement": u.residual_displacement,
                "residual_fraction": u.residual_displacement / depth,
                "dissipated_energy": cycle_energy(result, 1, top + steps).work,
                "kappa": kappa_value,
                "zero_area_force": zero_area,
            }
            for name, value in row.items():
                values[name][i, j] = value
            if progress is not None:
                progress(i * len(seed_list) + j + 1, len(dims) * len(seed_list))
    coords = {"dimension": dims, "realization": np.arange(len(seed_list))}
    data: dict[str, Any] = {}
    for name, units in LAWS_STUDY_VARIABLES.items():
        v = xr.DataArray(values[name], dims=("dimension", "realization"), coords=coords)
        data[name] = v.assign_attrs(units=units)
        count = v.count("realization")
        data[f"{name}_mean"] = v.mean("realization").assign_attrs(units=units)
        half = confidence_halfwidth(v.std("realization", ddof=1).values, count.values, confidence)
        data[f"{name}_ci"] = xr.DataArray(half, dims=("dimension",), coords={"dimension": dims})
        data[f"{name}_ci"].attrs["units"] = units
    law_name = getattr(law, "name", "hertz") if law is not None else "hertz"
    return xr.Dataset(
        data,
        attrs={
            "law": law_name,
            "contact_type": "rough-on-flat" if flat else "rough-on-rough",
            "confidence": confidence,
            "load_fraction": load_fraction,
            "n_points": n_points,
            "length_um": length,
            "e_star_GPa": e_star,
        },
    )
