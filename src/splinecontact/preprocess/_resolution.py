"""What the smoothing spline of eqs. 2–3 resolves on a measured grid: :func:`spline_resolution`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import PreprocessingOptionError

#: Curvature bias (relative) at the smoothing wavelength above which :func:`spline_resolution`
#: flags the grid as too coarse.
CURVATURE_BIAS_LIMIT = 0.05


@dataclass(frozen=True)
class SplineResolution:
    """What the smoothing spline of eqs. 2–3 resolves on a grid of spacing ``dx``.

    Attributes
    ----------
    dx : float
        Grid spacing [µm].
    lam : float
        λ = (dx/x0)^α / 10 · x0³ [µm³] (eq. 3).
    cutoff_wavelength : float
        ℓ_c = 2π (λ·dx)^{1/4} [µm]: a sinusoid of this wavelength keeps half its amplitude in
        the spline; shorter ones are smoothed away, longer ones kept.
    points_per_cutoff : float
        ℓ_c / dx [1]: grid points per shortest kept wavelength.
    curvature_bias : float
        Relative error [1] of the spline's curvature f'' (hence of the sphere radii, eq. 5) for
        a sinusoid of wavelength ℓ_c sampled by ``points_per_cutoff`` points:
        6(1 − cos θ)/(θ²(2 + cos θ)) − 1 with θ = 2π dx/ℓ_c.
    interpolates : bool
        ℓ_c < 2 dx (the Nyquist wavelength): the spline smooths nothing, it passes through
        every measured point, noise included.
    coarse : bool
        ``curvature_bias`` exceeds ``CURVATURE_BIAS_LIMIT`` (5 %), or ``interpolates``.
    x0_for_limit : float or None
        Unit length x0 [µm] at which the bias would equal the limit at this ``dx`` and α
        (``None`` if no x0 can reach it, α ≥ 3).
    """

    dx: float
    lam: float
    cutoff_wavelength: float
    points_per_cutoff: float
    curvature_bias: float
    interpolates: bool
    coarse: bool
    x0_for_limit: float | None


def _curvature_bias(points: float) -> float:
    theta = 2.0 * np.pi / points
    return float(6.0 * (1.0 - np.cos(theta)) / (theta**2 * (2.0 + np.cos(theta))) - 1.0)


def spline_resolution(dx: float, *, alpha: float = 2.0, x0: float = 1.0) -> SplineResolution:
    """Smallest feature the smoothing spline of eqs. 2–3 keeps on a grid, and how well.

    On a uniform grid the spline minimising Σ(z_i − f_i)² + λ∫f''² attenuates a sinusoid of
    wavenumber k by 1/(1 + λ·dx·k⁴) (the sum over points is the integral divided by dx), so the
    half-amplitude wavelength is ℓ_c = 2π (λ·dx)^{1/4}. With eq. 3,
    ℓ_c/dx = 2π·10^{−1/4}·(dx/x0)^{(α−3)/4}: at the paper's grid (dx = 0.1 nm, α = 2,
    x0 = 1 µm) ℓ_c = 3.5 nm = 35 dx; on coarser grids the spline keeps features of only a
    few grid spacings, whose curvature (sphere radii, eq. 5) the cubic spline estimates with
    the bias given in :class:`SplineResolution`.

    Parameters
    ----------
    dx : float
        Grid spacing [µm].
    alpha : float, optional
        Tightness exponent α [1] (eq. 3; paper: 2).
    x0 : float, optional
        Unit length x0 [µm] (eqs. 2–3; paper: 1 µm).
    """
    for name, value in (("dx", dx), ("alpha", alpha), ("x0", x0)):
        if not (np.isfinite(value) and value > 0):
            raise PreprocessingOptionError(f"{name} = {value!r} must be a positive number")
    lam = (dx / x0) ** alpha / 10.0 * x0**3
    cutoff = 2.0 * np.pi * (lam * dx) ** 0.25
    points = cutoff / dx
    interpolates = points < 2.0
    bias = _curvature_bias(points) if not interpolates else float("inf")
    x0_for_limit = None
    if alpha < 3:
        # points(x0) = 2π·10^(−1/4)·(dx/x0)^((α−3)/4) grows with x0; bias(points) falls.
        lo, hi = 2.0, 1e6
        for _ in range(200):  # bisection on the number of points per cutoff
            mid = 0.5 * (lo + hi)
            if _curvature_bias(mid) > CURVATURE_BIAS_LIMIT:
                lo = mid
            else:
                hi = mid
        ratio = hi / (2.0 * np.pi * 10.0**-0.25)
        try:
            x0_for_limit = float(dx * ratio ** (4.0 / (3.0 - alpha)))
        except OverflowError:  # α just below 3: no representable x0 reaches the limit
            x0_for_limit = None
    return SplineResolution(
        dx=float(dx),
        lam=float(lam),
        cutoff_wavelength=float(cutoff),
        points_per_cutoff=float(points),
        curvature_bias=bias,
        interpolates=bool(interpolates),
        coarse=bool(interpolates or bias > CURVATURE_BIAS_LIMIT),
        x0_for_limit=x0_for_limit,
    )
