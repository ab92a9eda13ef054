"""Elastic–plastic line contacts with elastic unloading and a remembered residual interference.

Conventions as in :mod:`splinecontact.contact.adhesion` (R = R_eff/2, the law's width is √2·b
with b the contact half-width, δ the package's Hertz approach, ``docs/contact-laws.md``).

* **Yield onset** (plane strain, von Mises): the Hertz line contact first yields when its peak
  pressure reaches p0c = C(ν) S_y with C(ν) = min(1.164 + 2.975ν − 2.906ν², 1/(1 − 2ν)): Green's
  (2005) fit of the subsurface maximum, and the surface value (σ_vm = (1 − 2ν) p0 at x = z = 0),
  which governs for ν below ≈ 0.18 where the fit alone overestimates C by up to 16 %. The two
  agree with the exact first yield of McEwen's plane-strain Hertz field to 0.12 % over
  0 ≤ ν < 0.5 (``tests/test_contact_laws_closed_forms.py``). With
  p0 = E* b/(2R) and b² = R δ this is b_c = 2R p0c/E*, the critical interference
  δ_c = 4R (p0c/E*)² and the critical force F_c = (π/4) E* δ_c = π R p0c²/E*.
* **Beyond yield** (ω = δ/δ_c > 1): F = 2 b p_m with the mean pressure interpolated in ln ω from
  its Hertz value at yield, p_mc = (π/4) p0c, to the hardness H at the fully plastic onset
  ω_p = 54, and the half-width blended from Hertz (b² = Rδ) to the truncated profile
  (b² = 2Rδ) by a cubic with zero slope at both ends — the construction of Zhao, Maietta &
  Chang (2000) for spheres, transposed here to the line contact (not a fit to cylinder data).
  The force is continuous at yield and never above the Hertz force (min of the two: for ν near
  0 the interpolation starts slightly steeper than Hertz).
* **Unloading** from the largest interference δ_max (force F_max, half-width b_max) is elastic:
  in this package's convention the line-contact Hertz law is F = (π/4)E*(δ − δ_r) whatever the
  radius, so the residual interference is δ_r = δ_max − 4F_max/(πE*) and the flattened profile's
  half-width follows b² = R_u (δ − δ_r), R_u = b_max²/(δ_max − δ_r). Reloading retraces it up to
  δ_max, then continues on the loading curve: a second loading starts later (at δ_r > 0) and is
  stiffer than the first. The state (δ_max, F_max, b_max) persists per contact and survives
  separation.
* **History under sliding.** The memory is δ_max: the unloading line starts on the loading
  curve of the R_eff the law is evaluated with, (F_max, b_max) = the loading curve at δ_max for
  that R_eff. Where R_eff is the one that made the history these are the stored values (bit for
  bit); where it is not (on a sliding path another upper summit, or the same summit with
  another curvature, meets the point) the stored ones would end the unloading line off the
  loading curve and F would jump at δ = δ_max. So F is continuous in δ and in R_eff.

Inputs: ``yield_strength`` S_y or ``hardness`` H [GPa] (the other from Tabor's H = 2.8 S_y),
``poisson_ratio`` ν.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar, Self

import numba
import numpy as np
from numpy.typing import NDArray

from .._checks import MAGNITUDE_LIMIT
from ..errors import PoissonRatioError, YieldStrengthError

__all__ = [
    "FULLY_PLASTIC_RATIO",
    "TABOR_FACTOR",
    "ElasticPlastic",
    "critical_force",
    "critical_half_width",
    "critical_interference",
    "critical_pressure_coefficient",
    "plastic_evaluate",
    "plastic_loading",
    "residual_interference",
]

_PI = math.pi

#: Hardness over yield strength (Tabor): H = 2.8 S_y [1].
TABOR_FACTOR = 2.8

#: ω_p = δ/δ_c at which the contact is taken fully plastic (Zhao, Maietta & Chang 2000) [1].
FULLY_PLASTIC_RATIO = 54.0

#: State columns: δ_max [µm], F_max [mN/µm], b_max [µm].
N_STATE = 3


@numba.njit(cache=True, nogil=True)
def _yield_coefficient(nu: float) -> float:
    # Subsurface (Green 2005 fit) or surface (1/(1 − 2ν)) first yield, whichever comes first.
    return min(1.164 + 2.975 * nu - 2.906 * nu * nu, 1.0 / (1.0 - 2.0 * nu))


def critical_pressure_coefficient(poisson_ratio: float) -> float:
    """C(ν) = min(1.164 + 2.975ν − 2.906ν², 1/(1 − 2ν)): p0/S_y at first (von Mises) yield of
    the plane-strain Hertz line contact [1].

    The first term is Green's (2005) fit of the subsurface maximum of the von Mises stress, the
    second the surface value, which yields first for ν below about 0.18.
    """
    return float(_yield_coefficient(float(poisson_ratio)))


def critical_half_width(
    r_eff: float, e_star: float, yield_strength: float, poisson_ratio: float
) -> float:
    """b_c = 2R C(ν) S_y/E* [µm] (R = R_eff/2; S_y [GPa], E* [GPa])."""
    return r_eff * critical_pressure_coefficient(poisson_ratio) * yield_strength / e_star


def critical_interference(
    r_eff: float, e_star: float, yield_strength: float, poisson_ratio: float
) -> float:
    """δ_c = 4R (C(ν) S_y/E*)² = b_c²/R [µm]: the Hertz line contact yields beyond it."""
    p = critical_pressure_coefficient(poisson_ratio) * yield_strength / e_star
    return 2.0 * r_eff * p * p


def critical_force(
    r_eff: float, e_star: float, yield_strength: float, poisson_ratio: float
) -> float:
    """F_c = (π/4) E* δ_c = π R (C S_y)²/E* [mN/µm]."""
    return 0.25 * _PI * e_star * critical_interference(r_eff, e_star, yield_strength, poisson_ratio)


def residual_interference(max_interference: float, max_force: float, e_star: float) -> float:
    """δ_r = δ_max − 4 F_max/(π E*) [µm]: where elastic unloading from (δ_max, F_max) ends."""
    return max_interference - 4.0 * max_force / (_PI * e_star)


@numba.njit(cache=True, nogil=True)
def plastic_loading(
    delta: float, r_eff: float, e_star: float, yield_strength: float, hardness: float, nu: float
) -> tuple[float, float]:
    """First-loading curve: (force [mN/µm], half-width b [µm]) at interference δ [µm] ≥ 0."""
    r = 0.5 * r_eff
    p0c = _yield_coefficient(nu) * yield_strength
    delta_c = 4.0 * r * (p0c / e_star) ** 2
    if not delta > delta_c:
        return 0.25 * _PI * e_star * delta, math.sqrt(r * delta)
    omega = delta / delta_c
    x = min((omega - 1.0) / (FULLY_PLASTIC_RATIO - 1.0), 1.0)
    blend = x * x * (3.0 - 2.0 * x)
    b = math.sqrt(r * delta * (1.0 + blend))
    p_mc = 0.25 * _PI * p0c
    if omega >= FULLY_PLASTIC_RATIO:
        p_m = hardness
    else:
        p_m = hardness - (hardness - p_mc) * math.log(FULLY_PLASTIC_RATIO / omega) / math.log(
            FULLY_PLASTIC_RATIO
        )
    # Never above the elastic force (for ν near 0 the interpolation starts slightly steeper than
    # Hertz): keeps the residual interference ≥ 0 and unloading below the loading curve.
    return min(2.0 * b * p_m, 0.25 * _PI * e_star * delta), b


@numba.njit(cache=True, nogil=True)
def plastic_evaluate(
    delta: float,
    r_eff: float,
    e_star: float,
    yield_strength: float,
    hardness: float,
    nu: float,
    state: NDArray[np.float64],
) -> tuple[float, float, float, float, float]:
    """One elastic–plastic contact with its history.

    Parameters
    ----------
    delta : float
        Overlap of the surface spheres δ [µm] (eq. 10).
    r_eff : float
        R_eff [µm].
    e_star, yield_strength, hardness : float
        E*, S_y, H [GPa] (S_y = ∞ gives Hertz exactly).
    nu : float
        Poisson's ratio [1].
    state : ndarray
        The contact's :data:`N_STATE` history values (δ_max, F_max, b_max); zeros when new.

    Returns
    -------
    (force, width, delta_max, force_max, b_max)
        Force [mN/µm], width √2·b [µm] and the new state values.
    """
    d_max = state[0]
    f_max = state[1]
    b_max = state[2]
    p0c = _yield_coefficient(nu) * yield_strength
    delta_c = 2.0 * r_eff * (p0c / e_star) ** 2
    if delta >= d_max:
        if not delta > 0.0:
            return 0.0, 0.0, d_max, f_max, b_max
        force, b = plastic_loading(delta, r_eff, e_star, yield_strength, hardness, nu)
        if not delta > delta_c:  # Hertz exactly (the width as the Hertz law computes it)
            return force, math.sqrt(delta * r_eff), delta, force, b
        return force, math.sqrt(2.0) * b, delta, force, b
    if not d_max > delta_c:  # elastic history: Hertz exactly
        if not delta > 0.0:
            return 0.0, 0.0, d_max, f_max, b_max
        return 0.25 * _PI * e_star * delta, math.sqrt(r_eff * delta), d_max, f_max, b_max
    # the unloading line from the remembered δ_max on the loading curve of this R_eff (the
    # stored F_max, b_max where R_eff is the history's: the same values, bit for bit), so F is
    # continuous at δ = δ_max whatever summit meets the point (module docstring)
    f_max, b_max = plastic_loading(d_max, r_eff, e_star, yield_strength, hardness, nu)
    # ≥ 0 as the loading curve's elastic cap promises (where that cap holds F_max the difference
    # is rounding, and a negative one would give a force at δ ≤ 0)
    residual = max(d_max - 4.0 * f_max / (_PI * e_star), 0.0)
    if not delta > residual:
        return 0.0, 0.0, d_max, f_max, b_max
    recovered = d_max - residual
    if not recovered > 0.0:
        return 0.0, 0.0, d_max, f_max, b_max
    b = b_max * math.sqrt((delta - residual) / recovered)
    return 0.25 * _PI * e_star * (delta - residual), math.sqrt(2.0) * b, d_max, f_max, b_max


def _check_positive(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise YieldStrengthError(f"{name} = {value!r} is not a number; give it in GPa (> 0)")
    number = float(value)
    if not math.isfinite(number) or number <= 0.0 or number > MAGNITUDE_LIMIT:
        raise YieldStrengthError(f"{name} = {number!r} GPa must be a finite number > 0")
    return number


@dataclass(frozen=True)
class ElasticPlastic:
    """Elastic–plastic line contact: Hertz up to Green's (2005) yield onset, a mean-pressure law
    to the fully plastic state beyond it, elastic unloading to a remembered residual
    interference.

    Parameters
    ----------
    yield_strength : float or None
        Yield strength S_y [GPa] (give this or ``hardness``).
    hardness : float or None
        Hardness H [GPa] (give this or ``yield_strength``; the other follows from H = 2.8 S_y).
    poisson_ratio : float
        Poisson's ratio ν [1] of the yielding body, in [0, 0.5).
    """

    code: ClassVar[int] = 4
    name: ClassVar[str] = "elastic-plastic"
    n_state: ClassVar[int] = N_STATE

    yield_strength: float | None = None
    hardness: float | None = None
    poisson_ratio: float = 0.3

    def validate(self) -> None:
        """Raise :class:`~splinecontact.errors.YieldStrengthError` or
        :class:`~splinecontact.errors.PoissonRatioError`."""
        if (self.yield_strength is None) == (self.hardness is None):
            raise YieldStrengthError(
                "give exactly one of yield_strength and hardness [GPa] for the elastic-plastic "
                f"law (got yield_strength = {self.yield_strength!r}, hardness = {self.hardness!r})"
            )
        if self.yield_strength is not None:
            _check_positive("yield_strength", self.yield_strength)
        else:
            _check_positive("hardness", self.hardness)
        nu = self.poisson_ratio
        if (
            isinstance(nu, bool)
            or not isinstance(nu, int | float | np.floating | np.integer)
            or not 0.0 <= float(nu) < 0.5
        ):
            raise PoissonRatioError(
                f"poisson_ratio = {nu!r} must be a number in [0, 0.5) (typical 0.3)"
            )

    @property
    def sy(self) -> float:
        """Yield strength S_y [GPa] (given, or H/2.8)."""
        if self.yield_strength is not None:
            return float(self.yield_strength)
        return float(self.hardness) / TABOR_FACTOR  # type: ignore[arg-type]

    @property
    def h(self) -> float:
        """Hardness H [GPa] (given, or 2.8 S_y)."""
        if self.hardness is not None:
            return float(self.hardness)
        return TABOR_FACTOR * float(self.yield_strength)  # type: ignore[arg-type]

    def parameters(self) -> NDArray[np.float64]:
        """Kernel parameters: ``[S_y [GPa], H [GPa], ν]``."""
        return np.array([self.sy, self.h, float(self.poisson_ratio)])

    def kernel_parameters(self, e_star: float) -> NDArray[np.float64]:
        """``[E* [GPa], S_y [GPa], H [GPa], ν]``."""
        return np.concatenate(([float(e_star)], self.parameters()))

    def settings(self) -> dict[str, float]:
        """Parameters recorded with results: both strengths [GPa] (the derived one included)
        and ν."""
        return {
            "yield_strength": self.sy,
            "hardness": self.h,
            "poisson_ratio": float(self.poisson_ratio),
        }

    def reach_for(self, e_star: float, r_eff_max: float) -> float:
        """No force at a gap: 0 [µm]."""
        return 0.0

    @property
    def reach(self) -> float:
        """0 [µm]: force only in overlap."""
        return 0.0

    def bind(self, e_star: float, r_eff_max: float) -> Self:
        """This law (nothing depends on E*)."""
        return replace(self)
