"""The Maugis–Dugdale root predicted from the last evaluation is the root solved afresh.

Along a path of small overlap steps, a contact on the contact branch is finished in one
evaluation (a cubic prediction of ln t from the memo of its last evaluation, a second-order
Taylor finish, accepted on an a-posteriori error bound; otherwise Newton as before). Each step
must give what an evaluation without any memo gives (Newton from the committed t), to
rounding: 1e-12 of the force scale |P| + the line-contact pull-off force, and 1e-12 relative in
the width, plus what the solves' own tolerance (Newton accepts ln t to 1e-12) and δ, known to
rounding, leave open in t (ln t to 2e-12 + 1e-13 |δ|/|dδ/d ln t|);
on loading, unloading through the fold (jump-out), reloading, steps of every size. At the fold
itself δ(t) is flat, so δ fixes t only to ~√(rounding): there (|dδ/d ln t| below 1e-4 |δ|)
both are held to the attainable 1e-6 of the force scale and of the width scale √(|δ_f| R_eff),
as in the closed-form round trip.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.contact import adhesion as ad
from splinecontact.contact import maugis_dugdale as md

E_STAR = 10.0  # GPa
W = 1e-4  # mN/µm = 0.1 J/m²


def _sigma_for(tabor: float, r_eff: float) -> float:
    return tabor / 2.0 * (math.pi * W * E_STAR**2 / (0.5 * r_eff)) ** (1.0 / 3.0)


def _assert_same_root(
    out: tuple[float, ...], ref: tuple[float, ...], delta: float, r_eff: float, sigma0: float
) -> None:
    """``out`` (memo) and ``ref`` (fresh) agree to rounding and to what δ leaves open in t."""
    scale = abs(ad.jkr_pull_off_force(r_eff, E_STAR, W))
    assert out[2] == ref[2]  # the same branch
    if out[2] != 2.0:
        assert out[:2] == ref[:2]
        return
    t = ref[3]
    b, _, _, d_delta, d_b = md._md_of_t_d(t, r_eff, E_STAR, W, sigma0)
    _, d_f = md.md_fold(r_eff, E_STAR, W, sigma0)
    if abs(d_delta) < 1e-4 * abs(delta):  # flat: at the fold
        assert abs(out[0] - ref[0]) <= 1e-6 * (abs(ref[0]) + scale)
        assert abs(out[1] - ref[1]) <= 1e-6 * math.sqrt(abs(d_f) * r_eff)
        return
    # ln t left open: each solve accepts |δ(t) − δ| ≤ 1e-12 |dδ/d ln t| (Newton's test), and δ
    # is known to rounding
    open_x = 2e-12 + 1e-13 * abs(delta) / abs(d_delta)
    d_force = (math.pi * E_STAR * b / r_eff - 2.0 * sigma0 * t) * d_b  # dP/d ln t
    d_force -= 2.0 * sigma0 * b * t
    assert abs(out[0] - ref[0]) <= 1e-12 * (abs(ref[0]) + scale) + open_x * abs(d_force)
    assert abs(out[1] - ref[1]) <= 1e-12 * ref[1] + open_x * math.sqrt(2.0) * abs(d_b)


def _path(d_f: float, top: float, steps: int, cycles: int) -> np.ndarray:
    low = 1.5 * d_f if d_f < 0.0 else -0.5 * top
    legs = []
    for _ in range(cycles):
        legs.append(np.linspace(low, top, steps))
        legs.append(np.linspace(top, low, steps))
    return np.concatenate(legs)


@settings(max_examples=40, deadline=None)
@given(
    tabor=st.floats(0.3, 5.0),
    r_eff=st.floats(0.002, 2.0),
    top_factor=st.floats(2.0, 200.0),
    steps=st.integers(20, 400),
    cycles=st.integers(1, 2),
)
def test_predicted_root_is_the_fresh_root(
    tabor: float, r_eff: float, top_factor: float, steps: int, cycles: int
) -> None:
    sigma0 = _sigma_for(tabor, r_eff)
    _, d_f = md.md_fold(r_eff, E_STAR, W, sigma0)
    top = top_factor * abs(d_f)
    memo = np.zeros(md.N_STATE)
    for delta in _path(d_f, top, steps, cycles):
        fresh = memo.copy()
        fresh[5:] = 0.0  # no memo of the last evaluation: Newton from the committed t
        out = md.md_evaluate(float(delta), r_eff, E_STAR, W, sigma0, memo)
        ref = md.md_evaluate(float(delta), r_eff, E_STAR, W, sigma0, fresh)
        _assert_same_root(out, ref, float(delta), r_eff, sigma0)
        memo[:5] = out[2:]  # committed, as the kernels do


def test_a_smooth_loading_is_predicted() -> None:
    """Small steps on the contact branch take the predicted finish (its derivative estimates
    are in the state) and agree with the fresh root."""
    r_eff = 0.05
    sigma0 = _sigma_for(1.0, r_eff)
    _, d_f = md.md_fold(r_eff, E_STAR, W, sigma0)
    memo = np.zeros(md.N_STATE)
    memo[0] = 2.0
    predicted = 0
    for delta in np.linspace(abs(d_f), 50 * abs(d_f), 200):
        out = md.md_evaluate(float(delta), r_eff, E_STAR, W, sigma0, memo)
        memo[:5] = out[2:]
        predicted += memo[14] != 0.0  # the step of the last divided difference
    assert predicted >= 190


@settings(max_examples=30, deadline=None)
@given(
    tabor=st.floats(0.3, 5.0),
    offsets=st.lists(st.sampled_from([0.0, 1e-3, -1e-3, 5e-2, -5e-2]), min_size=3, max_size=3),
)
def test_trials_back_and_forth_as_force_control(tabor: float, offsets: list[float]) -> None:
    """A force-controlled step tries several δ before committing one, back and forth (a step
    back by exactly the last one leaves no second difference): each evaluation is still the
    fresh root."""
    r_eff = 0.05
    sigma0 = _sigma_for(tabor, r_eff)
    _, d_f = md.md_fold(r_eff, E_STAR, W, sigma0)
    memo = np.zeros(md.N_STATE)
    for base in np.linspace(2 * abs(d_f), 20 * abs(d_f), 12):
        for delta in [base * (1.0 + o) for o in offsets] + [base, base * 1.01, base]:
            fresh = memo.copy()
            fresh[5:] = 0.0
            out = md.md_evaluate(float(delta), r_eff, E_STAR, W, sigma0, memo)
            ref = md.md_evaluate(float(delta), r_eff, E_STAR, W, sigma0, fresh)
            _assert_same_root(out, ref, float(delta), r_eff, sigma0)
        memo[:5] = out[2:]  # the last trial is committed
