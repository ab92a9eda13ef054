"""The BEM's solvers: load control (Polonsky–Keer), displacement control, load and gap paths.

Load control runs the compiled loop of :mod:`._kernel` on every grid; displacement control is
the projected conjugate-gradient iteration without the force constraint (numpy, scipy.fft).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._fft import CirculantConvolution
from ..errors import BEMParameterError, FullContactError, NegativeLoadError, NoConvergenceError
from ._kernel import _k_pk_loop, _sparse_limit
from ._problem import DEFAULT_MAX_ITERATIONS, DEFAULT_TOLERANCE, ContactProblem, _apply
from ._results import STEP_UNITS, BEMPath, BEMStep, contact_statistics

__all__ = ["gap_path", "load_path", "solve_gap", "solve_pressure"]

#: A pressure field [GPa] that warm-starts the next step of a path, or None.
_Field = NDArray[np.float64] | None


# --- solvers --------------------------------------------------------------------------------


def _check_solver_args(tol: float, max_iterations: int) -> None:
    if not np.isfinite(tol) or tol <= 0.0:
        raise BEMParameterError(f"tol must be positive and finite, got {tol!r}")
    if int(max_iterations) < 1:
        raise BEMParameterError(f"max_iterations must be ≥ 1, got {max_iterations!r}")


def _diagonal(response: NDArray[np.float64], n: int) -> float:
    """Diagonal element of the (circulant) influence matrix [µm/GPa]."""
    full = 2.0 * response[1:].sum()
    if n % 2 == 0:
        full -= response[-1]
    return float(full / n)


@dataclass
class _Solution:
    pressure: NDArray[np.float64]
    gap: NDArray[np.float64]
    separation: float
    iterations: int
    residual: float


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Scalar product without BLAS (threaded BLAS costs milliseconds per call on busy cores)."""
    return float(np.multiply(a, b).sum())


def _residual(g: NDArray[np.float64], loaded: NDArray[np.bool_], scale: float) -> float:
    worst = 0.0
    if loaded.any():
        worst = float(np.abs(g[loaded]).max())
    free = ~loaded
    if free.any():
        worst = max(worst, float(-min(g[free].min(), 0.0)))
    return worst / scale


def _pk_load(
    problem: ContactProblem,
    mean_pressure: float,
    initial: NDArray[np.float64],
    tol: float,
    max_iterations: int,
) -> _Solution:
    """Polonsky–Keer constrained conjugate gradients at fixed mean pressure (any grid size).

    Sets up the operator (:class:`splinecontact._fft.CirculantConvolution`), its column (the
    response to a unit load at node 0, for the sparse updates) and the work arrays, and runs
    the compiled loop :func:`._kernel._k_pk_loop`.
    """
    z = problem.heights
    lam = problem.response
    n = z.size
    apply = CirculantConvolution(lam, n)
    column = np.empty(n)
    unit = np.zeros(n)
    unit[0] = 1.0
    apply(unit, column)
    column2 = np.concatenate([column, column])
    limit = _sparse_limit(n)
    changed = np.empty(max(limit, 0), dtype=np.int64)
    delta = np.empty(max(limit, 0))
    p = initial * (mean_pressure / initial.mean())
    g = np.empty(n)
    converged, iteration, residual, separation = _k_pk_loop(
        z, p, np.zeros(n), g, np.empty(n), np.empty(n), column2, changed, delta, limit,
        problem.rms_height, tol, 1.0 / _diagonal(lam, n), mean_pressure, max_iterations,
        apply.arguments,
    )  # fmt: skip
    if converged:
        return _Solution(p, g, separation, iteration, residual)
    raise NoConvergenceError(
        f"load control at mean pressure {mean_pressure:.6g} GPa did not converge in "
        f"{max_iterations} iterations (residual {residual:.3g} > tol {tol:.3g}); raise "
        "max_iterations or tol, or approach this load in smaller steps (load_path)"
    )


def _pcg_gap(
    problem: ContactProblem,
    separation: float,
    initial: NDArray[np.float64],
    tol: float,
    max_iterations: int,
) -> _Solution:
    """Projected conjugate gradients at fixed rigid position s (displacement control)."""
    z = problem.heights
    lam = problem.response
    n = z.size
    scale = problem.rms_height
    tau_fallback = 1.0 / _diagonal(lam, n)
    p = initial.copy()
    t = np.zeros(n)
    g_norm_old = 0.0
    conjugate = False
    residual = np.inf
    for iteration in range(max_iterations + 1):
        g = _apply(lam, p) + separation - z
        loaded = p > 0.0
        residual = _residual(g, loaded, scale)
        if residual <= tol:
            return _Solution(p, g, separation, iteration, residual)
        if iteration == max_iterations:
            break
        g_loaded = np.where(loaded, g, 0.0)
        g_norm = float(_dot(g_loaded, g_loaded))
        if conjugate and g_norm_old > 0.0:
            t = g_loaded + (g_norm / g_norm_old) * t
        else:
            t = g_loaded
        t[~loaded] = 0.0
        g_norm_old = g_norm
        if not loaded.any():
            # nothing loaded yet: exact line search along the overlap d = max(−g, 0)
            d = np.clip(-g, 0.0, None)
            curvature = _dot(d, _apply(lam, d))
            step = _dot(d, d) / curvature if curvature > 0.0 else tau_fallback
            p = step * d
            conjugate = False
            continue
        r = _apply(lam, t)
        denominator = float(_dot(r[loaded], t[loaded]))
        tau = float(_dot(g_loaded, t)) / denominator if denominator > 0.0 else tau_fallback
        if loaded.all():
            # every node loaded: the uniform mode costs no elastic energy, so do not step
            # beyond the first node that unloads
            positive = t > 0.0
            if positive.any():
                tau = min(tau, float(np.min(p[positive] / t[positive])))
        p = p - tau * t
        p[p < 0.0] = 0.0
        overlap = (p == 0.0) & (g < 0.0)
        if overlap.any():
            conjugate = False
            p[overlap] = -tau * g[overlap]
        else:
            conjugate = True
    raise NoConvergenceError(
        f"displacement control at mean gap {separation - problem.mean_height:.6g} µm did not "
        f"converge in {max_iterations} iterations (residual {residual:.3g} > tol {tol:.3g}); "
        "raise max_iterations or tol, or approach this gap in smaller steps (gap_path)"
    )


def _initial_guess(problem: ContactProblem, mean_pressure: float) -> NDArray[np.float64]:
    """Bearing-area guess: pressure ∝ height above the level that leaves a fraction in contact."""
    z = problem.heights
    fraction = min(max(mean_pressure / problem.full_contact_pressure, 1.0 / z.size), 0.5)
    level = float(np.quantile(z, 1.0 - fraction))
    p = np.clip(z - level, 0.0, None)
    if p.sum() <= 0.0:
        p = np.zeros_like(z)
        p[np.argmax(z)] = 1.0
    return p


def _make_step(
    problem: ContactProblem, sol: _Solution, mean_pressure: float, fields: bool
) -> BEMStep:
    stats = contact_statistics(sol.pressure, problem.dx)
    mean_gap = sol.separation - problem.mean_height
    pressure = gap = None
    if fields:
        pressure = sol.pressure.copy()
        gap = np.where(sol.pressure > 0.0, 0.0, np.clip(sol.gap, 0.0, None))
        pressure.setflags(write=False)
        gap.setflags(write=False)
    return BEMStep(
        mean_pressure=float(mean_pressure),
        force=float(mean_pressure * problem.length),
        mean_gap=float(mean_gap),
        approach=float(problem.first_contact_gap - mean_gap),
        contact_nodes=stats.contact_nodes,
        contact_length=stats.contact_length,
        contact_length_subgrid=stats.contact_length_subgrid,
        n_patches=stats.n_patches,
        iterations=sol.iterations,
        residual=sol.residual,
        pressure=pressure,
        gap=gap,
    )


def _touching(problem: ContactProblem, fields: bool) -> BEMStep:
    """Zero load: the flat touches the highest node(s) without pressure."""
    z = problem.heights
    gap_field = z.max() - z
    pressure = gap = None
    if fields:
        pressure = np.zeros_like(z)
        gap = gap_field
        pressure.setflags(write=False)
        gap.setflags(write=False)
    return BEMStep(
        mean_pressure=0.0,
        force=0.0,
        mean_gap=problem.first_contact_gap,
        approach=0.0,
        contact_nodes=0,
        contact_length=0.0,
        contact_length_subgrid=0.0,
        n_patches=0,
        iterations=0,
        residual=0.0,
        pressure=pressure,
        gap=gap,
    )


def _check_load(problem: ContactProblem, mean_pressure: float) -> float:
    value = float(mean_pressure)
    if not np.isfinite(value):
        raise NegativeLoadError(f"mean pressure must be finite [GPa], got {mean_pressure!r}")
    if value < 0.0:
        raise NegativeLoadError(
            f"mean pressure {value!r} GPa is negative; the contact is non-adhesive — pass p̄ ≥ 0"
        )
    if value >= problem.full_contact_pressure:
        raise FullContactError(
            f"mean pressure {value!r} GPa is at or beyond full contact "
            f"(p_full = {problem.full_contact_pressure!r} GPa, force "
            f"{problem.full_contact_pressure * problem.length!r} mN/µm): every node touches "
            "there; pass a smaller load"
        )
    return value


def _solve_load_state(
    problem: ContactProblem,
    mean_pressure: float,
    initial: NDArray[np.float64] | None,
    tol: float,
    max_iterations: int,
) -> _Solution:
    guess = initial
    if guess is None or guess.shape != problem.heights.shape or not np.any(guess > 0.0):
        guess = _initial_guess(problem, mean_pressure)
    else:
        guess = np.clip(np.asarray(guess, dtype=np.float64), 0.0, None)
    return _pk_load(problem, mean_pressure, guess, tol, max_iterations)


def solve_pressure(
    problem: ContactProblem,
    mean_pressure: float,
    *,
    initial_pressure: ArrayLike | None = None,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMStep:
    """Solve the contact at a given mean pressure (load control).

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_pressure : float
        p̄ [GPa], 0 ≤ p̄ < ``problem.full_contact_pressure``; the force is p̄·L [mN/µm].
    initial_pressure : array_like, optional
        Warm start [GPa] (for example the previous step's field); rescaled to p̄.
    tol : float
        Largest complementarity violation / rms height at convergence [1].
    max_iterations : int
        Iteration limit.
    fields : bool
        Also return the pressure and gap fields.

    Returns
    -------
    BEMStep

    Raises
    ------
    NegativeLoadError
        p̄ < 0 or not finite.
    FullContactError
        p̄ ≥ full-contact pressure.
    NoConvergenceError
        The tolerance was not reached within ``max_iterations``.
    BEMParameterError
        tol ≤ 0 or max_iterations < 1.
    """
    _check_solver_args(tol, max_iterations)
    value = _check_load(problem, mean_pressure)
    if value == 0.0:
        return _touching(problem, fields)
    initial = None if initial_pressure is None else np.asarray(initial_pressure, dtype=np.float64)
    sol = _solve_load_state(problem, value, initial, tol, max_iterations)
    return _make_step(problem, sol, value, fields)


def _check_gap(problem: ContactProblem, mean_gap: float) -> float:
    value = float(mean_gap)
    if not np.isfinite(value):
        raise FullContactError(f"mean gap must be finite [µm], got {mean_gap!r}")
    if value <= 0.0:
        raise FullContactError(
            f"mean gap {value!r} µm is at or beyond full contact (reached at mean gap 0, mean "
            f"pressure {problem.full_contact_pressure!r} GPa); pass a positive mean gap"
        )
    return value


def solve_gap(
    problem: ContactProblem,
    mean_gap: float,
    *,
    initial_pressure: ArrayLike | None = None,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMStep:
    """Solve the contact at a given mean gap (displacement control).

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_gap : float
        ḡ [µm], 0 < ḡ; at ḡ ≥ max z − z̄ the surfaces do not touch (zero load).
    initial_pressure : array_like, optional
        Warm start [GPa].
    tol, max_iterations, fields
        As in :func:`solve_pressure`.

    Returns
    -------
    BEMStep
        With the resulting mean pressure and force.

    Raises
    ------
    FullContactError
        ḡ ≤ 0 or not finite.
    NoConvergenceError
        The tolerance was not reached within ``max_iterations``.
    """
    _check_solver_args(tol, max_iterations)
    value = _check_gap(problem, mean_gap)
    if value >= problem.first_contact_gap:
        step = _touching(problem, fields)
        if value == problem.first_contact_gap:
            return step
        return BEMStep(
            **{
                **{k: getattr(step, k) for k in STEP_UNITS},
                "mean_gap": value,
                "approach": problem.first_contact_gap - value,
                "pressure": step.pressure,
                "gap": None if step.gap is None else step.gap + (value - step.mean_gap),
            }
        )
    separation = value + problem.mean_height
    if initial_pressure is None:
        guess = np.zeros(problem.n_points)
    else:
        guess = np.clip(np.asarray(initial_pressure, dtype=np.float64), 0.0, None)
        if guess.shape != problem.heights.shape:
            guess = np.zeros(problem.n_points)
    sol = _pcg_gap(problem, separation, guess, tol, max_iterations)
    return _make_step(problem, sol, float(sol.pressure.mean()), fields)


def load_path(
    problem: ContactProblem,
    mean_pressures: Sequence[float] | NDArray[np.float64],
    *,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMPath:
    """Solve a sequence of loads, each warm-started from the previous solution.

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_pressures : sequence of float
        p̄ per step [GPa] (any order; increasing is fastest). Forces are p̄·L [mN/µm].
    tol, max_iterations, fields
        As in :func:`solve_pressure`.

    Returns
    -------
    BEMPath

    Raises
    ------
    NegativeLoadError, FullContactError
        For the first offending step, before anything is solved.
    NoConvergenceError
        A step did not converge.

    Examples
    --------
    A sinusoid pressed flat (Westergaard): p̄/p* = sin²(πa/λ), so at half the full-contact
    pressure p* the contact covers half the wavelength.

    >>> import numpy as np
    >>> from splinecontact import bem
    >>> n, wavelength = 256, 10.0
    >>> x = np.arange(n) * (wavelength / n)
    >>> z = 0.01 * np.cos(2 * np.pi * x / wavelength)
    >>> problem = bem.contact_problem(z, e_star=10.0, dx=wavelength / n)
    >>> path = bem.load_path(problem, [0.25 * problem.full_contact_pressure,
    ...                                0.5 * problem.full_contact_pressure])
    >>> round(path.steps[-1].contact_length_subgrid, 1), path.steps[-1].n_patches
    (5.0, 1)
    >>> path.to_xarray()["contact_length_subgrid"].attrs["units"]
    'µm'
    """
    _check_solver_args(tol, max_iterations)
    loads = [_check_load(problem, p) for p in np.asarray(mean_pressures, dtype=np.float64)]

    def solve(load: float, previous: _Field) -> tuple[BEMStep, _Field]:
        if load == 0.0:
            return _touching(problem, fields), previous
        sol = _solve_load_state(problem, load, previous, tol, max_iterations)
        return _make_step(problem, sol, load, fields), sol.pressure

    return _warm_started(problem, loads, solve, tol)


def gap_path(
    problem: ContactProblem,
    mean_gaps: Sequence[float] | NDArray[np.float64],
    *,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMPath:
    """Solve a sequence of mean gaps (displacement control), each warm-started.

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_gaps : sequence of float
        ḡ per step [µm], each > 0 (decreasing is fastest).
    tol, max_iterations, fields
        As in :func:`solve_pressure`.

    Returns
    -------
    BEMPath
    """
    _check_solver_args(tol, max_iterations)
    gaps = [_check_gap(problem, g) for g in np.asarray(mean_gaps, dtype=np.float64)]

    def solve(value: float, previous: _Field) -> tuple[BEMStep, _Field]:
        step = solve_gap(
            problem, value, initial_pressure=previous, tol=tol, max_iterations=max_iterations,
            fields=True,
        )  # fmt: skip
        pressure = None if step.pressure is None else np.array(step.pressure)
        if not fields:
            step = BEMStep(**{k: getattr(step, k) for k in STEP_UNITS})
        return step, pressure

    return _warm_started(problem, gaps, solve, tol)


def _warm_started(
    problem: ContactProblem,
    values: list[float],
    solve: Callable[[float, _Field], tuple[BEMStep, _Field]],
    tol: float,
) -> BEMPath:
    """The path of ``solve`` over ``values`` in order, each step warm-started from the pressure
    field [GPa] the step before left (``None`` before the first)."""
    steps: list[BEMStep] = []
    previous: _Field = None
    for value in values:
        step, previous = solve(value, previous)
        steps.append(step)
    return BEMPath(tuple(steps), problem.e_star, problem.dx, problem.n_points, float(tol))
