"""The load-path kernels' conservative eq. 9 filter never drops a contact the exact test accepts.

The sliding and fixed-shift steps flag, in one branch-free pass, the closed points that may pass
Table 1, δ > −reach and eq. 9 (``_filter._may_touch``: the tests of
``geometry.sphere_contact`` multiplied through by their positive denominators and widened);
only the flagged points are decided exactly. Here the filter is checked against the exact test
itself on points drawn around the eq. 9 boundary (upper slope s1 = −s^l + ε with ε set so that
the contact centre falls near ±dx/2 from the point), for overlaps and for gaps within a law's
reach: every point the exact test accepts must pass the filter. The sliding pass widens its
tests by a constant, that of an upper bound G ≥ |g| over all its closed points
(``_filter.widenings`` at K·G, ``_filter._touches``): every check here holds for it too, at
the tightest G = |g| and at larger ones, and fails with the widening removed.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.contact._filter import _may_touch, _touches, widenings
from splinecontact.contact.geometry import sphere_contact
from splinecontact.contact.path_kernel import _upper_sphere

_DX = 1e-4  # [µm]
_KAPPA_MAX = 2.0 / _DX  # 1/r_min with r_min = dx/2 [1/µm]


def _point(s_l: float, c_l: float, c_u: float, ratio: float, g: float) -> tuple[float, ...]:
    """(g, s1, s2, κ^l, n^l_x, n^l_z) of a point whose eq. 9 offset is about ratio·dx/2."""
    norm_l = math.sqrt(1.0 + s_l * s_l)
    k_l = min(max(-c_l / norm_l**3, -_KAPPA_MAX), _KAPPA_MAX)
    k_sum = abs(k_l) + abs(c_u) + 1.0
    s1 = -s_l + ratio * 0.5 * _DX * k_sum * norm_l**3
    return g, s1, c_u, k_l, s_l / norm_l, 1.0 / norm_l


@settings(max_examples=400, deadline=None)
@given(
    s_l=st.floats(-3.0, 3.0),
    c_l=st.floats(-5e3, 5e3),
    c_u=st.floats(-5e3, 5e3),
    ratio=st.floats(-1.5, 1.5),
    g_scale=st.floats(-1e-3, 1e-5),
    reach=st.sampled_from([0.0, 1e-6, 1e-4]),
)
def test_the_filter_keeps_every_point_the_exact_test_accepts(
    s_l: float, c_l: float, c_u: float, ratio: float, g_scale: float, reach: float
) -> None:
    g, s1, s2, k_l, n_x, n_z = _point(s_l, c_l, c_u, ratio, g_scale)
    k_u, m_x, m_z = _upper_sphere(s1, s2, _KAPPA_MAX)
    accepted = sphere_contact(g, k_l, k_u, m_x, m_z, -n_x, n_z, 0.5 * _DX, -reach)[0]
    kept = _may_touch(g, s1, s2, k_l, -n_x, n_z, _KAPPA_MAX, _DX, reach)
    assert kept or not accepted
    for gap in (abs(g), 1e-3):
        assert _constant(g, s1, s2, k_l, -n_x, n_z, reach, gap) or not accepted


def test_the_filter_comparison_is_not_vacuous() -> None:
    """The points drawn around the boundary are accepted on one side and refused on the other,
    and the filter refuses points well outside the cell."""
    outcomes = []
    for ratio in (-3.0, -0.5, 0.0, 0.5, 3.0):
        g, s1, s2, k_l, n_x, n_z = _point(0.3, -200.0, -300.0, ratio, -1e-5)
        k_u, m_x, m_z = _upper_sphere(s1, s2, _KAPPA_MAX)
        accepted = sphere_contact(g, k_l, k_u, m_x, m_z, -n_x, n_z, 0.5 * _DX, 0.0)[0]
        kept = _may_touch(g, s1, s2, k_l, -n_x, n_z, _KAPPA_MAX, _DX, 0.0)
        outcomes.append((accepted, kept))
    assert outcomes[2] == (True, True)
    assert (False, False) in outcomes


def _sphere_point(
    s_l: float, s1: float, k_u: float, k_l: float
) -> tuple[float, float, float, float, float]:
    """(s2, κ^l, n^l_x, n^l_z, κ^u as the kernel evaluates it) for target curvatures κ^u, κ^l."""
    norm_l = math.sqrt(1.0 + s_l * s_l)
    s2 = -k_u * math.sqrt(1.0 + s1 * s1) ** 3
    k_l = min(max(k_l, -_KAPPA_MAX), _KAPPA_MAX)
    return s2, k_l, -s_l / norm_l, 1.0 / norm_l, _upper_sphere(s1, s2, _KAPPA_MAX)[0]


def _constant(
    g: float, s1: float, s2: float, k_l: float, n_x: float, n_z: float, reach: float, gap: float
) -> bool:
    """The filter with the constant widening of a gap bound ``gap`` (G ≥ |g|) [µm]."""
    e_d, e_9 = widenings(_KAPPA_MAX * gap, _KAPPA_MAX, _DX, reach)
    return bool(_touches(g, s1, s2, k_l, n_x, n_z, _KAPPA_MAX, _DX, reach, e_d, e_9))


def _check(
    g: float, s1: float, s2: float, k_l: float, n_x: float, n_z: float, reach: float
) -> bool:
    """Assert that the filter keeps the point if the exact test accepts it, with its own and
    with constant widenings (gap bounds |g|, 2|g| + reach, 10⁻³ µm); return the exact test."""
    k_u, m_x, m_z = _upper_sphere(s1, s2, _KAPPA_MAX)
    accepted = sphere_contact(g, k_l, k_u, m_x, m_z, n_x, n_z, 0.5 * _DX, -reach)[0]
    kept = _may_touch(g, s1, s2, k_l, n_x, n_z, _KAPPA_MAX, _DX, reach)
    assert kept or not accepted, (g, s1, s2, k_l, n_x, n_z, reach)
    for gap in (abs(g), 2.0 * abs(g) + reach, max(abs(g), 1e-3)):
        kept = _constant(g, s1, s2, k_l, n_x, n_z, reach, gap)
        assert kept or not accepted, (g, s1, s2, k_l, n_x, n_z, reach, gap)
    return bool(accepted)


_TINY = st.sampled_from([0.0, 5e-324, 1e-300, 1e-200, 1e-30, 1e-17, 1e-16, 3e-16, 1e-15, 1e-12])


@settings(max_examples=600, deadline=None)
@given(
    s_l=st.floats(-3.0, 3.0),
    slope_gap=st.one_of(_TINY, st.floats(-1e-3, 1e-3)),
    k_u=st.one_of(st.floats(-2.5e4, 2.5e4), st.floats(-1e-6, 1e-6)),
    cancel=st.one_of(_TINY, st.floats(-1e-6, 1e-6), st.floats(-2.0, 2.0)),
    g=st.one_of(_TINY, st.floats(-1e-9, 1e-9), st.floats(-1e-3, 1e-4)),
    reach=st.sampled_from([0.0, 1e-9, 1e-6, 1e-4, 1e-2]),
    sign=st.sampled_from([-1.0, 1.0]),
)
def test_the_filter_keeps_every_accepted_point_where_the_test_is_ill_conditioned(
    s_l: float,
    slope_gap: float,
    k_u: float,
    cancel: float,
    g: float,
    reach: float,
    sign: float,
) -> None:
    """κ^l + κ^u near zero (κ^l = −κ^u(1 + ε)), |Y| near zero (matching slopes, equal and
    opposite curvatures, g ≈ 0), gaps near zero and within a law's reach, tiny curvatures:
    where both computations round most differently, no accepted point is dropped."""
    s1 = -s_l + sign * slope_gap
    s2, k_l, n_x, n_z, k_u_kernel = _sphere_point(s_l, s1, k_u, 0.0)
    k_l = min(max(-k_u_kernel * (1.0 + cancel), -_KAPPA_MAX), _KAPPA_MAX)
    _check(sign * g, s1, s2, k_l, n_x, n_z, reach)


def test_the_ill_conditioned_points_are_accepted_and_kept() -> None:
    """Near-cancelling curvature sums and near-zero |Y| at which the exact test does accept
    (the property above is not vacuous there), on a deterministic grid."""
    accepted = 0
    for s_l in (0.0, 0.4, -1.7):
        for k_u in (3e3, -3e3, 1e-3, 2e4):
            for cancel in (-1e-15, -1e-12, -1e-9, -1e-6, -1e-3, 0.5):
                for g in (-1e-18, -1e-12, -1e-7, 0.0, 1e-9):
                    for reach in (0.0, 1e-6, 1e-2):
                        s1 = -s_l + 1e-9
                        s2, _, n_x, n_z, k_u_kernel = _sphere_point(s_l, s1, k_u, 0.0)
                        k_l = -k_u_kernel * (1.0 + cancel)
                        accepted += _check(g, s1, s2, k_l, n_x, n_z, reach)
    assert accepted > 100


def test_the_widening_keeps_few_points_the_exact_test_refuses() -> None:
    """The widening does not make the filter vacuous: on random closed points (about half of
    them refused by eq. 9, their contact centre in another cell) the filter keeps every point
    the exact test accepts and hardly any other."""
    rng = np.random.default_rng(5)
    kept = accepted = kept_constant = 0
    total = 2000
    for _ in range(total):
        s_l = rng.uniform(-0.5, 0.5)
        s1 = -s_l + rng.uniform(-0.05, 0.05)
        s2, k_l, n_x, n_z, _ = _sphere_point(s_l, s1, rng.uniform(-50, 300), rng.uniform(-50, 300))
        g = rng.uniform(-1e-4, 0.0)
        accepted += _check(g, s1, s2, k_l, n_x, n_z, 0.0)
        kept += _may_touch(g, s1, s2, k_l, n_x, n_z, _KAPPA_MAX, _DX, 0.0)
        # the sliding pass's constant widening (the largest |g| drawn here)
        kept_constant += _constant(g, s1, s2, k_l, n_x, n_z, 0.0, 1e-4)
    assert 0.2 * total < accepted <= kept <= accepted + 2 < 0.8 * total
    assert kept <= kept_constant <= accepted + 2


def _edge(accepts: Callable[[float], bool], inside: float, outside: float) -> float:
    """The last accepted float between ``inside`` (accepted) and ``outside`` (refused), by
    bisection down to adjacent floats: a point the exact test accepts by the last ulp."""
    assert accepts(inside) and not accepts(outside)
    while True:
        mid = 0.5 * (inside + outside)
        if mid in (inside, outside):
            return inside
        if accepts(mid):
            inside = mid
        else:
            outside = mid


def _accepts(
    s1: float,
    g: float,
    *args: float,
    rest: tuple[float, ...] = (),
) -> bool:
    """The exact test at upper slope s1, gap g; ``args`` or ``rest``: s2, κ^l, n_x, n_z, reach."""
    s2, k_l, n_x, n_z, reach = args or rest
    k_u, m_x, m_z = _upper_sphere(s1, s2, _KAPPA_MAX)
    return bool(sphere_contact(g, k_l, k_u, m_x, m_z, n_x, n_z, 0.5 * _DX, -reach)[0])


def _accepts_at_slope(g: float, rest: tuple[float, ...], s1: float) -> bool:
    return _accepts(s1, g, rest=rest)


def _edge_cases() -> list[tuple[float, float, float, float, float, float, float]]:
    """Points on the float-level boundary of each exact test (eq. 9 on both sides of the cell,
    δ > −reach, Table 1), for curvatures from well- to ill-conditioned."""
    out = []
    rng = np.random.default_rng(12)
    configurations = [
        (0.3, -300.0, -200.0, 0.0),
        (-1.2, 5e3, 40.0, 1e-4),
        (0.05, 2e4, -1.9e4, 0.0),
        (0.7, 1e3, -1e3 * (1.0 - 1e-9), 1e-6),
        (0.0, 1e-3, 2e-3, 1e-2),
    ]
    for _ in range(60):
        k_u = float(rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-3.0, 4.3))
        k_l = float(-k_u * (1.0 + rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-12.0, 0.5)))
        reach = float(rng.choice([0.0, 1e-6, 1e-4]))
        configurations.append((float(rng.uniform(-2.0, 2.0)), k_u, k_l, reach))
    for s_l, k_u, k_l, reach in configurations:
        s2, k_l, n_x, n_z, _ = _sphere_point(s_l, -s_l, k_u, k_l)
        rest = (s2, k_l, n_x, n_z, reach)
        g = -1e-6
        for side in (-1.0, 1.0):  # eq. 9 at −dx/2 and +dx/2: the slope mismatch
            far = -s_l + side * 2.0
            if _accepts(-s_l, g, *rest) and not _accepts(far, g, *rest):
                s1 = _edge(functools.partial(_accepts_at_slope, g, rest), -s_l, far)
                out.append((g, s1, *rest))
        s1 = -s_l + 1e-7
        if _accepts(s1, 0.0, *rest) and not _accepts(s1, 1.0, *rest):  # δ > −reach: the gap
            g = _edge(functools.partial(_accepts, s1, rest=rest), 0.0, 1.0)
            out.append((g, s1, *rest))
        # Table 1: κ^l at the smallest κ^l + κ^u > 0 (matching slopes, zero gap, reach > 0)
        k_u_kernel = _upper_sphere(-s_l, s2, _KAPPA_MAX)[0]
        k_edge = math.nextafter(-k_u_kernel, math.inf)
        table_1 = (s2, k_edge, n_x, n_z, max(reach, 1e-9))
        if _accepts(-s_l, 0.0, *table_1):  # (else eq. 9 refuses it: |Y| is tiny)
            out.append((0.0, -s_l, *table_1))
    return out


def test_the_filter_keeps_the_points_accepted_by_the_last_ulp() -> None:
    """On the float-level boundary of every exact test (found by bisection) the accepted
    point is kept: the widening covers the different rounding of the two computations.
    (Without it, the filter's own rounding falls on the wrong side of some of these.)"""
    cases = _edge_cases()
    assert len(cases) >= 80
    for g, s1, s2, k_l, n_x, n_z, reach in cases:
        assert _check(g, s1, s2, k_l, n_x, n_z, reach)


def test_the_constant_widening_is_needed_at_the_last_ulp() -> None:
    """The constant-widening variant without its widening (E_δ = E₉ = 0) drops some of the
    points accepted by the last ulp: the checks above would catch a missing widening."""
    dropped = 0
    for g, s1, s2, k_l, n_x, n_z, reach in _edge_cases():
        accepted = _accepts(s1, g, s2, k_l, n_x, n_z, reach)
        bare = _touches(g, s1, s2, k_l, n_x, n_z, _KAPPA_MAX, _DX, reach, 0.0, 0.0)
        dropped += accepted and not bare
        assert _constant(g, s1, s2, k_l, n_x, n_z, reach, abs(g))
    assert dropped > 0


def test_the_widening_grows_with_the_gap_bound() -> None:
    """E_δ and E₉ never decrease as the gap bound grows (so a bound G ≥ |g| widens at least
    as much as |g| itself) and are positive at G = 0."""
    gaps = np.sort(np.r_[0.0, 5e-324, np.geomspace(1e-300, 1e3, 400)])
    for reach in (0.0, 1e-6, 1e-2):
        widths = np.array([widenings(_KAPPA_MAX * gap, _KAPPA_MAX, _DX, reach) for gap in gaps])
        assert np.all(np.diff(widths, axis=0) >= 0.0)
        assert widths[0, 0] > 0.0 and widths[0, 1] > 0.0
