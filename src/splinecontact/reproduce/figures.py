"""The inputs of the paper's figures, made once at the top, for ``reproduce`` and ``plot``.

A study store keeps curves and statistics, not the 10⁶-point profiles. The illustrative figures
(Figs. 3a, 4, 5, 8, 9) and the measured Hurst exponents of Fig. 12 need profiles, so they are
regenerated here, ONCE each, from the study's seed rule (realization 0: the lower profile of
every D, and the pair at the focus D, whose lower profile is the one of Fig. 3a), together with
their splines and the one short simulation Fig. 9 draws; then they are handed down to
:mod:`splinecontact.plotting`, which only draws.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .. import analysis
from ..errors import SplineContactError
from ..plotting import IllustrativeInputs, build_figures, drawable_study

__all__ = ["FigureInputs", "draw_figures", "figure_inputs", "hurst_dataset", "illustrative_inputs"]


def _generator_kwargs(params: Mapping[str, Any]) -> dict[str, Any]:
    from ..generate import GENERATOR_PARAMETERS

    return {n: params[n] for n in GENERATOR_PARAMETERS if n in params}


def _simulate_kwargs(params: Mapping[str, Any]) -> dict[str, Any]:
    from ..contact import SIMULATION_PARAMETERS

    return {n: params[n] for n in SIMULATION_PARAMETERS if params.get(n) is not None}


def _scalar(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


def illustrative_inputs(
    *,
    dimensions: Sequence[float] = (1.0, 1.2, 1.4, 1.6, 1.8, 1.9),
    params: Mapping[str, Any] | None = None,
    seed: int = 2015,
    alphas: Sequence[float] = (1.0, 2.0, 3.0),
    focus_dimension: float = 1.4,
    study_seed: bool = False,
    final_displacement: float | None = None,
) -> IllustrativeInputs:
    """Generate, fit and simulate, once each, what Figs. 3a, 4, 5, 8 and 9 draw.

    Profiles generated: one per D of ``dimensions`` (Fig. 3a) and the upper profile of the
    pair at ``focus_dimension`` (Figs. 4, 5, 8, 9) — ``len(dimensions) + 1`` profiles (one more
    if ``focus_dimension`` is not in ``dimensions`` or ``study_seed`` is false). Splines: the
    lower profile at each α of ``alphas`` and at the simulation's α (reused when it is among
    them), the upper at the simulation's α. Fig. 9 simulates the pair up to a quarter of the
    steps, with the increments of the full run.

    Parameters
    ----------
    dimensions : sequence of float
        Fractal dimensions D [1] of Fig. 3a.
    params : mapping, optional
        Generator and simulation parameters (``n_points``, ``length`` [µm], ``e_star`` [GPa],
        ``alpha``, ``steps``, ...; unknown keys are ignored).
    seed : int
        Seed of the profiles.
    alphas : sequence of float
        Tightness exponents α [1] of Fig. 4 (eq. 3).
    focus_dimension : float
        D [1] of the pair used in Figs. 4, 5, 8 and 9 (paper Fig. 4: D = 1.4).
    study_seed : bool
        Interpret ``seed`` as a study seed: the profiles are then those of the study's
        realization 0 (lower profile of each D, and the rough-on-rough pair at
        ``focus_dimension``), by the seed rule of :func:`splinecontact.study.realization_seed`.
    final_displacement : float, optional
        Final displacement of the pair [µm] (e.g. the one the study stored for realization 0);
        default: the ``final_displacement_factor`` rule of :func:`splinecontact.simulate`.

    Returns
    -------
    IllustrativeInputs
    """
    from ..contact import simulate
    from ..generate import child_seed, weierstrass_mandelbrot
    from ..spline import fit_spline
    from ..study import realization_seed

    params = {k: _scalar(v) for k, v in dict(params or {}).items()}
    gen = _generator_kwargs(params)
    sim = _simulate_kwargs(params)
    alpha = float(sim.get("alpha", 2.0))
    x0 = float(sim.get("x0", 1.0))
    dims = [float(d) for d in dimensions]
    if study_seed:
        parent = realization_seed(int(seed), 0)
        lower_seeds: list[Any] = [child_seed(parent, 0)] * len(dims)
        focus_seeds = (child_seed(parent, 0), child_seed(parent, 1))
    else:
        spawned = np.random.SeedSequence(seed).spawn(len(dims) + 1)
        lower_seeds = list(spawned[: len(dims)])
        focus_seeds = (child_seed(spawned[-1], 0), child_seed(spawned[-1], 1))
    profiles = [
        weierstrass_mandelbrot(d, seed=s, **gen) for d, s in zip(dims, lower_seeds, strict=True)
    ]
    focus = float(focus_dimension)
    same = [i for i, d in enumerate(dims) if d == focus]
    lower = (
        profiles[same[0]]
        if same and study_seed
        else weierstrass_mandelbrot(focus, seed=focus_seeds[0], **gen)
    )
    upper = weierstrass_mandelbrot(focus, seed=focus_seeds[1], **gen)
    fits = [fit_spline(lower, alpha=a, x0=x0) for a in alphas]
    fit_l = next((f for f in fits if f.alpha == alpha), None) or fit_spline(
        lower, alpha=alpha, x0=x0
    )
    fit_u = fit_spline(upper, alpha=alpha, x0=x0)

    steps = int(sim.pop("steps", 1000))
    step = max(1, steps // 4)
    if final_displacement is None:
        factor = float(sim.pop("final_displacement_factor", 0.2))
        final = sim.pop("final_displacement", None)
        final_displacement = float(final) if final is not None else factor * float(np.ptp(lower.z))
    sim.pop("final_displacement", None)
    sim.pop("final_displacement_factor", None)
    # the same increments as the full run, stopped at the step drawn
    result = simulate(
        lower,
        upper,
        steps=step,
        final_displacement=float(final_displacement) * step / steps,
        record_contacts=[step],
        **sim,
    )
    return IllustrativeInputs(
        dimensions=tuple(dims),
        profiles=tuple(profiles),
        focus_dimension=focus,
        lower=lower,
        fits=tuple(fits),
        lower_fit=fit_l,
        upper_fit=fit_u,
        record=result.contacts[0],
        displacement=float(result.curves["displacement"][step]),
    )


def hurst_dataset(dims: Sequence[float], measured: Mapping[float, float]) -> xr.Dataset:
    """One measured Hurst exponent per D as ensemble statistics, beside the nominal H = 2 − D.

    Returns
    -------
    xarray.Dataset
        On ``dimension``: ``hurst_measured_{mean,std,count,...}`` and ``hurst_nominal`` [1].
    """
    values = xr.DataArray(
        np.array([[measured[d]] for d in dims]),
        dims=("dimension", "profile"),
        coords={"dimension": list(dims)},
        attrs={"units": "1", "long_name": "Hurst exponent from the PSD slope"},
    )
    out = analysis.ensemble_statistics(values, dim="profile", name="hurst_measured")
    out["hurst_nominal"] = xr.DataArray(
        analysis.nominal_hurst(dims),
        dims=("dimension",),
        attrs={"units": "1", "long_name": "H = 2 − D"},
    )
    return out


@dataclass(frozen=True)
class FigureInputs:
    """What the figures of a study need beyond the store, made once.

    Attributes
    ----------
    illustrative : IllustrativeInputs or None
        Profiles, splines and contact record of Figs. 3a, 4, 5, 8, 9 (None: not drawn).
    hurst : xarray.Dataset or None
        Measured Hurst exponents per D (None without a ``dimension`` sweep or when not asked).
    notes : list of str
        What could not be made, and why (the notes on the store itself are
        :func:`splinecontact.plotting.build_figures`' to give).
    """

    illustrative: IllustrativeInputs | None
    hurst: xr.Dataset | None
    notes: list[str] = field(default_factory=list)

    @property
    def measured_hurst(self) -> dict[float, float] | None:
        """D → mean measured Hurst exponent [1], or None."""
        if self.hurst is None:
            return None
        return {
            float(d): float(h)
            for d, h in zip(
                self.hurst["dimension"].values,
                self.hurst["hurst_measured_mean"].values,
                strict=True,
            )
        }


def _final_displacement(ds: xr.Dataset, focus: float) -> float | None:
    """The final displacement the study stored for realization 0 at ``focus`` [µm]."""
    if not ("final_displacement" in ds and "realization" in ds.dims):
        return None
    pick = ds["final_displacement"].sel({"dimension": focus})
    if "contact_type" in pick.dims:
        pick = (
            pick.sel(contact_type="rough-on-rough")
            if ("rough-on-rough" in pick["contact_type"].values)
            else pick.isel(contact_type=0)
        )
    pick = pick.isel({d: 0 for d in pick.dims})
    value = float(pick)
    return value if math.isfinite(value) and value > 0 else None


def figure_inputs(
    ds: xr.Dataset,
    *,
    illustrative: bool = True,
    hurst_profiles: int = 1,
    seed: int | None = None,
) -> FigureInputs:
    """Regenerate, once each, the profiles a study's figures need (the store does not keep them).

    The illustrative figures use the study's own realization-0 profiles (one lower profile per
    D and the upper profile at the focus D = 1.4, or the middle D), regenerated from the stored
    seed rule by :func:`illustrative_inputs`; their PSD slopes give the measured Hurst
    exponents of Fig. 12 (``hurst_profiles`` > 1 regenerates further realizations' lower
    profiles by :func:`splinecontact.analysis.study_hurst` for a mean).

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    illustrative : bool
        Make the inputs of Figs. 3a, 4, 5, 8, 9.
    hurst_profiles : int
        Lower profiles per D whose Hurst exponent is measured (1: the illustrative profiles,
        no extra generation; 0: none).
    seed : int, optional
        Study seed (default: the ``study_seed`` attribute, else 2015).

    Raises
    ------
    AnalysisError
        The study has nothing to draw (see :func:`splinecontact.plotting.drawable_study`).
    """
    ds, _ = drawable_study(ds)  # its notes are build_figures' to give
    notes: list[str] = []
    has_d = "dimension" in ds.dims
    dims = [float(d) for d in ds["dimension"].values] if has_d else [1.0, 1.4, 1.8]
    if seed is None:
        seed = int(ds.attrs.get("study_seed", 2015))
    inputs: IllustrativeInputs | None = None
    hurst: xr.Dataset | None = None
    if illustrative:
        focus = 1.4 if 1.4 in dims else dims[len(dims) // 2]
        params = dict(ds.attrs)
        if "alpha" in ds.dims:
            params["alpha"] = float(ds["alpha"].values[0])
        try:
            inputs = illustrative_inputs(
                dimensions=dims,
                params=params,
                seed=int(seed),
                focus_dimension=focus,
                study_seed=True,
                final_displacement=_final_displacement(ds, focus) if has_d else None,
            )
        except (SplineContactError, ValueError, FloatingPointError) as exc:
            notes.append(f"illustrative figures not drawn: {exc}")
        else:
            if has_d and hurst_profiles == 1:
                measured = analysis.measured_hurst(inputs.profiles)
                hurst = hurst_dataset(
                    dims, dict(zip(dims, (float(h) for h in measured), strict=True))
                )
    if has_d and hurst_profiles and hurst is None:
        hurst = analysis.study_hurst(ds, n_profiles=hurst_profiles)
    return FigureInputs(illustrative=inputs, hurst=hurst, notes=notes)


def draw_figures(
    ds: xr.Dataset,
    *,
    illustrative: bool = True,
    seed: int | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    hurst_profiles: int = 1,
) -> tuple[dict[str, Figure], xr.Dataset | None, list[str]]:
    """Every figure of the paper from a study Dataset, in memory: inputs made once, then drawn.

    :func:`figure_inputs` regenerates what the store does not keep, then
    :func:`splinecontact.plotting.build_figures` draws (see both for the parameters).

    Returns
    -------
    (dict, xarray.Dataset or None, list of str)
        Figures by name; the Hurst exponents (None without them); notes on what could not be
        drawn.

    Raises
    ------
    AnalysisError
        The study has nothing to draw.
    """
    inputs = figure_inputs(ds, illustrative=illustrative, hurst_profiles=hurst_profiles, seed=seed)
    figures, notes = build_figures(
        ds,
        illustrative=inputs.illustrative,
        measured_hurst=inputs.measured_hurst,
        kappa_options=kappa_options,
    )
    return figures, inputs.hurst, [*notes, *inputs.notes]
