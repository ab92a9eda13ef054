"""Streamed realizations: very long profiles in chunks, in memory O(chunk + closing points).

A realization of n points needs the heights (eq. 1), the smoothing spline f, f′, f″ of both
bodies (eqs. 2–3), and then only the points whose gap closes (eqs. 7–9). Held whole, that is
about nine arrays of n values (7 GB at 10⁸ points), and on virtual machines every first touch
of fresh memory costs system time. Here the grid is walked in chunks of ``chunk_points``
points, in buffers reused from chunk to chunk:

1. **Heights** (generated bodies): eq. 1's cosine sum is pointwise, so a chunk's heights are
   those of the whole profile, bit for bit, when the chunk starts on a block of the kernel
   (``generate._BLOCK``). Scaling to R_A needs Σ|z| over the whole profile: a first pass sums
   the chunks without keeping them (the heights' mean is known in closed form); the second
   pass regenerates each chunk and scales it exactly as the whole run does.
2. **Spline**: eq. 2's minimiser is a global banded solve, but the influence of a value on the
   fit decays geometrically, like ρ^d at d points, ρ the largest root inside the unit circle
   of the system's characteristic polynomial λ'r⁴ + (1/6 − 4λ')r³ + (2/3 + 6λ')r² +
   (1/6 − 4λ')r + λ' (λ' = λ/dx³, :func:`margin_points`). Each chunk is fitted on a window
   that extends ``margin`` points past each side (the profile's own ends excepted), with the
   margin chosen so that ρ^margin (1 + 16λ') < 2⁻⁶⁰: the window's fit inside the chunk is the
   global fit to round-off.
3. **Geometry**: the highest point of f^u + f^l (the placement, gap 0) is only known at the
   end, so each chunk keeps the points within the final displacement (plus the law's reach)
   of the highest point seen so far, which contains every final candidate; the final gaps
   are formed at the end, with the same expression as the whole run.
4. **Statistics** (R_A, R_q, R_Sq of the bodies and of the gap, the spline slopes' rms): sums
   per chunk; the height differences at the seams use the window's point before the chunk.

Then the loading loop runs on the closing points as for a whole run. The result keeps what
:func:`splinecontact.simulate` keeps (curves, scalars, parameters, metadata, recorded
contacts): none of it is O(n). Agreement with the whole run: the heights are bit-identical,
the fits agree to round-off, the forces, counts and areas to ≤ 1e−9 relative (tested; the
measured deviation is in ``docs/performance.md``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._checks import check_integer
from ..errors import ParameterError
from ..generate import (
    _BLOCK,
    _check_peak,
    _check_variation,
    _heights_kernel,
    _metadata,
    _shift_scale,
    _Terms,
    _terms,
    _validate,
    as_seed_sequence,
    child_seed,
)
from ..profile import Profile
from ..results import ContactRecord, SimulationResult
from ..spline import grid_smoothing
from ._arguments import check_model_arguments, check_reserved, run_parameters
from ._chunks import _final_gaps, _rounded, _stream, margin_points
from .geometry import ContactGeometry, displacement_steps, order_candidates
from .kernel import run_loading
from .laws import ContactLaw, Hertz, bind_law, law_record

__all__ = [
    "CHUNK_POINTS",
    "STREAM_MIN_POINTS",
    "margin_points",
    "simulate_generated",
    "simulate_streamed",
]

#: Profiles of at least this many points are simulated in chunks (2·10⁷ points: 160 MB per
#: array). Below it the whole-array pipeline runs, bit-identical to before.
STREAM_MIN_POINTS = 20_000_000

#: Default chunk [points] (a multiple of the generator's block): 2²⁰ points, 8 MB per buffer.
CHUNK_POINTS = 1 << 20

# --- the bodies' heights, in pieces ---------------------------------------------------------------


class _Heights:
    """The heights [µm] of one body, written into a buffer for grid indices [start, stop)."""

    mean: float  # the heights' mean [µm], the centre of R_A and R_q

    def fill(self, out: NDArray[np.float64], start: int) -> NDArray[np.float64]:
        raise NotImplementedError


class _GivenHeights(_Heights):
    def __init__(self, z: NDArray[np.float64]) -> None:
        self.z = np.ascontiguousarray(z, dtype=np.float64)
        self.mean = float(np.mean(self.z))

    def fill(self, out: NDArray[np.float64], start: int) -> NDArray[np.float64]:
        return self.z[start : start + out.size]  # a view: nothing copied


class _GeneratedHeights(_Heights):
    """Eq. 1 after its first pass: the shift and R_A factor of the whole profile."""

    def __init__(self, terms: _Terms, dx: float, residual_mean: float, factor: float) -> None:
        self.terms, self.dx = terms, dx
        self.residual_mean, self.factor = residual_mean, factor
        self.mean = 0.0  # zero to rounding (≤ 1e−15 R_A): the closed-form mean is removed

    def fill(self, out: NDArray[np.float64], start: int) -> NDArray[np.float64]:
        t = self.terms
        _heights_kernel(
            out, self.dx, t.omega, t.amp_re, t.amp_im, _BLOCK, t.prefactor, t.constant, t.shift,
            start, 0.0, 0.0,
        )  # fmt: skip
        _shift_scale(out, self.residual_mean, self.factor)
        return out


def _first_pass(terms: _Terms, n: int, dx: float, chunk: int) -> tuple[float, float, float, float]:
    """Σ z, Σ |z| (as one whole run sums them), max and min of eq. 1's unscaled heights."""
    buffer = np.empty(min(chunk, n))
    total = total_abs = 0.0
    high, low = -math.inf, math.inf
    for start in range(0, n, chunk):
        out = buffer[: min(chunk, n - start)]
        total, total_abs = _heights_kernel(
            out, dx, terms.omega, terms.amp_re, terms.amp_im, _BLOCK, terms.prefactor,
            terms.constant, terms.shift, start, total, total_abs,
        )  # fmt: skip
        high, low = max(high, float(out.max())), min(low, float(out.min()))
    return total, total_abs, high, low


def _generated(
    params: tuple[Any, ...], seed: Any, chunk: int
) -> tuple[_GeneratedHeights, dict[str, Any], float]:
    """A generated body ready to stream: its heights, metadata and peak-to-valley height [µm]."""
    dimension, n, length, wavelength, gamma, directions, n_max, ra, law = params
    terms = _terms(dimension, n, length, wavelength, gamma, directions, n_max, law, seed)
    dx = length / (n - 1)
    total, total_abs, high, low = _first_pass(terms, n, dx, chunk)
    residual_mean, mean_abs = total / n, total_abs / n
    _check_variation(mean_abs, terms, wavelength, length)
    factor = ra / mean_abs
    # (z − shift)·factor is monotone in z, so these are the scaled profile's max and min
    top = (np.float64(high) - residual_mean) * factor
    bottom = (np.float64(low) - residual_mean) * factor
    _check_peak(max(float(top), -float(bottom)), ra)
    heights = _GeneratedHeights(terms, dx, residual_mean, factor)
    return heights, _metadata(params, seed, terms), float(top - bottom)


# --- a realization ------------------------------------------------------------------------------


def _grid_positions(points: NDArray[np.int64], length: float, n: int) -> NDArray[np.float64]:
    """x at grid indices, bit for bit as :func:`splinecontact._memory.grid` makes the grid."""
    x = points.astype(np.float64) * (np.float64(length) / (n - 1)) + 0.0
    x[points == n - 1] = length
    return x


def _run(
    lower: _Heights,
    upper: _Heights | None,
    *,
    n: int,
    length: float,
    x: NDArray[np.float64] | None,
    peak_to_valley: float,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    record_steps: NDArray[np.int64],
    law: ContactLaw,
    chunk: int,
    max_recorded: int,
) -> tuple[dict[str, NDArray[Any]], tuple[ContactRecord, ...], dict[str, float], float]:
    """Placement, candidates and the loading loop of a streamed realization (units as in
    :func:`simulate_streamed`); returns curves, recorded contacts, statistics and dx [µm]."""
    dx = length / (n - 1)
    _, lam_grid = grid_smoothing(dx, alpha, x0)
    displacement = displacement_steps(
        final_displacement, final_displacement_factor, peak_to_valley, steps
    )
    limit = float(displacement[-1]) + law.reach
    columns, offset, mean_gap0, stats = _stream(lower, upper, n, dx, lam_grid, limit, chunk)
    flat = upper is None
    gaps = _final_gaps(offset, columns["f_l"], columns["f_u"], flat)
    chosen = gaps <= limit
    points = columns["point"][chosen]
    at = {name: values[chosen] for name, values in columns.items()}
    geometry: ContactGeometry = order_candidates(
        gaps[chosen], points, float(mean_gap0), displacement, law.reach,
        x=_grid_positions(points, length, n) if x is None else x[points],
        height_lower=at["f_l"], slope_lower=at["slope_l"], second_lower=at["second_l"],
        slope_upper=None if flat else at["slope_u"], second_upper=None if flat else at["second_u"],
        dx=dx,
    )  # fmt: skip
    check_reserved(geometry.first_step_index, record_steps, max_recorded)
    run = run_loading(
        geometry, e_star=e_star, g_star=g_star, mu0=mu0, record_steps=record_steps, law=law
    )
    return run.curves, run.contacts, stats, dx


def _result(
    curves: dict[str, NDArray[Any]],
    contacts: tuple[ContactRecord, ...],
    stats: dict[str, float],
    *,
    flat: bool,
    n: int,
    length: float,
    dx: float,
    steps: int,
    final_displacement_factor: float,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    law: ContactLaw,
    lower_metadata: Mapping[str, Any],
    upper_metadata: Mapping[str, Any],
) -> SimulationResult:
    """The :class:`SimulationResult` a whole run builds (``contact.simulation.build_result``)."""
    parameters = run_parameters(
        curves, flat=flat, steps=steps, final_displacement_factor=final_displacement_factor,
        e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, dx=dx, n_points=n,
        length=length, extra=law_record(law),
    )  # fmt: skip
    return SimulationResult(
        curves=curves,
        scalars={**stats, "final_displacement": parameters["final_displacement"]},
        parameters=parameters,
        contacts=contacts,
        lower_metadata=dict(lower_metadata),
        upper_metadata=dict(upper_metadata),
    )


def _chunk(chunk_points: int | None) -> int:
    if chunk_points is None:
        return CHUNK_POINTS
    chunk = check_integer("chunk_points", chunk_points, minimum=_BLOCK)
    return _rounded(chunk)


def simulate_streamed(
    lower: Profile,
    upper: Profile | None,
    *,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    record_steps: NDArray[np.int64],
    law: ContactLaw,
    max_recorded: int = 20_000_000,
    chunk_points: int | None = None,
) -> SimulationResult:
    """:func:`splinecontact.simulate` of two given profiles, fitted and placed in chunks.

    Arguments as :func:`splinecontact.simulate` checks them (``upper`` None for a flat,
    ``law`` bound, ``record_steps`` the recorded step indices, at most ``max_recorded`` [1]
    contact slots reserved for them); ``chunk_points`` [1] the chunk
    (default :data:`CHUNK_POINTS`, rounded up to a multiple of 2048). ``simulate`` calls it
    for profiles of :data:`STREAM_MIN_POINTS` points or more: the spline's f, f′ and f″ (six
    arrays of n values) are never made. Bodies must share one grid (``simulate`` checks it).
    """
    n = lower.n_points
    curves, contacts, stats, _ = _run(
        _GivenHeights(lower.z), None if upper is None else _GivenHeights(upper.z),
        n=n, length=lower.length, x=lower.x, peak_to_valley=lower.peak_to_valley, steps=steps,
        final_displacement=final_displacement, final_displacement_factor=final_displacement_factor,
        e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, record_steps=record_steps,
        law=law, chunk=_chunk(chunk_points), max_recorded=max_recorded,
    )  # fmt: skip
    return _result(
        curves, contacts, stats, flat=upper is None, n=n, length=lower.length, dx=lower.dx,
        steps=steps, final_displacement_factor=final_displacement_factor, e_star=e_star,
        g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, law=law,
        lower_metadata=lower.metadata,
        upper_metadata={"source": "flat"} if upper is None else upper.metadata,
    )  # fmt: skip


def simulate_generated(
    dimension: float,
    *,
    seed: int | np.random.SeedSequence | None,
    flat: bool = False,
    generator: Mapping[str, Any] | None = None,
    steps: int = 1000,
    final_displacement: float | None = None,
    final_displacement_factor: float = 0.2,
    e_star: float = 10.0,
    g_star: float | None = None,
    mu0: float = 0.3,
    alpha: float = 2.0,
    x0: float = 1.0,
    law: ContactLaw | None = None,
    chunk_points: int | None = None,
) -> SimulationResult:
    """Generate a Weierstrass–Mandelbrot pair and simulate its contact, all in chunks.

    The result equals ``simulate(*weierstrass_mandelbrot_pair(dimension, seed=seed,
    **generator), ...)`` (rough-on-flat: the pair's lower profile on a flat) — heights bit for
    bit, forces, counts and areas to ≤ 1e−9 relative — in memory O(chunk + closing points):
    no array of n values is made (eq. 1, eqs. 2–3 and the placement in chunks, then eqs. 7–14
    on the closing points). The study runner uses it from :data:`STREAM_MIN_POINTS` points.

    Parameters
    ----------
    dimension : float
        Fractal dimension D [1].
    seed : int, SeedSequence or None
        Seed of the pair (as :func:`splinecontact.weierstrass_mandelbrot_pair`).
    flat : bool, optional
        Rough-on-flat: only the pair's lower profile is generated, pressed on a rigid flat.
    generator : mapping, optional
        Keyword arguments of :func:`splinecontact.weierstrass_mandelbrot` (``n_points`` [1],
        ``length``, ``wavelength``, ``ra`` [µm], ``gamma``, ``directions``, ``n_max``,
        ``amplitude_law``, ``max_points``, ``max_work``).
    steps, final_displacement, final_displacement_factor, e_star, g_star, mu0, alpha, x0, law
        As in :func:`splinecontact.simulate` (δ [µm], E*, G* [GPa], x0 [µm]).
    chunk_points : int, optional
        Points per chunk [1] (default :data:`CHUNK_POINTS`; rounded up to a multiple of 2048).

    Returns
    -------
    SimulationResult
        As :func:`splinecontact.simulate`; no contacts are recorded.

    Raises
    ------
    ParameterError
        A parameter out of range, as the generator and ``simulate`` raise it; a law that needs
        the bodies' radii (adhesive laws with a reach: use the whole-array pipeline).
    """
    import inspect

    from ..generate import weierstrass_mandelbrot

    steps, e_star, g_star, mu0, law = check_model_arguments(
        steps=steps, final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, law=law,
    )  # fmt: skip
    if getattr(law, "needs_radius", False):
        raise ParameterError(
            f"the law {type(law).__name__} needs the bodies' radii, which a streamed "
            "realization does not keep; use simulate() on generated profiles"
        )
    if law.code != Hertz.code:
        law = bind_law(law, e_star, 0.0)
    chunk = _chunk(chunk_points)
    bound = inspect.signature(weierstrass_mandelbrot).bind(dimension, **dict(generator or {}))
    bound.apply_defaults()
    arguments = dict(bound.arguments)
    del arguments["seed"]
    checked = _validate(**arguments, seed=None)
    params = (*checked, arguments["amplitude_law"])
    parent = as_seed_sequence(seed)
    seeds = (child_seed(parent, 0), child_seed(parent, 1))
    if flat:
        parts = [_generated(params, seeds[0], chunk)]
    else:
        with ThreadPoolExecutor(max_workers=2) as pool:
            parts = list(pool.map(lambda s: _generated(params, s, chunk), seeds))
    n, length = int(params[1]), float(params[2])
    curves, contacts, stats, dx = _run(
        parts[0][0], None if flat else parts[1][0], n=n, length=length, x=None,
        peak_to_valley=parts[0][2], steps=steps, final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, record_steps=np.zeros(0, dtype=np.int64), law=law,
        chunk=chunk, max_recorded=0,
    )  # fmt: skip
    return _result(
        curves, contacts, stats, flat=flat, n=n, length=length, dx=dx, steps=steps,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, law=law, lower_metadata=parts[0][1],
        upper_metadata={"source": "flat"} if flat else parts[1][1],
    )  # fmt: skip
