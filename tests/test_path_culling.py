"""The culled load-path steps against an un-culled reference evaluation (exact equality).

A displacement-controlled segment runs compiled (``path_kernel.run_steps``): a fixed-shift
segment visits one candidate list sorted by a bound with the upper body evaluated once, and a
sliding step visits only the runs of 8-point sub-blocks whose bound says they may touch,
flags them in one vector pass and decides the few flagged points exactly. The reference here
visits every grid point at every step with the scalar evaluation (``path_step`` with all points
as candidates and infinite bounds): every per-step output of a sliding step must be the same
to the bit; the global sums of a fixed-shift step (its contacts added in the order of the
sorted candidates, as before) to round-off, 1e-12, and its counts exactly.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact import Segment, weierstrass_mandelbrot_pair
from splinecontact.contact import loadpath as lp
from splinecontact.contact import path_kernel as pk
from splinecontact.contact.laws import Hertz
from splinecontact.spline import fit_spline_pair

E_STAR, G_STAR, MU0, ALPHA, X0 = 10.0, 4.0, 0.3, 2.0, 1.0

#: Per-step outputs compared (the names of run_path's curves).
_SUMS = (
    "normal_force",
    "tangential_force",
    "contact_area",
    "n_contacts",
    "n_slipping",
    "normal_force_normal_part",
    "normal_force_tangential_part",
    "n_tilted_contacts",
    "n_candidates",
)


def _reference(lower, upper, path):  # type: ignore[no-untyped-def]
    """Every grid point visited at every step (scalar evaluation, no culling)."""
    fits = fit_spline_pair(lower, None if isinstance(upper, str) else upper, alpha=ALPHA, x0=X0)
    geo = lp._prepare(lower, *fits)
    n = lower.n_points
    state = lp._State(n, Hertz(), E_STAR, G_STAR, MU0)
    state.ensure(n + 1)
    cand = np.arange(n, dtype=np.int64)
    bound = np.full(n, np.inf)
    rows = []

    def step(u: float, d: float, du: float, dd: float) -> None:
        sums = pk.path_step(
            u, d, du, dd, True, geo.surf, cand, bound, True, state.material,
            lp._migrate_cells(geo, du, dd), state.springs, state.scratch, state.springs.claimed,
            False, pk._NONE,
        )  # fmt: skip
        rows.append((d, u, *sums))

    step(0.0, 0.0, 0.0, 0.0)
    u_cur = d_cur = 0.0
    for seg in path:
        u_a, d_a = u_cur, d_cur
        u_b = u_a if seg.tangential is None else float(seg.tangential)
        d_b = d_a if seg.normal is None else float(seg.normal)
        for s in range(1, seg.steps + 1):
            u = u_b if s == seg.steps else u_a + (u_b - u_a) * (s / seg.steps)
            d = d_b if s == seg.steps else d_a + (d_b - d_a) * (s / seg.steps)
            step(u, d, u - u_cur, d - d_cur)
            u_cur, d_cur = u, d
    table = np.array(rows)
    names = ("displacement", "tangential_displacement", *pk.StepSums._fields)
    return {name: table[:, j] for j, name in enumerate(names)}


def _culled(lower, upper, path):  # type: ignore[no-untyped-def]
    curves, _ = lp.run_path(
        lower, upper, path, e_star=E_STAR, g_star=G_STAR, mu0=MU0, alpha=ALPHA, x0=X0
    )
    return curves


def _assert_same(lower, upper, path) -> int:  # type: ignore[no-untyped-def]
    """Compare; returns the largest number of contacts of a step."""
    ref = _reference(lower, upper, path)
    got = _culled(lower, upper, path)
    np.testing.assert_array_equal(got["displacement"], ref["displacement"])
    np.testing.assert_array_equal(got["tangential_displacement"], ref["tangential_displacement"])
    # Sliding steps visit the points in grid order, as the reference: equal to the bit. A
    # fixed-shift segment visits its candidates sorted by their bound, so its global sums add
    # the same per-contact values in another order: equal to round-off (1e-12 of the scale).
    tang = got["tangential_displacement"]
    sliding = np.r_[False, tang[1:] != tang[:-1]]
    assert sliding.sum() > 0
    for name in _SUMS:
        a, b = got[name], ref[name]
        np.testing.assert_array_equal(a[sliding], b[sliding], err_msg=name)
        if name.startswith("n_"):
            np.testing.assert_array_equal(a, b, err_msg=name)
        else:
            scale = np.abs(b).max()
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * scale, err_msg=name)
    work = np.cumsum(ref["step_work"])
    np.testing.assert_allclose(got["dissipated_work"], work, rtol=1e-12, atol=1e-300)
    return int(got["n_contacts"].max())


@settings(max_examples=12, deadline=None)
@given(
    dimension=st.floats(1.2, 1.8),
    seed=st.integers(0, 10_000),
    depth=st.floats(0.05, 0.3),
    travel=st.floats(0.002, 0.05),
    sign=st.sampled_from([-1.0, 1.0]),
    flat=st.booleans(),
)
def test_culled_steps_equal_the_uncull_reference(
    dimension: float, seed: int, depth: float, travel: float, sign: float, flat: bool
) -> None:
    """Loading, sliding (several cells per step), reversal while unloading, reloading."""
    lower, upper = weierstrass_mandelbrot_pair(dimension, seed=seed, n_points=1500, length=0.15)
    d = depth * lower.peak_to_valley
    path = [
        Segment(normal=d, steps=12),
        Segment(tangential=sign * travel, steps=15),
        Segment(tangential=-0.5 * sign * travel, normal=0.6 * d, steps=10),
        Segment(normal=d, steps=6),
    ]
    _assert_same(lower, "flat" if flat else upper, path)


@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 10_000), cells=st.integers(1, 3))
def test_whole_cell_shifts_equal_the_uncull_reference(seed: int, cells: int) -> None:
    """Shifts that are whole numbers of cells: every point evaluated on a knot (exactly)."""
    dx = 2.0**-13  # u = s·dx exactly, so u/dx is a whole number at every step
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=seed, n_points=1200, length=1199 * dx)
    assert lower.dx == dx
    d = 0.2 * lower.peak_to_valley
    path = [Segment(normal=d, steps=8), Segment(tangential=16 * cells * dx, steps=16)]
    _assert_same(lower, upper, path)


def test_the_comparisons_are_not_vacuous() -> None:
    """Fixed cases where contacts are accepted at most steps (sliding over whole cells too)."""
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=1, n_points=1500, length=0.15)
    d = 0.2 * lower.peak_to_valley
    path = [Segment(normal=d, steps=10), Segment(tangential=0.03, steps=15)]
    assert _assert_same(lower, upper, path) >= 3
    dx = 2.0**-13
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=1, n_points=1200, length=1199 * dx)
    d = 0.2 * lower.peak_to_valley
    path = [Segment(normal=d, steps=8), Segment(tangential=16 * dx, steps=16)]
    assert _assert_same(lower, upper, path) >= 3


def _runs_reference(cull, n, blocks, shift, threshold):  # type: ignore[no-untyped-def]
    """step_runs' rule in plain Python: sub-block q is kept when max f^l over it + the largest
    envelope of the envelope sub-blocks q + a … q + b (clipped) + margin ≥ threshold."""
    sub = cull.sub
    c = int(np.floor(-shift))
    a, b = (c - 1) // sub, (sub + 1 + c) // sub
    last = cull.envelope_sub.size - 1
    kept, bounds = [], []
    per_block = cull.block // sub
    for blk in blocks:
        for q in range(blk * per_block, min(cull.f_l_sub.size, (blk + 1) * per_block)):
            lo, hi = max(0, q + a), min(last, q + b)
            if hi < lo:
                continue
            v = cull.f_l_sub[q] + max(cull.envelope_sub[lo : hi + 1]) + cull.margin
            if v >= threshold:
                kept.append(q)
                bounds.append(v)
    runs: list[list[int]] = []
    for q in kept:
        if runs and runs[-1][1] == q * sub:
            runs[-1][1] += sub
        else:
            runs.append([q * sub, q * sub + sub])
    starts = [r[0] for r in runs]
    lengths = [min(r[1], n) - r[0] for r in runs]
    return starts, lengths, max(bounds, default=-np.inf)


def _check_step_runs(seed: int, shift: float, depth: float, window: int) -> int:
    """Compare step_runs with the plain rule at one shift; returns the number of runs."""
    from splinecontact.contact import _sliding as cu

    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=seed, n_points=1500, length=0.15)
    geo = lp._prepare(lower, *fit_spline_pair(lower, upper, alpha=ALPHA, x0=X0))
    surf, cull = geo.surf, geo.cull
    n = surf.f_l.size
    threshold = surf.placement - depth * lower.peak_to_valley
    c = int(np.floor(-shift))
    blocks = np.empty(cull.f_l_block.size, dtype=np.int64)
    count = cu.candidate_blocks(surf, cull, c - 1 - window, c + 1 + window, threshold, blocks)
    run_start = np.empty(cull.f_l_sub.size, dtype=np.int64)
    run_len = np.empty(cull.f_l_sub.size, dtype=np.int64)
    n_runs, top = cu.step_runs(surf, cull, blocks[:count], shift, threshold, run_start, run_len)
    starts, lengths, top_ref = _runs_reference(cull, n, blocks[:count], shift, threshold)
    assert list(run_start[:n_runs]) == starts
    assert list(run_len[:n_runs]) == lengths
    assert top == top_ref
    in_runs = np.zeros(n, dtype=bool)
    for s, length in zip(starts, lengths, strict=True):
        in_runs[s : s + length] = True
    for i in range(n):
        inside, h_u, _, _ = pk._upper_height(surf, i, shift)
        if inside and h_u + surf.f_l[i] >= threshold:
            assert in_runs[i]
        if inside and in_runs[i]:
            assert h_u + surf.f_l[i] <= top
    return n_runs


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    shift=st.floats(-1400.0, 1400.0),
    depth=st.floats(0.0, 0.5),
    window=st.integers(0, 60),
)
def test_step_runs_equal_the_plain_rule_and_bound_every_point(
    seed: int, shift: float, depth: float, window: int
) -> None:
    """The runs of a sliding step (compiled, without a branch per sub-block) are those of the
    plain rule; every point whose gap can close at the shift is in a run, and the returned
    bound is at least f^l + f^u(ξ) at every point of the runs (what the filter's constant
    widening rests on)."""
    _check_step_runs(seed, shift, depth, window)


def test_step_runs_comparison_is_not_vacuous() -> None:
    """Fixed draws with several runs."""
    assert _check_step_runs(seed=2, shift=3.3, depth=0.5, window=10) >= 3
    assert _check_step_runs(seed=2, shift=-40.7, depth=0.2, window=10) >= 3


def _window_bound_reference(f_max, coarse, width, first, last, lo, hi, m, margin):  # type: ignore[no-untyped-def]
    """f_max + the largest coarse entry over the knot intervals [first + lo, last + hi]."""
    k_lo, k_hi = max(0, first + lo), min(m - 1, last + hi)
    if k_hi < k_lo:
        return -np.inf
    return f_max + max(coarse[k_lo // width : min(coarse.size - 1, k_hi // width) + 1]) + margin


def _check_candidate_blocks(
    seed: int, n_points: int, shift: float, window: int, depth: float
) -> int:
    """Compare candidate_blocks with the plain rule; returns the number of blocks."""
    from splinecontact.contact import _sliding as cu

    lower, upper = weierstrass_mandelbrot_pair(
        1.5, seed=seed, n_points=n_points, length=1e-4 * (n_points - 1)
    )
    geo = lp._prepare(lower, *fit_spline_pair(lower, upper, alpha=ALPHA, x0=X0))
    surf, cull = geo.surf, geo.cull
    n, m = surf.f_l.size, cull.envelope.size
    threshold = surf.placement - depth * lower.peak_to_valley
    lo = int(np.floor(-shift)) - 1 - window
    hi = int(np.floor(-shift)) + 1 + window
    blocks = np.empty(cull.f_l_block.size, dtype=np.int64)
    count = cu.candidate_blocks(surf, cull, lo, hi, threshold, blocks)
    span = cull.block * cull.per_super
    expected = []
    for sb in range(cull.f_l_super.size):
        last = min(n, (sb + 1) * span) - 1
        args = (cull.envelope_super, span, sb * span, last, lo, hi, m, cull.margin)
        if _window_bound_reference(cull.f_l_super[sb], *args) < threshold:
            continue
        for b in range(sb * cull.per_super, min(cull.f_l_block.size, (sb + 1) * cull.per_super)):
            last = min(n, (b + 1) * cull.block) - 1
            args = (cull.envelope_block, cull.block, b * cull.block, last, lo, hi, m, cull.margin)
            if _window_bound_reference(cull.f_l_block[b], *args) >= threshold:
                expected.append(b)
    assert list(blocks[:count]) == expected
    return count


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n_points=st.integers(1100, 12_000),
    shift=st.floats(-12_500.0, 12_500.0),
    window=st.one_of(st.integers(0, 100), st.integers(0, 3000)),
    depth=st.floats(0.0, 0.6),
)
def test_candidate_blocks_equal_the_plain_rule(
    seed: int, n_points: int, shift: float, window: int, depth: float
) -> None:
    """The blocks of a sliding chunk (compiled, the windows of whole (super-)blocks without
    divisions) are those of the plain rule: super-block bound, then block bound ≥ threshold,
    with the windows clipped at both bodies' ends."""
    _check_candidate_blocks(seed, n_points, shift, window, depth)


def test_candidate_blocks_comparison_is_not_vacuous() -> None:
    """Fixed draws keeping some blocks but not all, inside the bodies and at their ends."""
    n_b = -(-10_001 // 64)
    for shift, depth in ((0.5, 0.3), (-9000.2, 0.3), (5000.5, 0.6)):
        assert 0 < _check_candidate_blocks(3, 10_001, shift, 40, depth) < n_b
