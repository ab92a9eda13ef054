"""The memo a trial evaluation leaves for the commit (JKR) changes no result.

``normal_law`` (trial) then ``commit_law`` must give the forces and branches of solving each
contact afresh (``law_step``), including when the commit's δ is not the trial's (a
force-controlled step tries several δ_N) and after a contact let go (``release_law``).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.contact import make_law
from splinecontact.contact.laws import commit_law, law_step, normal_law, release_law

E_STAR = 10.0
R_EFFS = (0.05, 0.4, 2.0)  # µm

deltas = st.lists(st.floats(-2e-3, 5e-3, allow_nan=False), min_size=1, max_size=40)


@settings(max_examples=60, deadline=None)
@given(
    path=deltas,
    r_index=st.integers(0, len(R_EFFS) - 1),
    w=st.sampled_from([0.0, 0.05, 0.5, 2.0]),
    trial_offsets=st.lists(st.sampled_from([0.0, 0.0, 1e-4, -3e-4]), min_size=40, max_size=40),
    releases=st.lists(st.booleans(), min_size=40, max_size=40),
)
def test_jkr_trial_memo_is_the_fresh_solution(
    path: list[float], r_index: int, w: float, trial_offsets: list[float], releases: list[bool]
) -> None:
    law = make_law("jkr", work_of_adhesion=w)
    params = law.kernel_parameters(E_STAR)
    r_eff = R_EFFS[r_index]
    memo = np.zeros((3, law.n_state))
    fresh = np.zeros((3, law.n_state))
    for k, delta in enumerate(path):
        if releases[k]:
            release_law(law.code, memo, 1)
            release_law(law.code, fresh, 1)
        trial = delta + trial_offsets[k]  # a trial at another δ first, as force control does
        if trial != delta:
            normal_law(law.code, params, trial, r_eff, memo, 1)
        f_memo, width_memo = normal_law(law.code, params, delta, r_eff, memo, 1)
        commit_law(law.code, params, delta, r_eff, memo, 1)
        f_fresh, width_fresh = law_step(law.code, params, delta, r_eff, fresh, 1)
        assert (f_memo, width_memo) == (f_fresh, width_fresh)
        assert memo[1, 0] == fresh[1, 0]  # the committed branch
        if trial != delta:  # the commit of δ after a trial at another δ solves afresh
            commit_law(law.code, params, trial, r_eff, memo, 1)
            law_step(law.code, params, trial, r_eff, fresh, 1)
            assert memo[1, 0] == fresh[1, 0]
    assert not memo[[0, 2]].any()  # other points untouched
