"""Closed-form contact solutions of plane-strain elasticity, used as oracles.

Each solution lives here once and serves the tests of :mod:`splinecontact.bem`, the accuracy
documentation (``docs/accuracy.md``) and anyone who wants to check a number by hand.

Conventions (the same as :mod:`splinecontact.bem`): plane strain, a rigid profile pressed against
an elastic half-space of effective modulus E* [GPa]; forces are per µm of out-of-plane thickness
[mN/µm]; a mean pressure p̄ [GPa] over a period λ [µm] carries the force p̄·λ [mN/µm]. The
surface displacement caused by a pressure p(x) = p₀ cos(qx) is u(x) = 2 p₀ cos(qx)/(E*|q|)
(plane strain; Johnson, *Contact Mechanics*, 1985).

Westergaard (1939; Johnson 1985, ch. 13): the profile z(x) = h cos(2πx/λ) pressed against a flat.

* Full contact needs p* = π E* h / λ.
* For 0 ≤ p̄ ≤ p*, the contact half-width a obeys sin²(πa/λ) = p̄/p*.
* Pressure inside the contact:
  p(x) = 2 p̄ cos(πx/λ) √(sin²(πa/λ) − sin²(πx/λ)) / sin²(πa/λ).
* Mean gap (the distance between the flat's mean line and the profile's mean line, both surfaces
  deformed): ḡ = h [1 − ψ + ψ ln ψ] with ψ = p̄/p*. Derivation: ḡ = h − u(0), where u(0) is the
  zero-mean surface displacement at the centre of the contact; with the periodic Green function
  u(x) = −(2/(πE*)) ∫ p(s) ln|2 sin(π(x − s)/λ)| ds and the pressure above, the substitution
  t = sin(πs/λ) reduces u(0) to (λ p̄/(π E*)) (1 − ln ψ) = h ψ (1 − ln ψ). Checked against the
  boundary element solver to 1e−8 relative (``tests/test_bem.py``).

Hertz, cylinder on a flat (Johnson 1985, ch. 4): force P per unit thickness on a cylinder of
radius R gives the half-width a = √(4 R P / (π E*)) and p(x) = (2P/(πa²)) √(a² − x²).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import ParameterError

__all__ = [
    "hertz_cylinder_half_width",
    "hertz_cylinder_pressure",
    "westergaard_contact_half_width",
    "westergaard_full_contact_pressure",
    "westergaard_mean_gap",
    "westergaard_pressure",
]


def _positive(value: float, name: str, unit: str) -> float:
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise ParameterError(f"{name} must be a positive finite number [{unit}], got {value!r}")
    return value


def _load_ratio(
    mean_pressure: ArrayLike, amplitude: float, wavelength: float, e_star: float
) -> NDArray[np.float64]:
    p_star = westergaard_full_contact_pressure(amplitude, wavelength, e_star)
    p = np.asarray(mean_pressure, dtype=np.float64)
    bad = ~np.isfinite(p) | (p < 0.0) | (p > p_star)
    if np.any(bad):
        first = p[bad].ravel()[0]
        raise ParameterError(
            f"mean pressure {first!r} GPa is outside [0, p*] with p* = {p_star!r} GPa "
            "(Westergaard's solution is partial contact only); pass 0 ≤ p̄ ≤ p*"
        )
    return np.asarray(p / p_star, dtype=np.float64)


def westergaard_full_contact_pressure(amplitude: float, wavelength: float, e_star: float) -> float:
    """Mean pressure p* = π E* h / λ at which a sinusoid is flattened completely.

    Parameters
    ----------
    amplitude : float
        Amplitude h of the profile z = h cos(2πx/λ) [µm] (half the peak-to-valley height).
    wavelength : float
        Wavelength λ [µm].
    e_star : float
        Effective modulus E* [GPa].

    Returns
    -------
    float
        p* [GPa].
    """
    h = _positive(amplitude, "amplitude", "µm")
    lam = _positive(wavelength, "wavelength", "µm")
    e = _positive(e_star, "e_star", "GPa")
    return float(np.pi * e * h / lam)


def westergaard_contact_half_width(
    mean_pressure: ArrayLike, amplitude: float, wavelength: float, e_star: float
) -> NDArray[np.float64]:
    """Contact half-width a of a sinusoid on a flat: sin²(πa/λ) = p̄/p*.

    Parameters
    ----------
    mean_pressure : array_like
        Mean pressure p̄ [GPa], 0 ≤ p̄ ≤ p*.
    amplitude : float
        Amplitude h [µm].
    wavelength : float
        Wavelength λ [µm].
    e_star : float
        Effective modulus E* [GPa].

    Returns
    -------
    ndarray
        a [µm]; the contact length per period is 2a.

    Raises
    ------
    ParameterError
        A non-positive amplitude, wavelength or modulus, or p̄ outside [0, p*].
    """
    psi = _load_ratio(mean_pressure, amplitude, wavelength, e_star)
    return np.asarray(float(wavelength) / np.pi * np.arcsin(np.sqrt(psi)), dtype=np.float64)


def westergaard_mean_gap(
    mean_pressure: ArrayLike, amplitude: float, wavelength: float, e_star: float
) -> NDArray[np.float64]:
    """Mean gap ḡ = h (1 − ψ + ψ ln ψ), ψ = p̄/p*, of a sinusoid pressed on a flat.

    Parameters
    ----------
    mean_pressure : array_like
        Mean pressure p̄ [GPa], 0 ≤ p̄ ≤ p*.
    amplitude : float
        Amplitude h [µm].
    wavelength : float
        Wavelength λ [µm].
    e_star : float
        Effective modulus E* [GPa].

    Returns
    -------
    ndarray
        ḡ [µm]: h at first touch (ψ = 0), 0 at full contact (ψ = 1).
    """
    psi = _load_ratio(mean_pressure, amplitude, wavelength, e_star)
    with np.errstate(divide="ignore", invalid="ignore"):
        psi_log_psi = np.where(psi > 0.0, psi * np.log(np.where(psi > 0.0, psi, 1.0)), 0.0)
    return np.asarray(float(amplitude) * (1.0 - psi + psi_log_psi), dtype=np.float64)


def westergaard_pressure(
    x: ArrayLike, mean_pressure: float, amplitude: float, wavelength: float, e_star: float
) -> NDArray[np.float64]:
    """Contact pressure of a sinusoid z = h cos(2πx/λ) on a flat (zero outside the contact).

    Parameters
    ----------
    x : array_like
        Positions [µm]; the contact is centred on x = 0 (mod λ).
    mean_pressure : float
        Mean pressure p̄ [GPa], 0 < p̄ < p*.
    amplitude, wavelength : float
        h and λ [µm].
    e_star : float
        Effective modulus E* [GPa].

    Returns
    -------
    ndarray
        p(x) [GPa].
    """
    psi = float(_load_ratio(mean_pressure, amplitude, wavelength, e_star))
    theta = np.pi * np.asarray(x, dtype=np.float64) / float(wavelength)
    inside = psi - np.sin(theta) ** 2
    root = np.sqrt(np.clip(inside, 0.0, None))
    if psi == 0.0:
        return np.zeros_like(theta)
    return np.asarray(
        2.0 * float(mean_pressure) * np.abs(np.cos(theta)) * root / psi, dtype=np.float64
    )


def hertz_cylinder_half_width(
    force: ArrayLike, radius: float, e_star: float
) -> NDArray[np.float64]:
    """Hertz half-width a = √(4 R P / (π E*)) of a cylinder on a flat (plane strain).

    Parameters
    ----------
    force : array_like
        Force per unit thickness P ≥ 0 [mN/µm].
    radius : float
        Cylinder radius R [µm] (for two cylinders: 1/R = 1/R₁ + 1/R₂).
    e_star : float
        Effective modulus E* [GPa].

    Returns
    -------
    ndarray
        a [µm].
    """
    r = _positive(radius, "radius", "µm")
    e = _positive(e_star, "e_star", "GPa")
    p = np.asarray(force, dtype=np.float64)
    if np.any(~np.isfinite(p) | (p < 0.0)):
        raise ParameterError(f"force must be finite and ≥ 0 [mN/µm], got {force!r}")
    return np.asarray(np.sqrt(4.0 * r * p / (np.pi * e)), dtype=np.float64)


def hertz_cylinder_pressure(
    x: ArrayLike, force: float, radius: float, e_star: float
) -> NDArray[np.float64]:
    """Hertz pressure p(x) = (2P/(πa²)) √(a² − x²) of a cylinder on a flat, centred on x = 0.

    Parameters
    ----------
    x : array_like
        Positions [µm].
    force : float
        Force per unit thickness P > 0 [mN/µm].
    radius : float
        Cylinder radius R [µm].
    e_star : float
        Effective modulus E* [GPa].

    Returns
    -------
    ndarray
        p(x) [GPa], zero outside |x| < a.
    """
    a = float(hertz_cylinder_half_width(force, radius, e_star))
    xx = np.asarray(x, dtype=np.float64)
    if a == 0.0:
        return np.zeros_like(xx)
    return np.asarray(
        2.0 * float(force) / (np.pi * a**2) * np.sqrt(np.clip(a**2 - xx**2, 0.0, None)),
        dtype=np.float64,
    )
