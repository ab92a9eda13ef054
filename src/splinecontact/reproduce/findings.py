"""The paper's findings (a)–(e), each checked on a study Dataset with a verdict and its numbers.

(a) at a given displacement F_N falls as D rises;
(b) at a given load the stiffness falls as D rises, and the curves converge at higher load;
(c) A_S grows near-linearly with F_N, and is lower for higher D;
(d) κ lies between the Persson and Bush values for D ≤ 1.6 and rises beyond;
(e) rough-on-rough and rough-on-flat κ agree.

The statistical tests are in :mod:`splinecontact.reproduce.statistics` and ``docs/analysis.md``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr
from scipy import stats

from .. import analysis
from ..errors import AnalysisError
from ._format import _TREND_HEADER, _fmt, _means_table, _steps_table, _trend_row
from .statistics import (
    _log10_pos,
    _ratio_interval,
    _spread,
    _spread_ratio,
    trend_from_estimates,
    trend_test,
)

__all__ = [
    "KAPPA_AGREEMENT_TOLERANCE",
    "LINEAR_EXPONENT_RANGE",
    "LOAD_QUANTILE",
    "VERDICTS",
    "Finding",
    "evaluate_findings",
]

#: Tolerance of finding (e): relative difference of mean κ, rough-on-rough vs rough-on-flat.
KAPPA_AGREEMENT_TOLERANCE = 0.2
#: Range of the power-law exponent of A_S(F_N) called "near-linear" in finding (c).
LINEAR_EXPONENT_RANGE = (0.8, 1.2)
#: The four verdicts, best first.
VERDICTS: tuple[str, ...] = ("reproduced", "partly reproduced", "not reproduced", "undetermined")

# --- findings ---------------------------------------------------------------------------------


@dataclass
class Finding:
    """One finding of the paper and what this study says about it.

    Attributes
    ----------
    key : str
        ``"a"`` … ``"e"``.
    claim : str
        The paper's statement.
    verdict : str
        ``reproduced``, ``partly reproduced``, ``not reproduced`` or ``undetermined``.
    summary : str
        One sentence with the decisive numbers.
    test : str
        How the verdict was decided.
    tables : list of (str, list of str, list of list of str)
        (caption, header, rows) tables of numbers.
    figures : list of str
        Figure base names behind the finding.
    numbers : dict
        The key numbers, machine-readable.
    """

    key: str
    claim: str
    verdict: str = "undetermined"
    summary: str = ""
    test: str = ""
    tables: list[tuple[str, list[str], list[list[str]]]] = field(default_factory=list)
    figures: list[str] = field(default_factory=list)
    numbers: dict[str, Any] = field(default_factory=dict)


def _groups(values: xr.DataArray) -> tuple[np.ndarray, list[np.ndarray]]:
    """Per-D lists of per-realization values of a (dimension, realization) array."""
    d = values["dimension"].values.astype(float)
    return d, [values.isel(dimension=i).values for i in range(d.size)]


def _overall(verdicts: Sequence[str]) -> str:
    """Verdict of a finding made of parts: all reproduced → reproduced, none → not."""
    vs = list(verdicts)
    if not vs or any(v == "undetermined" for v in vs):
        return "undetermined"
    if all(v == "reproduced" for v in vs):
        return "reproduced"
    if all(v == "not reproduced" for v in vs):
        return "not reproduced"
    return "partly reproduced"


def _share_verdict(flags: Sequence[bool]) -> str:
    if not flags:
        return "undetermined"
    if all(flags):
        return "reproduced"
    return "partly reproduced" if any(flags) else "not reproduced"


def _contact_types(ds: xr.Dataset) -> list[str]:
    if "contact_type" in ds.dims:
        return [str(c) for c in ds["contact_type"].values]
    return [str(ds.attrs.get("contact_type", "rough-on-rough"))]


def _select(ds: xr.Dataset, ctype: str) -> xr.Dataset:
    return ds.sel(contact_type=ctype) if "contact_type" in ds.dims else ds


#: Quantile of the realizations' final loads that sets the load range of findings (b), (c) and
#: of the load-based figures: final loads scatter by 100× within one D, so the smallest would let
#: one realization decide; at F_c at least 75 % of every D's realizations contribute.
LOAD_QUANTILE = 0.25


def _common_end(ds: xr.Dataset, variable: str, quantile: float = 0.0) -> float:
    """Smallest (over D) ``quantile`` of the last value of ``variable`` over the realizations."""
    last = ds[variable].isel(step=-1).where(analysis.ok_mask(ds))
    per_d = last.quantile(quantile, dim="realization", skipna=True)
    return float(per_d.min(skipna=True))


def _combine(f: Finding, verdicts: Sequence[tuple[str, str, str]], what: str) -> None:
    """Overall verdict from per-contact-type (ctype, verdict, why): the first type decides."""
    f.verdict = verdicts[0][1] if verdicts else "undetermined"
    parts = [f"{ctype}: {v}" + (f" ({why})" if why else "") for ctype, v, why in verdicts]
    f.summary = f"{what} — " + "; ".join(parts) + "."


_TREND_TEST_TEXT = (
    "Trend test: Spearman's ρ between D and the per-D estimates with its exact two-sided "
    "p-value (all orders of the D values), and the difference between every pair of adjacent D "
    "with a simultaneous 95 % interval (Welch, Bonferroni over the pairs). A step is ↓ (↑) when "
    "its whole interval lies below (above) 0. The quantity falls when ρ < 0 with p ≤ 0.05 or "
    "every step is ↓, and no step is ↑; it is not monotone when some step is ↓ and another ↑. "
    "Verdict on a claimed fall: reproduced if it falls; partly if it is not monotone with ρ < 0, "
    "or if some step is ↓, none ↑ and ρ < 0; not reproduced otherwise."
)


def _finding_a(ds: xr.Dataset, seed: int) -> Finding:
    f = Finding(
        "a",
        "At a given displacement F_N falls as D rises (Fig. 10a).",
        test=(
            "At three displacements (25 %, 50 %, 100 % of δ_c, the largest displacement reached "
            "by every realization of every D), the trend test on the per-realization F_N. "
            "Reproduced when F_N falls at all three, not reproduced when at none. "
            + _TREND_TEST_TEXT
        ),
        figures=["fig10"],
    )
    verdicts = []
    for ctype in _contact_types(ds):
        sub = _select(ds, ctype)
        delta_c = _common_end(sub, "displacement")
        tests = {}
        for frac in (0.25, 0.5, 1.0):
            v = analysis.values_at(sub, "displacement", "normal_force", frac * delta_c * 0.999)
            tests[f"δ_N = {_fmt(frac * delta_c * 1000)} nm"] = trend_test(*_groups(v))
        rows = [[name, *_trend_row(t)] for name, t in tests.items()]
        f.tables.append((f"{ctype}: trend of mean F_N with D", ["at", *_TREND_HEADER], rows))
        f.tables.append(_means_table(f"{ctype}: mean F_N [95 % CI] per D", tests, "mN/µm"))
        per = [t.verdict("decreasing") for t in tests.values()]
        verdict = _overall(per)
        why = (
            ", ".join(f"{k}: {t.shape}" for k, t in tests.items())
            if verdict != "reproduced"
            else ""
        )
        verdicts.append((ctype, verdict, why))
        f.numbers[ctype] = {
            k: {
                "rho": t.rho,
                "p_exact": t.p_value,
                "shape": t.shape,
                "verdict": t.verdict("decreasing"),
                "means": t.means.tolist(),
                "steps": t.step_sign.tolist(),
            }
            for k, t in tests.items()
        }
    _combine(f, verdicts, "F_N decreases with D at every tested displacement")
    return f


def _converges_verdict(hi: float) -> str:
    return "reproduced" if math.isfinite(hi) and hi < 1 else "not reproduced"


def _finding_b(ds: xr.Dataset, seed: int) -> Finding:
    f = Finding(
        "b",
        "At a given load the stiffness falls as D rises, and the curves converge at higher "
        "load (Fig. 11a).",
        test=(
            "Two stiffness estimators. (1) The paper's: the realizations' F_N(δ_N) curves are "
            "averaged per D (the paper averages its results over the realizations and Fig. 11a "
            "shows the averaged curves), and k̄ = dF̄_N/dδ_N is the Savitzky–Golay derivative "
            "of the mean curve, read at a load on the mean curve; its uncertainty is a "
            "bootstrap over realizations (k̄ ± 1.96 SE). (2) Per realization: k = dF_N/dδ_N of "
            "each realization at the load, averaged (Student-t interval). Loads: 0.1 F_c (low) "
            "and F_c (high), F_c = the smallest over D of the lower quartile of the final loads "
            "and of the end of the mean curve. Falls: the trend test on k/E* at the low load. "
            "Converges: the spread across D of log10 k (standard deviation) at the high load "
            "divided by that at the low load, with a 95 % bootstrap interval (log scale, the "
            "same resamples at both loads); converges when the whole interval is below 1. The "
            "verdict uses the paper's estimator (1); (2) is shown beside it. " + _TREND_TEST_TEXT
        ),
        figures=["fig11"],
    )
    verdicts = []
    for ctype in _contact_types(ds):
        sub = _select(ds, ctype)
        e_star = float(analysis.parameter(sub, "e_star"))
        e_l = e_star * float(analysis.parameter(sub, "length"))
        x_d = sub["dimension"].values.astype(float)
        plain = analysis.mean_curve_stiffness(sub, n_boot=0)
        f_end = float(plain["normal_force"].max("sample").min())
        f_c = min(_common_end(sub, "normal_force", LOAD_QUANTILE), f_end * 0.999)
        loads = np.array([0.1 * f_c, f_c])
        labels = [f"F_N/(E* L0) = {_fmt(load / e_l)}" for load in loads]
        mc = analysis.mean_curve_stiffness(sub, loads=loads, n_boot=1000, seed=seed)
        est = mc["stiffness_at_load"].transpose("dimension", "load").values / e_star
        se = mc["stiffness_at_load_se"].transpose("dimension", "load").values / e_star
        cnt = mc["count"].values
        paper = {
            f"{lab} (mean curve)": trend_from_estimates(x_d, est[:, j], se[:, j], counts=cnt)
            for j, lab in enumerate(labels)
        }
        boot = mc["stiffness_at_load_boot"].transpose("boot", "dimension", "load").values
        s_lo = float(_spread(_log10_pos(est[:, 0])))
        s_hi = float(_spread(_log10_pos(est[:, 1])))
        ratio_p = s_hi / s_lo if s_lo > 0 else math.nan
        with np.errstate(invalid="ignore", divide="ignore"):
            boots = _spread(_log10_pos(boot[:, :, 1])) / _spread(_log10_pos(boot[:, :, 0]))
        lo_p, hi_p = _ratio_interval(ratio_p, boots)

        k = (analysis.stiffness(sub) / e_star).assign_attrs(units="1")
        per_real = {}
        raw = []
        for lab, load in zip(labels, loads, strict=True):
            v = analysis.values_at(sub, "normal_force", k, float(load))
            groups = _groups(v)
            raw.append(groups[1])
            per_real[f"{lab} (per realization)"] = trend_test(*groups)
        ratio_r, lo_r, hi_r = _spread_ratio(raw[0], raw[1], seed)

        rows = [[name, *_trend_row(t)] for name, t in {**paper, **per_real}.items()]
        f.tables.append((f"{ctype}: trend of k/E* with D", ["at", *_TREND_HEADER], rows))
        f.tables.append(_means_table(f"{ctype}: k/E* [95 % CI] per D", {**paper, **per_real}, "1"))
        # per estimator (key, table name): its trend at the low load, the spread ratio and CI
        numbers: dict[str, Any] = {}
        conv_rows = []
        for key, name, t, ratio, lo, hi in (
            ("mean_curve", "mean curve (paper)", next(iter(paper.values())), ratio_p, lo_p, hi_p),
            ("per_realization", "per realization", next(iter(per_real.values())), ratio_r, lo_r,
             hi_r),
        ):  # fmt: skip
            falls, conv = t.verdict("decreasing"), _converges_verdict(hi)
            numbers[key] = {
                "rho_low_load": t.rho,
                "p_exact": t.p_value,
                "shape_low_load": t.shape,
                "spread_ratio": ratio,
                "spread_ratio_ci": [lo, hi],
                "falls": falls,
                "converges": conv,
            }
            conv_rows.append(
                [
                    name,
                    _fmt(ratio),
                    f"[{_fmt(lo)}, {_fmt(hi)}]",
                    "yes" if conv == "reproduced" else "no",
                ]
            )
        f.tables.append(
            (
                f"{ctype}: convergence (spread of log10 k across D, high load / low load)",
                ["estimator", "ratio", "95 % CI", "converges"],
                conv_rows,
            )
        )
        falls_p, conv_p = numbers["mean_curve"]["falls"], numbers["mean_curve"]["converges"]
        falls_r, conv_r = (
            numbers["per_realization"]["falls"],
            numbers["per_realization"]["converges"],
        )
        verdict = _overall([falls_p, conv_p])
        v_r = _overall([falls_r, conv_r])
        why = (
            f"mean curve: falls at low load {falls_p}, converges {conv_p}; per-realization "
            f"estimator: {v_r} (falls {falls_r}, converges {conv_r})"
        )
        verdicts.append((ctype, verdict, why))
        f.numbers[ctype] = {
            "estimator_for_verdict": "ensemble-mean curve (paper, Fig. 11a)",
            **numbers,
        }
    _combine(f, verdicts, "stiffness falls with D at low load and the spread shrinks at high load")
    return f


def _finding_c(ds: xr.Dataset, seed: int) -> Finding:
    lo_m, hi_m = LINEAR_EXPONENT_RANGE
    f = Finding(
        "c",
        "A_S grows near-linearly with F_N, and is lower for higher D (Fig. 11b).",
        test=(
            "Near-linear: the exponent m of a power-law fit A_S ∝ F_N^m to the ensemble-mean "
            "curve of each D over 10–100 % of its common load range lies in "
            f"[{lo_m}, {hi_m}] — reproduced for every D, partly for some. Lower for higher D: "
            "the trend test on the per-realization A_S at the load F_c/2 (F_c as in (b)). "
            "Reproduced when both parts are. " + _TREND_TEST_TEXT
        ),
        figures=["fig11"],
    )
    verdicts = []
    for ctype in _contact_types(ds):
        sub = _select(ds, ctype)
        ens = analysis.ensemble_vs_force(sub, ["contact_area"])
        rows = []
        exps = []
        for i, d in enumerate(ens["dimension"].values):
            e = ens.isel(dimension=i)
            fgrid = e["normal_force"].values
            sel = fgrid >= 0.1 * fgrid[-1]
            m = analysis.power_law_exponent(fgrid[sel], e["contact_area_mean"].values[sel])
            exps.append(m)
            rows.append([f"{float(d):g}", _fmt(m)])
        f_c = _common_end(sub, "normal_force", LOAD_QUANTILE)
        v = analysis.values_at(sub, "normal_force", "contact_area", 0.5 * f_c)
        t = trend_test(*_groups(v))
        linear = _share_verdict([bool(lo_m <= m <= hi_m) for m in exps])
        lower = t.verdict("decreasing")
        f.tables.append((f"{ctype}: exponent m of A_S ∝ F_N^m", ["D", "m"], rows))
        f.tables.append(
            _means_table(
                f"{ctype}: mean A_S at F_N = {_fmt(0.5 * f_c)} mN/µm [95 % CI]",
                {"A_S": t},
                "µm",
            )
        )
        f.tables.append((f"{ctype}: trend of A_S with D", _TREND_HEADER, [_trend_row(t)]))
        f.tables.append(_steps_table(f"{ctype}: A_S between adjacent D", t, "µm"))
        verdicts.append(
            (
                ctype,
                _overall([linear, lower]),
                f"near-linear {linear}; lower for higher D: {t.describe()}",
            )
        )
        f.numbers[ctype] = {
            "exponents": exps,
            "rho": t.rho,
            "p_exact": t.p_value,
            "shape": t.shape,
            "linear": linear,
            "lower_for_higher_d": lower,
            "steps": t.step_sign.tolist(),
        }
    _combine(f, verdicts, "A_S ∝ F_N^m with m near 1, and A_S at a given load falls with D")
    return f


def _finding_d(kap: xr.Dataset, seed: int) -> Finding:
    f = Finding(
        "d",
        "κ lies between the Persson (√(8/π) = 1.596) and Bush (√(2π) = 2.507) values for "
        "D ≤ 1.6 and rises beyond (Fig. 12).",
        test=(
            "Between: the mean κ of every D ≤ 1.6 lies within [1.596, 2.507] — reproduced for "
            "every such D, partly for some. Rises beyond: the trend test (for a rise) on the "
            "per-realization κ over D ≥ 1.6 (needs at least three such D). Reproduced when both "
            "parts are. " + _TREND_TEST_TEXT
        ),
        figures=["fig12_kappa"],
    )
    verdicts = []
    for ctype in (
        [str(c) for c in kap["contact_type"].values] if "contact_type" in kap.dims else ["study"]
    ):
        sub = kap.sel(contact_type=ctype) if "contact_type" in kap.dims else kap
        d = sub["dimension"].values.astype(float)
        mean = sub["kappa_mean"].values
        low_d = d <= 1.6 + 1e-9
        inside = [bool(analysis.PERSSON_KAPPA <= m <= analysis.BUSH_KAPPA) for m in mean[low_d]]
        high = sub.isel(dimension=np.flatnonzero(d >= 1.6 - 1e-9))
        t = trend_test(*_groups(high["kappa"]))
        rows = [
            [
                f"{di:g}",
                f"{2 - di:.2g}",
                f"{_fmt(m, 4)} [{_fmt(lo)}, {_fmt(hi)}]",
                "yes" if analysis.PERSSON_KAPPA <= m <= analysis.BUSH_KAPPA else "no",
                "yes" if hi >= analysis.PERSSON_KAPPA and lo <= analysis.BUSH_KAPPA else "no",
            ]
            for di, m, lo, hi in zip(
                d, mean, sub["kappa_ci_low"].values, sub["kappa_ci_high"].values, strict=True
            )
        ]
        f.tables.append(
            (
                f"{ctype}: κ per D",
                ["D", "H = 2 − D", "mean κ [95 % CI]", "mean in band", "CI overlaps band"],
                rows,
            )
        )
        f.tables.append((f"{ctype}: trend of κ over D ≥ 1.6", _TREND_HEADER, [_trend_row(t)]))
        between = _share_verdict(inside)
        rises = t.verdict("increasing")
        verdicts.append(
            (
                ctype,
                _overall([between, rises]),
                f"{sum(inside)}/{len(inside)} D ≤ 1.6 in the band; beyond 1.6: {t.describe()}",
            )
        )
        f.numbers[ctype] = {
            "kappa_mean": mean.tolist(),
            "dimension": d.tolist(),
            "in_band_d_le_1_6": f"{sum(inside)}/{len(inside)}",
            "between": between,
            "rises": rises,
            "rises_rho": t.rho,
            "rises_p_exact": t.p_value,
            "rises_shape": t.shape,
        }
    _combine(f, verdicts, "κ within [Persson, Bush] for D ≤ 1.6 and rising beyond")
    return f


def _finding_e(kap: xr.Dataset, tolerance: float) -> Finding:
    f = Finding(
        "e",
        "Rough-on-rough and rough-on-flat κ agree (Fig. 12).",
        test=(
            "For every D the relative difference of the mean κ, (κ_rr − κ_rf)/κ_rf, with its "
            "95 % Welch interval; they agree at a D when the relative difference lies within "
            f"±{tolerance:.0%}. Reproduced when they agree at every D, partly when at some."
        ),
        figures=["fig12_kappa"],
    )
    if "contact_type" not in kap.dims or kap.sizes["contact_type"] < 2:
        f.summary = "Needs both contact types in the study."
        return f
    rr = kap.sel(contact_type="rough-on-rough")
    rf = kap.sel(contact_type="rough-on-flat")
    rows = []
    agree = []
    rel_all = []
    for i, d in enumerate(kap["dimension"].values.astype(float)):
        a = rr["kappa"].isel(dimension=i).values
        b = rf["kappa"].isel(dimension=i).values
        a, b = a[np.isfinite(a)], b[np.isfinite(b)]
        if a.size < 2 or b.size < 2 or b.mean() == 0:
            rows.append([f"{d:g}", "–", "–", "–", "–"])
            continue
        diff = a.mean() - b.mean()
        va, vb = a.var(ddof=1) / a.size, b.var(ddof=1) / b.size
        se = math.sqrt(va + vb)
        dof = (va + vb) ** 2 / (va**2 / (a.size - 1) + vb**2 / (b.size - 1)) if se > 0 else 1.0
        half = float(stats.t.ppf(0.975, dof)) * se
        rel = diff / b.mean()
        ok = abs(rel) <= tolerance
        agree.append(ok)
        rel_all.append(rel)
        rows.append(
            [
                f"{d:g}",
                _fmt(a.mean()),
                _fmt(b.mean()),
                f"{rel:+.0%} [{(diff - half) / b.mean():+.0%}, {(diff + half) / b.mean():+.0%}]",
                "yes" if ok else "no",
            ]
        )
    f.tables.append(
        (
            "κ rough-on-rough vs rough-on-flat",
            ["D", "κ_rr", "κ_rf", "relative difference [95 % CI]", "agree"],
            rows,
        )
    )
    f.numbers = {"relative_difference": rel_all, "agree": agree}
    if len(agree) < 1:
        f.verdict = "undetermined"
    elif all(agree):
        f.verdict = "reproduced"
    elif any(agree):
        f.verdict = "partly reproduced"
    else:
        f.verdict = "not reproduced"
    f.summary = f"κ agrees within ±{tolerance:.0%} at {sum(agree)} of {len(agree)} D values."
    return f


def evaluate_findings(
    ds: xr.Dataset,
    *,
    kappa_options: Mapping[str, Any] | None = None,
    seed: int = 0,
    tolerance: float = KAPPA_AGREEMENT_TOLERANCE,
) -> list[Finding]:
    """Check the paper's findings (a)–(e) on a study Dataset (see the module docstring).

    Parameters
    ----------
    ds : xarray.Dataset
        Study with a ``dimension`` grid dimension (and ``contact_type`` for (e)). Any further
        swept parameter is fixed at its first value.
    kappa_options : mapping, optional
        Options of :func:`splinecontact.analysis.kappa` (R_Sq source and method, fit range).
    seed : int
        Seed of the bootstrap resampling.
    tolerance : float
        Relative tolerance [1] of finding (e).

    Returns
    -------
    list of Finding
    """
    if "dimension" not in ds.dims:
        raise AnalysisError(
            "the findings compare fractal dimensions: the study must sweep 'dimension'"
        )
    others = [d for d in analysis.grid_dims(ds) if d not in ("dimension", "contact_type")]
    if others:
        ds = ds.isel(dict.fromkeys(others, 0))
    kap = analysis.kappa(ds, **dict(kappa_options or {}))
    return [
        _finding_a(ds, seed),
        _finding_b(ds, seed),
        _finding_c(ds, seed),
        _finding_d(kap, seed),
        _finding_e(kap, tolerance),
    ]
