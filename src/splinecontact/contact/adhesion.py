"""Adhesive line contacts: 2D JKR and 2D DMT (plane strain, per unit thickness); 2D Maugis–Dugdale
is in :mod:`.maugis_dugdale`.

Each law replaces the Hertzian normal force of one SAD contact (paper eq. 10, F = (π/4) E* δ) by
an adhesive one, as the paper's Sec. 4 proposes. Conventions (``docs/contact-laws.md``):

* ``r_eff`` is the package's R_eff = 2/(κ^u + κ^l) [µm]; the textbook reduced radius of the two
  cylinders is R = R_eff/2 (for a circle of radius r on the rigid flat, R = r).
* ``b`` is the true contact half-width [µm]; the law's *width* output is √2·b, the paper's
  A_i = √(δ R_eff) for Hertz (``docs/conventions.md``), so A_S keeps its meaning.
* The work of adhesion is entered as ``work_of_adhesion`` in J/m² (typical 0.01–1) and converted
  once, ``w = 10⁻³ · work_of_adhesion`` in the package's force unit per length, mN/µm; every
  function below that takes ``w`` takes it in mN/µm.
* The approach δ [µm] in 2D is defined only up to a log term. The package's Hertz law
  F = (π/4) E* δ ⇔ b² = R δ is the elastic approach measured against reference points at the
  distance β·b from the contact, β = e^{3/2}/2, and the same rule is applied to every part of the
  pressure over the zone it loads: the Hertzian part over the contact |x| < b, the adhesive
  tractions over the adhesive zone |x| < c (c = b in JKR). This gives, per unit thickness,
  JKR: δ = b²/R − 3 P₁/(π E*) with the punch load P₁ = √(2π E* w b); Maugis–Dugdale: eq. (MD-δ)
  in :func:`md_approach`. At a positive gap (DMT, Maugis–Dugdale out of contact) δ < 0 is minus the
  gap of the undeformed surfaces.

All three laws are evaluated under displacement control of δ (SAD moves the upper body):
each contact keeps the branch it is on while that branch exists, so contact forms by a jump-in
and breaks by a jump-out (JKR, Maugis–Dugdale with a fold); the minimum force along a path is
the load-control pull-off whenever the path passes its half-width (JKR: b_c, eq. (J-c)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import ClassVar, Self

import numba
import numpy as np
from numpy.typing import NDArray

from .._checks import MAGNITUDE_LIMIT
from ..errors import CohesiveStressError, ContactLawError, WorkOfAdhesionError

__all__ = [
    "DMT",
    "JKR",
    "MILLINEWTON_PER_MICROMETRE_PER_JOULE_PER_SQUARE_METRE",
    "CohesiveZoneLaw",
    "dmt_evaluate",
    "dmt_pull_off_force",
    "jkr_approach",
    "jkr_evaluate",
    "jkr_force",
    "jkr_jump_in_half_width",
    "jkr_jump_out_half_width",
    "jkr_pull_off_force",
    "jkr_pull_off_half_width",
]

#: 1 J/m² = 1 N/m = 10⁻³ mN/µm: multiply a work of adhesion in J/m² by this to get mN/µm.
MILLINEWTON_PER_MICROMETRE_PER_JOULE_PER_SQUARE_METRE = 1e-3

_PI = math.pi
#: ln(2β) with β = e^{3/2}/2: the reference distance that makes Hertz F = (π/4)E*δ.
_LOG_2BETA = 1.5
#: State columns of JKR: the branch (0 apart, 2 in contact), then a memo of the contact's last
#: evaluation (δ [µm], R_eff [µm], the branch it started from and the branch it gave), so that
#: committing a step does not solve the contact again.
N_STATE = 5


def _check_number(
    value: object, error: type[ContactLawError], name: str, unit: str, zero_ok: bool, hint: str
) -> float:
    # A finite number ≥ 0 (zero_ok) or > 0, not above MAGNITUDE_LIMIT; else ``error`` naming
    # the value and its unit, and how to give it (``hint``).
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise error(f"{name} = {value!r} is not a number; {hint}")
    number = float(value)
    low_ok = number >= 0.0 if zero_ok else number > 0.0
    if not math.isfinite(number) or not low_ok or number > MAGNITUDE_LIMIT:
        bound = "≥ 0 (0 is Hertz)" if zero_ok else "> 0"
        raise error(f"{name} = {number!r} {unit} must be a finite number {bound}; {hint}")
    return number


def _check_w(value: object) -> float:
    return _check_number(
        value, WorkOfAdhesionError, "work_of_adhesion", "J/m²", True,
        "give the work of adhesion in J/m² (typical 0.01–1)",
    )  # fmt: skip


def _check_sigma(value: object) -> float:
    return _check_number(
        value, CohesiveStressError, "cohesive_stress", "GPa", False,
        "give the Dugdale stress σ0 in GPa (typical 0.1–10)",
    )  # fmt: skip


# --- 2D JKR (Barquins 1988; Chaudhury, Weaver, Hui & Kramer 1996) -----------------------------


@numba.njit(cache=True, nogil=True)
def jkr_force(half_width: float, r_eff: float, e_star: float, w: float) -> float:
    """Force of a JKR line contact of half-width b (eq. J-F): P = π E* b²/(4R) − √(2π E* w b).

    Parameters
    ----------
    half_width : float
        Contact half-width b [µm].
    r_eff : float
        R_eff = 2/(κ^u + κ^l) [µm] (R = R_eff/2).
    e_star : float
        Contact modulus E* [GPa].
    w : float
        Work of adhesion [mN/µm].

    Returns
    -------
    float
        Normal force per unit thickness [mN/µm] (negative = tensile).
    """
    return 0.5 * _PI * e_star * half_width * half_width / r_eff - math.sqrt(
        2.0 * _PI * e_star * w * half_width
    )


@numba.njit(cache=True, nogil=True)
def jkr_approach(half_width: float, r_eff: float, e_star: float, w: float) -> float:
    """Approach of a JKR line contact of half-width b (eq. J-δ): δ = b²/R − 3√(2wb/(π E*)) [µm].

    Hertz part b²/R (the package's F = (π/4)E*δ) minus the flat-punch part 3P₁/(πE*) with the
    same reference rule (see the module docstring); inputs as :func:`jkr_force`.
    """
    return 2.0 * half_width * half_width / r_eff - 3.0 * math.sqrt(
        2.0 * w * half_width / (_PI * e_star)
    )


def jkr_pull_off_half_width(r_eff: float, e_star: float, w: float) -> float:
    """Half-width at the load-control pull-off (eq. J-c): b_c = (2 w R²/(π E*))^{1/3} [µm]."""
    r = 0.5 * r_eff
    return float((2.0 * w * r * r / (_PI * e_star)) ** (1.0 / 3.0))


def jkr_pull_off_force(r_eff: float, e_star: float, w: float) -> float:
    """Load-control pull-off force (eq. J-c): P_c = −3 (π E* R w²/16)^{1/3} [mN/µm].

    It is also the minimum force along a displacement-controlled unloading that passes b_c
    (b_c lies on the stable branch: b_c > :func:`jkr_jump_out_half_width`).
    """
    r = 0.5 * r_eff
    return float(-3.0 * (_PI * e_star * r * w * w / 16.0) ** (1.0 / 3.0))


def jkr_jump_out_half_width(r_eff: float, e_star: float, w: float) -> float:
    """Half-width where a displacement-controlled JKR contact jumps out (dδ/db = 0, eq. J-m):
    b_m = (9 w R²/(8π E*))^{1/3} [µm]."""
    r = 0.5 * r_eff
    return float((9.0 * w * r * r / (8.0 * _PI * e_star)) ** (1.0 / 3.0))


def jkr_jump_in_half_width(r_eff: float, e_star: float, w: float) -> float:
    """Half-width the contact jumps to when the surfaces touch (δ = 0 on the stable branch):
    b_0 = (18 w R²/(π E*))^{1/3} [µm]."""
    r = 0.5 * r_eff
    return float((18.0 * w * r * r / (_PI * e_star)) ** (1.0 / 3.0))


@numba.njit(cache=True, nogil=True)
def _jkr_stable_root(delta: float, r: float, a: float) -> float:
    # Largest root s = √b of s⁴/R − a s − δ = 0 (a = 3√(2w/(πE*))): f is convex for s > 0, so
    # Newton from a point with f ≥ 0 right of the root decreases monotonically onto it.
    s = (r * abs(delta)) ** 0.25 + (r * a) ** (1.0 / 3.0)
    for _ in range(200):
        s3 = s * s * s
        f = s3 * s / r - a * s - delta
        df = 4.0 * s3 / r - a
        if df <= 0.0:
            break
        step = f / df
        s_new = s - step
        if not s_new < s:
            break
        s = s_new
        if step <= 1e-16 * s:
            break
    return s * s


@numba.njit(cache=True, nogil=True)
def jkr_evaluate(
    delta: float, r_eff: float, e_star: float, w: float, branch: float
) -> tuple[float, float, float]:
    """One JKR contact under displacement control.

    Parameters
    ----------
    delta : float
        Overlap of the undeformed surface spheres δ [µm] (eq. 10).
    r_eff : float
        R_eff [µm].
    e_star : float
        E* [GPa].
    w : float
        Work of adhesion [mN/µm] (0: Hertz exactly).
    branch : float
        The contact's state: 0 apart, 2 in contact (from the previous committed step).

    Returns
    -------
    (force, width, branch)
        Force [mN/µm], width √2·b [µm] and the new branch.
    """
    if w == 0.0:
        if delta > 0.0:
            return 0.25 * _PI * e_star * delta, math.sqrt(delta * r_eff), 2.0
        return 0.0, 0.0, 0.0
    r = 0.5 * r_eff
    if branch == 2.0:
        b_m = (9.0 * w * r * r / (8.0 * _PI * e_star)) ** (1.0 / 3.0)
        if delta < jkr_approach(b_m, r_eff, e_star, w):
            return 0.0, 0.0, 0.0  # jump-out
    elif delta < 0.0:
        return 0.0, 0.0, 0.0  # apart: JKR has no attraction at a gap
    a = 3.0 * math.sqrt(2.0 * w / (_PI * e_star))
    b = _jkr_stable_root(delta, r, a)
    return jkr_force(b, r_eff, e_star, w), math.sqrt(2.0) * b, 2.0


@dataclass(frozen=True)
class JKR:
    """2D JKR line contact (Barquins 1988; Chaudhury, Weaver, Hui & Kramer 1996).

    P = π E* b²/(4R) − √(2π E* w b) with R = R_eff/2; approach δ = b²/R − 3√(2wb/(πE*))
    (package convention, ``docs/contact-laws.md``). No attraction at a positive gap.

    Parameters
    ----------
    work_of_adhesion : float
        Work of adhesion w [J/m²] (≥ 0; 0 gives Hertz exactly).
    """

    code: ClassVar[int] = 1
    name: ClassVar[str] = "jkr"
    n_state: ClassVar[int] = N_STATE
    #: The reach depends on the largest R_eff (``bind`` needs it).
    needs_radius: ClassVar[bool] = True

    work_of_adhesion: float = 0.1
    reach_bound: float = field(default=0.0, repr=False, compare=False)

    def validate(self) -> None:
        """Raise :class:`~splinecontact.errors.WorkOfAdhesionError` for a bad w."""
        _check_w(self.work_of_adhesion)

    @property
    def w(self) -> float:
        """Work of adhesion in the package's unit [mN/µm]."""
        return float(self.work_of_adhesion) * MILLINEWTON_PER_MICROMETRE_PER_JOULE_PER_SQUARE_METRE

    def parameters(self) -> NDArray[np.float64]:
        """Kernel parameters: ``[w [mN/µm]]``."""
        return np.array([self.w])

    def kernel_parameters(self, e_star: float) -> NDArray[np.float64]:
        """``[E* [GPa], w [mN/µm]]``."""
        return np.concatenate(([float(e_star)], self.parameters()))

    def settings(self) -> dict[str, float]:
        """Parameters as given, recorded with results (``work_of_adhesion`` [J/m²])."""
        return {"work_of_adhesion": float(self.work_of_adhesion)}

    def reach_for(self, e_star: float, r_eff_max: float) -> float:
        """Deepest separation [µm] at which a contact of R_eff ≤ ``r_eff_max`` [µm] still holds:
        −δ(b_m), the overlap where it jumps out."""
        if self.w == 0.0:
            return 0.0
        b_m = jkr_jump_out_half_width(r_eff_max, e_star, self.w)
        return max(0.0, -float(jkr_approach(b_m, r_eff_max, e_star, self.w)))

    @property
    def reach(self) -> float:
        """Reach [µm] bound by :meth:`bind` (0 before)."""
        return self.reach_bound

    def bind(self, e_star: float, r_eff_max: float) -> Self:
        """This law with its reach for E* [GPa] and R_eff ≤ ``r_eff_max`` [µm]."""
        return replace(self, reach_bound=self.reach_for(e_star, r_eff_max))


# --- 2D DMT ----------------------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def dmt_evaluate(
    delta: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float]:
    """2D DMT force [mN/µm] and width [µm] (eq. D): Hertzian deformation, Dugdale attraction
    σ0 over the undeformed gap < h0 = w/σ0 (Derjaguin approximation), frozen at its value at
    touching while in contact:

    * δ ≥ 0: F = (π/4) E* δ − 2σ0 √(2R h0), width √(δ R_eff);
    * −h0 < δ < 0: F = −2σ0 √(2R (h0 + δ)), width 0;  δ ≤ −h0: 0.

    ``w`` in mN/µm, ``sigma0`` in GPa, lengths in µm; R = R_eff/2.
    """
    if w == 0.0:
        if delta > 0.0:
            return 0.25 * _PI * e_star * delta, math.sqrt(delta * r_eff)
        return 0.0, 0.0
    h0 = w / sigma0
    if delta >= 0.0:
        return (
            0.25 * _PI * e_star * delta - 2.0 * sigma0 * math.sqrt(r_eff * h0),
            math.sqrt(delta * r_eff),
        )
    if delta > -h0:
        return -2.0 * sigma0 * math.sqrt(r_eff * (h0 + delta)), 0.0
    return 0.0, 0.0


def dmt_pull_off_force(r_eff: float, w: float, sigma0: float) -> float:
    """2D DMT pull-off (eq. D-c): P_c = −2σ0 √(2R h0) = −2 √(2R w σ0) [mN/µm] (R = R_eff/2).

    Unlike in 3D it depends on the range h0 = w/σ0, not on w alone.
    """
    return float(-2.0 * math.sqrt(r_eff * w * sigma0))


@dataclass(frozen=True)
class CohesiveZoneLaw:
    """Parameters and bookkeeping shared by the laws with a Dugdale cohesive zone (:class:`DMT`,
    :class:`~splinecontact.contact.maugis_dugdale.MaugisDugdale`): work of adhesion w [J/m²],
    Dugdale stress σ0 [GPa] and the reach bound for a given E* and R_eff.
    """

    work_of_adhesion: float = 0.1
    cohesive_stress: float = 1.0
    reach_bound: float = field(default=0.0, repr=False, compare=False)

    def validate(self) -> None:
        """Raise :class:`~splinecontact.errors.WorkOfAdhesionError` or
        :class:`~splinecontact.errors.CohesiveStressError`."""
        _check_w(self.work_of_adhesion)
        _check_sigma(self.cohesive_stress)

    @property
    def w(self) -> float:
        """Work of adhesion [mN/µm]."""
        return float(self.work_of_adhesion) * MILLINEWTON_PER_MICROMETRE_PER_JOULE_PER_SQUARE_METRE

    @property
    def range(self) -> float:
        """Range of the attraction h0 = w/σ0 [µm]."""
        return self.w / float(self.cohesive_stress)

    def parameters(self) -> NDArray[np.float64]:
        """Kernel parameters: ``[w [mN/µm], σ0 [GPa]]``."""
        return np.array([self.w, float(self.cohesive_stress)])

    def kernel_parameters(self, e_star: float) -> NDArray[np.float64]:
        """``[E* [GPa], w [mN/µm], σ0 [GPa]]``."""
        return np.concatenate(([float(e_star)], self.parameters()))

    def settings(self) -> dict[str, float]:
        """Parameters as given, recorded with results (``work_of_adhesion`` [J/m²],
        ``cohesive_stress`` [GPa])."""
        return {
            "work_of_adhesion": float(self.work_of_adhesion),
            "cohesive_stress": float(self.cohesive_stress),
        }

    @property
    def reach(self) -> float:
        """Reach [µm] bound by :meth:`bind` (0 before)."""
        return self.reach_bound

    def bind(self, e_star: float, r_eff_max: float) -> Self:
        """This law with its reach for E* [GPa] and R_eff ≤ ``r_eff_max`` [µm]."""
        return replace(self, reach_bound=self.reach_for(e_star, r_eff_max))

    def reach_for(self, e_star: float, r_eff_max: float) -> float:  # pragma: no cover - abstract
        """Largest gap [µm] at which the law attracts (each law's own)."""
        raise NotImplementedError


@dataclass(frozen=True)
class DMT(CohesiveZoneLaw):
    """2D DMT line contact (Hertzian deformation plus Dugdale attraction outside it).

    Parameters
    ----------
    work_of_adhesion : float
        Work of adhesion w [J/m²] (≥ 0; 0 gives Hertz exactly).
    cohesive_stress : float
        Dugdale stress σ0 [GPa] (> 0); the range is h0 = w/σ0.
    """

    code: ClassVar[int] = 2
    name: ClassVar[str] = "dmt"
    n_state: ClassVar[int] = 0
    #: The reach h0 does not depend on R_eff.
    needs_radius: ClassVar[bool] = False

    def reach_for(self, e_star: float, r_eff_max: float) -> float:
        """Largest gap [µm] at which the law attracts: h0."""
        return self.range
