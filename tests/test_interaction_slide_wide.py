"""The sliding and force-controlled interacting drivers leave the model's validity with the
ParameterError of the normal path (a contact too wide for the period), never with inf/NaN."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import splinecontact as sc
from splinecontact.errors import ParameterError


def _circle() -> sc.Profile:
    """Circle of radius 0.5 µm on 401 points at 1 Å spacing (segment 0.04 µm long)."""
    x = np.arange(401) * 1e-4
    x = x - x.mean()
    return sc.Profile(x=x, z=np.sqrt(0.25 - x * x) - 0.5)


def _run(path: list[sc.Segment]) -> sc.SimulationResult:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # form warning: the circle is all form
        return sc.simulate(_circle(), "flat", path=path, interaction=True, diagnostics=False)


def test_sliding_too_wide_raises_where_the_normal_path_does() -> None:
    """Pressed to 5e−4 µm in 40 steps: the normal path leaves the validity at step 10; sliding
    along the same displacements, the driver raises the same error one step earlier (its three
    width updates per step against the normal path's one let the widths grow faster), naming
    the path's step and δ_N."""
    with pytest.raises(ParameterError, match=r"left its validity at step 10 \(displacement"):
        _run([sc.Segment(normal=5e-4, steps=40)])
    for travel in (1e-6, 1e-4):
        with pytest.raises(
            ParameterError, match=r"left its validity at step 9 \(displacement 0.0001125 µm\)"
        ):
            _run([sc.Segment(normal=5e-4, tangential=travel, steps=40)])


def test_sliding_inside_validity_is_finite() -> None:
    result = _run([sc.Segment(normal=1e-4, tangential=1e-4, steps=4)])
    assert np.all(np.isfinite(result.normal_force)) and result.normal_force[-1] > 0.0


def test_force_trial_beyond_validity_counts_as_above_the_target() -> None:
    """A force-controlled step whose bracketing tries a δ_N beyond the validity still meets a
    target reachable inside it (the invalid trial counts as F_N = +inf)."""
    from splinecontact.contact import interaction_slide as slide

    calls: list[float] = []

    def evaluate(d: float) -> float:
        calls.append(d)
        return d if d < 0.5 else float("inf")

    d, f = slide._solve_continuous(0.4, evaluate, 0.1, 0.1, 10.0)
    assert f == pytest.approx(0.4, rel=1e-9) and d == pytest.approx(0.4, rel=1e-9)


def test_force_control_beyond_validity_raises() -> None:
    """A force target that F_N reaches only beyond the validity raises the ParameterError at
    that step (not a miss, nor a ForceControlError about the bodies' full height); a target
    inside it is held. The bound: a Hertz half-width √(2PR/(πE*)) of L_p/π, P = 0.0102 mN/µm
    for this circle (R = 0.5 µm on the flat, E* = 10 GPa, L_p = 0.0802 µm)."""
    inside = _run([sc.Segment(normal=1e-4, steps=4), sc.Segment(normal_force=0.005, steps=2)])
    assert inside.normal_force[-2:] == pytest.approx([0.005, 0.005], rel=1e-6)
    for target in (0.011, 0.05):
        with pytest.raises(ParameterError, match="left its validity at step 5"):
            _run([sc.Segment(normal=1e-4, steps=4), sc.Segment(normal_force=target, steps=2)])
