"""The elastic–plastic law's history on sliding paths: the memory is δ_max.

On a sliding path the history of a lower grid point (δ_max, F_max, b_max) was made by the
upper summit that was there; another summit (another R_eff) may meet the point later. The law
starts its unloading line on the loading curve at δ_max for the R_eff it is evaluated with, so:

* **Continuity** (hypothesis): F is continuous at δ = δ_max whatever the R_eff that made the
  history, and continuous in R_eff below δ_max; the rule before (the line ending at the
  stored F_max) jumps there by ≥ 1 % (planted here as ``_stored_rule_force``, and caught).
* **Bit for bit where R_eff is the history's**: the state and the unloading line are those of
  the stored F_max, b_max exactly (every normal path, and a summit that keeps its curvature:
  one circle slid over a flat and back, both paths).
* **Both sliding paths obey the rule**: on a rough pair slid over its own width of summits
  (4096 points; displacement- or force-controlled; the interacting solve stopped with a
  ``NoConvergenceError`` at the first sliding step under the rule before), every recorded
  contact's force is the law's at its (δ, R_eff) and the largest δ its point saw before,
  F_max and b_max unknown (NaN); the pair meets points with a plastic history under another
  R_eff (the premise, counted).
* **Energy**: a closed (u_T, δ_N) cycle on the pair does driver work ≥ 0 on both paths.
* ``slow``: the 2·10⁴-point pair of ``docs/accuracy.md`` slides to the end in 10 and 40 steps,
  and force-controlled.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from splinecontact import Profile, Segment, simulate
from splinecontact.analysis import driver_work
from splinecontact.contact import ElasticPlastic
from splinecontact.contact import plasticity as pl
from splinecontact.generate import weierstrass_mandelbrot

from conftest import ANGSTROM, circle_cap

E_STAR = 10.0
LAW = ElasticPlastic(yield_strength=0.2)


def _history(d_max: float, r_eff: float, sy: float, nu: float) -> np.ndarray:
    """The state a first loading to ``d_max`` [µm] with R_eff = ``r_eff`` [µm] leaves."""
    out = pl.plastic_evaluate(d_max, r_eff, E_STAR, sy, pl.TABOR_FACTOR * sy, nu, np.zeros(3))
    return np.array(out[2:])


def _law(delta: float, r_eff: float, sy: float, nu: float, state: np.ndarray) -> tuple:
    return pl.plastic_evaluate(delta, r_eff, E_STAR, sy, pl.TABOR_FACTOR * sy, nu, state)


def _stored_rule_force(delta: float, state: np.ndarray) -> float:
    """The rule before (planted bug): the unloading line ends at the stored F_max."""
    residual = state[0] - 4.0 * state[1] / (math.pi * E_STAR)
    return 0.25 * math.pi * E_STAR * max(delta - residual, 0.0)


histories = st.fixed_dictionaries(
    {
        "nu": st.floats(0.0, 0.49),
        "sy": st.floats(0.01, 1.0),
        "r_old": st.floats(0.01, 100.0),
        "ratio": st.floats(0.2, 5.0),
        "omega": st.floats(1.01, 500.0),
    }
)


@settings(max_examples=300, deadline=None)
@given(histories)
def test_force_is_continuous_at_delta_max_when_r_eff_changes(h: dict) -> None:
    nu, sy, r_old = h["nu"], h["sy"], h["r_old"]
    r_new = h["ratio"] * r_old
    d_max = h["omega"] * pl.critical_interference(r_old, E_STAR, sy, nu)
    state = _history(d_max, r_old, sy, nu)
    step = 1e-9 * d_max
    below = _law(d_max - step, r_new, sy, nu, state)
    above = _law(d_max + step, r_new, sy, nu, state)
    at = _law(d_max, r_new, sy, nu, state)
    k_h = 0.25 * math.pi * E_STAR
    # F is Lipschitz with constant k_H on both sides: across δ_max it moves by ≤ 2 k_H h
    assert abs(above[0] - below[0]) <= 2.0 * k_h * step * (1.0 + 1e-6) + 1e-12 * at[0]
    assert abs(at[0] - below[0]) <= k_h * step * (1.0 + 1e-6) + 1e-12 * at[0]
    assert above[1] == pytest.approx(below[1], rel=1e-6)
    loading = pl.plastic_loading(d_max, r_new, E_STAR, sy, pl.TABOR_FACTOR * sy, nu)
    assert at[0] == pytest.approx(loading[0], rel=1e-12)
    # the rule before ends the line at the stored F_max: a jump of ≥ 1 % of F wherever both
    # radii differ by 1.5× or more and the history is plastic (ν ≥ 0.2: for small ν the law is
    # Hertz some way beyond yield, where F does not depend on R_eff)
    if nu >= 0.2 and h["omega"] >= 2.0 and abs(math.log(h["ratio"])) >= math.log(1.5):
        jump = abs(_stored_rule_force(d_max - step, state) - above[0])
        assert jump >= 1e-2 * above[0]


@settings(max_examples=200, deadline=None)
@given(histories, st.floats(0.0, 1.0))
# small ν: the loading curve's elastic cap holds F_max at δ_max, so δ_r is 0 up to rounding
# (−4.3e−19 µm here), and the law must not push at δ = 0 (it did, by 1e−21 mN/µm)
@example(
    {"nu": 0.029516155673789575, "sy": 0.2828094160018847, "r_old": 0.5972409853005871,
     "ratio": 2.1471289495132044, "omega": 3.326012315152351},
    0.0,
)  # fmt: skip
# δ → δ_max: the line and the loading curve meet at F(δ_max); they differ there by rounding only
@example({"nu": 0.0, "sy": 1.0, "r_old": 1.0, "ratio": 4.0, "omega": 15.0}, 0.9999999999999999)
def test_force_is_continuous_in_r_eff_below_delta_max(h: dict, fraction: float) -> None:
    nu, sy, r_old = h["nu"], h["sy"], h["r_old"]
    r_new = h["ratio"] * r_old
    d_max = h["omega"] * pl.critical_interference(r_old, E_STAR, sy, nu)
    state = _history(d_max, r_old, sy, nu)
    delta = fraction * d_max
    here = _law(delta, r_new, sy, nu, state)
    there = _law(delta, r_new * (1.0 + 1e-9), sy, nu, state)
    scale = 0.25 * math.pi * E_STAR * d_max
    assert abs(there[0] - here[0]) <= 1e-7 * scale
    # the unloading line lies below the loading curve; they meet at δ_max (equal there up to the
    # rounding of two different expressions: a few ulps of F allowed, nothing at δ = 0)
    loading = pl.plastic_loading(delta, r_new, E_STAR, sy, pl.TABOR_FACTOR * sy, nu)[0]
    assert here[0] <= loading + 4.0 * math.ulp(loading)


@settings(max_examples=200, deadline=None)
@given(histories, st.floats(0.0, 1.0))
# ν = 0: the elastic cap holds F_max, the unclamped δ_r would be −4.3e−19 µm
@example(
    {"nu": 0.0, "sy": 1.0, "r_old": 0.0644762322222609, "ratio": 1.0,
     "omega": 2.4267079445364423},
    0.0,
)  # fmt: skip
def test_same_r_eff_unloads_on_the_stored_line_bit_for_bit(h: dict, fraction: float) -> None:
    nu, sy, r_eff = h["nu"], h["sy"], h["r_old"]
    d_max = h["omega"] * pl.critical_interference(r_eff, E_STAR, sy, nu)
    state = _history(d_max, r_eff, sy, nu)
    # the law's δ_r: clamped at 0 (where the elastic cap holds F_max the difference is rounding)
    residual = max(state[0] - 4.0 * state[1] / (math.pi * E_STAR), 0.0)
    delta = residual + fraction * (d_max - residual)
    force, width, *after = _law(delta, r_eff, sy, nu, state)
    assert tuple(after) == tuple(state)  # (δ_max, F_max, b_max) exactly
    if delta > residual and delta < d_max:
        assert force == 0.25 * math.pi * E_STAR * (delta - residual)
        b = state[2] * math.sqrt((delta - residual) / (d_max - residual))
        assert width == math.sqrt(2.0) * b


@pytest.mark.parametrize("interaction", [False, True], ids=["plain", "interacting"])
def test_single_circle_sliding_keeps_the_stored_line_bit_for_bit(interaction: bool) -> None:
    """A circle (R = 1 µm) slid over a flat while pressed to 0.004 µm (δ_max ≈ 3 δ_c at the
    far end), then at 0.002 µm slid back: it meets the points it pressed below their δ_max
    with the R_eff that pressed them (bit for bit), and every such contact's force is the
    unloading line of the stored F_max, exactly (the law before the rule)."""
    x = np.arange(-400, 401) * 10 * ANGSTROM
    flat, circle = Profile(x, np.zeros_like(x)), Profile(x, circle_cap(x, 1.0))
    law = ElasticPlastic(yield_strength=0.1)
    path = [
        Segment(normal=0.0, tangential=-0.02, steps=2),
        Segment(normal=0.004, tangential=0.02, steps=40),
        Segment(normal=0.002, steps=4),
        Segment(tangential=-0.02, steps=40),
    ]
    result = simulate(
        flat, circle, path=path, law=law, interaction=interaction, e_star=E_STAR, mu0=0.3,
        record_contacts="all", diagnostics=False,
    )  # fmt: skip
    history: dict[int, tuple[np.ndarray, float]] = {}  # point → (stored state, its R_eff)
    met = 0
    for rec in result.contacts:
        for p, delta, r_eff, force in zip(
            rec.point.tolist(), rec.overlap.tolist(), rec.effective_radius.tolist(),
            rec.normal_force.tolist(), strict=True,
        ):  # fmt: skip
            state, made_by = history.get(p, (np.zeros(3), r_eff))
            if delta < state[0]:
                assert r_eff == made_by
                assert force == _stored_rule_force(delta, state)
                met += 1
            else:  # a first loading to δ: the state it stores
                history[p] = (_history(delta, r_eff, law.sy, law.poisson_ratio), r_eff)
    assert met >= 20


@pytest.fixture(scope="module")
def pair() -> tuple[Profile, Profile, float]:
    """Rough on rough (D = 1.5/1.3, seeds 1/2, 4096 points over 0.41 µm) and the approach
    0.1 × the summed peak-to-valley heights [µm]."""
    lower = weierstrass_mandelbrot(1.5, n_points=4096, length=0.41, seed=1)
    upper = weierstrass_mandelbrot(1.3, n_points=4096, length=0.41, seed=2)
    return lower, upper, 0.1 * (lower.peak_to_valley + upper.peak_to_valley)


@pytest.mark.parametrize("interaction", [False, True], ids=["plain", "interacting"])
@pytest.mark.parametrize("control", ["displacement", "force"])
def test_sliding_contacts_obey_the_rule(pair, interaction: bool, control: str) -> None:  # type: ignore[no-untyped-def]
    """Slid 0.05 µm in 10 steps at the δ_N (or the F_N) of 0.1 × the summed peak-to-valley
    heights: every step converges, every contact obeys the rule."""
    lower, upper, top = pair
    kwargs = {"law": LAW, "interaction": interaction, "e_star": E_STAR, "diagnostics": False}
    normal = [Segment(normal=top, steps=10)]
    target = float(simulate(lower, upper, path=normal, **kwargs).normal_force[-1])
    if control == "force":
        path = [*normal, Segment(normal_force=target, tangential=0.05, steps=10)]
    else:
        path = [*normal, Segment(tangential=0.05, steps=10)]
    result = simulate(lower, upper, path=path, mu0=0.3, record_contacts="all", **kwargs)
    assert result.normal_force.size == 21 and np.all(np.isfinite(result.normal_force))
    assert result.tangential_displacement[-1] == 0.05 and result.normal_force[-1] > 0.0
    if control == "force":
        np.testing.assert_allclose(result.normal_force[11:], target, rtol=1e-6)
    d_max: dict[int, tuple[float, float]] = {}  # point → (largest δ so far, its R_eff)
    checked = other_summit = 0
    for rec in result.contacts:
        seen = {}
        for p, delta, r_eff, force in zip(
            rec.point.tolist(), rec.overlap.tolist(), rec.effective_radius.tolist(),
            rec.normal_force.tolist(), strict=True,
        ):  # fmt: skip
            largest, made_by = d_max.get(p, (0.0, r_eff))
            state = np.array([largest, math.nan, math.nan])  # F_max, b_max: not needed
            assert force == _law(delta, r_eff, LAW.sy, LAW.poisson_ratio, state)[0]
            checked += 1
            plastic = largest > pl.critical_interference(made_by, E_STAR, LAW.sy, 0.3)
            other_summit += delta < largest and plastic and abs(r_eff / made_by - 1.0) > 0.01
            seen[p] = (delta, r_eff) if delta >= largest else (largest, made_by)
        d_max.update(seen)
    assert checked > 200
    # the premise: plastic histories met by another R_eff (below their δ_max)
    assert other_summit >= 10


@pytest.mark.parametrize("interaction", [False, True], ids=["plain", "interacting"])
@pytest.mark.parametrize("mu0", [0.0, 0.3])
def test_sliding_cycle_dissipates(pair, interaction: bool, mu0: float) -> None:  # type: ignore[no-untyped-def]
    lower, upper, top = pair
    path = [
        Segment(normal=-0.2 * top, steps=2),
        Segment(normal=top, steps=6),
        Segment(tangential=0.05, steps=8),
        Segment(tangential=0.0, steps=8),
        Segment(normal=-0.2 * top, steps=6),
    ]
    result = simulate(
        lower, upper, path=path, law=LAW, interaction=interaction, e_star=E_STAR, mu0=mu0,
        diagnostics=False,
    )  # fmt: skip
    assert result.normal_force[-1] == 0.0 and result.n_contacts.max() >= 5
    scale = float(np.abs(result.normal_force).max()) * top
    assert driver_work(result, 2, result.displacement.size - 1) >= -1e-9 * scale
    assert np.all(np.diff(result.dissipated_work) >= 0.0)


@pytest.mark.slow
@pytest.mark.parametrize("steps", [10, 40])
def test_cost_figure_pair_slides_to_the_end(steps: int) -> None:
    """The 2·10⁴-point pair of ``docs/accuracy.md`` (S_y = 0.2 GPa): every step converges,
    displacement- and force-controlled."""
    lower = weierstrass_mandelbrot(1.5, n_points=20000, length=2.0, seed=1)
    upper = weierstrass_mandelbrot(1.3, n_points=20000, length=2.0, seed=2)
    top = 0.1 * (lower.peak_to_valley + upper.peak_to_valley)
    normal = [Segment(normal=top, steps=steps)]
    kwargs = {"law": LAW, "interaction": True, "diagnostics": False}
    slid = simulate(lower, upper, path=[*normal, Segment(tangential=0.05, steps=steps)], **kwargs)
    assert slid.tangential_displacement[-1] == 0.05 and np.all(np.isfinite(slid.normal_force))
    target = float(slid.normal_force[steps])
    held = [*normal, Segment(normal_force=target, tangential=0.05, steps=steps)]
    forced = simulate(lower, upper, path=held, **kwargs)
    assert forced.tangential_displacement[-1] == 0.05
    assert np.all(np.isfinite(forced.normal_force))
