"""Weierstrass–Mandelbrot fractal profiles (paper eq. 1).

.. math::

    z(x) = L^{4-2D} \\ln\\gamma \\sum_{m=1}^{M}\\sum_{n=0}^{n_{max}} a_n
           \\left\\{\\cos\\phi_{m,n} - \\cos\\left[\\frac{2\\pi\\gamma^n x}{L}
           \\cos\\left(\\frac{\\pi m}{M}\\right) + \\phi_{m,n}\\right]\\right\\}

with ``a_n = γ^{n(D−2)}`` (``amplitude_law="hurst"``, Hurst exponent H = 2 − D, the default) or
``a_n = γ^{2n(D−2)}`` (``amplitude_law="as_printed"``, the paper's printed law, H = 2(2 − D)).
The phase table has M × (n_max + 1) entries (n runs from 0 to n_max). Heights are then shifted to
zero mean and scaled so that R_A = mean|z| equals the target.

Evaluation: the terms m and M − m have opposite frequencies and are merged into one cosine; the
term m = M/2 has zero frequency and vanishes identically. Terms above the grid's Nyquist frequency
1/(2 dx) would alias and are dropped (counted in the metadata). Each remaining cosine is advanced
by the three-term recurrence cos((j + 1)θ) = 2 cos θ cos(jθ) − cos((j − 1)θ) (one multiply-add per
term and point) over runs of ``_SUB_BLOCK`` points, restarted from phasors that are rotated
from run to run and re-anchored with exact cos/sin every ``_BLOCK`` points, so the cost is
O(points × terms) multiply-adds with no transcendental calls in the inner loop.
The grid mean of the sum is known in closed form, so the kernel writes heights about their mean
and sums |z| in the same pass; one more pass scales them to R_A.
"""

from __future__ import annotations

import inspect
import math
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal, NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

from ._checks import LENGTH_LIMIT, check_integer, check_real, check_seed
from ._memory import empty, grid
from ._roughness import mean_abs_about
from .errors import ParameterError
from .profile import MIN_STEP, Profile

__all__ = [
    "GENERATOR_PARAMETERS",
    "MAX_POINTS",
    "MAX_WORK",
    "AmplitudeLaw",
    "SeedLike",
    "as_seed_sequence",
    "child_seed",
    "weierstrass_mandelbrot",
    "weierstrass_mandelbrot_pair",
]

AmplitudeLaw = Literal["hurst", "as_printed"]
SeedLike = int | np.random.SeedSequence | np.random.Generator | None

_BLOCK = 2048

#: Points per run of the three-term cosine recurrence between two phasor rotations (a divisor
#: of ``_BLOCK``).
_SUB_BLOCK = 64

#: Profiles of at least this many points are generated two at a time (one thread each) by
#: :func:`weierstrass_mandelbrot_pair`; below it a thread costs more than it saves.
_PAIR_THREAD_MIN_POINTS = 32_768

#: Default ceiling on ``n_points`` and on the number of terms ``directions × (n_max + 1)`` [1]
#: (2·10⁷: 160 MB per array of heights; the paper uses 10⁶ points and 420 terms). Raise it with
#: ``max_points=``.
MAX_POINTS = 20_000_000

#: Default ceiling on ``n_points × directions × (n_max + 1)``, the multiply-adds of the sum
#: [1] (10¹⁰, about ten times the paper's 10⁶ × 420; ~10 s of one core). Raise it with
#: ``max_work=``.
MAX_WORK = 10_000_000_000

#: A profile whose mean |z| after removing the mean is below this fraction of the summed term
#: amplitudes is rounding noise of the sum (every kept wavelength far longer than the profile).
_MIN_RELATIVE_VARIATION = 1e-8

#: Smallest length, wavelength and R_A accepted [µm] (smaller heights would be subnormal numbers).
_MIN_LENGTH = 1e-50

#: Keyword parameters of :func:`weierstrass_mandelbrot` besides ``dimension`` and ``seed``.
GENERATOR_PARAMETERS = (
    "n_points",
    "length",
    "wavelength",
    "gamma",
    "directions",
    "n_max",
    "ra",
    "amplitude_law",
)


def as_seed_sequence(seed: int | np.random.SeedSequence | None) -> np.random.SeedSequence:
    """Return ``seed`` as a :class:`numpy.random.SeedSequence` (fresh entropy for ``None``).

    Raises
    ------
    ParameterError
        ``seed`` is negative, not an integer (``1.5``, ``True``, a string) or a Generator.
    """
    check_seed(seed)
    if isinstance(seed, np.random.Generator):
        raise ParameterError(
            "seed is a numpy.random.Generator; a seed sequence is needed here: give a "
            "non-negative integer or a numpy.random.SeedSequence"
        )
    if isinstance(seed, np.random.SeedSequence):
        return seed
    return np.random.SeedSequence(seed)


def child_seed(parent: np.random.SeedSequence, index: int) -> np.random.SeedSequence:
    """The ``index``-th child of ``parent``, as ``parent.spawn`` would give, without mutating it.

    ``SeedSequence.spawn`` advances a counter inside the parent, so calling it twice gives
    different children; this function is pure.
    """
    return np.random.SeedSequence(
        entropy=parent.entropy,
        spawn_key=(*parent.spawn_key, index),
        pool_size=parent.pool_size,
    )


def _seed_metadata(seed: SeedLike) -> dict[str, Any]:
    if isinstance(seed, np.random.SeedSequence):
        return {"seed_entropy": str(seed.entropy), "seed_spawn_key": list(seed.spawn_key)}
    if isinstance(seed, np.random.Generator):
        return {"seed_entropy": None, "seed_spawn_key": None, "seed_note": "Generator passed"}
    return {"seed_entropy": None if seed is None else str(seed), "seed_spawn_key": []}


@numba.njit(cache=True, fastmath=True, nogil=True)
def _heights_kernel(
    out: NDArray[np.float64],
    dx: float,
    omega: NDArray[np.float64],
    amp_re: NDArray[np.float64],
    amp_im: NDArray[np.float64],
    block: int,
    prefactor: float,
    constant: float,
    shift: float,
    first_index: int,
    total: float,
    total_abs: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """out_j = prefactor·(constant − Σ_k Re(A_k exp(i ω_k x_j))) − shift; return Σ out, Σ |out|.

    ``out`` holds the grid points ``first_index + j`` (x_j = (first_index + j)·dx); ``total`` and
    ``total_abs`` are the sums so far, continued here. With ``first_index`` a multiple of
    ``block``, a run in pieces writes and sums bit for bit what one whole run does.

    Each term c_k(j) = Re(A_k exp(i θ_k j)), θ_k = ω_k dx, obeys the three-term (Chebyshev)
    recurrence c(j + 1) = 2 cos θ_k · c(j) − c(j − 1): one multiply-add per term and point. It
    runs over sub-blocks of ``_SUB_BLOCK`` points, started from the phasors P_k = A_k exp(i θ_k j),
    which are rotated from one sub-block to the next by exp(i θ_k · _SUB_BLOCK) and re-anchored
    with exact cos/sin at the start of every ``block`` points. The recurrence's rounding error
    grows like ε·j²/2 over j steps, about 2e−13 of a term's amplitude over a sub-block. The loop
    over terms is the inner, vectorised one; four consecutive points are advanced per pass over
    the terms (register blocking).
    """
    n_points = out.size
    n_terms = omega.size
    sub = _SUB_BLOCK
    p_re = np.empty(n_terms)
    p_im = np.empty(n_terms)
    r_re = np.empty(n_terms)  # exp(i θ)
    r_im = np.empty(n_terms)
    s_re = np.empty(n_terms)  # exp(i θ · sub)
    s_im = np.empty(n_terms)
    twice = np.empty(n_terms)  # 2 cos θ
    now = np.empty(n_terms)  # c(j)
    before = np.empty(n_terms)  # c(j − 1)
    for k in range(n_terms):
        r_re[k] = math.cos(omega[k] * dx)
        r_im[k] = math.sin(omega[k] * dx)
        s_re[k] = math.cos(omega[k] * dx * sub)
        s_im[k] = math.sin(omega[k] * dx * sub)
        twice[k] = 2.0 * r_re[k]
    for start in range(0, n_points, block):
        stop = min(start + block, n_points)
        x_start = (first_index + start) * dx
        for k in range(n_terms):
            c = math.cos(omega[k] * x_start)
            s = math.sin(omega[k] * x_start)
            p_re[k] = amp_re[k] * c - amp_im[k] * s
            p_im[k] = amp_re[k] * s + amp_im[k] * c
        for first in range(start, stop, sub):
            last = min(first + sub, stop)
            for k in range(n_terms):
                # c(first) and c(first − 1) = Re(P exp(−i θ)); then P moves one sub-block on
                now[k] = p_re[k]
                before[k] = p_re[k] * r_re[k] + p_im[k] * r_im[k]
                x = p_re[k] * s_re[k] - p_im[k] * s_im[k]
                p_im[k] = p_re[k] * s_im[k] + p_im[k] * s_re[k]
                p_re[k] = x
            j = first
            while j + 4 <= last:
                a0 = 0.0
                a1 = 0.0
                a2 = 0.0
                a3 = 0.0
                for k in range(n_terms):
                    t = twice[k]
                    c0 = now[k]
                    c1 = t * c0 - before[k]
                    c2 = t * c1 - c0
                    c3 = t * c2 - c1
                    a0 += c0
                    a1 += c1
                    a2 += c2
                    a3 += c3
                    before[k] = c3
                    now[k] = t * c3 - c2
                for value in (a0, a1, a2, a3):
                    height = prefactor * (constant - value) - shift
                    out[j] = height
                    total += height
                    total_abs += abs(height)
                    j += 1
            while j < last:
                acc = 0.0
                for k in range(n_terms):
                    c0 = now[k]
                    acc += c0
                    now[k] = twice[k] * c0 - before[k]
                    before[k] = c0
                height = prefactor * (constant - acc) - shift
                out[j] = height
                total += height
                total_abs += abs(height)
                j += 1
    return total, total_abs


@numba.njit(cache=True, fastmath=True, nogil=True)
def _shift_scale(z: NDArray[np.float64], shift: float, factor: float) -> None:  # pragma: no cover
    """z ← (z − shift)·factor in place."""
    for i in range(z.size):
        z[i] = (z[i] - shift) * factor


def _mean_of_cosines(
    n_points: int, dx: float, omega: NDArray[np.float64], coeff: NDArray[np.complex128]
) -> float:
    """Mean over x_j = j·dx, j < n_points, of Σ_k Re(A_k exp(i ω_k x_j)), in closed form.

    Σ_j exp(i θ j) = exp(i θ (n − 1)/2) · sin(nθ/2) / sin(θ/2), with θ = ω dx ∈ (0, π].
    """
    theta = omega * dx
    half = 0.5 * theta
    ratio = np.sin(n_points * half) / (n_points * np.sin(half))
    phase = np.exp(1j * (n_points - 1) * half)
    return float(np.sum((coeff * phase).real * ratio))


def _positive_length(name: str, value: Any) -> float:
    return check_real(name, value, "µm", minimum=_MIN_LENGTH, maximum=LENGTH_LIMIT)


def _validate(
    dimension: Any,
    n_points: Any,
    length: Any,
    wavelength: Any,
    gamma: Any,
    directions: Any,
    n_max: Any,
    ra: Any,
    amplitude_law: Any,
    seed: Any,
    max_points: Any,
    max_work: Any,
) -> tuple[float, int, float, float, float, int, int, float]:
    """Check every argument before anything is allocated; return them as float/int.

    With L in [1e−50, 1e50] µm and D in [1, 2], the scale L^(4−2D) ln γ of eq. 1 lies within
    about 10^±116, so only γ^n_max can overflow.
    """
    dimension = check_real("fractal dimension D", dimension)
    if not 1.0 <= dimension <= 2.0:
        raise ParameterError(
            f"fractal dimension D = {dimension!r} is outside [1, 2] (profiles of a 3D surface "
            "of dimension D + 1)"
        )
    max_points = check_integer("max_points", max_points, minimum=5)
    max_work = check_integer("max_work", max_work, minimum=5)
    n_points = check_integer(
        "n_points",
        n_points,
        minimum=5,
        maximum=max_points,
        note="the paper uses 10⁶",
        raise_with="max_points",
    )
    length = _positive_length("length", length)
    wavelength = _positive_length("wavelength L", wavelength)
    gamma = check_real(
        "gamma", gamma, minimum=1.0, exclusive_minimum=True, note="frequency density of eq. 1"
    )
    directions = check_integer("directions M", directions, minimum=1)
    n_max = check_integer("n_max", n_max, minimum=0)
    ra = _positive_length("ra", ra)
    if not isinstance(amplitude_law, str) or amplitude_law not in ("hurst", "as_printed"):
        raise ParameterError(
            f"amplitude_law = {amplitude_law!r}; use 'hurst' (a_n = γ^(n(D−2)), H = 2 − D) or "
            "'as_printed' (a_n = γ^(2n(D−2)), the paper's printed eq. 1)"
        )
    check_seed(seed)
    dx = length / (n_points - 1)
    if dx < MIN_STEP:
        raise ParameterError(
            f"the grid step length/(n_points − 1) = {dx!r} µm is below {MIN_STEP:g} µm; "
            "use fewer points or a longer profile"
        )
    terms = directions * (n_max + 1)
    if terms > max_points:
        raise ParameterError(
            f"directions × (n_max + 1) = {terms} terms is above the ceiling {max_points} "
            "(the paper uses 20 × 21 = 420); use fewer, or pass max_points= to allow more"
        )
    if n_points * terms > max_work:
        raise ParameterError(
            f"n_points × directions × (n_max + 1) = {n_points} × {terms} = {n_points * terms:.3g} "
            f"multiply-adds is above the ceiling max_work = {max_work:.3g}; use fewer points or "
            "terms, or pass max_work= to allow more"
        )
    log_gamma = math.log(gamma)
    if n_max * log_gamma > 700.0:  # γ^n_max below ~1e304 (the float limit is 1.8e308)
        # Highest n with γ^n/L below the Nyquist frequency 1/(2 dx), computed in logs.
        useful = max(0, math.ceil((math.log(0.5 / dx) + math.log(wavelength)) / log_gamma))
        raise ParameterError(
            f"gamma^n_max = {gamma!r}^{n_max} overflows; terms with γ^n/L above the Nyquist "
            f"frequency 1/(2 dx) are dropped anyway, so use n_max ≤ {useful} for this grid"
        )
    return dimension, n_points, length, wavelength, gamma, directions, n_max, ra


def weierstrass_mandelbrot(
    dimension: float,
    *,
    n_points: int = 1_000_000,
    length: float = 100.0,
    wavelength: float = 1.0,
    gamma: float = 1.5,
    directions: int = 20,
    n_max: int = 20,
    ra: float = 0.005,
    amplitude_law: AmplitudeLaw = "hurst",
    seed: SeedLike = None,
    max_points: int = MAX_POINTS,
    max_work: int = MAX_WORK,
) -> Profile:
    """Generate a random Weierstrass–Mandelbrot profile (paper eq. 1).

    Parameters
    ----------
    dimension : float
        Fractal dimension D of the profile [1], 1 ≤ D ≤ 2.
    n_points : int, optional
        Number of grid points [1] (paper: 10⁶). The grid is ``x = linspace(0, length, n_points)``.
    length : float, optional
        Profile length L0 [µm] (paper: 100 L).
    wavelength : float, optional
        Stochastic length parameter L [µm] (largest characteristic wavelength).
    gamma : float, optional
        Frequency density γ [1] (not given in the paper; 1.5 as in the cited generators).
    directions : int, optional
        Number of directions M [1] (paper: 20).
    n_max : int, optional
        Highest frequency index n_max [1] (paper: 20); n runs from 0 to n_max.
    ra : float, optional
        Target mean roughness R_A [µm] (paper: L/200 = 0.005 µm).
    amplitude_law : {"hurst", "as_printed"}, optional
        ``"hurst"``: a_n = γ^(n(D−2)), Hurst exponent H = 2 − D (default; the reading consistent
        with the paper's Fig. 12). ``"as_printed"``: a_n = γ^(2n(D−2)) as printed in eq. 1.
    seed : int, SeedSequence, Generator or None, optional
        Source of the random phases φ_{m,n} ~ U(0, 2π). The same seed gives a bit-identical
        profile. An integer seed must be ≥ 0.
    max_points : int, optional
        Ceiling [1] on ``n_points`` and on the number of terms ``directions × (n_max + 1)``
        (default ``MAX_POINTS`` = 2·10⁷), checked before anything is allocated.
    max_work : int, optional
        Ceiling [1] on ``n_points × directions × (n_max + 1)`` (default ``MAX_WORK`` = 10¹⁰),
        checked before anything is allocated.

    Returns
    -------
    Profile
        Heights [µm] with zero mean and R_A equal to ``ra``. ``metadata`` records every
        parameter, the seed, the number of terms kept and dropped above the Nyquist frequency.

    Raises
    ------
    ParameterError
        A parameter is not a finite number of the right kind or is out of range (D ∉ [1, 2],
        n_points < 5, length ≤ 0, γ ≤ 1, a negative seed, ...), a ceiling is exceeded, or the
        parameters would overflow (γ^n_max, the scale L^(4−2D)) or give a profile below the
        rounding error of the sum.

    Examples
    --------
    >>> from splinecontact import weierstrass_mandelbrot
    >>> profile = weierstrass_mandelbrot(1.5, n_points=2048, length=10.0, seed=1)
    >>> profile.n_points, round(profile.length, 9)
    (2048, 10.0)
    >>> round(profile.ra, 9)  # scaled to the requested R_A [µm]
    0.005
    """
    dimension, n_points, length, wavelength, gamma, directions, n_max, ra = _validate(
        dimension, n_points, length, wavelength, gamma, directions, n_max, ra, amplitude_law,
        seed, max_points, max_work,
    )  # fmt: skip
    return _generate(
        dimension, n_points, length, wavelength, gamma, directions, n_max, ra, amplitude_law, seed
    )


class _Terms(NamedTuple):
    """The cosines of eq. 1 kept on a grid, as :func:`_heights_kernel` takes them."""

    omega: NDArray[np.float64]  # angular frequencies [1/µm]
    amp_re: NDArray[np.float64]  # Re A_k [1]
    amp_im: NDArray[np.float64]  # Im A_k [1]
    prefactor: float  # L^(4−2D) ln γ [µm]
    constant: float  # Σ a_n cos φ [1]
    shift: float  # the grid mean of prefactor·(constant − Σ) [µm]
    amplitude_sum: float  # Σ |A_k| [1]
    n_dropped: int
    n_zero: int


def _terms(
    dimension: float, n_points: int, length: float, wavelength: float, gamma: float,
    directions: int, n_max: int, amplitude_law: AmplitudeLaw, seed: SeedLike,
) -> _Terms:  # fmt: skip
    """Draw the phases of eq. 1 and merge its terms (validated parameters; ParameterError
    when every term lies above the grid's Nyquist frequency)."""
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    phases = rng.uniform(0.0, 2.0 * np.pi, size=(directions, n_max + 1))  # φ[m-1, n]

    dx = length / (n_points - 1)
    nyquist = 0.5 / dx  # [1/µm]
    exponent = (dimension - 2.0) * (1.0 if amplitude_law == "hurst" else 2.0)
    n = np.arange(n_max + 1)
    amplitude = gamma ** (exponent * n)  # a_n
    prefactor = wavelength ** (4.0 - 2.0 * dimension) * math.log(gamma)

    # Merge m and M − m (cos(π(M−m)/M) = −cos(πm/M)): cos(−|ω|x + φ) = cos(|ω|x − φ).
    omegas: list[float] = []
    amps: list[complex] = []
    constant, n_dropped, n_zero = 0.0, 0, 0
    for m in range(1, directions + 1):
        partner = directions - m
        if 1 <= partner < m:
            continue  # already merged with its partner
        direction = math.cos(math.pi * m / directions)
        if 2 * m == directions:
            n_zero += n_max + 1  # zero frequency: cos φ − cos φ = 0
            continue
        for k in range(n_max + 1):
            frequency = gamma**k * abs(direction) / wavelength  # [1/µm]
            members = [(m, direction)]
            if 1 <= partner <= directions and partner != m:
                members.append((partner, -direction))
            if frequency > nyquist:
                n_dropped += len(members)
                continue
            coefficient = 0j
            for member, cosine in members:
                phi = phases[member - 1, k]
                constant += amplitude[k] * math.cos(phi)
                sign = 1.0 if cosine > 0 else -1.0
                coefficient += amplitude[k] * complex(math.cos(sign * phi), math.sin(sign * phi))
            omegas.append(2.0 * math.pi * frequency)
            amps.append(coefficient)

    omega = np.asarray(omegas, dtype=np.float64)
    coeff = np.asarray(amps, dtype=np.complex128)
    if omega.size == 0:
        raise ParameterError(
            "every term of eq. 1 lies above the Nyquist frequency of this grid; "
            f"use more points than {n_points} or a longer wavelength than {wavelength} µm"
        )
    # the mean of eq. 1 on the grid is known in closed form, so the kernel writes heights
    # about their mean and sums |z| on the fly
    shift = prefactor * (constant - _mean_of_cosines(n_points, dx, omega, coeff))
    return _Terms(
        omega, np.ascontiguousarray(coeff.real), np.ascontiguousarray(coeff.imag), prefactor,
        constant, shift, float(np.abs(coeff).sum()), n_dropped, n_zero,
    )  # fmt: skip


def _check_variation(mean_abs: float, terms: _Terms, wavelength: float, length: float) -> None:
    if not mean_abs > _MIN_RELATIVE_VARIATION * terms.prefactor * terms.amplitude_sum:
        raise ParameterError(
            f"the profile varies by less than the rounding error of eq. 1's sum: every kept "
            f"wavelength is much longer than the profile (L = {wavelength!r} µm, length = "
            f"{length!r} µm); use a wavelength L of the order of the profile length or shorter"
        )


def _check_peak(peak: float, ra: float) -> None:
    if not peak <= LENGTH_LIMIT:
        raise ParameterError(
            f"ra = {ra!r} µm gives heights up to {peak:.3g} µm, beyond {LENGTH_LIMIT:g} µm where "
            "the contact computation would overflow; give a smaller ra"
        )


def _metadata(params: tuple[Any, ...], seed: SeedLike, terms: _Terms) -> dict[str, Any]:
    """A generated profile's metadata; ``params`` as :func:`_validate` returns them, then the
    amplitude law."""
    dimension, n_points, length, wavelength, gamma, directions, n_max, ra, amplitude_law = params
    return {
        "source": "weierstrass_mandelbrot",
        "dimension": float(dimension),
        "nominal_hurst": (2.0 - dimension) * (1.0 if amplitude_law == "hurst" else 2.0),
        "n_points": n_points,
        "length": float(length),
        "wavelength": float(wavelength),
        "gamma": float(gamma),
        "directions": directions,
        "n_max": n_max,
        "ra": float(ra),
        "amplitude_law": amplitude_law,
        "n_terms": directions * (n_max + 1),
        "n_terms_zero_frequency": terms.n_zero,
        "n_terms_dropped_above_nyquist": terms.n_dropped,
        "n_cosines_evaluated": int(terms.omega.size),
        "units": {"x": "µm", "z": "µm"},
        **_seed_metadata(seed),
    }


def _generate(
    dimension: float, n_points: int, length: float, wavelength: float, gamma: float,
    directions: int, n_max: int, ra: float, amplitude_law: AmplitudeLaw, seed: SeedLike,
    x: NDArray[np.float64] | None = None,
) -> Profile:  # fmt: skip
    """Eq. 1 on validated parameters; ``x`` is a read-only grid to share (e.g. within a pair)."""
    n_points, directions, n_max = int(n_points), int(directions), int(n_max)
    terms = _terms(
        dimension, n_points, length, wavelength, gamma, directions, n_max, amplitude_law, seed
    )
    dx = length / (n_points - 1)
    z = empty(n_points)
    total, total_abs = _heights_kernel(
        z, dx, terms.omega, terms.amp_re, terms.amp_im, _BLOCK, terms.prefactor, terms.constant,
        terms.shift, 0, 0.0, 0.0,
    )  # fmt: skip
    residual_mean = total / n_points  # the rounding left of the closed-form mean, removed below
    mean_abs = mean_abs_about(total_abs / n_points, residual_mean, lambda: (z,))
    _check_variation(mean_abs, terms, wavelength, length)
    _shift_scale(z, residual_mean, ra / mean_abs)
    _check_peak(max(float(z.max()), -float(z.min())), ra)
    if x is None:
        x = grid(length, n_points)
        x.setflags(write=False)
    params = (dimension, n_points, length, wavelength, gamma, directions, n_max, ra,
              amplitude_law)  # fmt: skip
    metadata = _metadata(params, seed, terms)
    z.setflags(write=False)
    return Profile._from_trusted(x, z, metadata)


def weierstrass_mandelbrot_pair(
    dimension: float,
    *,
    seed: int | np.random.SeedSequence | None,
    **kwargs: Any,
) -> tuple[Profile, Profile]:
    """Two independent profiles for a rough-on-rough contact (paper Sec. 2.1).

    The two phase sets come from the children 0 and 1 of ``SeedSequence(seed)`` (spawned
    without mutating ``seed``), so the pair is reproducible from one seed.

    Parameters
    ----------
    dimension : float
        Fractal dimension D [1], 1 ≤ D ≤ 2.
    seed : int, SeedSequence or None
        Seed of the pair.
    **kwargs
        Any other parameter of :func:`weierstrass_mandelbrot` (lengths in [µm]).

    Returns
    -------
    (lower, upper) : tuple of Profile
        Both with heights pointing out of their own body, as a profilometer records them.

    Notes
    -----
    From 32 768 points up the two profiles are generated on two threads at once (the compiled
    sum releases the GIL); each depends only on its own seed, so the pair is bit-identical to
    two :func:`weierstrass_mandelbrot` calls with the child seeds.

    Examples
    --------
    >>> from splinecontact import weierstrass_mandelbrot_pair
    >>> lower, upper = weierstrass_mandelbrot_pair(1.5, seed=7, n_points=1024, length=10.0)
    >>> lower.n_points == upper.n_points == 1024
    True
    >>> bool((lower.z != upper.z).any())  # independent phases
    True
    >>> again, _ = weierstrass_mandelbrot_pair(1.5, seed=7, n_points=1024, length=10.0)
    >>> bool((again.z == lower.z).all())  # reproducible from the one seed
    True
    """
    if isinstance(seed, np.random.Generator):
        raise ParameterError(
            "a pair needs a seed sequence, not a numpy.random.Generator: give a non-negative "
            "integer, a numpy.random.SeedSequence or None"
        )
    parent = as_seed_sequence(seed)
    # the arguments as weierstrass_mandelbrot would take them (TypeError for an unknown one)
    bound = inspect.signature(weierstrass_mandelbrot).bind(dimension, **kwargs)
    bound.apply_defaults()
    arguments = dict(bound.arguments)
    del arguments["seed"]
    dimension, n_points, length, wavelength, gamma, directions, n_max, ra = _validate(
        **arguments, seed=None
    )
    # both profiles share one read-only grid array
    x = grid(length, n_points)
    x.setflags(write=False)
    params = (dimension, n_points, length, wavelength, gamma, directions, n_max, ra,
              arguments["amplitude_law"])  # fmt: skip
    seeds = (child_seed(parent, 0), child_seed(parent, 1))
    if n_points < _PAIR_THREAD_MIN_POINTS:
        lower = _generate(*params, seeds[0], x)
        upper = _generate(*params, seeds[1], x)
        return lower, upper
    # the two sums run at once: the kernel releases the GIL, and each profile depends only on
    # its own seed, so the result is bit-identical to generating them one after the other
    with ThreadPoolExecutor(max_workers=2) as pool:
        futures = [pool.submit(_generate, *params, s, x) for s in seeds]
        return futures[0].result(), futures[1].result()
