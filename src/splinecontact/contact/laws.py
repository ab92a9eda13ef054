"""Local contact laws: the normal force of one accepted contact, and the tangential spring.

A normal law maps the local geometry of one contact (the overlap δ [µm] of the two surface
spheres, eq. 10, and R_eff = 2/(κ^u + κ^l) [µm]) and the contact's history state to a normal
force per unit thickness [mN/µm] and a contact half-width [µm] (the contact's share of A_S).
Both kernels (the monotone loading of :mod:`.kernel` and the load paths of :mod:`.path_kernel`)
call the same compiled functions:

* :func:`normal_law` ``(code, params, delta, r_eff, state, point) -> (force, width)``: a trial
  evaluation (e.g. while a force-controlled step solves for δ_N) that changes no history; it
  may leave a memo of a pure function of its inputs (JKR: the branch this δ, R_eff and branch
  give; Maugis–Dugdale: the fold and the last root), which :func:`commit_law` reuses;
* :func:`commit_law` ``(code, params, delta, r_eff, state, point) -> None``: called once per
  accepted contact when a step is committed; a history-dependent law updates ``state[point]``;
* :func:`tangential_spring` ``(previous, increment, mu0, normal_force) -> (force, slipping,
  trial)``: eqs. 11–13.

``code`` is the law's :attr:`ContactLaw.code`, ``params`` is :meth:`ContactLaw.kernel_parameters`
(E* [GPa] first, then the law's own parameters), ``state`` a 2-D float array with one row per
lower-body grid point and :attr:`ContactLaw.n_state` columns (it survives separation and persists
across the steps of a run), and ``point`` the lower grid index of the contact. A law with a
:attr:`ContactLaw.reach` > 0 [µm] acts before the spheres touch: the kernels then visit points whose
gap is ≤ reach and accept contacts with δ > −reach.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, ClassVar, NamedTuple, Protocol, runtime_checkable

import numba
import numpy as np
from numba.core import types
from numba.extending import overload
from numpy.typing import NDArray

from .._memory import sparse_zeros
from ..errors import ContactLawError, ParameterError, UnknownContactLawError
from .adhesion import DMT, JKR, dmt_evaluate, jkr_evaluate
from .geometry import add_contact_forces
from .maugis_dugdale import MaugisDugdale, md_evaluate
from .plasticity import ElasticPlastic, plastic_evaluate

__all__ = [
    "DMT",
    "HERTZ",
    "JKR",
    "LAWS",
    "ContactLaw",
    "ElasticPlastic",
    "Hertz",
    "Material",
    "MaugisDugdale",
    "bind_law",
    "check_law",
    "commit_law",
    "kernel_material",
    "law_record",
    "law_step",
    "make_law",
    "new_law_state",
    "normal_law",
    "release_law",
    "spring_sums",
    "tangential_spring",
]

_QUARTER_PI = 0.25 * math.pi

#: Kernel code of the Hertzian line contact.
HERTZ = 0
_JKR = 1  # kernel codes of the other laws (their classes' ``code``)
_DMT = 2
_MD = 3


@runtime_checkable
class ContactLaw(Protocol):
    """What a local normal contact law exposes to :func:`splinecontact.simulate`.

    Attributes
    ----------
    code : int
        Dispatch code of :func:`normal_law` [1].
    name : str
        Name recorded with the results.
    reach : float
        Largest positive gap [µm] at which the law carries force (0 for laws acting only in
        overlap).
    n_state : int
        History values kept per lower-body grid point [1] (0 for history-free laws).
    """

    code: ClassVar[int]
    name: ClassVar[str]
    n_state: ClassVar[int]

    @property
    def reach(self) -> float: ...

    def validate(self) -> None:
        """Raise a :class:`~splinecontact.errors.ParameterError` subclass on bad parameters."""

    def parameters(self) -> NDArray[np.float64]:
        """The law's own parameters in the order the kernel reads them (units per law)."""

    def kernel_parameters(self, e_star: float) -> NDArray[np.float64]:
        """``[E*, *parameters()]``: E* [GPa] first, as :func:`normal_law` reads it."""

    def settings(self) -> dict[str, float]:
        """The parameters as the user gives them (recorded with the results)."""

    def bind(self, e_star: float, r_eff_max: float) -> ContactLaw:
        """The law with its :attr:`reach` resolved for E* [GPa] and R_eff ≤ ``r_eff_max`` [µm]."""


@dataclass(frozen=True)
class Hertz:
    """Hertzian line contact (paper eq. 10): F = (π/4) E* δ, half-width a = √(δ R_eff).

    No parameters besides E* (given to :func:`splinecontact.simulate`), no reach, no history.
    """

    code: ClassVar[int] = HERTZ
    name: ClassVar[str] = "hertz"
    n_state: ClassVar[int] = 0

    @property
    def reach(self) -> float:
        """Gap [µm] below which the law acts: 0 (force only in overlap, δ > 0)."""
        return 0.0

    def validate(self) -> None:
        """Nothing to check (no parameters)."""

    def parameters(self) -> NDArray[np.float64]:
        """No parameters: an empty array."""
        return np.zeros(0)

    def kernel_parameters(self, e_star: float) -> NDArray[np.float64]:
        """``[E*]`` [GPa]."""
        return np.concatenate(([float(e_star)], self.parameters()))

    def settings(self) -> dict[str, float]:
        """No parameters to record."""
        return {}

    def bind(self, e_star: float, r_eff_max: float) -> Hertz:
        """This law (nothing depends on E*)."""
        return self


def check_law(law: object) -> ContactLaw:
    """Validate ``law`` (a :class:`ContactLaw` such as ``Hertz()``) and return it.

    Raises
    ------
    ParameterError
        ``law`` is not a contact law, or its parameters are invalid.
    """
    if not isinstance(law, ContactLaw) or isinstance(law, type):
        raise ParameterError(
            f"law = {law!r} is not a contact law; give an instance such as "
            "splinecontact.contact.Hertz()"
        )
    law.validate()
    return law


#: Law name → class, as study files and the command line name them.
LAWS: dict[str, Any] = {cls.name: cls for cls in (Hertz, JKR, DMT, MaugisDugdale, ElasticPlastic)}


def make_law(name: str, **parameters: Any) -> ContactLaw:
    """The validated law called ``name`` (``hertz``, ``jkr``, ``dmt``, ``maugis-dugdale``,
    ``elastic-plastic``) with ``parameters`` (see each law for their units).

    Raises
    ------
    UnknownContactLawError
        ``name`` is not a known law.
    ContactLawError
        A parameter the law does not have, or an invalid value (a specific subclass).
    """
    cls = LAWS.get(name.strip().lower()) if isinstance(name, str) else None
    if cls is None:
        raise UnknownContactLawError(
            f"contact law {name!r} does not exist; choose one of {', '.join(LAWS)}"
        )
    fields = {f.name for f in dataclasses.fields(cls)} - {"reach_bound"}
    unknown = sorted(set(parameters) - fields)
    if unknown:
        have = ", ".join(sorted(fields)) if fields else "none"
        raise ContactLawError(
            f"the {cls.name} law has no parameter {', '.join(unknown)}; its parameters: {have}"
        )
    law: ContactLaw = cls(**parameters)
    law.validate()
    return law


def law_record(law: ContactLaw) -> dict[str, Any]:
    """What results record about the law: ``law`` (its name) and ``law_<parameter>`` for each
    parameter as the user gave it (units in the law's documentation)."""
    return {"law": law.name, **{f"law_{k}": v for k, v in law.settings().items()}}


def bind_law(law: ContactLaw, e_star: float, r_eff_max: float) -> ContactLaw:
    """``law`` with its reach [µm] resolved for E* [GPa] and contacts of R_eff ≤ ``r_eff_max``
    [µm] (adhesive laws hold or attract down to an overlap that depends on both)."""
    return law.bind(e_star, r_eff_max)


@numba.njit(cache=True, nogil=True)
def convex_samples(
    slope: NDArray[np.float64], second: NDArray[np.float64], stride: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """The slope [1] and second derivative [1/µm] of a fit at every ``stride``-th point where
    the second derivative is negative (the convex points), in one pass: what the reach radius
    of an adhesive law is taken from (the curvature itself is left to numpy, whose power
    function is not the C library's)."""
    n = (slope.size + stride - 1) // stride
    out_slope = np.empty(n)
    out_second = np.empty(n)
    m = 0
    for i in range(0, slope.size, stride):
        if second[i] < 0.0:
            out_slope[m] = slope[i]
            out_second[m] = second[i]
            m += 1
    return out_slope[:m], out_second[:m]


def new_law_state(law: ContactLaw, n_points: int) -> NDArray[np.float64]:
    """Zeroed history state: one row per lower-body grid point, ``law.n_state`` columns (only
    the rows of the points that touch are ever written: a sparse array)."""
    return sparse_zeros(n_points, law.n_state)


class Material(NamedTuple):
    """What the compiled kernels know of the contact law and of the tangential spring.

    Attributes
    ----------
    law_code : int
        :attr:`ContactLaw.code`.
    law_params : ndarray or tuple
        :meth:`ContactLaw.kernel_parameters`: ``[E* [GPa], *law parameters]``, or for Hertz
        the 1-tuple ``(E*,)`` (``hertz_alone`` of :func:`kernel_material`), a type of its own,
        so that a kernel running Hertz compiles Hertz alone (the other laws' code is typed,
        hence compiled, only for an array).
    law_state : ndarray
        History state, shape (n lower grid points, :attr:`ContactLaw.n_state`); persists across
        the steps of a run (and across separation).
    reach : float
        :attr:`ContactLaw.reach` [µm].
    g_star : float
        Effective shear modulus G* [GPa] (eq. 11).
    mu0 : float
        Molecular friction coefficient μ0 [1] (eqs. 12–13).
    """

    law_code: int
    law_params: NDArray[np.float64] | tuple[float]
    law_state: NDArray[np.float64]
    reach: float
    g_star: float
    mu0: float


def kernel_material(
    law: ContactLaw,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    n_points: int,
    hertz_alone: bool = False,
) -> Material:
    """The kernels' view of ``law`` with E* [GPa], G* [GPa], μ0 [1], and a fresh zero state for
    ``n_points`` lower grid points.

    With ``hertz_alone``, Hertz's parameters are the 1-tuple ``(E*,)``: a kernel typed with it
    compiles Hertz alone (the monotone loading loop uses it: a Hertz run does not compile the
    other laws). Without it they are an array, as for every other law, so a kernel has one
    compiled form for all laws (the load-path kernel, whose own compilation is the larger).
    """
    params = law.kernel_parameters(e_star)
    return Material(
        law_code=law.code,
        law_params=(float(params[0]),) if hertz_alone and law.code == HERTZ else params,
        law_state=new_law_state(law, n_points),
        reach=float(law.reach),
        g_star=float(g_star),
        mu0=float(mu0),
    )


# What one evaluation of a law does with the contact's history (the ``mode`` of _evaluate).
_TRIAL = 0  # normal_law: no history changed (memos only)
_FUSED = 1  # law_step: evaluate and commit at once
_COMMIT = 2  # commit_law: update the history (reusing the trial's memo where there is one)


def _evaluate_hertz(
    code: int, params: tuple[float], delta: float, r_eff: float, state: Any, point: int, mode: int
) -> tuple[float, float]:  # pragma: no cover - compiled
    if mode == _COMMIT:
        return 0.0, 0.0  # no history
    return _QUARTER_PI * params[0] * delta, math.sqrt(delta * r_eff)


def _evaluate(
    code: int,
    params: Any,
    delta: float,
    r_eff: float,
    state: NDArray[np.float64],
    point: int,
    mode: int,
) -> tuple[float, float]:  # pragma: no cover - compiled
    # Compiled only (numba), in two forms chosen by the type of ``params`` (below).
    if code == HERTZ or code == _DMT:
        if mode == _COMMIT:
            return 0.0, 0.0  # no history
        if code == HERTZ:
            return _QUARTER_PI * params[0] * delta, math.sqrt(delta * r_eff)
        return dmt_evaluate(delta, r_eff, params[0], params[1], params[2])
    if mode == _COMMIT:
        if (
            code == _JKR
            and state.shape[1] >= 5
            and state[point, 1] == delta
            and state[point, 2] == r_eff
            and state[point, 3] == state[point, 0]
        ):
            state[point, 0] = state[point, 4]  # this δ, R_eff and branch were just evaluated
            return 0.0, 0.0
        if code == _MD and state[point, 5] == delta and state[point, 6] == r_eff:
            # the trial evaluation of this step (same δ and R_eff, same committed state) is kept
            state[point, 0] = state[point, 7]
            state[point, 1] = state[point, 8]
            return 0.0, 0.0
    out = _history_law(code, params, delta, r_eff, state, point)
    if mode != _TRIAL:
        _store(state, point, out)
    elif code == _JKR and state.shape[1] >= 5:
        # Memo of a pure function of (δ, R_eff, branch): commit_law reuses it.
        state[point, 1] = out[3]
        state[point, 2] = out[4]
        state[point, 3] = out[5]
        state[point, 4] = out[6]
    return out[0], out[1]


@overload(_evaluate, jit_options={"nogil": True}, strict=False, inline="always")
def _evaluate_typed(code: Any, params: Any, *rest: Any) -> Any:
    # Chosen when a kernel is typed: Hertz's 1-tuple of parameters compiles Hertz alone.
    return _evaluate_hertz if isinstance(params, types.BaseTuple) else _evaluate


@numba.njit(cache=True, nogil=True)
def normal_law(
    code: int,
    params: NDArray[np.float64] | tuple[float],
    delta: float,
    r_eff: float,
    state: NDArray[np.float64],
    point: int,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Normal force [mN/µm] and contact half-width [µm] of one contact (eq. 10).

    Parameters
    ----------
    code : int
        The law's dispatch code (:data:`HERTZ`).
    params : ndarray or tuple
        ``[E* [GPa], *law parameters]`` (:attr:`Material.law_params`).
    delta : float
        Overlap of the surface spheres [µm] (> −reach).
    r_eff : float
        Effective radius 2/(κ^u + κ^l) [µm].
    state : ndarray
        History state, shape (n_points, n_state); only memos are written (no history).
    point : int
        Lower-body grid index of the contact.
    """
    return _evaluate(code, params, delta, r_eff, state, point, _TRIAL)


@numba.njit(cache=True, nogil=True)
def law_step(
    code: int,
    params: NDArray[np.float64] | tuple[float],
    delta: float,
    r_eff: float,
    state: NDArray[np.float64],
    point: int,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """:func:`normal_law` and :func:`commit_law` in one evaluation (the monotone loading loop)."""
    return _evaluate(code, params, delta, r_eff, state, point, _FUSED)


@numba.njit(cache=True, nogil=True)
def commit_law(
    code: int,
    params: NDArray[np.float64] | tuple[float],
    delta: float,
    r_eff: float,
    state: NDArray[np.float64],
    point: int,
) -> None:  # pragma: no cover - compiled
    """Update the history ``state[point]`` of an accepted contact when its step is committed."""
    _evaluate(code, params, delta, r_eff, state, point, _COMMIT)


@numba.njit(cache=True, nogil=True)
def _history_law(
    code: int,
    params: NDArray[np.float64],
    delta: float,
    r_eff: float,
    state: NDArray[np.float64],
    point: int,
) -> tuple[float, float, float, float, float, float, float]:  # pragma: no cover - compiled
    # (force, width, new state values) of the laws that keep a history.
    e_star = params[0]
    if code == _JKR:
        before = state[point, 0]
        f, width, branch = jkr_evaluate(delta, r_eff, e_star, params[1], before)
        return f, width, branch, delta, r_eff, before, branch  # the branch, then the memo
    if code == _MD:
        return md_evaluate(delta, r_eff, e_star, params[1], params[2], state[point])
    f, width, d_max, f_max, b_max = plastic_evaluate(
        delta, r_eff, e_star, params[1], params[2], params[3], state[point]
    )
    return f, width, d_max, f_max, b_max, 0.0, 0.0


@numba.njit(cache=True, nogil=True)
def release_law(code: int, state: NDArray[np.float64], point: int) -> None:  # pragma: no cover
    """A contact that is no longer accepted lets go: the adhesive laws' branch returns to
    "apart" (the plastic history is kept)."""
    if code == _JKR:
        state[point, 0] = 0.0
    elif code == _MD:
        state[point, 0] = 0.0
        state[point, 1] = 0.0


@numba.njit(cache=True, nogil=True)
def _store(
    state: NDArray[np.float64],
    point: int,
    out: tuple[float, float, float, float, float, float, float],
) -> None:  # pragma: no cover - compiled
    n = state.shape[1]
    if n > 0:
        state[point, 0] = out[2]
    if n > 1:
        state[point, 1] = out[3]
    if n > 2:
        state[point, 2] = out[4]
    if n > 3:
        state[point, 3] = out[5]
    if n > 4:
        state[point, 4] = out[6]


@numba.njit(cache=True, nogil=True)
def tangential_spring(
    previous: float, increment: float, mu0: float, normal_force: float
) -> tuple[float, bool, float]:  # pragma: no cover - compiled
    """Incremental tangential force with the Coulomb cap (eqs. 11–13).

    Parameters
    ----------
    previous : float
        Spring force of the contact at the previous step [mN/µm] (0 for a new contact).
    increment : float
        G* times the relative tangential displacement increment [mN/µm] (eq. 11).
    mu0 : float
        Molecular friction coefficient μ0 [1].
    normal_force : float
        Normal force of the contact [mN/µm].

    Returns
    -------
    (force, slipping, trial)
        The capped force |F^t| ≤ μ0 F^n [mN/µm] (sign kept, eq. 13), whether the cap acted,
        and the uncapped trial force [mN/µm] (eq. 11).
    """
    trial = previous - increment
    cap = mu0 * max(normal_force, 0.0)  # an adhesive (tensile) contact carries no friction
    if trial > cap:
        return cap, True, trial
    if trial < -cap:
        return -cap, True, trial
    return trial, False, trial


@numba.njit(cache=True, nogil=True)
def spring_sums(
    du: float, dd: float, n_c: int, g_star: float, mu0: float, springs: Any, scratch: Any
) -> tuple[tuple[float, float, float, float, float, int], int, float, int]:  # pragma: no cover
    """Eqs. 11–13 on the ``n_c`` accepted contacts of a load-path step, and their sums.

    ``scratch`` (:class:`.path_kernel.Scratch`) holds each contact's normal force ``fn``
    [mN/µm], direction ``ex``, ``ez`` [1], half-width ``width`` [µm] and the previous contact
    ``src`` it continues (−1: new), whose spring force ``ft`` and direction are in ``springs``
    (:class:`.path_kernel.Springs`); ``du``, ``dd`` the step's Δu_T, Δδ_N [µm]. Writes each
    contact's ``ft`` and ``slip``; returns the sums of :func:`.geometry.add_contact_forces`,
    the slipping contacts, the slip work [mN·µm/µm] and the contacts that touch.
    """
    sums = (0.0, 0.0, 0.0, 0.0, 0.0, 0)
    work = 0.0
    n_slip = 0
    n_touch = 0
    for c in range(n_c):
        f_n = scratch.fn[c]
        e_x = scratch.ex[c]
        e_z = scratch.ez[c]
        src = scratch.src[c]
        previous = 0.0
        increment = 0.0
        if src >= 0:
            # Eq. 11 with the upper body's increment (Δu_T, −Δδ_N) projected on the mean of the
            # old and new tangents t = (e_z, −e_x) (trapezoidal rule: reversible without slip).
            proj = 0.5 * (du * (springs.ez[src] + e_z) + dd * (springs.ex[src] + e_x))
            previous = springs.ft[src]
            increment = g_star * proj
        f_t, slipping, trial = tangential_spring(previous, increment, mu0, f_n)
        if slipping:
            n_slip += 1
            if g_star > 0.0:
                cap = mu0 * max(f_n, 0.0)
                work += cap * (abs(trial) - cap) / g_star
        scratch.ft[c] = f_t
        scratch.slip[c] = slipping
        sums = add_contact_forces(sums, f_n, f_t, e_x, e_z, scratch.width[c])
        if f_n != 0.0 or scratch.width[c] > 0.0:
            n_touch += 1  # a law acting at a gap also visits points it leaves without force
    return sums, n_slip, work, n_touch
