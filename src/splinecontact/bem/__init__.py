"""Exact reference: a rigid rough profile on an elastic half-space (plane strain, periodic).

The boundary element method (BEM) here solves the non-adhesive, frictionless hard-wall contact of
a rigid line profile pressed against an elastic half-space of effective modulus E*, exactly within
linear elasticity and the small-slope approximation. It is the reference against which the
independent-contact model of SAD (paper eq. 10, F = (π/4) E* δ per contact) is measured
(``splinecontact compare``, ``docs/accuracy.md``).

Model
-----
* The surface is periodic with period L = n·dx (``n`` nodes; the node after the last is the
  first one again, so do not repeat the first point at the end).
* Surface response in Fourier space (plane strain): p̂(q) = E*|q|/2 · û(q), q_k = 2πk/L, i.e.
  û(q) = 2 p̂(q)/(E*|q|) for q ≠ 0. The q = 0 mode of the displacement is set to zero: the
  elastic surface's mean line stays at the reference position s.
* Rough on rough: the composite profile z = z_lower + z_upper (both heights as a profilometer
  records them, pointing out of their own body) against a flat, with one effective modulus —
  the standard reduction. Local contact normals and tangential forces are beyond it (that is
  where SAD is needed; see ``docs/accuracy.md``).
* Gap g(x) = s + u(x) − z(x) ≥ 0, pressure p ≥ 0, p·g = 0. The mean gap is ḡ = s − z̄
  (u has zero mean), the distance between the mean lines of the two deformed surfaces.
* Discretisation: nodal pressures, the displacement from the exact spectral response of their
  trigonometric interpolant (collocation). Checked against Westergaard's and Hertz's solutions
  (:mod:`splinecontact.reference`).

Solvers
-------
* Load control (given mean pressure p̄ [GPa], force p̄·L [mN/µm]): constrained conjugate
  gradients of Polonsky & Keer (Wear 231, 1999, 206–219), with the mean-pressure constraint
  enforced at every iteration.
* Displacement control (given mean gap ḡ [µm]): the same projected conjugate gradients without
  the force constraint.
* Convergence: the largest complementarity violation — |g| at a loaded node, or the overlap −g at
  an unloaded one — divided by the rms height of the composite profile, below ``tol``.
  Otherwise :class:`~splinecontact.errors.NoConvergenceError`.
* Load paths (:func:`load_path`, :func:`gap_path`) warm-start every step from the previous
  pressure field.

Modules
-------
* ``_problem``: :class:`ContactProblem`, :func:`contact_problem`, :func:`mirror_extend`.
* ``_results``: :func:`contact_statistics`, :class:`BEMStep`, :class:`BEMPath`.
* ``_kernel``: the compiled Polonsky–Keer loop and its fused passes (every grid size; the
  operator is ``splinecontact._fft.circulant``).
* ``_solver``: :func:`solve_pressure`, :func:`solve_gap`, :func:`load_path`, :func:`gap_path`.
"""

from __future__ import annotations

from ..errors import (
    BEMGridError,
    BEMInputError,
    BEMParameterError,
    FullContactError,
    NegativeLoadError,
    NonPeriodicProfileError,
)
from ._kernel import _k_add_columns as _k_add_columns  # the column update (tests)
from ._problem import (
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_TOLERANCE,
    MIN_BEM_POINTS,
    PERIODIC_JUMP_FACTOR,
    ContactProblem,
    contact_problem,
    mirror_extend,
)
from ._results import STEP_UNITS, BEMPath, BEMStep, ContactStatistics, contact_statistics
from ._solver import _initial_guess as _initial_guess  # the bearing-area guess (tests)
from ._solver import gap_path, load_path, solve_gap, solve_pressure

__all__ = [
    "DEFAULT_MAX_ITERATIONS",
    "DEFAULT_TOLERANCE",
    "MIN_BEM_POINTS",
    "PERIODIC_JUMP_FACTOR",
    "STEP_UNITS",
    "BEMGridError",
    "BEMInputError",
    "BEMParameterError",
    "BEMPath",
    "BEMStep",
    "ContactProblem",
    "ContactStatistics",
    "FullContactError",
    "NegativeLoadError",
    "NonPeriodicProfileError",
    "contact_problem",
    "contact_statistics",
    "gap_path",
    "load_path",
    "mirror_extend",
    "solve_gap",
    "solve_pressure",
]
