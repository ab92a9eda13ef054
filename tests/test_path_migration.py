"""The spring migration of a load-path step against a plain global greedy assignment.

:func:`splinecontact.contact._migration.migrate` finds, with merged sweeps and a greedy
assignment per group of contacts sharing a candidate (or bisections and one global pass when
the contacts are not in grid order), which committed contact each accepted contact continues.
The reference here is the rule itself, written the plain way: the same cell continues its
contact; every other contact may continue a vanished one within the window, all such pairs
taken by increasing centre distance (ties in generation order: contacts in their order, each
one's candidates by distance in cells, the left one first), each side at most once.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.contact import loadpath as lp
from splinecontact.contact._migration import migrate
from splinecontact.contact.laws import Hertz


def _reference(old_cells, old_xc, new_cells, new_xc, window):  # type: ignore[no-untyped-def]
    src = [-1] * len(new_cells)
    position = {cell: p for p, cell in enumerate(old_cells)}
    own = set()
    for c, i in enumerate(new_cells):
        if i in position:
            src[c] = position[i]
            own.add(position[i])
    vanished = [p for p in range(len(old_cells)) if p not in own]
    pairs = []
    for c, i in enumerate(new_cells):
        if src[c] >= 0:
            continue
        near = [p for p in vanished if abs(old_cells[p] - i) <= window]
        near.sort(key=lambda p: (abs(old_cells[p] - i), old_cells[p] > i))
        pairs += [(abs(old_xc[p] - new_xc[c]), c, p) for p in near]
    order = sorted(range(len(pairs)), key=lambda k: pairs[k][0])  # stable
    claimed = set()
    for k in order:
        _, c, p = pairs[k]
        if src[c] < 0 and p not in claimed:
            src[c] = p
            claimed.add(p)
    return src


@settings(max_examples=150, deadline=None)
@given(
    data=st.data(),
    n_grid=st.integers(8, 60),
    window=st.integers(1, 6),
    shuffle=st.booleans(),
)
def test_migration_equals_the_global_greedy_rule(
    data: st.DataObject, n_grid: int, window: int, shuffle: bool
) -> None:
    _check(data, n_grid, window, shuffle, reuse=False)


@settings(max_examples=150, deadline=None)
@given(
    data=st.data(),
    n_grid=st.integers(8, 80),
    window=st.integers(1, 12),
    shuffle=st.booleans(),
)
def test_migration_in_the_step_scratch_equals_the_global_greedy_rule(
    data: st.DataObject, n_grid: int, window: int, shuffle: bool
) -> None:
    # the kernels' form: its work arrays in the free scratch columns (large groups included)
    _check(data, n_grid, window, shuffle, reuse=True)


def _check(data: st.DataObject, n_grid: int, window: int, shuffle: bool, reuse: bool) -> None:
    cells = st.lists(st.integers(0, n_grid - 1), unique=True, min_size=1, max_size=n_grid // 2)
    old_cells = sorted(data.draw(cells))
    new_cells = sorted(data.draw(cells))
    if shuffle:
        new_cells = list(np.random.default_rng(len(new_cells)).permutation(new_cells))
    # centres on a coarse lattice so that equal distances (ties) occur
    old_xc = [c + data.draw(st.integers(-2, 2)) / 2 for c in old_cells]
    new_xc = [c + data.draw(st.integers(-2, 2)) / 2 for c in new_cells]
    state = lp._State(n_grid, Hertz(), 10.0, 4.0, 0.3)
    state.ensure(n_grid + 1)
    springs, scratch = state.springs, state.scratch
    n_old = len(old_cells)
    springs.cells[:n_old] = old_cells
    springs.xc[:n_old] = old_xc
    springs.n_committed[0] = n_old
    n_c = len(new_cells)
    scratch.idx[:n_c] = new_cells
    scratch.xc[:n_c] = new_xc
    migrate(n_grid, n_c, window, springs, scratch, reuse)
    expected = _reference(old_cells, old_xc, new_cells, new_xc, window)
    assert list(scratch.src[:n_c]) == expected
    assert not springs.claimed.any()  # the scratch flags are left clear


@settings(max_examples=200, deadline=None)
@given(
    data=st.data(),
    n_grid=st.integers(2, 400),
    window=st.integers(0, 30),
    crowd=st.sampled_from([0.02, 0.2, 0.6, 0.95]),
    tight=st.booleans(),
)
def test_migration_of_contacts_in_grid_order_equals_the_global_greedy_rule(
    data: st.DataObject, n_grid: int, window: int, crowd: float, tight: bool
) -> None:
    # The sliding step's form (contacts in grid order, 4 draws in 5) on sparse and crowded
    # grids: clusters of one previous and one new contact, of a few (the branch-free settling),
    # of 63 and more (the pair list), empty windows, contacts vanishing and appearing, equal
    # distances (ties) on the coarse lattice; ``tight``: work arrays of the smallest size the
    # kernels give, so that crowded clusters have more pairs than they hold (settled after
    # the pass).
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    old_cells = np.flatnonzero(rng.random(n_grid) < crowd)
    new_cells = np.flatnonzero(rng.random(n_grid) < crowd)
    if data.draw(st.booleans()):  # the new contacts mostly the previous ones moved by a few cells
        shift = data.draw(st.integers(-window - 1, window + 1))
        moved = old_cells + shift
        keep = (moved >= 0) & (moved < n_grid) & (rng.random(old_cells.size) < 0.9)
        new_cells = np.union1d(moved[keep], new_cells[rng.random(new_cells.size) < 0.1])
    old_xc = old_cells + rng.integers(-2, 3, old_cells.size) / 2
    new_xc = new_cells + rng.integers(-2, 3, new_cells.size) / 2
    if data.draw(st.integers(0, 4)) == 0:  # (not in grid order: the bisections, pairs grown)
        new_cells, new_xc = new_cells[::-1], new_xc[::-1]
    state = lp._State(n_grid, Hertz(), 10.0, 4.0, 0.3)
    state.ensure(max(old_cells.size + 1, new_cells.size, 1) if tight else n_grid + 1)
    springs, scratch = state.springs, state.scratch
    n_old = old_cells.size
    springs.cells[:n_old] = old_cells
    springs.xc[:n_old] = old_xc
    springs.n_committed[0] = n_old
    n_c = new_cells.size
    scratch.idx[:n_c] = new_cells
    scratch.xc[:n_c] = new_xc
    migrate(n_grid, n_c, window, springs, scratch, True)
    expected = _reference(list(old_cells), list(old_xc), list(new_cells), list(new_xc), window)
    assert list(scratch.src[:n_c]) == expected
    assert not springs.claimed.any()
