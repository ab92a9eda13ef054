"""Study figures drawn from datasets: Figs. 10, 11, 12 and the force-split diagnostics.

Every plotting function takes ``ax=`` (a matplotlib ``Axes``; a new figure is made when it is
``None``) and returns the axes. The data are study Datasets (:mod:`splinecontact.study`) or
their ensemble statistics (:mod:`splinecontact.analysis`); nothing is simulated or generated
here. Axes carry their units: lengths µm (nanometre-sized ones in nm), forces mN per µm of
thickness.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from .. import analysis
from ..errors import ParameterError
from ..outputs import OutputFolder
from ._base import NM_PER_UM, dimension_colors, figure_of, new_axes, write_figures

__all__ = [
    "drawable_study",
    "make_study_figures",
    "plot_area_force",
    "plot_dimensionless_stiffness",
    "plot_force_displacement",
    "plot_force_split",
    "plot_kappa_hurst",
    "plot_separation_force",
    "study_figures",
]


def _hue_label(hue: str, value: Any) -> str:
    if hue == "dimension":
        return f"D = {float(value):.2g}"
    if isinstance(value, float | np.floating):
        return f"{hue} = {float(value):.3g}"
    return f"{hue} = {value}"


def _hue_values(ds: xr.Dataset, hue: str) -> Iterator[tuple[Any, xr.Dataset]]:
    if hue not in ds.dims:
        raise ParameterError(
            f"hue dimension {hue!r} is not a dimension of the data (dims {tuple(ds.dims)})"
        )
    extra = [d for d in ds.dims if d not in (hue, "sample", "realization")]
    if extra:
        raise ParameterError(
            f"select one value of {extra} first (e.g. ens.sel(contact_type='rough-on-rough'))"
        )
    for i in range(ds.sizes[hue]):
        sub = ds.isel({hue: i})
        yield sub[hue].values.item() if hue in sub.coords else i, sub


def _curve_family(
    ens: xr.Dataset,
    xname: str,
    yname: str,
    *,
    ax: Axes | None,
    hue: str,
    band: bool,
    xscale: float = 1.0,
    yscale: float = 1.0,
) -> Axes:
    ax = new_axes(ax)
    values = list(_hue_values(ens, hue))
    colors = (
        dimension_colors([v for v, _ in values])
        if all(isinstance(v, float | int | np.number) for v, _ in values)
        else {v: f"C{i}" for i, (v, _) in enumerate(values)}
    )
    for value, sub in values:
        key = float(value) if isinstance(value, float | int | np.number) else value
        x = sub[xname].values * xscale
        color = colors[key]
        ax.plot(
            x,
            sub[f"{yname}_mean"].values * yscale,
            color=color,
            lw=1.6,
            label=_hue_label(hue, value),
        )
        if band:
            ax.fill_between(
                x,
                sub[f"{yname}_ci_low"].values * yscale,
                sub[f"{yname}_ci_high"].values * yscale,
                color=color,
                alpha=0.2,
                lw=0,
            )
    ax.legend(fontsize="small", ncol=2 if len(values) > 5 else 1, frameon=False)
    return ax


def plot_force_displacement(
    ens: xr.Dataset,
    *,
    ax: Axes | None = None,
    hue: str = "dimension",
    variable: str = "normal_force",
    band: bool = True,
) -> Axes:
    """Fig. 10a: ensemble-mean F_N [mN/µm] against δ_N [nm], one curve per ``hue`` value.

    Parameters
    ----------
    ens : xarray.Dataset
        Output of :func:`splinecontact.analysis.ensemble_vs_displacement`, with every grid
        dimension but ``hue`` selected.
    ax : Axes, optional
        Axes to draw on.
    hue : str
        Dimension giving one curve each (default ``dimension``, the fractal dimension D).
    variable : str
        Variable to draw (``normal_force``, ``tangential_force``, ``contact_area``).
    band : bool
        Shade the confidence band of the mean.
    """
    ax = _curve_family(ens, "displacement", variable, ax=ax, hue=hue, band=band, xscale=NM_PER_UM)
    ax.set_xlabel("normal displacement δ_N [nm]")
    units = ens[f"{variable}_mean"].attrs.get("units", "")
    names = {
        "normal_force": "normal force F_N",
        "tangential_force": "tangential force F_T",
        "contact_area": "contact area A_S",
    }
    ax.set_ylabel(f"{names.get(variable, variable)} [{units}]")
    ax.set_title(f"mean ± {ens.attrs.get('confidence', 0.95):.0%} CI", fontsize="small")
    return ax


def plot_separation_force(
    ens: xr.Dataset, *, ax: Axes | None = None, hue: str = "dimension", band: bool = True
) -> Axes:
    """Fig. 10b: mean separation [nm] against F_N [mN/µm] (output of ``ensemble_vs_force``)."""
    ax = _curve_family(
        ens, "normal_force", "mean_separation", ax=ax, hue=hue, band=band, yscale=NM_PER_UM
    )
    ax.set_xlabel("normal force F_N [mN/µm]")
    ax.set_ylabel("mean separation [nm]")
    return ax


def plot_area_force(
    ens: xr.Dataset, *, ax: Axes | None = None, hue: str = "dimension", band: bool = True
) -> Axes:
    """Fig. 11b: contact area A_S [µm per µm thickness] against F_N [mN/µm]."""
    ax = _curve_family(ens, "normal_force", "contact_area", ax=ax, hue=hue, band=band)
    ax.set_xlabel("normal force F_N [mN/µm]")
    ax.set_ylabel("contact area A_S [µm]")
    return ax


def plot_dimensionless_stiffness(
    ens: xr.Dataset, *, ax: Axes | None = None, hue: str = "dimension", band: bool = True
) -> Axes:
    """Fig. 11a: k/E* [1] against F_N/(E* L0) [1], log–log (``dimensionless_stiffness``)."""
    ax = new_axes(ax)
    sub = ens.where(ens["dimensionless_load"] > 0)
    ax = _curve_family(
        sub, "dimensionless_load", "dimensionless_stiffness", ax=ax, hue=hue, band=band
    )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("dimensionless load F_N / (E* L0) [1]")
    ax.set_ylabel("dimensionless stiffness k / E* [1]")
    return ax


def plot_kappa_hurst(
    kappas: Mapping[str, xr.Dataset],
    *,
    ax: Axes | None = None,
    measured_hurst: Mapping[float, float] | None = None,
) -> Axes:
    """Fig. 12: κ [1] against the Hurst exponent H [1], with the Persson and Bush values.

    Parameters
    ----------
    kappas : mapping of str to xarray.Dataset
        Label (e.g. ``"rough-on-rough"``) → output of :func:`splinecontact.analysis.kappa`
        restricted to the ``dimension`` grid dimension.
    ax : Axes, optional
        Axes to draw on.
    measured_hurst : mapping of float to float, optional
        D → measured H (PSD slope); if given, κ is drawn against the measured H with open
        markers as well as against the nominal H = 2 − D.
    """
    ax = new_axes(ax)
    markers = itertools.cycle(["o", "s", "^", "D"])
    for i, (label, kap) in enumerate(kappas.items()):
        d = kap["dimension"].values.astype(float)
        h = analysis.nominal_hurst(d)
        mean = kap["kappa_mean"].values
        err = np.vstack([mean - kap["kappa_ci_low"].values, kap["kappa_ci_high"].values - mean])
        marker = next(markers)
        ax.errorbar(
            h,
            mean,
            yerr=err,
            marker=marker,
            color=f"C{i}",
            capsize=3,
            lw=1.2,
            label=f"{label} (H = 2 − D)",
        )
        if measured_hurst is not None:
            hm = np.array([measured_hurst.get(float(v), np.nan) for v in d])
            ax.plot(
                hm,
                mean,
                marker=marker,
                mfc="none",
                ls="none",
                color=f"C{i}",
                label=f"{label} (measured H)",
            )
    ax.axhline(
        analysis.PERSSON_KAPPA,
        color="0.3",
        ls="--",
        lw=1,
        label=f"Persson √(8/π) = {analysis.PERSSON_KAPPA:.3f}",
    )
    ax.axhline(
        analysis.BUSH_KAPPA,
        color="0.3",
        ls=":",
        lw=1.4,
        label=f"Bush et al. √(2π) = {analysis.BUSH_KAPPA:.3f}",
    )
    ax.set_yscale("log")
    ax.set_xlabel("Hurst exponent H [1]")
    ax.set_ylabel("κ = R_Sq A_S E* / F_N [1] (log scale)")
    ax.legend(fontsize="small", frameon=False)
    return ax


def plot_force_split(
    summary: xr.Dataset, *, ax: Axes | None = None, hue: str = "contact_type"
) -> Axes:
    """Diagnostics: tangential-spring share of F_N and tilted-contact share at the last step vs D.

    Parameters
    ----------
    summary : xarray.Dataset
        ``tangential_part_fraction_{mean,ci_low,ci_high}`` and ``tilted_fraction_{...}`` [1] on
        (dimension[, hue]) — see :func:`make_study_figures`.
    """
    ax = new_axes(ax)
    groups = (
        [(v, summary.sel({hue: v})) for v in summary[hue].values]
        if hue in summary.dims
        else [("", summary)]
    )
    for i, (label, sub) in enumerate(groups):
        d = sub["dimension"].values
        for name, style, what in (
            ("tangential_part_fraction", "-o", "tangential part of F_N"),
            ("tilted_fraction", "--s", "tilted contacts"),
        ):
            mean = sub[f"{name}_mean"].values
            err = np.vstack(
                [mean - sub[f"{name}_ci_low"].values, sub[f"{name}_ci_high"].values - mean]
            )
            ax.errorbar(
                d,
                100 * mean,
                yerr=100 * err,
                fmt=style,
                color=f"C{i}",
                capsize=3,
                label=f"{what}, {label}".rstrip(", "),
            )
    ax.set_xlabel("fractal dimension D [1]")
    ax.set_ylabel("share at the final step [%]")
    ax.legend(fontsize="small", frameon=False)
    return ax


def _panel_selections(ens: xr.Dataset, hue: str) -> list[tuple[str, dict[str, Any]]]:
    others = [str(d) for d in ens.dims if d not in (hue, "sample", "realization", "load", "boot")]
    if not others:
        return [("", {})]
    out = []
    for combo in itertools.product(*(ens[d].values for d in others)):
        sel = dict(zip(others, combo, strict=True))
        suffix = "_".join(str(v) if d == "contact_type" else f"{d}-{v}" for d, v in sel.items())
        out.append((f"_{suffix}", sel))
    return out


def _summary_at_final_step(split: xr.Dataset, confidence: float) -> xr.Dataset:
    last = split.isel(step=-1)
    parts = [
        analysis.ensemble_statistics(last[n], confidence=confidence, name=str(n))
        for n in ("tangential_part_fraction", "tilted_fraction")
    ]
    return xr.merge(parts, compat="override", combine_attrs="override")


def drawable_study(ds: xr.Dataset) -> tuple[xr.Dataset, list[str]]:
    """The part of a study the figures can be drawn from, and notes on what was left out.

    A study without any swept parameter gets a one-value ``dimension`` grid dimension (from its
    ``dimension`` attribute); realizations whose displacement or force curves are not finite
    are treated as failed; values of D at which some grid point has no usable realization are
    left out.

    Raises
    ------
    AnalysisError
        Nothing is left to draw (no successful realization with finite curves).
    """
    from ..study import STATUS_OK

    notes: list[str] = []
    for name in ("status", "displacement", "normal_force"):
        if name not in ds.variables:
            raise analysis.AnalysisError(f"the study has no variable {name!r}: nothing to draw")
    if not analysis.grid_dims(ds):
        d = float(ds.attrs.get("dimension", np.nan))
        ds = ds.expand_dims(dimension=[d])
    ok = analysis.ok_mask(ds)
    finite = xr.apply_ufunc(np.isfinite, ds["displacement"]).all("step") & xr.apply_ufunc(
        np.isfinite, ds["normal_force"]
    ).all("step")
    bad = ok & ~finite
    if bool(bad.any()):
        notes.append(
            f"{int(bad.sum())} realization(s) with non-finite displacement or force left out"
        )
        ds = ds.assign(status=ds["status"].where(~bad, 2).astype(ds["status"].dtype))
        ok = analysis.ok_mask(ds)
    usable = ok.any("realization")
    if "dimension" in ds.dims:
        others = [d for d in usable.dims if d != "dimension"]
        keep_d = usable.all(others) if others else usable
        dropped = [float(v) for v in ds["dimension"].values[~keep_d.values]]
        if dropped and keep_d.any():
            notes.append(
                "D = " + ", ".join(f"{v:g}" for v in dropped) + " left out (no successful "
                "realization at some grid point)"
            )
        ds = ds.isel(dimension=np.flatnonzero(keep_d.values))
        usable = analysis.ok_mask(ds).any("realization")
    if ds.sizes.get("dimension", 1) == 0 or not bool(usable.all()):
        n_ok = int((ds["status"] == STATUS_OK).sum()) if ds["status"].size else 0
        raise analysis.AnalysisError(
            f"the study has no grid point with a successful realization with finite curves "
            f"({n_ok} usable realizations): nothing to draw; run or resume the study first"
        )
    return ds, notes


def study_figures(
    ds: xr.Dataset,
    *,
    measured_hurst: Mapping[float, float] | None = None,
    kappa_options: Mapping[str, Any] | None = None,
) -> dict[str, Figure]:
    """Figs. 10, 11, 12 and the force-split diagnostics as in-memory figures (nothing written).

    Fig. 11a shows the stiffness of the ensemble-mean F_N(δ_N) curve
    (:func:`splinecontact.analysis.mean_curve_stiffness`), the estimator of the paper.

    Returns
    -------
    dict of str to Figure
        Figure name (with suffix) → figure.
    """
    hue = "dimension" if "dimension" in ds.dims else analysis.grid_dims(ds)[0]
    ens_d = analysis.ensemble_vs_displacement(ds, ["normal_force"])
    ens_f = analysis.ensemble_vs_force(ds)
    ens_k = analysis.mean_curve_stiffness(ds, n_boot=200)
    figures: dict[str, Figure] = {}
    for suffix, sel in _panel_selections(ens_d, hue):
        fig = Figure(figsize=(11, 4.4), layout="constrained")
        a, b = fig.subplots(1, 2)
        plot_force_displacement(ens_d.sel(sel), ax=a, hue=hue)
        plot_separation_force(ens_f.sel(sel), ax=b, hue=hue)
        a.set_title(f"(a) {suffix.lstrip('_')}", loc="left", fontsize="medium")
        b.set_title("(b)", loc="left", fontsize="medium")
        figures[f"fig10{suffix}"] = fig
        fig = Figure(figsize=(11, 4.4), layout="constrained")
        a, b = fig.subplots(1, 2)
        plot_dimensionless_stiffness(ens_k.sel(sel), ax=a, hue=hue)
        plot_area_force(ens_f.sel(sel), ax=b, hue=hue)
        a.set_title(
            f"(a) {suffix.lstrip('_')}: k of the ensemble-mean curve, ± 95 % bootstrap",
            loc="left",
            fontsize="small",
        )
        b.set_title("(b)", loc="left", fontsize="medium")
        figures[f"fig11{suffix}"] = fig
    if "dimension" in ds.dims:
        kap = analysis.kappa(ds, **dict(kappa_options or {}))
        others = [d for d in analysis.grid_dims(ds) if d not in ("dimension", "contact_type")]
        kap_sel = kap.isel(dict.fromkeys(others, 0)) if others else kap
        if "contact_type" in kap_sel.dims:
            kappas = {str(c): kap_sel.sel(contact_type=c) for c in kap_sel["contact_type"].values}
        else:
            kappas = {str(ds.attrs.get("contact_type", "study")): kap_sel}
        ax = new_axes(figsize=(6.4, 4.8))
        plot_kappa_hurst(kappas, ax=ax, measured_hurst=measured_hurst)
        ax.set_title(
            f"R_Sq: {kap.attrs['rsq_method']} ({kap.attrs['rsq_source']}); fit F_N ≤ "
            f"{kap.attrs['fit_fraction']:g} × final load; mean ± 95 % CI",
            fontsize="small",
        )
        figures["fig12_kappa"] = figure_of(ax)
        split = analysis.force_split(ds)
        summary = _summary_at_final_step(split, 0.95)
        if others:
            summary = summary.isel(dict.fromkeys(others, 0))
        ax = new_axes()
        plot_force_split(summary, ax=ax)
        figures["diag_force_split"] = figure_of(ax)
    return figures


def make_study_figures(
    ds: xr.Dataset,
    out_dir: str | Path | OutputFolder,
    *,
    measured_hurst: Mapping[float, float] | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    overwrite: bool = False,
) -> dict[str, list[Path]]:
    """Figs. 10, 11, 12 and the force-split diagnostics, written as PNG and SVG.

    ``out_dir`` follows the package's output rule (:func:`write_figures`).

    Returns
    -------
    dict of str to list of Path
        Figure name (with suffix) → written files (PNG and SVG).
    """
    figures = study_figures(ds, measured_hurst=measured_hurst, kappa_options=kappa_options)
    return write_figures(figures, out_dir, overwrite=overwrite)
