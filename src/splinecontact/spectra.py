"""Power spectra of profiles and the Hurst exponent from their slope.

For a self-affine profile with Hurst exponent H the one-sided power spectral density falls as
``C(q) ∝ q^{−(1+2H)}``. The power *integrated over logarithmic frequency bins* [f, b·f) then
falls as ``f^{−2H}``; integrating first makes the estimate robust for line spectra such as the
Weierstrass–Mandelbrot sum of eq. 1, whose power sits on a few discrete frequencies.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .errors import ParameterError
from .profile import Profile

__all__ = ["binned_power", "hurst_exponent", "power_spectrum"]


def power_spectrum(profile: Profile) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """One-sided periodogram of the mean-free heights with a Hann window.

    Parameters
    ----------
    profile : Profile
        Heights [µm] on a uniform grid [µm].

    Returns
    -------
    frequency : ndarray
        Spatial frequencies 1/λ [1/µm], excluding zero.
    psd : ndarray
        Power spectral density [µm³] (µm² per 1/µm).
    """
    z = profile.z - profile.z.mean()
    n = z.size
    window = np.hanning(n)
    spectrum = np.fft.rfft(z * window)
    norm = profile.dx / float(np.sum(window * window))
    psd = 2.0 * norm * np.abs(spectrum) ** 2
    frequency = np.fft.rfftfreq(n, d=profile.dx)
    return np.asarray(frequency[1:], dtype=np.float64), np.asarray(psd[1:], dtype=np.float64)


def binned_power(
    profile: Profile, *, bins_per_decade: int = 8
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Power integrated over logarithmic frequency bins.

    Parameters
    ----------
    profile : Profile
        Heights [µm] on a uniform grid [µm].
    bins_per_decade : int, optional
        Number of bins per decade of frequency [1].

    Returns
    -------
    centre : ndarray
        Geometric centre of each non-empty bin [1/µm].
    power : ndarray
        Mean-square height in each bin [µm²].
    """
    frequency, psd = power_spectrum(profile)
    df = frequency[1] - frequency[0] if frequency.size > 1 else frequency[0]
    lo = math.log10(frequency[0])
    hi = math.log10(frequency[-1])
    n_bins = max(1, math.ceil((hi - lo) * bins_per_decade))
    edges = np.logspace(lo, hi, n_bins + 1)
    edges[-1] *= 1.0 + 1e-12
    index = np.clip(np.searchsorted(edges, frequency, side="right") - 1, 0, n_bins - 1)
    power = np.bincount(index, weights=psd * df, minlength=n_bins)[:n_bins]
    centre = np.sqrt(edges[:-1] * edges[1:])
    keep = power > 0
    return np.asarray(centre[keep], dtype=np.float64), np.asarray(power[keep], dtype=np.float64)


def _default_band(profile: Profile) -> tuple[float, float]:
    f_lo = 20.0 / profile.length
    f_hi = 1.0 / (8.0 * profile.dx)
    meta = profile.metadata
    if meta.get("source") == "weierstrass_mandelbrot":
        wavelength = float(meta["wavelength"])
        directions = int(meta["directions"])
        lowest_direction = min(
            abs(math.cos(math.pi * m / directions))
            for m in range(1, directions + 1)
            if 2 * m != directions
        )
        f_lo = max(f_lo, 1.0 / wavelength)
        top = float(meta["gamma"]) ** int(meta["n_max"]) * lowest_direction / wavelength
        f_hi = min(f_hi, top)
    return f_lo, f_hi


def hurst_exponent(
    profile: Profile,
    *,
    min_frequency: float | None = None,
    max_frequency: float | None = None,
    bins_per_decade: int = 8,
) -> float:
    """Hurst exponent H from the slope of the log-binned power spectrum.

    Fits ``log P_bin = c − 2H log f`` by least squares over the chosen frequency band.

    Parameters
    ----------
    profile : Profile
        Heights [µm] on a uniform grid [µm].
    min_frequency : float, optional
        Lowest frequency of the fit [1/µm]; default 20 / length (the longest wavelengths are
        poorly sampled), or for a Weierstrass–Mandelbrot profile (recognised from its
        metadata) 1/L, below which eq. 1's frequency groups are incomplete.
    max_frequency : float, optional
        Highest frequency of the fit [1/µm]; default 1/(8 dx), a quarter of the Nyquist
        frequency (window leakage and aliasing dominate above), or for a
        Weierstrass–Mandelbrot profile at most γ^n_max cos(π(M/2 − 1)/M)/L, above which its
        groups are incomplete.
    bins_per_decade : int, optional
        Logarithmic bins per decade [1].

    Returns
    -------
    float
        H [1]. For a Weierstrass–Mandelbrot profile with ``amplitude_law="hurst"`` it estimates
        2 − D; with the printed law, 2(2 − D).

    Raises
    ------
    ParameterError
        Fewer than three bins fall within the band.
    """
    default_lo, default_hi = _default_band(profile)
    f_lo = default_lo if min_frequency is None else float(min_frequency)
    f_hi = default_hi if max_frequency is None else float(max_frequency)
    centre, power = binned_power(profile, bins_per_decade=bins_per_decade)
    band = (centre >= f_lo) & (centre <= f_hi)
    if int(band.sum()) < 3:
        raise ParameterError(
            f"only {int(band.sum())} spectral bins lie between {f_lo:.3g} and {f_hi:.3g} 1/µm; "
            "the profile is too short or too coarse to measure a Hurst exponent"
        )
    slope = np.polyfit(np.log(centre[band]), np.log(power[band]), 1)[0]
    return float(-slope / 2.0)
