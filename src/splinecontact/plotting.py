"""Figures of the paper (Figs. 3a, 4, 5, 8, 9, 10, 11, 12) from profiles and study results.

Every plotting function takes ``ax=`` (a matplotlib ``Axes``; a new figure is made when it is
``None``) and returns the axes, so figures can be composed freely. No pyplot state is used and
importing this module never changes the matplotlib backend: new figures are
:class:`matplotlib.figure.Figure` objects, written by their own canvas. Axes carry
their units: lengths µm (heights in nm where they are nanometre-sized), forces mN per µm of
thickness.

:func:`make_figures` builds every figure from a study Dataset in memory (:func:`build_figures`),
then writes PNG and SVG files under the package's output rule (:func:`write_figures`); it is what
``splinecontact plot`` and ``splinecontact reproduce`` call.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from numpy.typing import NDArray

from . import analysis
from .errors import ParameterError, SplineContactError
from .outputs import OutputFolder, atomic_path, prepare_output_folder
from .profile import Profile

__all__ = [
    "FIGURE_FILES",
    "build_figures",
    "dimension_colors",
    "drawable_study",
    "illustrative_figures",
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
    "study_figures",
    "write_figures",
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
    """Return ``ax``, or the axes of a new :class:`~matplotlib.figure.Figure` [inch size]."""
    if ax is not None:
        return ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def save_figure(
    fig: Figure, stem: str | Path, *, formats: Sequence[str] = ("png", "svg"), dpi: int = 150
) -> list[Path]:
    """Write ``fig`` as ``stem.png`` and ``stem.svg`` (or ``formats``) and return the paths.

    Each file is written to a temporary name beside it and renamed (no partial file). The
    folder of ``stem`` must exist. For a folder of figures use :func:`write_figures`, which
    follows the package's output rule.
    """
    stem = Path(stem)
    paths = []
    for i, fmt in enumerate(formats):
        path = stem.with_name(f"{stem.name}.{fmt}")
        with atomic_path(path) as tmp:
            _render(fig, tmp, fmt, dpi)
        if i == 0 and fig.get_layout_engine() is not None:
            fig.set_layout_engine("none")  # keep the first layout: no second constrained layout
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
        # the sphere arrays are properties computed over the whole profile: evaluate them once
        curvature, normal_x, normal_z = sph.curvature, sph.normal_x, sph.normal_z
        centre_x, centre_z = sph.centre_x, sph.centre_z
        z = offset + sign * body.f
        ax.plot(body.x[sel] * s, z[sel] * s, color=color, lw=1.5, label=f"{name} spline")
        arrow = 0.06 * width * s
        for i in sel[::every]:
            k = curvature[i]
            nx, nz = normal_x[i], sign * normal_z[i]
            ax.annotate(
                "",
                xy=(body.x[i] * s + arrow * nx, z[i] * s + arrow * nz),
                xytext=(body.x[i] * s, z[i] * s),
                arrowprops={"arrowstyle": "->", "color": color, "lw": 0.7},
            )
            if k == 0 or 1 / abs(k) > rmax:
                continue
            cx = centre_x[i]
            cz = offset + sign * centre_z[i]
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
    kl_all, clx, clz = sph_l.curvature, sph_l.centre_x, sph_l.centre_z
    ku_all = sph_u.curvature if sph_u is not None else None
    cux = sph_u.centre_x if sph_u is not None else None
    cuz = sph_u.centre_z if sph_u is not None else None
    for n, i in enumerate(inside):
        kl = kl_all[i]
        if kl != 0:
            ax.add_patch(
                Circle(
                    (clx[i] * s, clz[i] * s),
                    s / abs(kl),
                    fill=False,
                    color="red",
                    lw=0.8,
                    label="accepted contact spheres\n(solid lower, dashed upper)"
                    if n == 0
                    else None,
                )
            )
        if ku_all is not None and cux is not None and cuz is not None and ku_all[i] != 0:
            ku = ku_all[i]
            cz = offset - displacement - cuz[i]
            ax.add_patch(
                Circle(
                    (cux[i] * s, cz * s),
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
    from .study import STATUS_OK

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
        figures["fig12_kappa"] = _figure_of(ax)
        split = analysis.force_split(ds)
        summary = _summary_at_final_step(split, 0.95)
        if others:
            summary = summary.isel(dict.fromkeys(others, 0))
        ax = new_axes()
        plot_force_split(summary, ax=ax)
        figures["diag_force_split"] = _figure_of(ax)
    return figures


def _figure_of(ax: Axes) -> Figure:
    fig = ax.figure
    assert isinstance(fig, Figure)
    return fig


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


def illustrative_figures(
    *,
    dimensions: Sequence[float] = (1.0, 1.2, 1.4, 1.6, 1.8, 1.9),
    params: Mapping[str, Any] | None = None,
    seed: int = 2015,
    alphas: Sequence[float] = (1.0, 2.0, 3.0),
    focus_dimension: float = 1.4,
    study_seed: bool = False,
    final_displacement: float | None = None,
) -> tuple[dict[str, Figure], dict[float, float]]:
    """Figs. 3a, 4, 5, 8 and 9 as in-memory figures, from generated profiles.

    Profiles generated: one per D of ``dimensions`` (Fig. 3a; their Hurst exponents are
    returned) and the upper profile of the pair at ``focus_dimension`` (Figs. 4, 5, 8, 9) —
    ``len(dimensions) + 1`` profiles (one more if ``focus_dimension`` is not in
    ``dimensions``). Fig. 9 simulates the pair up to a quarter of the steps only.

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
        Tightness exponents α [1] of Fig. 4.
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
    (dict, dict)
        Figures by name, and D → measured Hurst exponent (PSD slope) of the Fig. 3a profiles.
    """
    from .contact import simulate
    from .generate import child_seed, weierstrass_mandelbrot
    from .spline import fit_spline
    from .study import realization_seed

    params = {k: _scalar(v) for k, v in dict(params or {}).items()}
    gen = _generator_kwargs(params)
    sim = _simulate_kwargs(params)
    alpha = float(sim.get("alpha", 2.0))
    x0 = float(sim.get("x0", 1.0))
    figures: dict[str, Figure] = {}
    dims = [float(d) for d in dimensions]
    if study_seed:
        parent = realization_seed(int(seed), 0)
        lower_seeds = [child_seed(parent, 0)] * len(dims)
        focus_seeds = (child_seed(parent, 0), child_seed(parent, 1))
    else:
        spawned = np.random.SeedSequence(seed).spawn(len(dims) + 1)
        lower_seeds = list(spawned[: len(dims)])
        focus_seeds = (child_seed(spawned[-1], 0), child_seed(spawned[-1], 1))
    profiles = [
        weierstrass_mandelbrot(d, seed=s, **gen) for d, s in zip(dims, lower_seeds, strict=True)
    ]
    hurst = dict(zip(dims, (float(h) for h in analysis.measured_hurst(profiles)), strict=True))
    length = float(profiles[0].length)
    ax = new_axes(figsize=(8, 6))
    plot_profiles(
        profiles, labels=[f"D = {d:g}" for d in dims], ax=ax, xlim=(0.0, min(10.0, length))
    )
    ax.set_title(
        f"first {min(10.0, length):g} µm of {length:g} µm profiles, "
        f"R_A = {profiles[0].ra * NM_PER_UM:.3g} nm",
        fontsize="small",
    )
    figures["fig03_profiles"] = _figure_of(ax)

    focus = float(focus_dimension)
    same = [i for i, d in enumerate(dims) if d == focus]
    lower = (
        profiles[same[0]]
        if same and study_seed
        else weierstrass_mandelbrot(focus, seed=focus_seeds[0], **gen)
    )
    upper = weierstrass_mandelbrot(focus, seed=focus_seeds[1], **gen)
    dx = lower.dx
    fits = [fit_spline(lower, alpha=a, x0=x0) for a in alphas]
    centre = float(lower.x[np.argmax(lower.z)])
    ax = new_axes()
    plot_spline_fits(lower, fits, ax=ax, xlim=(centre - 60 * dx, centre + 60 * dx))
    ax.set_title(f"D = {focus:g}, dx = {dx * NM_PER_UM:.3g} nm", fontsize="small")
    figures["fig04_spline_alpha"] = _figure_of(ax)

    fit_l = next((f for f in fits if f.alpha == alpha), None) or fit_spline(
        lower, alpha=alpha, x0=x0
    )
    fit_u = fit_spline(upper, alpha=alpha, x0=x0)
    zu, _ = _upper_global(fit_l, fit_u)
    i0 = int(np.argmin(zu - fit_l.f))
    x_first = float(fit_l.x[i0])
    ax = new_axes(figsize=(8, 5.2))
    plot_spheres(
        fit_l, upper_fit=fit_u, ax=ax, xlim=(x_first - 60 * dx, x_first + 60 * dx), every=6
    )
    ax.set_title(f"D = {focus:g}, at the first contact point, α = {alpha:g}", fontsize="small")
    figures["fig05_spheres"] = _figure_of(ax)

    ax = new_axes(figsize=(9, 4))
    half = min(5.0, length / 2)
    lo = max(float(lower.x[0]), x_first - half)
    plot_first_contact(fit_l, fit_u, ax=ax, xlim=(lo, lo + 2 * half))
    ax.set_title(f"D = {focus:g}, δ_N = 0 (10 µm around the first contact)", fontsize="small")
    figures["fig08_first_contact"] = _figure_of(ax)

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
    record = result.contacts[0]
    ax = new_axes(figsize=(8, 5.2))
    plot_contact_zoom(fit_l, fit_u, record, float(result.curves["displacement"][step]), ax=ax)
    figures["fig09_contact_zoom"] = _figure_of(ax)
    return figures, hurst


def make_illustrative_figures(
    out_dir: str | Path | OutputFolder,
    *,
    dimensions: Sequence[float] = (1.0, 1.2, 1.4, 1.6, 1.8, 1.9),
    params: Mapping[str, Any] | None = None,
    seed: int = 2015,
    alphas: Sequence[float] = (1.0, 2.0, 3.0),
    focus_dimension: float = 1.4,
    overwrite: bool = False,
) -> tuple[dict[str, list[Path]], dict[float, float]]:
    """Figs. 3a, 4, 5, 8 and 9 written as PNG and SVG (see :func:`illustrative_figures`).

    Returns
    -------
    (dict, dict)
        Written files per figure, and D → measured Hurst exponent (PSD slope) of the Fig. 3a
        profiles.
    """
    figures, hurst = illustrative_figures(
        dimensions=dimensions,
        params=params,
        seed=seed,
        alphas=alphas,
        focus_dimension=focus_dimension,
    )
    return write_figures(figures, out_dir, overwrite=overwrite), hurst


def _render(fig: Figure, path: Path, fmt: str, dpi: int) -> None:
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "splinecontact"}):
        fig.savefig(path, dpi=dpi, format=fmt)


def write_figures(
    figures: Mapping[str, Figure],
    out: str | Path | OutputFolder,
    *,
    prefix: str = "",
    overwrite: bool = False,
    command: str = "plot",
    formats: Sequence[str] = ("png", "svg"),
    dpi: int = 150,
) -> dict[str, list[Path]]:
    """Write each figure as ``NAME.png`` and ``NAME.svg``, under the package's output rule.

    Parameters
    ----------
    figures : mapping of str to Figure
        Name → figure.
    out : path or OutputFolder
        A folder path (prepared with :func:`splinecontact.outputs.prepare_output_folder`: a
        non-empty folder is refused unless splinecontact wrote it and ``overwrite`` is given),
        or an already prepared :class:`~splinecontact.outputs.OutputFolder`.
    prefix : str
        Sub-folder of ``out`` for the files (e.g. ``"figures/"``).
    overwrite : bool
        Whether a folder splinecontact wrote earlier may be reused.
    command : str
        Command recorded in the folder's marker.
    formats : sequence of str
        File formats.
    dpi : int
        Resolution of raster formats [dots per inch].

    Returns
    -------
    dict of str to list of Path
        Name → written files. Every file is written to a temporary name and renamed.
    """
    folder = (
        out
        if isinstance(out, OutputFolder)
        else prepare_output_folder(out, overwrite=overwrite, command=command)
    )
    written: dict[str, list[Path]] = {}
    for name, fig in figures.items():
        for fmt in formats:
            folder.file(f"{prefix}{name}.{fmt}")
        written[name] = save_figure(fig, folder.path / f"{prefix}{name}", formats=formats, dpi=dpi)
    return written


def build_figures(
    ds: xr.Dataset,
    *,
    illustrative: bool = True,
    seed: int | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    hurst_profiles: int = 1,
) -> tuple[dict[str, Figure], xr.Dataset | None, list[str]]:
    """Every figure of the paper from a study Dataset, in memory (nothing is written).

    The illustrative figures (Figs. 3a, 4, 5, 8, 9) are drawn from the study's own realization
    0 profiles, regenerated once from the stored seed rule: one lower profile per D and the
    upper profile at the focus D; their PSD slopes give the measured Hurst exponents of Fig. 12
    (``hurst_profiles`` > 1 regenerates further realizations' lower profiles for a mean).

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    illustrative : bool
        Also draw Figs. 3a, 4, 5, 8, 9.
    seed : int, optional
        Study seed (default: the ``study_seed`` attribute, else 2015).
    kappa_options : mapping, optional
        Keyword arguments of :func:`splinecontact.analysis.kappa` for Fig. 12.
    hurst_profiles : int
        Lower profiles per D whose Hurst exponent is measured (0: none).

    Returns
    -------
    (dict, xarray.Dataset or None, list of str)
        Figures by name; the Hurst exponents (None without them); notes on what could not be
        drawn.

    Raises
    ------
    AnalysisError
        The study has nothing to draw (see :func:`drawable_study`).
    """
    ds, notes = drawable_study(ds)
    figures: dict[str, Figure] = {}
    has_d = "dimension" in ds.dims
    dims = [float(d) for d in ds["dimension"].values] if has_d else [1.0, 1.4, 1.8]
    if seed is None:
        seed = int(ds.attrs.get("study_seed", 2015))
    measured: dict[float, float] | None = None
    hurst: xr.Dataset | None = None
    if illustrative:
        focus = 1.4 if 1.4 in dims else dims[len(dims) // 2]
        params = dict(ds.attrs)
        if "alpha" in ds.dims:
            params["alpha"] = float(ds["alpha"].values[0])
        final = None
        if has_d and "final_displacement" in ds and "realization" in ds.dims:
            sel: dict[str, Any] = {"dimension": focus}
            pick = ds["final_displacement"].sel(sel)
            if "contact_type" in pick.dims:
                pick = (
                    pick.sel(contact_type="rough-on-rough")
                    if ("rough-on-rough" in pick["contact_type"].values)
                    else pick.isel(contact_type=0)
                )
            pick = pick.isel({d: 0 for d in pick.dims})
            value = float(pick)
            final = value if math.isfinite(value) and value > 0 else None
        try:
            fig_ill, measured_ill = illustrative_figures(
                dimensions=dims,
                params=params,
                seed=int(seed),
                focus_dimension=focus,
                study_seed=True,
                final_displacement=final,
            )
        except (SplineContactError, ValueError, FloatingPointError) as exc:
            notes.append(f"illustrative figures not drawn: {exc}")
        else:
            figures.update(fig_ill)
            if has_d and hurst_profiles == 1:
                measured = measured_ill
                hurst = _hurst_dataset(dims, measured_ill)
    if has_d and hurst_profiles and hurst is None:
        hurst = analysis.study_hurst(ds, n_profiles=hurst_profiles)
        measured = {
            float(d): float(h)
            for d, h in zip(
                hurst["dimension"].values, hurst["hurst_measured_mean"].values, strict=True
            )
        }
    figures.update(study_figures(ds, measured_hurst=measured, kappa_options=kappa_options))
    return figures, hurst, notes


def _hurst_dataset(dims: Sequence[float], measured: Mapping[float, float]) -> xr.Dataset:
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


def make_figures(
    ds: xr.Dataset,
    out_dir: str | Path | OutputFolder,
    *,
    illustrative: bool = True,
    seed: int | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    hurst_profiles: int = 1,
    overwrite: bool = False,
    prefix: str = "",
) -> tuple[dict[str, list[Path]], xr.Dataset | None]:
    """Every figure of the paper from a study Dataset, as PNG and SVG in ``out_dir``.

    Every figure is drawn in memory first (:func:`build_figures`), so a study with nothing to
    draw raises before anything is written; the files then follow the package's output rule
    (:func:`write_figures`).

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    out_dir : path or OutputFolder
        Output folder.
    illustrative : bool
        Also make Figs. 3a, 4, 5, 8, 9 from the study's realization-0 profiles (regenerated
        once from the stored seed rule).
    seed : int, optional
        Study seed (default: the ``study_seed`` attribute, else 2015).
    kappa_options : mapping, optional
        Keyword arguments of :func:`splinecontact.analysis.kappa` for Fig. 12.
    hurst_profiles : int
        Lower profiles per D whose Hurst exponent is measured and drawn in Fig. 12 (1: the
        illustrative profiles, no extra generation; 0 to skip).
    overwrite : bool
        Whether a folder splinecontact wrote earlier may be reused.
    prefix : str
        Sub-folder of ``out_dir`` for the files.

    Returns
    -------
    (dict, xarray.Dataset or None)
        Written files per figure; the Hurst exponents (None without a ``dimension`` sweep or
        with ``hurst_profiles = 0``).
    """
    figures, hurst, _ = build_figures(
        ds,
        illustrative=illustrative,
        seed=seed,
        kappa_options=kappa_options,
        hurst_profiles=hurst_profiles,
    )
    written = write_figures(figures, out_dir, overwrite=overwrite, prefix=prefix)
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
