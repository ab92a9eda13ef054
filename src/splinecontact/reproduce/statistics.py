"""Statistics of the report of ``splinecontact reproduce``: trend tests and bootstrap intervals.

Is a quantity monotone in the fractal dimension D? :func:`trend_test` and
:func:`trend_from_estimates` combine Spearman's ρ with its exact p-value
(:func:`spearman_pvalue`) and simultaneous intervals of the differences between adjacent D
(:class:`TrendTest`). The spread ratio of finding (b) gets a bootstrap interval
(:func:`bootstrap_means`, ``_spread_ratio``). ``docs/analysis.md`` gives the reasoning.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from ..errors import ParameterError

__all__ = [
    "EXACT_SPEARMAN_MAX",
    "TrendTest",
    "bootstrap_means",
    "spearman_pvalue",
    "trend_from_estimates",
    "trend_test",
]

Verdict = Literal["reproduced", "partly reproduced", "not reproduced", "undetermined"]
TrendShape = Literal["decreasing", "increasing", "not monotone", "no clear trend"]


@dataclass(frozen=True)
class TrendTest:
    """Is a quantity monotone in a parameter? Rank correlation plus adjacent differences.

    Two pieces of evidence, because either alone misleads with a handful of parameter values:

    * Spearman's ρ between the parameter and the group estimates, with its **exact** two-sided
      p-value over the groups (:func:`spearman_pvalue`). A bootstrap interval of ρ is not a test
      of a monotone trend: a U-shape can give ρ < 0 in every resample.
    * The difference between each pair of adjacent groups with a simultaneous (Bonferroni)
      confidence interval: a step is *down* (*up*) when its whole interval lies below (above) 0.

    :attr:`shape` combines them: ``decreasing`` when ρ < 0 is significant (p ≤ ``alpha``) or
    every step is down, and no step is up; ``not monotone`` when some step is down and another
    up; ``no clear trend`` otherwise (symmetrically for ``increasing``).

    Attributes
    ----------
    x : ndarray
        Parameter value of each group (e.g. D).
    means : ndarray
        Estimate of each group (the mean of its realizations for :func:`trend_test`).
    ci_low, ci_high : ndarray
        Confidence interval of each group estimate (contains the estimate).
    counts : ndarray
        Number of realizations behind each estimate.
    rho : float
        Spearman ρ [1] of the group estimates with ``x`` (NaN with fewer than 3 finite groups).
    p_value : float
        Exact two-sided p-value [1] of ρ.
    step_x : ndarray
        (n_steps, 2): the two parameter values of each adjacent pair (finite groups only).
    step_diff, step_low, step_high : ndarray
        Difference (later − earlier) and its simultaneous interval, per adjacent pair.
    step_sign : ndarray
        −1 (down), +1 (up) or 0 (interval contains 0, or not computable) per adjacent pair.
    alpha : float
        Significance level of ρ [1].
    confidence : float
        Level of the group intervals and the family level of the step intervals [1].
    """

    x: NDArray[np.float64]
    means: NDArray[np.float64]
    ci_low: NDArray[np.float64]
    ci_high: NDArray[np.float64]
    counts: NDArray[np.int64]
    rho: float
    p_value: float
    step_x: NDArray[np.float64]
    step_diff: NDArray[np.float64]
    step_low: NDArray[np.float64]
    step_high: NDArray[np.float64]
    step_sign: NDArray[np.int64]
    alpha: float = 0.05
    confidence: float = 0.95
    extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def enough(self) -> bool:
        """At least three groups with an estimate and an interval."""
        ok = np.isfinite(self.means) & np.isfinite(self.ci_low) & np.isfinite(self.ci_high)
        return bool(ok.sum() >= 3 and math.isfinite(self.rho))

    @property
    def shape(self) -> TrendShape:
        """``decreasing``, ``increasing``, ``not monotone`` or ``no clear trend`` (see class)."""
        down = bool((self.step_sign == -1).any())
        up = bool((self.step_sign == 1).any())
        if down and up:
            return "not monotone"
        significant = math.isfinite(self.p_value) and self.p_value <= self.alpha
        every = self.step_sign.size >= 2
        if not up and ((significant and self.rho < 0) or (every and (self.step_sign == -1).all())):
            return "decreasing"
        if not down and ((significant and self.rho > 0) or (every and (self.step_sign == 1).all())):
            return "increasing"
        return "no clear trend"

    @property
    def decreasing(self) -> bool:
        """True if :attr:`shape` is ``decreasing``."""
        return self.shape == "decreasing"

    @property
    def increasing(self) -> bool:
        """True if :attr:`shape` is ``increasing``."""
        return self.shape == "increasing"

    def verdict(self, direction: Literal["decreasing", "increasing"]) -> Verdict:
        """Verdict on the claim "the quantity is monotone ``direction`` in x".

        ``reproduced`` when :attr:`shape` equals ``direction``; ``partly reproduced`` when the
        groups are not monotone but ρ has the claimed sign, or when there is no clear trend
        but some step goes the claimed way and none the other; ``not reproduced`` otherwise;
        ``undetermined`` with fewer than three usable groups.
        """
        if direction not in ("decreasing", "increasing"):
            raise ParameterError(
                f"direction must be 'decreasing' or 'increasing', got {direction!r}"
            )
        if not self.enough:
            return "undetermined"
        sign = -1 if direction == "decreasing" else 1
        shape = self.shape
        if shape == direction:
            return "reproduced"
        along = bool((self.step_sign == sign).any())
        against = bool((self.step_sign == -sign).any())
        rho_along = math.isfinite(self.rho) and self.rho * sign > 0
        if shape == "not monotone":
            return "partly reproduced" if rho_along else "not reproduced"
        if shape == "no clear trend" and along and not against and rho_along:
            return "partly reproduced"
        return "not reproduced"

    def describe(self) -> str:
        """One phrase: the shape, ρ with its exact p, and the significant steps."""
        words = {
            "decreasing": "falls",
            "increasing": "rises",
            "not monotone": "not monotone",
            "no clear trend": "no clear trend",
        }
        text = f"{words[self.shape]} (ρ = {_num(self.rho, 2)}, exact p = {_num(self.p_value, 2)}"
        steps = [
            f"{'↓' if s < 0 else '↑'} {a:g}→{b:g}"
            for (a, b), s in zip(self.step_x, self.step_sign, strict=True)
            if s != 0
        ]
        n = int(self.step_sign.size)
        text += f"; significant steps {len(steps)} of {n}" + (
            f": {', '.join(steps)}" if steps else ""
        )
        return text + ")"


def _num(x: float, digits: int) -> str:
    return f"{x:.{digits}g}" if math.isfinite(x) else "–"


@functools.lru_cache(maxsize=32)
def _spearman_null(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact null distribution of Spearman's ρ for n untied values: (ρ values, probabilities).

    Counts the permutations π by S = Σ i·π(i) with a dynamic programme over subsets (2ⁿ states),
    so n = 12 costs milliseconds where enumerating 12! orders would not finish.
    """
    s_max = sum(i * i for i in range(n))
    dp = np.zeros((1 << n, s_max + 1), dtype=np.float64)
    dp[0, 0] = 1.0
    for mask in range(1 << n):
        row = dp[mask]
        if not row.any():
            continue
        i = mask.bit_count()
        for v in range(n):
            if not (mask >> v) & 1:
                shift = i * v
                dp[mask | (1 << v), shift:] += row[: s_max + 1 - shift]
    counts = dp[-1]
    s = np.arange(s_max + 1, dtype=np.float64)
    sum_d2 = 2.0 * s_max - 2.0 * s
    rho = 1.0 - 6.0 * sum_d2 / (n * (n * n - 1.0))
    keep = counts > 0
    return rho[keep], counts[keep] / counts.sum()


#: Largest number of groups with an exact p-value (above: Student-t approximation).
EXACT_SPEARMAN_MAX = 12


def spearman_pvalue(rho: float, n: int) -> float:
    """Two-sided p-value of Spearman's ρ for n groups without ties.

    Exact for n ≤ :data:`EXACT_SPEARMAN_MAX` (all n! orders, counted by a dynamic programme);
    the Student-t approximation of scipy above. For the handful of parameter values of a study
    the t approximation is far off (it gives p = 0 for ρ = ±1 with n = 3, where the exact value
    is 1/3).
    """
    if not math.isfinite(rho) or n < 3:
        return math.nan
    if n <= EXACT_SPEARMAN_MAX:
        values, probs = _spearman_null(n)
        return float(probs[np.abs(values) >= abs(rho) - 1e-12].sum())
    t = rho * math.sqrt((n - 2) / max(1e-300, 1.0 - rho * rho))
    return float(2 * stats.t.sf(abs(t), n - 2))


def _spearman(x: NDArray[np.float64], y: NDArray[np.float64]) -> float:
    good = np.isfinite(y)
    if good.sum() < 3 or np.ptp(y[good]) == 0 or np.ptp(x[good]) == 0:
        return math.nan
    return float(stats.spearmanr(x[good], y[good]).statistic)


def bootstrap_means(
    groups: Sequence[NDArray[np.float64]], n_boot: int, rng: np.random.Generator
) -> NDArray[np.float64]:
    """Means of ``n_boot`` resamples (with replacement) of every group: shape (n_boot, groups).

    NaN values are left out of the means; an empty group gives NaN.
    """
    out = np.full((n_boot, len(groups)), np.nan)
    for g, v in enumerate(groups):
        if v.size:
            idx = rng.integers(0, v.size, (n_boot, v.size))
            with np.errstate(invalid="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                out[:, g] = np.nanmean(v[idx], axis=1)
    return out


def trend_from_estimates(
    x: ArrayLike,
    estimates: ArrayLike,
    standard_errors: ArrayLike,
    *,
    dof: ArrayLike | None = None,
    counts: ArrayLike | None = None,
    confidence: float = 0.95,
    alpha: float = 0.05,
) -> TrendTest:
    """Trend test (see :class:`TrendTest`) from per-group estimates and standard errors.

    Parameters
    ----------
    x : array_like
        Parameter of each group, increasing.
    estimates : array_like
        Estimate of each group (NaN: no estimate).
    standard_errors : array_like
        Standard error of each estimate [unit of the estimates].
    dof : array_like, optional
        Degrees of freedom of each standard error (n − 1 for a mean): Student-t and Welch
        intervals. Without it (e.g. bootstrap standard errors) normal quantiles are used.
    counts : array_like, optional
        Realizations behind each estimate (reported only).
    confidence : float
        Level of the group intervals, and the family-wise level of the step intervals [1].
    alpha : float
        Significance level of the exact Spearman test [1].

    Returns
    -------
    TrendTest
    """
    if not 0.0 < confidence < 1.0:
        raise ParameterError(f"confidence must lie in (0, 1), got {confidence!r}")
    if not 0.0 < alpha < 1.0:
        raise ParameterError(f"alpha must lie in (0, 1), got {alpha!r}")
    xa = np.asarray(x, dtype=np.float64)
    est = np.asarray(estimates, dtype=np.float64)
    se = np.asarray(standard_errors, dtype=np.float64)
    if not xa.shape == est.shape == se.shape or xa.ndim != 1:
        raise ParameterError(
            f"x, estimates and standard_errors must be 1-D of one length, got shapes "
            f"{xa.shape}, {est.shape}, {se.shape}"
        )
    nu = np.asarray(dof, dtype=np.float64) if dof is not None else np.full(xa.shape, np.inf)
    cnt = (
        np.asarray(counts, dtype=np.int64)
        if counts is not None
        else np.where(np.isfinite(est), 1, 0).astype(np.int64)
    )

    def quantile(level: float, df: NDArray[np.float64]) -> NDArray[np.float64]:
        with np.errstate(invalid="ignore"):
            return np.asarray(
                np.where(
                    np.isinf(df),
                    stats.norm.ppf(level),
                    stats.t.ppf(level, np.where(df > 0, df, np.nan)),
                )
            )

    half = quantile(0.5 + confidence / 2.0, nu) * se
    good = np.flatnonzero(np.isfinite(est))
    rho = _spearman(xa, est)
    p_value = spearman_pvalue(rho, int(good.size))
    a, b = good[:-1], good[1:]
    m = max(1, a.size)
    diff = est[b] - est[a]
    with np.errstate(invalid="ignore", divide="ignore"):
        se_d = np.sqrt(se[a] ** 2 + se[b] ** 2)
        welch = se_d**4 / (se[a] ** 4 / nu[a] + se[b] ** 4 / nu[b])
    welch = np.where(np.isinf(nu[a]) & np.isinf(nu[b]), np.inf, welch)
    half_d = quantile(1.0 - (1.0 - confidence) / (2.0 * m), welch) * se_d
    low, high = diff - half_d, diff + half_d
    sign = np.where(high < 0, -1, np.where(low > 0, 1, 0)).astype(np.int64)
    sign[~np.isfinite(low) | ~np.isfinite(high)] = 0
    return TrendTest(
        x=xa,
        means=est,
        ci_low=est - half,
        ci_high=est + half,
        counts=cnt,
        rho=rho,
        p_value=p_value,
        step_x=np.column_stack([xa[a], xa[b]]) if a.size else np.empty((0, 2)),
        step_diff=diff,
        step_low=low,
        step_high=high,
        step_sign=sign,
        alpha=alpha,
        confidence=confidence,
    )


def trend_test(
    x: ArrayLike,
    groups: Sequence[ArrayLike],
    *,
    confidence: float = 0.95,
    alpha: float = 0.05,
) -> TrendTest:
    """Does the group mean rise or fall monotonically with ``x``?

    Group means with Student-t intervals, adjacent differences with simultaneous Welch
    intervals (Bonferroni over the adjacent pairs), and Spearman's ρ of the means with its
    exact p-value; see :class:`TrendTest` for how they are combined.

    Parameters
    ----------
    x : array_like
        Parameter of each group, increasing (at least 3 groups for a verdict).
    groups : sequence of array_like
        Per-realization values of each group (NaN are dropped).
    confidence : float
        Level of the intervals [1].
    alpha : float
        Significance level of the exact Spearman test [1].

    Returns
    -------
    TrendTest
    """
    xa = np.asarray(x, dtype=np.float64)
    vals = [np.asarray(g, dtype=np.float64).ravel() for g in groups]
    vals = [v[np.isfinite(v)] for v in vals]
    if xa.size != len(vals):
        raise ParameterError(f"x has {xa.size} values but there are {len(vals)} groups")
    counts = np.array([v.size for v in vals], dtype=np.int64)
    means = np.array([v.mean() if v.size else np.nan for v in vals])
    stds = np.array([v.std(ddof=1) if v.size >= 2 else np.nan for v in vals])
    with np.errstate(invalid="ignore", divide="ignore"):
        se = stds / np.sqrt(counts)
    return trend_from_estimates(
        xa,
        means,
        se,
        dof=np.where(counts >= 2, counts - 1.0, np.nan),
        counts=counts,
        confidence=confidence,
        alpha=alpha,
    )


# --- bootstrap of the spread across D (finding (b)) ------------------------------------------


def _spread(logk: np.ndarray) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.asarray(np.nanstd(logk, axis=-1, ddof=1))


def _log10_pos(a: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.log10(np.where(a > 0, a, np.nan))


def _ratio_interval(
    ratio: float, boots: np.ndarray, confidence: float = 0.95
) -> tuple[float, float]:
    """Normal bootstrap interval of a positive ratio on the log scale (it contains the ratio)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        logs = np.log(boots[np.isfinite(boots) & (boots > 0)])
    if logs.size < 2 or not (math.isfinite(ratio) and ratio > 0):
        return math.nan, math.nan
    half = float(stats.norm.ppf(0.5 + confidence / 2)) * float(logs.std(ddof=1))
    return ratio * math.exp(-half), ratio * math.exp(half)


def _spread_ratio(
    low: Sequence[np.ndarray], high: Sequence[np.ndarray], seed: int, n_boot: int = 1000
) -> tuple[float, float, float]:
    """Ratio of the spread across D of log10(mean k) at high vs low load, bootstrap interval.

    ``low[g]`` and ``high[g]`` hold the same realizations of group g (NaN where a realization
    does not reach the load); the resamples draw the same realizations at both loads.
    """

    def nanmean(a: np.ndarray) -> float:
        return float(np.nanmean(a)) if np.isfinite(a).any() else math.nan

    m_lo = np.array([nanmean(g) for g in low])
    m_hi = np.array([nanmean(g) for g in high])
    s_lo, s_hi = float(_spread(_log10_pos(m_lo))), float(_spread(_log10_pos(m_hi)))
    ratio = s_hi / s_lo if s_lo > 0 else math.nan
    rng = np.random.default_rng(seed)
    b_lo = np.full((n_boot, len(low)), np.nan)
    b_hi = np.full((n_boot, len(low)), np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for g, (a, b) in enumerate(zip(low, high, strict=True)):
            if a.size:
                idx = rng.integers(0, a.size, (n_boot, a.size))
                b_lo[:, g] = np.nanmean(a[idx], axis=1)
                b_hi[:, g] = np.nanmean(b[idx], axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            boots = _spread(_log10_pos(b_hi)) / _spread(_log10_pos(b_lo))
    lo, hi = _ratio_interval(ratio, boots)
    return ratio, lo, hi
