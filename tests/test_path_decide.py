"""The load-path kernels' exact decision of the packed points is the scalar loop's, to the bit;
the sliding step's list of flagged points is numpy's.

``_decide.decide_packed`` runs the two-sphere contact (``geometry.sphere_contact``, Table 1,
eqs. 7–10, eq. 9) on every packed point in one pass without branches (on vector units) and
keeps the accepted points in order; ``_decide.apply_law`` gives them their normal force and
width (eq. 10). Both are checked here against the scalar loop they replace, kept below as a
Python reference calling the same compiled scalar functions one point at a time, on points
drawn around Table 1's and eq. 9's boundaries, some of them not kept, for a law without
history (Hertz, in both of its kernel forms) and one with a memo in its state (JKR).
``_decide.flag_list`` (the flagged positions, read off bit masks without a branch per flag)
is checked against ``numpy.flatnonzero``, sparse and dense, at every length modulo 64.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.contact._decide import apply_law, decide_packed, flag_list
from splinecontact.contact.geometry import contact_centre_height, sphere_contact
from splinecontact.contact.laws import Hertz, bind_law, kernel_material, make_law, normal_law
from splinecontact.contact.loadpath import _scratch
from splinecontact.contact.path_kernel import _upper_sphere

_DX = 1e-4  # [µm]
_KAPPA_MAX = 2.0 / _DX  # [1/µm]
_N_GRID = 64  # lower grid points [1]
_E_STAR = 10.0  # [GPa]

_LAWS = {
    "hertz": kernel_material(
        Hertz(), e_star=_E_STAR, g_star=4.0, mu0=0.3, n_points=_N_GRID, hertz_alone=True
    ),
    "hertz-array": kernel_material(Hertz(), e_star=_E_STAR, g_star=4.0, mu0=0.3, n_points=_N_GRID),
    "jkr": kernel_material(
        bind_law(make_law("jkr", work_of_adhesion=0.05), _E_STAR, 1.0),
        e_star=_E_STAR,
        g_star=4.0,
        mu0=0.3,
        n_points=_N_GRID,
    ),
}

_point = st.tuples(
    st.floats(-3.0, 3.0),  # lower slope s^l [1]
    st.floats(-5e3, 5e3),  # lower f″ [1/µm]
    st.floats(-5e3, 5e3),  # upper f″ s2 [1/µm]
    st.floats(-1.5, 1.5),  # eq. 9 offset, about this many half cells
    st.floats(-1e-3, 1e-5),  # gap g [µm]
    st.booleans(),  # kept by the filter
)


def _packed(points: list[tuple[float, ...]], rng: np.random.Generator) -> list[tuple[Any, ...]]:
    """(i, g, s1, s2, κ^l, n^l_x, n^l_z, keep) per drawn point (distinct i, ascending)."""
    cells = np.sort(rng.choice(_N_GRID, size=len(points), replace=False))
    out = []
    for i, (s_l, c_l, c_u, ratio, g, keep) in zip(cells, points, strict=True):
        norm_l = math.sqrt(1.0 + s_l * s_l)
        k_l = min(max(-c_l / norm_l**3, -_KAPPA_MAX), _KAPPA_MAX)
        k_sum = abs(k_l) + abs(c_u) + 1.0
        s1 = -s_l + ratio * 0.5 * _DX * k_sum * norm_l**3  # centre near ratio·dx/2
        out.append((int(i), g, s1, c_u, k_l, -s_l / norm_l, 1.0 / norm_l, keep))
    return out


def _reference(
    packed: list[tuple[Any, ...]],
    f_l: np.ndarray,
    cell_test: float,
    material: Any,
) -> list[tuple[float, ...]]:
    """The scalar decision (the kernel's loop before the vector pass): one point at a time."""
    out = []
    for i, g, s1, s2, k_l, n_x, n_z, keep in packed:
        if not keep:
            continue
        k_u, m_x, m_z = _upper_sphere(s1, s2, _KAPPA_MAX)
        accepted, delta, offset, e_x, e_z, y_norm = sphere_contact(
            g, k_l, k_u, m_x, m_z, n_x, n_z, cell_test, -material.reach
        )
        if not accepted:
            continue
        reff = 2.0 / (k_l + k_u)
        f_n, width = normal_law(
            material.law_code, material.law_params, delta, reff, material.law_state, i
        )
        z = f_l[i] + contact_centre_height(g, k_l, k_u, m_z, n_z, delta, y_norm)
        out.append((i, f_n, e_x, e_z, i * _DX + offset, z, delta, reff, width))
    return out


def _decided(
    packed: list[tuple[Any, ...]], f_l: np.ndarray, cell_test: float, material: Any
) -> list[tuple[float, ...]]:
    """The same points through decide_packed and apply_law."""
    scratch = _scratch(_N_GRID)
    for q, (i, g, s1, s2, k_l, n_x, n_z, keep) in enumerate(packed):
        scratch.cl_i[q] = i
        scratch.cl_g[q] = g
        scratch.cl_s1[q] = s1
        scratch.cl_s2[q] = s2
        scratch.cl_kl[q] = k_l
        scratch.cl_nx[q] = n_x
        scratch.cl_nz[q] = n_z
        scratch.cl_keep[q] = keep
    n_c = decide_packed(len(packed), f_l, _DX, _KAPPA_MAX, cell_test, -material.reach, scratch)
    apply_law(material.law_code, material.law_params, material.law_state, n_c, scratch)
    columns = ("idx", "fn", "ex", "ez", "xc", "z", "delta", "reff", "width")
    return [tuple(getattr(scratch, c)[k] for c in columns) for k in range(n_c)]


def _bits(rows: list[tuple[float, ...]]) -> list[tuple[int, ...]]:
    return [tuple(int(np.float64(v).view(np.int64)) for v in row) for row in rows]


@settings(max_examples=150, deadline=None)
@given(
    points=st.lists(_point, min_size=0, max_size=40),
    seed=st.integers(0, 2**32 - 1),
    law=st.sampled_from(sorted(_LAWS)),
    given_cells=st.booleans(),
)
def test_the_vector_decision_is_the_scalar_one_to_the_bit(
    points: list[tuple[float, ...]], seed: int, law: str, given_cells: bool
) -> None:
    rng = np.random.default_rng(seed)
    packed = _packed(points, rng)
    f_l = rng.normal(size=_N_GRID)
    cell_test = math.inf if given_cells else 0.5 * _DX  # the contact cells given: no eq. 9
    material = _LAWS[law]
    state = material.law_state
    state[:] = 0.0
    expected = _reference(packed, f_l, cell_test, material)
    memo = state.copy()  # (JKR leaves a memo per evaluated contact: the same one)
    state[:] = 0.0
    got = _decided(packed, f_l, cell_test, material)
    assert _bits(got) == _bits(expected)
    assert np.array_equal(state, memo)


def test_the_decision_comparison_is_not_vacuous() -> None:
    """The drawn points are accepted and refused by each of the tests (Table 1, eq. 9, the kept
    flag), and a refused point among accepted ones moves the later ones down."""
    rng = np.random.default_rng(3)
    points = [
        (0.2, -300.0, -200.0, 0.3, -1e-4, True),  # accepted
        (0.2, -300.0, -200.0, 0.3, -1e-4, False),  # not kept
        (0.1, 800.0, 900.0, 0.0, -1e-4, True),  # Table 1: κ^l + κ^u ≤ 0
        (-0.4, -100.0, -50.0, 1.4, -2e-4, True),  # eq. 9: the centre outside the cell
        (-0.4, -100.0, -50.0, -0.5, -2e-4, True),  # accepted
    ]
    packed = _packed(points, rng)
    f_l = rng.normal(size=_N_GRID)
    hertz = _LAWS["hertz"]
    got = _decided(packed, f_l, 0.5 * _DX, hertz)
    assert [row[0] for row in got] == [packed[0][0], packed[4][0]]
    assert _bits(got) == _bits(_reference(packed, f_l, 0.5 * _DX, hertz))
    assert all(row[1] > 0.0 and row[8] > 0.0 for row in got)  # overlapping: force and width
    # the contact cells given: the centre outside the cell is accepted too
    assert len(_decided(packed, f_l, math.inf, hertz)) == 3


@settings(max_examples=200, deadline=None)
@given(
    total=st.integers(0, 300),
    density=st.sampled_from([0.0, 0.02, 0.2, 0.7, 1.0]),
    seed=st.integers(0, 2**32 - 1),
)
def test_the_flag_list_is_the_positions_of_the_set_flags(
    total: int, density: float, seed: int
) -> None:
    rng = np.random.default_rng(seed)
    flags = np.zeros(total + (-total) % 8 + 8, dtype=np.uint8)  # (whole words, as the kernel's)
    set_ = rng.random(total) < density
    flags[:total] = set_ * rng.integers(1, 4, size=total)
    flags[total:] = 3  # past the end: never listed
    hits = np.full(total, -1, dtype=np.int64)  # exactly ``total`` entries: no room past them
    masks = np.empty(total // 8 + 8, dtype=np.uint8)
    n_hits = flag_list(flags, total, hits, masks)
    assert n_hits == np.count_nonzero(set_)
    assert np.array_equal(hits[:n_hits], np.flatnonzero(set_))
