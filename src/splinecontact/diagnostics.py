"""Checks that say when a simulation's input or result is outside what SAD is meant for.

SAD (spline assisted discretization) models rough contact as independent Hertzian asperities
on a smoothed profile. Three situations make its numbers meaningless without any error being
raised, and each is detected here:

* **form**: a profile whose heights are dominated by an instrument tilt or a curved form (a
  polynomial of degree ≤ 2 explains at least :data:`FORM_VARIANCE_LIMIT` of the height
  variance). The bodies then touch along the high end of the form, not on the roughness.
* **coarse grid**: the grid spacing is too coarse for the spline of eqs. 2–3, so its curvature,
  hence the sphere radii of eq. 5, are biased (see
  :func:`splinecontact.preprocess.spline_resolution`).
* **large contact**: the final contact area A_S reaches :data:`CONTACT_FRACTION_LIMIT` of the
  profile length. SAD's asperities no longer interact weakly; the load has gone far beyond
  the sparse-contact regime the method describes.

:func:`simulation_diagnostics` returns the findings as :class:`Diagnostic` records;
:func:`warn_simulation` issues each one as a Python warning of a specific
:class:`SimulationWarning` subclass. :func:`splinecontact.simulate` calls the latter, so a
script sees the same warnings the command line prints.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

if TYPE_CHECKING:
    from .profile import Profile

__all__ = [
    "CONTACT_FRACTION_LIMIT",
    "FORM_VARIANCE_LIMIT",
    "CoarseGridWarning",
    "Diagnostic",
    "FormWarning",
    "LargeContactWarning",
    "SimulationWarning",
    "contact_diagnostic",
    "form_diagnostic",
    "grid_diagnostic",
    "simulation_diagnostics",
    "warn_simulation",
]

#: Share of the height variance [1] explained by a tilt or a quadratic form above which a
#: profile is reported as dominated by its form.
FORM_VARIANCE_LIMIT = 0.5

#: Points (at most) of the strided subsample on which the form is fitted.
FORM_SAMPLE_POINTS = 65_536

#: Final A_S / profile length [1] at or above which the load is reported as too large.
CONTACT_FRACTION_LIMIT = 0.3


class SimulationWarning(UserWarning):
    """Base class of the warnings about a simulation's input or result."""


class FormWarning(SimulationWarning):
    """A profile's heights are dominated by a tilt or form, not by its roughness."""


class CoarseGridWarning(SimulationWarning):
    """The grid is too coarse for the smoothing spline (biased curvature, eq. 5)."""


class LargeContactWarning(SimulationWarning):
    """The load reaches a contact area near full contact, beyond SAD's sparse-contact range."""


@dataclass(frozen=True)
class Diagnostic:
    """One finding about a simulation.

    Attributes
    ----------
    kind : {"form", "coarse_grid", "large_contact"}
        What was found.
    message : str
        One sentence: what was found, with its value, and what to do.
    value : float
        The measured quantity [1]: variance share of the form, curvature bias, or A_S / length.
    """

    kind: Literal["form", "coarse_grid", "large_contact"]
    message: str
    value: float

    @property
    def category(self) -> type[SimulationWarning]:
        """The warning class issued for this finding."""
        return _CATEGORY[self.kind]


_CATEGORY: dict[str, type[SimulationWarning]] = {
    "form": FormWarning,
    "coarse_grid": CoarseGridWarning,
    "large_contact": LargeContactWarning,
}


def form_diagnostic(profile: Profile, *, name: str = "profile") -> Diagnostic | None:
    """Report a profile whose height variance is mostly a tilt or a quadratic form.

    Parameters
    ----------
    profile : Profile
        Heights [µm] on a grid [µm].
    name : str
        How to call the profile in the message (e.g. ``"lower profile"``).

    Returns
    -------
    Diagnostic or None
        ``None`` when the form explains less than :data:`FORM_VARIANCE_LIMIT` of the variance.
    """
    # a tilt or form is a large-scale feature: an evenly strided subsample of at most
    # FORM_SAMPLE_POINTS points estimates both its share and the roughness variance, at a
    # cost independent of the profile size
    stride = max(1, -(-profile.n_points // FORM_SAMPLE_POINTS))
    x = np.asarray(profile.x[::stride], dtype=np.float64)
    z = np.asarray(profile.z[::stride], dtype=np.float64)
    if x.size < 4:
        return None
    span = float(x[-1] - x[0])
    if not np.isfinite(span) or span <= 0.0:
        return None
    t = (x - x[0]) / span * 2.0 - 1.0
    zc = z - z.mean()
    total = float(np.multiply(zc, zc).sum())
    if not np.isfinite(total) or total <= 0.0:
        return None
    shares = {}
    trends = {}
    # least squares by the normal equations of the basis (t^degree … t, 1), with element-wise
    # sums rather than BLAS/LAPACK calls (a threaded BLAS costs ~3× the CPU on a busy machine)
    powers = [np.ones_like(t), t, t * t]
    moments = [float(np.multiply(a, b).sum()) for a in powers for b in powers]
    projections = [float(np.multiply(a, zc).sum()) for a in powers]
    for degree in (1, 2):
        k = degree + 1
        gram = np.array([[moments[3 * i + j] for j in range(k)] for i in range(k)])
        coef = np.linalg.solve(gram, np.array(projections[:k]))
        trend = sum(c * a for c, a in zip(coef, powers, strict=False))
        resid = zc - trend
        shares[degree] = 1.0 - float(np.multiply(resid, resid).sum()) / total
        trends[degree] = float(np.ptp(trend))
    if shares[2] < FORM_VARIANCE_LIMIT:
        return None
    if shares[1] >= FORM_VARIANCE_LIMIT:
        what, share, height, fix = "a tilt", shares[1], trends[1], "tilt"
    else:
        what, share, height, fix = "a curved form", shares[2], trends[2], "poly2"
    return Diagnostic(
        "form",
        f"the {name} is dominated by {what}: {height:.3g} µm across the scan, "
        f"{100 * share:.0f} % of its height variance, so the bodies touch where the form is "
        f"highest rather than on the roughness; remove it before simulating "
        f"(--detrend {fix} on the command line, Preprocessing(detrend={fix!r}) in Python)",
        share,
    )


def grid_diagnostic(dx: float, *, alpha: float = 2.0, x0: float = 1.0) -> Diagnostic | None:
    """Report a grid too coarse for the smoothing spline of eqs. 2–3.

    Parameters
    ----------
    dx : float
        Grid spacing [µm].
    alpha : float
        Spline tightness exponent α [1] (eq. 3).
    x0 : float
        Spline unit length x0 [µm] (eq. 3).

    Returns
    -------
    Diagnostic or None
        ``None`` when the curvature bias is within the limit of
        :func:`splinecontact.preprocess.spline_resolution`.
    """
    from .preprocess import spline_resolution

    res = spline_resolution(dx, alpha=alpha, x0=x0)
    if not res.coarse:
        return None
    if res.x0_for_limit is not None:
        remedy = f"raise x0 (--x0 ≥ {res.x0_for_limit:.3g} µm) or use a finer scan"
    else:
        remedy = f"lower α below 3 (α = {alpha:g}: no x0 can help) or use a finer scan"
    if res.interpolates:
        text = (
            f"the spacing {dx:.3g} µm is coarser than the spline's smoothing wavelength "
            f"({res.cutoff_wavelength:.3g} µm < 2 dx): the spline passes through every "
            "measured point, noise included, and the sphere radii (eq. 5) come from "
            f"point-to-point curvature; {remedy}"
        )
        value = float("inf")
    else:
        text = (
            f"the spacing {dx:.3g} µm is coarse for the spline: the shortest feature it keeps "
            f"({res.cutoff_wavelength:.3g} µm) spans only {res.points_per_cutoff:.2g} grid "
            f"points (paper: 35), so its curvature and the sphere radii of eq. 5 are off by "
            f"{100 * res.curvature_bias:.0f} %; {remedy}"
        )
        value = res.curvature_bias
    return Diagnostic("coarse_grid", text, value)


def contact_diagnostic(curves: Mapping[str, Any], length: float) -> Diagnostic | None:
    """Report a final contact area A_S that is a large share of the profile length.

    Parameters
    ----------
    curves : mapping
        The per-step curves of a :class:`~splinecontact.results.SimulationResult`
        (``contact_area`` [µm] and ``displacement`` [µm] are used).
    length : float
        Profile length [µm].

    Returns
    -------
    Diagnostic or None
        ``None`` when A_S stays below :data:`CONTACT_FRACTION_LIMIT` × length.
    """
    area = np.asarray(curves["contact_area"], dtype=np.float64)
    if area.size == 0 or not np.isfinite(length) or length <= 0.0:
        return None
    fraction = area / length
    finite = np.isfinite(fraction)
    if not finite.any() or float(np.max(fraction[finite])) < CONTACT_FRACTION_LIMIT:
        return None
    first = int(np.flatnonzero(finite & (fraction >= CONTACT_FRACTION_LIMIT))[0])
    final = float(fraction[finite][-1])
    disp = np.asarray(curves["displacement"], dtype=np.float64)
    return Diagnostic(
        "large_contact",
        f"the contact area A_S reaches {100 * final:.0f} % of the profile length "
        f"(≥ {100 * CONTACT_FRACTION_LIMIT:.0f} % from step {first}, displacement "
        f"{disp[first]:.3g} µm): near full contact SAD's independent asperities no longer "
        "describe the contact; use a smaller final displacement (--final-displacement) or "
        "check the profile for form (--detrend)",
        final,
    )


def simulation_diagnostics(
    lower: Profile,
    upper: Profile | str,
    curves: Mapping[str, Any] | None = None,
    *,
    alpha: float = 2.0,
    x0: float = 1.0,
) -> list[Diagnostic]:
    """Every finding about a simulation's bodies and (if given) its curves.

    Parameters
    ----------
    lower : Profile
        Lower body.
    upper : Profile or "flat"
        Upper body.
    curves : mapping, optional
        Per-step curves of the result (for the contact-area check).
    alpha : float
        Spline tightness exponent α [1] (eq. 3).
    x0 : float
        Spline unit length x0 [µm] (eq. 3).

    Returns
    -------
    list of Diagnostic
        Form of each body, grid, contact area; empty when nothing was found.
    """
    found: list[Diagnostic | None] = [form_diagnostic(lower, name="lower profile")]
    if not isinstance(upper, str):
        found.append(form_diagnostic(upper, name="upper profile"))
    found.append(grid_diagnostic(lower.dx, alpha=alpha, x0=x0))
    if curves is not None:
        found.append(contact_diagnostic(curves, lower.length))
    return [d for d in found if d is not None]


def warn_simulation(
    lower: Profile,
    upper: Profile | str,
    curves: Mapping[str, Any] | None = None,
    *,
    alpha: float = 2.0,
    x0: float = 1.0,
    stacklevel: int = 3,
) -> list[Diagnostic]:
    """Issue every finding of :func:`simulation_diagnostics` as a :class:`SimulationWarning`.

    Parameters
    ----------
    lower, upper, curves, alpha, x0
        As in :func:`simulation_diagnostics`.
    stacklevel : int
        Passed to :func:`warnings.warn` (3: the caller of the function that calls this one).

    Returns
    -------
    list of Diagnostic
        The findings that were issued.
    """
    found = simulation_diagnostics(lower, upper, curves, alpha=alpha, x0=x0)
    for item in found:
        warnings.warn(item.message, item.category, stacklevel=stacklevel)
    return found
