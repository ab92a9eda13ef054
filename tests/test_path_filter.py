"""The load-path kernels' conservative eq. 9 filter never drops a contact the exact test accepts.

The sliding and fixed-shift steps flag, in one branch-free pass, the closed points that may pass
Table 1, δ > −reach and eq. 9 (``_culling._may_touch``: the tests of
``geometry.sphere_contact`` multiplied through by their positive denominators and widened);
only the flagged points are decided exactly. Here the filter is checked against the exact test
itself on points drawn around the eq. 9 boundary (upper slope s1 = −s^l + ε with ε set so that
the contact centre falls near ±dx/2 from the point), for overlaps and for gaps within a law's
reach: every point the exact test accepts must pass the filter.
"""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.contact._culling import _may_touch
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
