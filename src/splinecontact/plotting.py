"""Figures of the paper (Figs. 3a, 4, 5, 8, 9, 10, 11, 12) from profiles and study results.

Every plotting function takes ``ax=`` (a matplotlib ``Axes``; a new figure is made when it is
``None``) and returns the axes, so figures can be composed freely. No pyplot state is used: new
figures are :class:`matplotlib.figure.Figure` objects rendered with the Agg backend. Axes carry
their units: lengths µm (heights in nm where they are nanometre-sized), forces mN per µm of
thickness.

:func:`make_figures` builds every figure from a study Dataset and writes PNG and SVG files; it is
what ``splinecontact plot`` and ``splinecontact reproduce`` call.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg", force=False)

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from numpy.typing import NDArray

from . import analysis
from .errors import ParameterError
from .profile import Profile

__all__ = [
    "FIGURE_FILES",
    "dimension_colors",
    "make_figures",
    "make_illustrative_figures",
    "make_study_figures",
    "new_axes",
    "plot_area_force",
    "plot_contact_zoom",
    "plot_dimensionless_stiffness",
    "plot_first_contact",
    "plot_force_displacement",
    "plot_force_split",
    "plot_kappa_hurst",
    "plot_profiles",
    "plot_separation_force",
    "plot_spheres",
    "plot_spline_fits",
    "save_figure",
]

#: Base names of the figures :func:`make_figures` writes (each as .png and .svg). Per-grid-point
#: figures get a suffix naming the contact type (and any further swept parameter).
FIGURE_FILES: dict[str, str] = {
    "fig03_profiles": "Fig. 3a: profiles across D",
    "fig04_spline_alpha": "Fig. 4: spline fits for several α",
    "fig05_spheres": "Fig. 5: surface spheres and normals on a segment",
    "fig08_first_contact": "Fig. 8: opposing profiles at first contact",
    "fig09_contact_zoom": "Fig. 9: zoom with the accepted contact spheres",
    "fig10": "Fig. 10: (a) F_N vs δ_N, (b) mean separation vs F_N",
    "fig11": "Fig. 11: (a) k/E* vs F_N/(E* L0), (b) A_S vs F_N",
    "fig12_kappa": "Fig. 12: κ vs H with the Persson and Bush values",
    "diag_force_split": "Diagnostics: tangential part of F_N and tilted contacts vs D",
}

NM_PER_UM = 1000.0


# --- basics -----------------------------------------------------------------------------------


def new_axes(ax: Axes | None = None, *, figsize: tuple[float, float] = (6.4, 4.6)) -> Axes:
    """Return ``ax``, or the axes of a new Agg-rendered figure of ``figsize`` [inch]."""
    if ax is not None:
        return ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def save_figure(
    fig: Figure, stem: str | Path, *, formats: Sequence[str] = ("png", "svg"), dpi: int = 150
) -> list[Path]:
    """Write ``fig`` as ``stem.png`` and ``stem.svg`` (or ``formats``) and return the paths."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = []
    for fmt in formats:
        path = stem.with_name(f"{stem.name}.{fmt}")
        fig.savefig(path, dpi=dpi, format=fmt)
        paths.append(path)
    return paths


def dimension_colors(values: Sequence[float] | NDArray[Any]) -> dict[float, Any]:
    """A viridis colour per fractal dimension (or any ordered parameter), dark = low."""
    vals = [float(v) for v in np.asarray(values, dtype=float)]
    cmap = matplotlib.colormaps["viridis"]
    lo, hi = min(vals), max(vals)
    span = hi - lo if hi > lo else 1.0
    return {v: cmap(0.9 * (v - lo) / span) for v in vals}


def _decimate(
    x: NDArray[np.float64], z: NDArray[np.float64], max_points: int = 4000
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Min/max envelope per bin, so a 10⁶-point profile draws as it looks but stays small."""
    n = x.size
    bins = max_points // 2
    if n <= max_points:
        return x, z
    size = n // bins
    m = bins * size
    zb = z[:m].reshape(bins, size)
    xb = x[:m].reshape(bins, size)
    imin = zb.argmin(axis=1)
    imax = zb.argmax(axis=1)
    first = np.minimum(imin, imax)
    second = np.maximum(imin, imax)
    rows = np.arange(bins)
    xo = np.column_stack([xb[rows, first], xb[rows, second]]).ravel()
    zo = np.column_stack([zb[rows, first], zb[rows, second]]).ravel()
    return xo, zo


def _window(x: NDArray[np.float64], xlim: tuple[float, float] | None) -> NDArray[np.bool_]:
    if xlim is None:
        return np.ones(x.shape, dtype=bool)
    return np.asarray((x >= xlim[0]) & (x <= xlim[1]))


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


# --- study figures ----------------------------------------------------------------------------


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


# --- profile figures --------------------------------------------------------------------------


def plot_profiles(
    profiles: Sequence[Profile],
    *,
    labels: Sequence[str] | None = None,
    ax: Axes | None = None,
    xlim: tuple[float, float] | None = None,
    spacing: float | None = None,
) -> Axes:
    """Fig. 3a: profiles stacked with a vertical offset (heights in nm, x in µm).

    Parameters
    ----------
    profiles : sequence of Profile
        Profiles, drawn bottom to top.
    labels : sequence of str, optional
        One label per profile (written at the left).
    xlim : (float, float), optional
        Window [µm].
    spacing : float, optional
        Vertical offset between profiles [nm]; default 1.1 × the largest peak-to-valley height.
    """
    ax = new_axes(ax)
    cuts = []
    for p in profiles:
        sel = _window(p.x, xlim)
        cuts.append((p.x[sel], (p.z[sel] - p.z[sel].mean()) * NM_PER_UM))
    if spacing is None:
        spacing = 1.1 * max(float(np.ptp(z)) for _, z in cuts)
    colors = dimension_colors(range(len(cuts)))
    for i, (x, z) in enumerate(cuts):
        xd, zd = _decimate(x, z)
        ax.plot(xd, zd + i * spacing, lw=0.6, color=colors[float(i)])
        if labels is not None:
            ax.text(x[0], i * spacing + 0.35 * spacing, labels[i], fontsize="small", va="bottom")
    ax.set_xlabel("x [µm]")
    ax.set_ylabel(f"height z [nm] (profiles offset by {spacing:.3g} nm)")
    return ax


def plot_spline_fits(
    profile: Profile,
    fits: Sequence[Any],
    *,
    ax: Axes | None = None,
    xlim: tuple[float, float] | None = None,
) -> Axes:
    """Fig. 4: a profile's points and its smoothing splines for several α (eq. 3).

    Parameters
    ----------
    profile : Profile
        The profile.
    fits : sequence of SplineFit
        Splines of ``profile`` (each knows its ``alpha``).
    xlim : (float, float), optional
        Window [µm]; choose a few hundred grid spacings to see the differences.
    """
    ax = new_axes(ax)
    sel = _window(profile.x, xlim)
    ax.plot(
        profile.x[sel], profile.z[sel] * NM_PER_UM, ".", ms=2.5, color="0.5", label="profile points"
    )
    for i, fit in enumerate(fits):
        ax.plot(
            fit.x[sel],
            fit.f[sel] * NM_PER_UM,
            lw=1.3,
            color=f"C{i}",
            label=f"spline, α = {fit.alpha:g}",
        )
    ax.set_xlabel("x [µm]")
    ax.set_ylabel("height z [nm]")
    ax.legend(fontsize="small", frameon=False)
    return ax


def _upper_global(fit_lower: Any, fit_upper: Any | None) -> tuple[NDArray[np.float64], float]:
    """Upper surface in the global frame at δ_N = 0 (heights turned over, zero minimum gap)."""
    if fit_upper is None:
        offset = float(fit_lower.f.max())
        return np.full(fit_lower.f.shape, offset), offset
    offset = float((fit_lower.f + fit_upper.f).max())
    return offset - fit_upper.f, offset


def _draw_circle(ax: Axes, cx: float, cz: float, r: float, *, scale: float, **kw: Any) -> None:
    ax.add_patch(Circle((cx, cz * scale), r, fill=False, **kw))


def plot_spheres(
    fit: Any,
    *,
    ax: Axes | None = None,
    xlim: tuple[float, float] | None = None,
    every: int = 1,
    upper_fit: Any | None = None,
    max_radius: float | None = None,
) -> Axes:
    """Fig. 5: surface spheres and normals (eqs. 4–6) on a profile segment, equal axes [nm].

    Parameters
    ----------
    fit : SplineFit
        Spline of the lower profile (own frame = global frame).
    xlim : (float, float), optional
        Window [µm] (a few tens of grid spacings).
    every : int
        Draw the sphere and normal of every ``every``-th grid point in the window.
    upper_fit : SplineFit, optional
        Spline of the upper profile; drawn turned over at zero minimum gap, with its spheres.
    max_radius : float, optional
        Skip spheres larger than this [µm] (near-flat points); default half the window width.
    """
    from .spheres import surface_spheres

    ax = new_axes(ax)
    sel = np.flatnonzero(_window(fit.x, xlim))
    width = float(fit.x[sel[-1]] - fit.x[sel[0]]) if sel.size > 1 else fit.dx
    rmax = 0.5 * width if max_radius is None else max_radius
    bodies = [(fit, 1.0, 0.0, "C0", "lower")]
    if upper_fit is not None:
        _, offset = _upper_global(fit, upper_fit)
        bodies.append((upper_fit, -1.0, offset, "C3", "upper"))
    s = NM_PER_UM
    for body, sign, offset, color, name in bodies:
        sph = surface_spheres(body)
        z = offset + sign * body.f
        ax.plot(body.x[sel] * s, z[sel] * s, color=color, lw=1.5, label=f"{name} spline")
        arrow = 0.06 * width * s
        for i in sel[::every]:
            k = sph.curvature[i]
            nx, nz = sph.normal_x[i], sign * sph.normal_z[i]
            ax.annotate(
                "",
                xy=(body.x[i] * s + arrow * nx, z[i] * s + arrow * nz),
                xytext=(body.x[i] * s, z[i] * s),
                arrowprops={"arrowstyle": "->", "color": color, "lw": 0.7},
            )
            if k == 0 or 1 / abs(k) > rmax:
                continue
            cx = sph.centre_x[i]
            cz = offset + sign * sph.centre_z[i]
            ls = "-" if k > 0 else ":"
            ax.add_patch(
                Circle(
                    (cx * s, cz * s), s / abs(k), fill=False, color=color, lw=0.5, ls=ls, alpha=0.6
                )
            )
    x_lo, x_hi = float(fit.x[sel[0]]) * s, float(fit.x[sel[-1]]) * s
    zs = np.concatenate([(off + sign * b.f[sel]) for b, sign, off, _, _ in bodies]) * s
    z_mid = 0.5 * (float(zs.min()) + float(zs.max()))
    half = 0.5 * max(x_hi - x_lo, float(np.ptp(zs)) * 1.3)
    ax.set_xlim(0.5 * (x_lo + x_hi) - half, 0.5 * (x_lo + x_hi) + half)
    ax.set_ylim(z_mid - half, z_mid + half)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [nm]")
    ax.set_ylabel("z [nm]")
    ax.legend(
        fontsize="small",
        title="spheres: solid convex,\ndotted concave",
        title_fontsize="small",
        loc="upper left",
        bbox_to_anchor=(1.0, 1.0),
    )
    return ax


def plot_first_contact(
    lower_fit: Any,
    upper_fit: Any | None,
    *,
    ax: Axes | None = None,
    xlim: tuple[float, float] | None = None,
) -> Axes:
    """Fig. 8: the two smoothed profiles at first contact (δ_N = 0, zero minimum gap) [nm]."""
    ax = new_axes(ax)
    zu, _ = _upper_global(lower_fit, upper_fit)
    sel = _window(lower_fit.x, xlim)
    x = lower_fit.x[sel]
    for z, color, label in (
        (lower_fit.f[sel], "C0", "lower body"),
        (zu[sel], "C3", "upper body" if upper_fit is not None else "rigid flat"),
    ):
        xd, zd = _decimate(x, z * NM_PER_UM)
        ax.plot(xd, zd, color=color, lw=0.7, label=label)
    gap = zu - lower_fit.f
    i = int(np.argmin(np.where(_window(lower_fit.x, xlim), gap, np.inf)))
    ax.plot(lower_fit.x[i], lower_fit.f[i] * NM_PER_UM, "k*", ms=10, label="first contact")
    ax.set_xlabel("x [µm]")
    ax.set_ylabel("height z [nm]")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.0, 1.0))
    return ax


def plot_contact_zoom(
    lower_fit: Any,
    upper_fit: Any | None,
    record: Any,
    displacement: float,
    *,
    ax: Axes | None = None,
    xlim: tuple[float, float] | None = None,
) -> Axes:
    """Fig. 9: a zoom on the bodies at one step with the accepted contact spheres in red [nm].

    Parameters
    ----------
    lower_fit, upper_fit : SplineFit (upper may be None for a rigid flat)
        Splines of the two bodies, as used by the simulation.
    record : ContactRecord
        Accepted contacts at the step (``simulate(..., record_contacts=[step]).contacts[0]``).
    displacement : float
        δ_N at that step [µm]; the upper body is lowered by it.
    xlim : (float, float), optional
        Window [µm]; default: the 60 grid spacings holding the most accepted contacts.
    """
    from .spheres import surface_spheres

    ax = new_axes(ax)
    s = NM_PER_UM
    if xlim is None:
        half_w = 30 * lower_fit.dx
        if record.point.size:
            xs = np.sort(lower_fit.x[record.point])
            # the window of 60 grid spacings holding the most accepted contacts
            counts = np.searchsorted(xs, xs + 2 * half_w, side="right") - np.arange(xs.size)
            j = int(np.argmax(counts))
            xc = 0.5 * (float(xs[j]) + float(xs[j + counts[j] - 1]))
        else:
            xc = float(lower_fit.x[np.argmax(lower_fit.f)])
        xlim = (xc - half_w, xc + half_w)
    sel = _window(lower_fit.x, xlim)
    zu, offset = _upper_global(lower_fit, upper_fit)
    zu = zu - displacement
    ax.plot(lower_fit.x[sel] * s, lower_fit.f[sel] * s, color="C0", lw=1.5, label="lower body")
    ax.plot(
        lower_fit.x[sel] * s,
        zu[sel] * s,
        color="0.2",
        lw=1.5,
        label="upper body" if upper_fit is not None else "rigid flat",
    )
    sph_l = surface_spheres(lower_fit)
    sph_u = surface_spheres(upper_fit) if upper_fit is not None else None
    inside = [int(i) for i in record.point if xlim[0] <= lower_fit.x[i] <= xlim[1]]
    for n, i in enumerate(inside):
        kl = sph_l.curvature[i]
        if kl != 0:
            ax.add_patch(
                Circle(
                    (sph_l.centre_x[i] * s, sph_l.centre_z[i] * s),
                    s / abs(kl),
                    fill=False,
                    color="red",
                    lw=0.8,
                    label="accepted contact spheres\n(solid lower, dashed upper)"
                    if n == 0
                    else None,
                )
            )
        if sph_u is not None and sph_u.curvature[i] != 0:
            ku = sph_u.curvature[i]
            cz = offset - displacement - sph_u.centre_z[i]
            ax.add_patch(
                Circle(
                    (sph_u.centre_x[i] * s, cz * s),
                    s / abs(ku),
                    fill=False,
                    color="red",
                    lw=0.8,
                    ls="--",
                )
            )
    in_rec = (record.x >= xlim[0]) & (record.x <= xlim[1])
    ax.plot(record.x[in_rec] * s, record.z[in_rec] * s, "r.", ms=6, label="contact centres")
    zlo = float(min(lower_fit.f[sel].min(), zu[sel].min()))
    zhi = float(max(lower_fit.f[sel].max(), zu[sel].max()))
    half = 0.5 * max(xlim[1] - xlim[0], 1.4 * (zhi - zlo))
    xm, zm = 0.5 * (xlim[0] + xlim[1]), 0.5 * (zlo + zhi)
    ax.set_xlim((xm - half) * s, (xm + half) * s)
    ax.set_ylim((zm - half) * s, (zm + half) * s)
    ax.set_aspect("equal", adjustable="box")
    ax.ticklabel_format(useOffset=False)
    ax.set_xlabel("x [nm]")
    ax.set_ylabel("z [nm]")
    ax.set_title(
        f"δ_N = {displacement * s:.3g} nm; {len(inside)} of {record.point.size} accepted "
        "contacts in view",
        fontsize="small",
    )
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.0, 1.0))
    return ax


# --- all figures ------------------------------------------------------------------------------


def _panel_selections(ens: xr.Dataset, hue: str) -> list[tuple[str, dict[str, Any]]]:
    others = [str(d) for d in ens.dims if d not in (hue, "sample", "realization")]
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


def make_study_figures(
    ds: xr.Dataset,
    out_dir: str | Path,
    *,
    measured_hurst: Mapping[float, float] | None = None,
    kappa_options: Mapping[str, Any] | None = None,
) -> dict[str, list[Path]]:
    """Figs. 10, 11, 12 and the force-split diagnostics from a study Dataset.

    Returns
    -------
    dict of str to list of Path
        Figure name (with suffix) → written files (PNG and SVG).
    """
    out_dir = Path(out_dir)
    hue = "dimension" if "dimension" in ds.dims else analysis.grid_dims(ds)[0]
    ens_d = analysis.ensemble_vs_displacement(ds, ["normal_force"])
    ens_f = analysis.ensemble_vs_force(ds)
    ens_k = analysis.dimensionless_stiffness(ds)
    written: dict[str, list[Path]] = {}
    for suffix, sel in _panel_selections(ens_d, hue):
        fig = Figure(figsize=(11, 4.4), layout="constrained")
        a, b = fig.subplots(1, 2)
        plot_force_displacement(ens_d.sel(sel), ax=a, hue=hue)
        plot_separation_force(ens_f.sel(sel), ax=b, hue=hue)
        a.set_title(f"(a) {suffix.lstrip('_')}", loc="left", fontsize="medium")
        b.set_title("(b)", loc="left", fontsize="medium")
        written[f"fig10{suffix}"] = save_figure(fig, out_dir / f"fig10{suffix}")
        fig = Figure(figsize=(11, 4.4), layout="constrained")
        a, b = fig.subplots(1, 2)
        plot_dimensionless_stiffness(ens_k.sel(sel), ax=a, hue=hue)
        plot_area_force(ens_f.sel(sel), ax=b, hue=hue)
        a.set_title(f"(a) {suffix.lstrip('_')}", loc="left", fontsize="medium")
        b.set_title("(b)", loc="left", fontsize="medium")
        written[f"fig11{suffix}"] = save_figure(fig, out_dir / f"fig11{suffix}")
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
        fig_k = ax.figure
        assert isinstance(fig_k, Figure)
        written["fig12_kappa"] = save_figure(fig_k, out_dir / "fig12_kappa")
        split = analysis.force_split(ds)
        summary = _summary_at_final_step(split, 0.95)
        if others:
            summary = summary.isel(dict.fromkeys(others, 0))
        ax = new_axes()
        plot_force_split(summary, ax=ax)
        fig_s = ax.figure
        assert isinstance(fig_s, Figure)
        written["diag_force_split"] = save_figure(fig_s, out_dir / "diag_force_split")
    return written


def _generator_kwargs(params: Mapping[str, Any]) -> dict[str, Any]:
    from .generate import GENERATOR_PARAMETERS

    return {n: params[n] for n in GENERATOR_PARAMETERS if n in params}


def _simulate_kwargs(params: Mapping[str, Any]) -> dict[str, Any]:
    from .contact import SIMULATION_PARAMETERS

    return {n: params[n] for n in SIMULATION_PARAMETERS if params.get(n) is not None}


def _scalar(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


def make_illustrative_figures(
    out_dir: str | Path,
    *,
    dimensions: Sequence[float] = (1.0, 1.2, 1.4, 1.6, 1.8, 1.9),
    params: Mapping[str, Any] | None = None,
    seed: int = 2015,
    alphas: Sequence[float] = (1.0, 2.0, 3.0),
    focus_dimension: float = 1.4,
) -> tuple[dict[str, list[Path]], dict[float, float]]:
    """Figs. 3a, 4, 5, 8 and 9 from freshly generated profiles (the study's fixed parameters).

    Parameters
    ----------
    out_dir : path
        Directory for the figures.
    dimensions : sequence of float
        Fractal dimensions D of Fig. 3a (and of the measured Hurst exponents returned).
    params : mapping, optional
        Generator and simulation parameters (``n_points``, ``length`` [µm], ``e_star`` [GPa],
        ``alpha``, ``steps``, ...; unknown keys are ignored).
    seed : int
        Seed of the illustrative profiles.
    alphas : sequence of float
        Tightness exponents of Fig. 4.
    focus_dimension : float
        D of the pair used in Figs. 4, 5, 8 and 9 (paper Fig. 4: D = 1.4).

    Returns
    -------
    (dict, dict)
        Written files per figure, and D → measured Hurst exponent (PSD slope) of the Fig. 3a
        profiles.
    """
    from .contact import simulate
    from .generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
    from .spline import fit_spline

    out_dir = Path(out_dir)
    params = {k: _scalar(v) for k, v in dict(params or {}).items()}
    gen = _generator_kwargs(params)
    sim = _simulate_kwargs(params)
    alpha = float(sim.get("alpha", 2.0))
    x0 = float(sim.get("x0", 1.0))
    written: dict[str, list[Path]] = {}
    seeds = np.random.SeedSequence(seed).spawn(len(dimensions) + 1)
    profiles = [
        weierstrass_mandelbrot(float(d), seed=s, **gen)
        for d, s in zip(dimensions, seeds, strict=False)
    ]
    hurst = dict(
        zip(
            (float(d) for d in dimensions),
            (float(h) for h in analysis.measured_hurst(profiles)),
            strict=True,
        )
    )
    length = float(profiles[0].length)
    ax = new_axes(figsize=(8, 6))
    plot_profiles(
        profiles, labels=[f"D = {d:g}" for d in dimensions], ax=ax, xlim=(0.0, min(10.0, length))
    )
    ax.set_title(
        f"first {min(10.0, length):g} µm of {length:g} µm profiles, "
        f"R_A = {profiles[0].ra * NM_PER_UM:.3g} nm",
        fontsize="small",
    )
    written["fig03_profiles"] = _save_axes(ax, out_dir / "fig03_profiles")

    lower, upper = weierstrass_mandelbrot_pair(float(focus_dimension), seed=seeds[-1], **gen)
    dx = lower.dx
    fits = [fit_spline(lower, alpha=a, x0=x0) for a in alphas]
    centre = float(lower.x[np.argmax(lower.z)])
    ax = new_axes()
    plot_spline_fits(lower, fits, ax=ax, xlim=(centre - 60 * dx, centre + 60 * dx))
    ax.set_title(f"D = {focus_dimension:g}, dx = {dx * NM_PER_UM:.3g} nm", fontsize="small")
    written["fig04_spline_alpha"] = _save_axes(ax, out_dir / "fig04_spline_alpha")

    fit_l = fit_spline(lower, alpha=alpha, x0=x0)
    fit_u = fit_spline(upper, alpha=alpha, x0=x0)
    zu, _ = _upper_global(fit_l, fit_u)
    i0 = int(np.argmin(zu - fit_l.f))
    x_first = float(fit_l.x[i0])
    ax = new_axes(figsize=(8, 5.2))
    plot_spheres(
        fit_l, upper_fit=fit_u, ax=ax, xlim=(x_first - 60 * dx, x_first + 60 * dx), every=6
    )
    ax.set_title(
        f"D = {focus_dimension:g}, at the first contact point, α = {alpha:g}", fontsize="small"
    )
    written["fig05_spheres"] = _save_axes(ax, out_dir / "fig05_spheres")

    ax = new_axes(figsize=(9, 4))
    half = min(5.0, length / 2)
    lo = max(float(lower.x[0]), x_first - half)
    plot_first_contact(fit_l, fit_u, ax=ax, xlim=(lo, lo + 2 * half))
    ax.set_title(
        f"D = {focus_dimension:g}, δ_N = 0 (10 µm around the first contact)", fontsize="small"
    )
    written["fig08_first_contact"] = _save_axes(ax, out_dir / "fig08_first_contact")

    steps = int(sim.get("steps", 1000))
    step = max(1, steps // 4)
    result = simulate(lower, upper, record_contacts=[step], **sim)
    record = result.contacts[0]
    ax = new_axes(figsize=(8, 5.2))
    plot_contact_zoom(fit_l, fit_u, record, float(result.curves["displacement"][step]), ax=ax)
    written["fig09_contact_zoom"] = _save_axes(ax, out_dir / "fig09_contact_zoom")
    return written, hurst


def _save_axes(ax: Axes, stem: Path) -> list[Path]:
    fig = ax.figure
    assert isinstance(fig, Figure)
    return save_figure(fig, stem)


def make_figures(
    ds: xr.Dataset,
    out_dir: str | Path,
    *,
    illustrative: bool = True,
    seed: int | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    hurst_profiles: int = 3,
) -> tuple[dict[str, list[Path]], xr.Dataset | None]:
    """Every figure of the paper from a study Dataset, as PNG and SVG in ``out_dir``.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    out_dir : path
        Output directory (created).
    illustrative : bool
        Also make Figs. 3a, 4, 5, 8, 9 from profiles generated with the study's fixed
        parameters (a few seconds at 10⁶ points).
    seed : int, optional
        Seed of the illustrative profiles (default: the ``study_seed`` attribute, else 2015).
    kappa_options : mapping, optional
        Keyword arguments of :func:`splinecontact.analysis.kappa` for Fig. 12.
    hurst_profiles : int
        Lower profiles per D regenerated from the study's seeds to measure the Hurst exponent
        drawn in Fig. 12 (:func:`splinecontact.analysis.study_hurst`); 0 to skip.

    Returns
    -------
    (dict, xarray.Dataset or None)
        Written files per figure; the Hurst exponents (None without a ``dimension`` sweep or
        with ``hurst_profiles = 0``).
    """
    written: dict[str, list[Path]] = {}
    has_d = "dimension" in ds.dims
    if illustrative:
        dims = [float(d) for d in ds["dimension"].values] if has_d else [1.0, 1.4, 1.8]
        if seed is None:
            seed = int(ds.attrs.get("study_seed", 2015))
        focus = 1.4 if 1.4 in dims else dims[len(dims) // 2]
        params = dict(ds.attrs)
        if "alpha" in ds.dims:
            params["alpha"] = float(ds["alpha"].values[0])
        fig_files, _ = make_illustrative_figures(
            out_dir, dimensions=dims, params=params, seed=int(seed), focus_dimension=focus
        )
        written.update(fig_files)
    hurst = (
        analysis.study_hurst(ds, n_profiles=hurst_profiles) if has_d and hurst_profiles else None
    )
    measured = (
        {
            float(d): float(h)
            for d, h in zip(
                hurst["dimension"].values, hurst["hurst_measured_mean"].values, strict=True
            )
        }
        if hurst is not None
        else None
    )
    written.update(
        make_study_figures(ds, out_dir, measured_hurst=measured, kappa_options=kappa_options)
    )
    return written, hurst


# --- one simulation result ------------------------------------------------------------------

#: Figures of one simulation result: file stem -> (x variable, y variable, title).
RESULT_FIGURES: dict[str, tuple[str, str, str]] = {
    "normal_force_displacement": ("displacement", "normal_force", "F_N vs δ_N"),
    "tangential_force_displacement": ("displacement", "tangential_force", "F_T vs δ_N"),
    "area_force": ("normal_force", "contact_area", "A_S vs F_N"),
    "separation_force": ("normal_force", "mean_separation", "mean separation vs F_N"),
}

_RESULT_LABELS: dict[str, str] = {
    "displacement": "δ_N",
    "normal_force": "F_N",
    "tangential_force": "F_T",
    "contact_area": "A_S",
    "mean_separation": "mean separation",
}


def result_figures(ds: xr.Dataset, *, title: str = "") -> dict[str, Figure]:
    """The four curves of one simulation result (netCDF of ``splinecontact simulate``).

    F_N and F_T against δ_N, A_S and the mean separation against F_N, each on its own figure
    with the units stored in the file.

    Parameters
    ----------
    ds : xarray.Dataset
        A result written by :meth:`splinecontact.results.SimulationResult.to_netcdf`.
    title : str
        Prefix of every figure title (e.g. the file name).

    Returns
    -------
    dict of str to Figure
        One figure per key of :data:`RESULT_FIGURES`.

    Raises
    ------
    ParameterError
        A variable is missing, or a curve has fewer than two finite points.
    """
    figures: dict[str, Figure] = {}
    for stem, (xname, yname, what) in RESULT_FIGURES.items():
        for name in (xname, yname):
            if name not in ds.variables or ds[name].dims != ("step",):
                raise ParameterError(
                    f"the result has no per-step variable {name!r}: not a file written by "
                    "`splinecontact simulate`"
                )
        x = np.asarray(ds[xname].values, dtype=np.float64)
        y = np.asarray(ds[yname].values, dtype=np.float64)
        ok = np.isfinite(x) & np.isfinite(y)
        if int(ok.sum()) < 2:
            raise ParameterError(
                f"{what}: fewer than two finite points in the result; nothing to draw"
            )
        ax = new_axes(figsize=(5.6, 4.2))
        ax.plot(x[ok], y[ok], "C0-", lw=1.2)
        for axis, name in ((ax.set_xlabel, xname), (ax.set_ylabel, yname)):
            units = ds[name].attrs.get("units", "?")
            axis(f"{_RESULT_LABELS[name]} [{units}]")
        ax.grid(True, alpha=0.3)
        ax.set_title(f"{title}: {what}" if title else what, fontsize=9)
        fig = ax.figure
        assert isinstance(fig, Figure)
        figures[stem] = fig
    return figures
