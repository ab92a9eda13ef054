"""Friction against the fractal dimension: simulate an ensemble of load paths per D and reduce it.

:func:`friction_study` runs the load paths itself (it is a small study runner, not a reader of a
study store) and reduces each result with the quantities of :mod:`splinecontact.analysis.friction`;
it sits in the analysis stage because it needs them and the ensemble intervals.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import xarray as xr

from ..errors import ParameterError
from ._defaults import _MODEL_DEFAULTS
from .ensemble import confidence_halfwidth
from .friction import (
    dilatancy,
    dissipated_energy,
    force_control_counts,
    interface_stiffness,
    normal_stiffness,
    segment_steps,
    static_friction,
    tangential_stiffness,
)

__all__ = ["FRICTION_STUDY_VARIABLES", "friction_study"]

#: Per-realisation quantities of :func:`friction_study`: name -> (units, description).
FRICTION_STUDY_VARIABLES: dict[str, tuple[str, str]] = {
    "mu_s": (
        "1",
        "static friction coefficient max|F_T|/F_N while sliding at constant F_N (steps that "
        "missed the held F_N, force_control = 3, skipped)",
    ),
    "k_t": ("GPa", "tangential stiffness −dF_T/du_T at u_T = 0 (first increment)"),
    "k_n": ("GPa", "normal stiffness dF_N/dδ_N just before sliding (fit over 20 increments)"),
    "stiffness_ratio": ("1", "k_T/k_N of the finite differences (unstable for rough pairs)"),
    "interface_stiffness_ratio": (
        "1",
        "k_T/k_N of the stuck contacts before sliding (interface_stiffness; stable)",
    ),
    "dissipation": ("mN·µm/µm", "frictional work dissipated over one full cycle at constant F_N"),
    "dilatancy": (
        "µm",
        "rise of the upper body over the first slide at constant F_N (an end step that missed "
        "the held F_N, force_control = 3, counts with the δ_N of the jump across it)",
    ),
    "normal_force": ("mN/µm", "F_N held while sliding"),
    "force_held": ("1", "share of the constant-F_N steps where F_N is met to 1e−6"),
    "force_fixed_set": (
        "1",
        "share of the constant-F_N steps held with a contact set eq. 9 would not accept as a "
        "whole (force_control = 2: the held F_N lies inside a jump of the free model)",
    ),
}


def friction_study(
    dimensions: Any,
    seeds: Any,
    *,
    flat: bool = False,
    n_points: int = 100_000,
    length: float = 10.0,
    load_fraction: float = 0.1,
    travel: float = 0.05,
    normal_steps: int = 200,
    tangential_steps: int = 250,
    e_star: float = _MODEL_DEFAULTS["e_star"],
    g_star: float | None = None,
    mu0: float = _MODEL_DEFAULTS["mu0"],
    confidence: float = 0.95,
) -> Any:
    """μ_s, k_T, k_T/k_N, dissipation and dilatancy against D over an ensemble of pairs.

    Each realisation (``weierstrass_mandelbrot_pair(D, seed=s)``) is pressed to
    ``load_fraction`` × the lower peak-to-valley height in ``normal_steps`` steps; F_N reached
    there is then held while the upper body slides +travel, −travel, +travel
    (``tangential_steps``, 2×, 2× steps). k_T and k_N come from a separate run whose first
    tangential increment is travel/1000 at constant δ_N: k_T is the first difference there (the
    derivative at u_T = 0), k_N the least-squares slope of F_N(δ_N) over the last 20 normal
    increments (single normal increments are dominated by contacts appearing or vanishing).

    Parameters
    ----------
    dimensions : sequence of float
        Fractal dimensions D [1].
    seeds : sequence of int
        One realisation per seed [1].
    flat : bool
        Rough-on-flat instead of rough-on-rough.
    n_points : int
        Grid points [1].
    length : float
        Profile length [µm].
    load_fraction : float
        δ_N before sliding, as a fraction of the lower peak-to-valley height [1].
    travel : float
        Sliding amplitude [µm].
    normal_steps, tangential_steps : int
        Steps of the pressing and of the first slide [1].
    e_star, g_star : float
        E*, G* [GPa] (G* default E*/2.6).
    mu0 : float
        μ0 [1].
    confidence : float
        Level of the Student-t confidence interval of the ensemble mean [1].

    Returns
    -------
    xarray.Dataset
        Every ``FRICTION_STUDY_VARIABLES`` name on (dimension, realization), plus
        ``<name>_mean`` and ``<name>_ci`` (half-width) on (dimension); units in attributes.
    """
    from ..contact import Segment, simulate
    from ..generate import weierstrass_mandelbrot_pair

    dims = [float(d) for d in dimensions]
    seed_list = [int(s) for s in seeds]
    if not dims or not seed_list:
        raise ParameterError("give at least one dimension and one seed")
    values = {
        name: np.full((len(dims), len(seed_list)), np.nan) for name in FRICTION_STUDY_VARIABLES
    }
    for a, dimension in enumerate(dims):
        for b, seed in enumerate(seed_list):
            lower, upper = weierstrass_mandelbrot_pair(
                dimension, seed=seed, n_points=n_points, length=length
            )
            body: Any = "flat" if flat else upper
            d = load_fraction * lower.peak_to_valley
            material: dict[str, Any] = {"e_star": e_star, "g_star": g_star, "mu0": mu0}
            press = Segment(normal=d, steps=normal_steps)
            first = simulate(
                lower,
                body,
                path=[press, Segment(tangential=travel / 1000, steps=1)],
                record_contacts=[normal_steps],
                **material,
            )
            force = float(first.normal_force[normal_steps])
            if not force > 0:
                continue
            cycle = [
                press,
                Segment(normal_force=force, tangential=travel, steps=tangential_steps),
                Segment(normal_force=force, tangential=-travel, steps=2 * tangential_steps),
                Segment(normal_force=force, tangential=travel, steps=2 * tangential_steps),
            ]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # misses counted below
                result = simulate(lower, body, path=cycle, **material)
            bounds = segment_steps(result)
            held = np.isfinite(np.asarray(result.curves["normal_force_target"]))
            fn = np.asarray(result.curves["normal_force"])[held]
            counts = force_control_counts(result)
            k_t = tangential_stiffness(first)
            k_n = normal_stiffness(first, increments=min(20, normal_steps))
            row = {
                "mu_s": static_friction(result).mu_s,
                "k_t": k_t,
                "k_n": k_n,
                "stiffness_ratio": k_t / k_n if k_n != 0 else np.nan,
                "interface_stiffness_ratio": interface_stiffness(first, normal_steps).ratio,
                "dissipation": dissipated_energy(result, bounds[1][1], bounds[3][1]),
                "dilatancy": dilatancy(result, 1),
                "normal_force": force,
                "force_held": float(np.mean(np.abs(fn / force - 1) <= 1e-6)),
                "force_fixed_set": counts[2] / sum(counts.values()),
            }
            for name, value in row.items():
                values[name][a, b] = value
    data: dict[str, Any] = {}
    for name, (units, description) in FRICTION_STUDY_VARIABLES.items():
        v = values[name]
        data[name] = (("dimension", "realization"), v, {"units": units, "long_name": description})
        count = np.sum(np.isfinite(v), axis=1)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            mean = np.nanmean(v, axis=1)
            std = np.nanstd(v, axis=1, ddof=1)
        data[f"{name}_mean"] = ("dimension", mean, {"units": units, "long_name": f"mean {name}"})
        data[f"{name}_ci"] = (
            "dimension",
            confidence_halfwidth(std, count, confidence),
            {"units": units, "long_name": f"{confidence:.0%} confidence half-width of {name}"},
        )
    coords = {
        "dimension": ("dimension", dims, {"units": "1", "long_name": "fractal dimension D"}),
        "realization": ("realization", seed_list, {"units": "1", "long_name": "seed"}),
    }
    attrs = {
        "contact_type": "rough-on-flat" if flat else "rough-on-rough",
        "n_points": n_points,
        "length": length,
        "load_fraction": load_fraction,
        "travel": travel,
        "e_star": e_star,
        "g_star": e_star / 2.6 if g_star is None else g_star,
        "mu0": mu0,
        "confidence": confidence,
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)
