"""Tests of splinecontact.reproduce.statistics: the trend tests and exact Spearman p-values."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from splinecontact.errors import ParameterError
from splinecontact.reproduce import statistics


def test_trend_test_detects_a_clear_decrease() -> None:
    rng = np.random.default_rng(1)
    x = np.array([1.1, 1.3, 1.5, 1.7, 1.9])
    groups = [10 - 3 * xi + 0.1 * rng.standard_normal(20) for xi in x]
    t = statistics.trend_test(x, groups)
    assert t.rho == pytest.approx(-1.0)
    assert t.decreasing and not t.increasing
    assert (t.counts == 20).all()
    assert (t.ci_low < t.means).all() and (t.ci_high > t.means).all()


def test_trend_test_no_trend_is_not_called_one() -> None:
    rng = np.random.default_rng(2)
    x = np.arange(6.0)
    groups = [rng.standard_normal(5) for _ in x]
    t = statistics.trend_test(x, groups)
    assert t.shape == "no clear trend"
    assert t.verdict("decreasing") == "not reproduced"
    assert not t.decreasing and not t.increasing


def test_spearman_pvalue_exact_small_n() -> None:
    assert statistics.spearman_pvalue(1.0, 3) == pytest.approx(2 / 6)
    assert statistics.spearman_pvalue(-1.0, 5) == pytest.approx(2 / 120)
    assert statistics.spearman_pvalue(0.0, 4) == pytest.approx(1.0)
    # beyond the exact range: the t approximation, as scipy
    x = np.arange(14.0)
    y = np.array([1, 3, 2, 5, 4, 7, 6, 9, 8, 12, 10, 11.0, 14, 13])
    res = stats.spearmanr(x, y)
    assert statistics.spearman_pvalue(res.statistic, 14) == pytest.approx(res.pvalue, rel=1e-6)
    assert math.isnan(statistics.spearman_pvalue(0.5, 2))


@pytest.mark.parametrize("n", [3, 4, 5, 6, 7])
def test_spearman_pvalue_equals_enumeration_of_all_orders(n: int) -> None:
    perms = np.array(list(itertools.permutations(range(n))), dtype=float)
    null = 1.0 - 6.0 * ((perms - np.arange(n)) ** 2).sum(axis=1) / (n * (n * n - 1.0))
    for rho in np.unique(np.round(null, 12)):
        expected = float(np.mean(np.abs(null) >= abs(rho) - 1e-12))
        assert statistics.spearman_pvalue(float(rho), n) == pytest.approx(expected, abs=1e-12)


def test_spearman_pvalue_exact_up_to_twelve_groups() -> None:
    # ρ = −1 happens for one order of n!, two-sided: 2/n!
    assert statistics.spearman_pvalue(-1.0, 10) == pytest.approx(2 / math.factorial(10))
    assert statistics.spearman_pvalue(1.0, 12) == pytest.approx(2 / math.factorial(12))


def test_u_shape_is_not_monotone_and_never_reproduced() -> None:
    """The rough-on-rough A_S of the quick study: 0.069 → 0.030 → 0.042 µm, tight intervals."""
    rng = np.random.default_rng(3)
    x = np.array([1.2, 1.5, 1.8])
    groups = [m + 0.003 * rng.standard_normal(20) for m in (0.069, 0.030, 0.042)]
    t = statistics.trend_test(x, groups)
    assert t.rho == pytest.approx(-0.5)
    assert t.p_value == pytest.approx(1.0)
    assert t.shape == "not monotone"
    assert list(t.step_sign) == [-1, 1]
    assert t.verdict("decreasing") == "partly reproduced"
    assert t.verdict("increasing") == "not reproduced"


def test_clean_monotone_fall_is_reproduced_with_three_groups() -> None:
    rng = np.random.default_rng(4)
    x = np.array([1.2, 1.5, 1.8])
    groups = [m + 0.003 * rng.standard_normal(20) for m in (0.069, 0.050, 0.030)]
    t = statistics.trend_test(x, groups)
    # exact p of ρ = −1 over 3 groups is 1/3: the adjacent steps carry the evidence
    assert t.p_value == pytest.approx(1 / 3)
    assert t.shape == "decreasing"
    assert t.verdict("decreasing") == "reproduced"
    assert t.verdict("increasing") == "not reproduced"


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(4, 9),
    data=st.data(),
    noise=st.floats(1e-4, 1e-2),
)
def test_trend_verdicts_property(n: int, data: st.DataObject, noise: float) -> None:
    """A strict monotone fall is reproduced; any V shape with clear arms never is."""
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    x = np.linspace(1.0, 1.9, n)
    falling = np.cumsum(np.full(n, -1.0)) + 10.0
    groups = [m + noise * rng.standard_normal(15) for m in falling]
    assert statistics.trend_test(x, groups).verdict("decreasing") == "reproduced"
    vertex = data.draw(st.integers(1, n - 2))
    v = np.abs(np.arange(n) - vertex).astype(float) + 1.0
    groups = [m + noise * rng.standard_normal(15) for m in v]
    t = statistics.trend_test(x, groups)
    assert t.shape == "not monotone"
    assert t.verdict("decreasing") != "reproduced"
    assert t.verdict("increasing") != "reproduced"


def test_intervals_contain_their_estimates() -> None:
    rng = np.random.default_rng(5)
    t = statistics.trend_from_estimates(
        np.arange(5.0), rng.normal(size=5), rng.uniform(0.1, 1.0, 5)
    )
    assert (t.ci_low <= t.means).all() and (t.means <= t.ci_high).all()
    assert (t.step_low <= t.step_diff).all() and (t.step_diff <= t.step_high).all()
    with pytest.raises(ParameterError, match="direction"):
        t.verdict("up")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="shapes"):
        statistics.trend_from_estimates([1.0, 2.0], [1.0], [1.0])
