"""Illustrative figures drawn from profiles passed in: Figs. 3a, 4, 5, 8 and 9.

Every function takes the profiles, splines and contact records to draw (made by the caller:
nothing is generated, fitted or simulated here), ``ax=`` (a new figure when ``None``), and
returns the axes. Lengths are drawn in µm, or in nm for heights and zooms on a few grid
spacings. Curves longer than the figure's pixel resolution are decimated
(:func:`~splinecontact.plotting.decimate`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle
from numpy.typing import NDArray

from ..profile import Profile
from ..spheres import SurfaceSpheres, surface_spheres
from ._base import NM_PER_UM, decimate, dimension_colors, new_axes, window

__all__ = [
    "plot_contact_zoom",
    "plot_first_contact",
    "plot_profiles",
    "plot_spheres",
    "plot_spline_fits",
    "upper_global",
]


def plot_profiles(
    profiles: Sequence[Profile],
    *,
    labels: Sequence[str] | None = None,
    ax: Axes | None = None,
    xlim: tuple[float, float] | None = None,
    spacing: float | None = None,
) -> Axes:
    """Fig. 3a: profiles stacked with a vertical offset (heights in nm, x in µm).

    Each profile in the window is drawn decimated to the figure's pixel resolution
    (:func:`~splinecontact.plotting.decimate`: the min and max of each of 2000 bins), so a
    10⁶-point profile draws as it looks from 4000 vertices.

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
        sel = window(p.x, xlim)
        cuts.append((p.x[sel], (p.z[sel] - p.z[sel].mean()) * NM_PER_UM))
    if spacing is None:
        spacing = 1.1 * max(float(np.ptp(z)) for _, z in cuts)
    colors = dimension_colors(range(len(cuts)))
    for i, (x, z) in enumerate(cuts):
        xd, zd = decimate(x, z)
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
    sel = window(profile.x, xlim)
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


def upper_global(fit_lower: Any, fit_upper: Any | None) -> tuple[NDArray[np.float64], float]:
    """Upper surface in the global frame at δ_N = 0 (heights turned over, zero minimum gap)."""
    if fit_upper is None:
        offset = float(fit_lower.f.max())
        return np.full(fit_lower.f.shape, offset), offset
    offset = float((fit_lower.f + fit_upper.f).max())
    return offset - fit_upper.f, offset


def _spheres_in(fit: Any, lo: int, hi: int) -> SurfaceSpheres:
    """Surface spheres (eqs. 4–6) of the grid points ``lo … hi − 1`` of ``fit`` only.

    Each sphere depends on its own point alone (f, f′, f″ there; r_min = dx/2 of the whole
    grid), so these are the values over the whole profile, without evaluating 10⁶ points to
    draw a hundred.
    """
    part = dataclasses.replace(
        fit,
        x=fit.x[lo:hi],
        f=fit.f[lo:hi],
        slope=fit.slope[lo:hi],
        second_derivative=fit.second_derivative[lo:hi],
    )
    return surface_spheres(part, r_min=0.5 * fit.dx)


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
    ax = new_axes(ax)
    sel = np.flatnonzero(window(fit.x, xlim))
    width = float(fit.x[sel[-1]] - fit.x[sel[0]]) if sel.size > 1 else fit.dx
    rmax = 0.5 * width if max_radius is None else max_radius
    bodies = [(fit, 1.0, 0.0, "C0", "lower")]
    if upper_fit is not None:
        _, offset = upper_global(fit, upper_fit)
        bodies.append((upper_fit, -1.0, offset, "C3", "upper"))
    s = NM_PER_UM
    lo = int(sel[0])
    for body, sign, offset, color, name in bodies:
        sph = _spheres_in(body, lo, int(sel[-1]) + 1)
        # the sphere arrays are properties: evaluate them once (index j = i − lo)
        curvature, normal_x, normal_z = sph.curvature, sph.normal_x, sph.normal_z
        centre_x, centre_z = sph.centre_x, sph.centre_z
        z = offset + sign * body.f
        ax.plot(body.x[sel] * s, z[sel] * s, color=color, lw=1.5, label=f"{name} spline")
        arrow = 0.06 * width * s
        for i in sel[::every]:
            j = i - lo
            k = curvature[j]
            nx, nz = normal_x[j], sign * normal_z[j]
            ax.annotate(
                "",
                xy=(body.x[i] * s + arrow * nx, z[i] * s + arrow * nz),
                xytext=(body.x[i] * s, z[i] * s),
                arrowprops={"arrowstyle": "->", "color": color, "lw": 0.7},
            )
            if k == 0 or 1 / abs(k) > rmax:
                continue
            cx = centre_x[j]
            cz = offset + sign * centre_z[j]
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
    """Fig. 8: the two smoothed profiles at first contact (δ_N = 0, zero minimum gap) [nm].

    Both curves are drawn decimated to the figure's pixel resolution
    (:func:`~splinecontact.plotting.decimate`); the first-contact point is found on the full
    grid.

    Parameters
    ----------
    lower_fit : SplineFit
        Spline of the lower body.
    upper_fit : SplineFit or None
        Spline of the upper body (None: a rigid flat), turned over at zero minimum gap.
    ax : Axes, optional
        Axes to draw on.
    xlim : (float, float), optional
        Window [µm].
    """
    ax = new_axes(ax)
    zu, _ = upper_global(lower_fit, upper_fit)
    sel = window(lower_fit.x, xlim)
    x = lower_fit.x[sel]
    for z, color, label in (
        (lower_fit.f[sel], "C0", "lower body"),
        (zu[sel], "C3", "upper body" if upper_fit is not None else "rigid flat"),
    ):
        xd, zd = decimate(x, z * NM_PER_UM)
        ax.plot(xd, zd, color=color, lw=0.7, label=label)
    gap = zu - lower_fit.f
    i = int(np.argmin(np.where(window(lower_fit.x, xlim), gap, np.inf)))
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
    sel = window(lower_fit.x, xlim)
    zu, offset = upper_global(lower_fit, upper_fit)
    zu = zu - displacement
    ax.plot(lower_fit.x[sel] * s, lower_fit.f[sel] * s, color="C0", lw=1.5, label="lower body")
    ax.plot(
        lower_fit.x[sel] * s,
        zu[sel] * s,
        color="0.2",
        lw=1.5,
        label="upper body" if upper_fit is not None else "rigid flat",
    )
    inside = [int(i) for i in record.point if xlim[0] <= lower_fit.x[i] <= xlim[1]]
    lo, hi = (min(inside), max(inside) + 1) if inside else (0, 0)
    sph_l = _spheres_in(lower_fit, lo, hi)
    sph_u = _spheres_in(upper_fit, lo, hi) if upper_fit is not None else None
    kl_all, clx, clz = sph_l.curvature, sph_l.centre_x, sph_l.centre_z
    ku_all = sph_u.curvature if sph_u is not None else None
    cux = sph_u.centre_x if sph_u is not None else None
    cuz = sph_u.centre_z if sph_u is not None else None
    for n, i in enumerate(inside):
        j = i - lo  # index into the spheres of points lo … hi − 1
        kl = kl_all[j]
        if kl != 0:
            ax.add_patch(
                Circle(
                    (clx[j] * s, clz[j] * s),
                    s / abs(kl),
                    fill=False,
                    color="red",
                    lw=0.8,
                    label="accepted contact spheres\n(solid lower, dashed upper)"
                    if n == 0
                    else None,
                )
            )
        if ku_all is not None and cux is not None and cuz is not None and ku_all[j] != 0:
            ku = ku_all[j]
            cz = offset - displacement - cuz[j]
            ax.add_patch(
                Circle(
                    (cux[j] * s, cz * s),
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
