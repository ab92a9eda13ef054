"""``report.md`` of ``splinecontact reproduce``: the run, each finding with its verdict, numbers
and figures, the choices behind κ, diagnostics of the method and the Hurst exponents."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import xarray as xr

from .. import analysis
from ..analysis._defaults import DEFAULT_FIT_FRACTION, DEFAULT_RSQ_METHOD, DEFAULT_RSQ_SOURCE
from ._format import _fmt, _table
from .findings import Finding, _contact_types, _select

__all__ = ["write_report"]

_BADGE = {
    "reproduced": "✅ reproduced",
    "partly reproduced": "🟡 partly reproduced",
    "not reproduced": "❌ not reproduced",
    "undetermined": "⚪ undetermined",
}


def _figure_links(names: Sequence[str], figures: Mapping[str, Sequence[Path]], root: Path) -> str:
    out = []
    for name in names:
        for key, paths in figures.items():
            if key == name or key.startswith(name + "_"):
                png = [p for p in paths if p.suffix == ".png"]
                if png:
                    rel = png[0].relative_to(root).as_posix()
                    out.append(f"![{key}]({rel})")
    return "\n\n".join(out)


def write_report(
    path: str | Path,
    ds: xr.Dataset,
    findings: Sequence[Finding],
    figures: Mapping[str, Sequence[Path]],
    *,
    command: str = "",
    wall_time: float | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    hurst: xr.Dataset | None = None,
    root: str | Path | None = None,
) -> Path:
    """Write ``report.md``: run description, each finding with verdict, numbers and figure.

    Figures are linked relative to ``root`` (default: the report's folder).
    """
    path = Path(path)
    root = Path(root) if root is not None else path.parent
    opts = {
        "fit_fraction": DEFAULT_FIT_FRACTION,
        "rsq_source": DEFAULT_RSQ_SOURCE,
        "rsq_method": DEFAULT_RSQ_METHOD,
        **dict(kappa_options or {}),
    }
    status = ds["status"].values
    lines = ["# Reproducing Hanaor, Gan & Einav (2015), Section 3", ""]
    if command:
        lines += [f"Command: `{command}`", ""]
    run = [
        f"study `{ds.attrs.get('study_name', '?')}`, seed {ds.attrs.get('study_seed', '?')}",
        f"{int((status == 1).sum())} successful, {int((status == 2).sum())} failed, "
        f"{int((status == 0).sum())} not run realizations",
        "grid: "
        + ", ".join(
            f"{d} = {', '.join(str(v) for v in ds[d].values)}" for d in analysis.grid_dims(ds)
        ),
        f"{ds.sizes['realization']} realizations per grid point, "
        f"{ds.attrs.get('n_points', '?')} points over {ds.attrs.get('length', '?')} µm, "
        f"{ds.sizes['step'] - 1} steps, E* = {ds.attrs.get('e_star', '?')} GPa, "
        f"α = {ds.attrs.get('alpha', '?')}",
        f"package version {ds.attrs.get('splinecontact_version', '?')}",
    ]
    if wall_time is not None:
        run.append(f"wall time {wall_time:.1f} s (study, figures and report)")
    lines += [f"- {r}" for r in run] + [""]
    lines += ["## Findings", ""]
    lines += [
        _table(
            ["", "finding", "verdict", "in short"],
            [
                [f"({f.key})", f.claim, _BADGE.get(f.verdict, f.verdict), f.summary]
                for f in findings
            ],
        ),
        "",
    ]
    lines += [
        "## Choices behind κ (eq. 15)",
        "",
        f"- R_Sq source: `{opts['rsq_source']}` — the gap z^u − z^l for rough-on-rough, the "
        "rough profile for rough-on-flat (`auto`).",
        f"- R_Sq method: `{opts['rsq_method']}` — grid differences of the heights (eq. 15); the "
        "alternative `spline` uses the spline slope f′ and is much smaller at high D.",
        f"- A_S/F_N: least-squares slope through the origin over F_N ≤ {opts['fit_fraction']:g} × "
        "each realization's final load.",
        "- Alternatives: `splinecontact plot STORE --rsq-method spline --fit-fraction 0.1`, or "
        "`splinecontact.analysis.kappa(ds, rsq_method=..., fit_fraction=...)`. The table below "
        "shows how much they move κ.",
        "",
    ]
    alt = analysis.kappa_alternatives(
        ds.isel({d: 0 for d in analysis.grid_dims(ds) if d not in ("dimension", "contact_type")})
    )
    header = ["contact type", "D"] + [
        f"{m}, F ≤ {fr:g}" for m in alt["rsq_method"].values for fr in alt["fit_fraction"].values
    ]
    rows = []
    for ctype in _contact_types(ds):
        a = alt.sel(contact_type=ctype) if "contact_type" in alt.dims else alt
        for i, d in enumerate(a["dimension"].values):
            vals = a["kappa_mean"].isel(dimension=i)
            rows.append(
                [ctype, f"{float(d):g}"]
                + [
                    _fmt(float(vals.sel(rsq_method=m, fit_fraction=fr)))
                    for m in alt["rsq_method"].values
                    for fr in alt["fit_fraction"].values
                ]
            )
    lines += [_table(header, rows), ""]
    for f in findings:
        lines += [
            f"## ({f.key}) {f.claim}",
            "",
            f"**{_BADGE.get(f.verdict, f.verdict)}** — {f.summary}",
            "",
            f"*Test.* {f.test}",
            "",
        ]
        for caption, head, body in f.tables:
            lines += [f"*{caption}*", "", _table(head, body), ""]
        links = _figure_links(f.figures, figures, root)
        if links:
            lines += [links, ""]
    lines += ["## Diagnostics of the method", ""]
    split = analysis.force_split(ds)
    last = split.isel(step=-1)
    rows = []
    for ctype in _contact_types(ds):
        s = _select(last, ctype)
        for i, d in enumerate(s["dimension"].values):
            si = s.isel(dimension=i)
            rows.append(
                [
                    ctype,
                    f"{float(d):g}",
                    f"{float(si['tangential_part_fraction'].mean(skipna=True)):.1%}",
                    f"{float(si['tilted_fraction'].mean(skipna=True)):.1%}",
                ]
            )
    lines += [
        "Share of F_N carried by the tangential springs (eq. 14) and share of accepted contacts "
        "whose repulsive direction points below horizontal, at the final step (means over "
        "realizations). Large values at high D are a property of the method, not a bug.",
        "",
        _table(["contact type", "D", "tangential part of F_N", "tilted contacts"], rows),
        "",
        _figure_links(["diag_force_split"], figures, root),
        "",
    ]
    if hurst is not None:
        rows = [
            [
                f"{float(d):g}",
                _fmt(float(hurst["hurst_nominal"].isel(dimension=i)), 2),
                _fmt(float(hurst["hurst_measured_mean"].isel(dimension=i)), 2),
                _fmt(float(hurst["hurst_measured_std"].isel(dimension=i)), 2),
                str(int(hurst["hurst_measured_count"].isel(dimension=i))),
            ]
            for i, d in enumerate(hurst["dimension"].values)
        ]
        lines += [
            "## Hurst exponent: nominal and measured",
            "",
            "Measured from the PSD slope of the lower profiles of the first realizations "
            "(regenerated from the study's seed rule; with one profile per D these are the "
            "profiles of Fig. 3a, and the standard deviation is not defined: –). Fig. 12 uses "
            "the nominal H = 2 − D; the measured values show which amplitude law the profiles "
            "follow.",
            "",
            _table(["D", "H = 2 − D", "measured H (mean)", "std", "profiles"], rows),
            "",
        ]
    lines += ["## Illustrations", ""]
    lines += [
        _figure_links(
            [
                "fig03_profiles",
                "fig04_spline_alpha",
                "fig05_spheres",
                "fig08_first_contact",
                "fig09_contact_zoom",
            ],
            figures,
            root,
        ),
        "",
    ]
    lines += ["## All figures", ""]
    for key, paths in sorted(figures.items()):
        lines.append(
            f"- {key}: "
            + ", ".join(f"[{p.suffix[1:]}]({p.relative_to(root).as_posix()})" for p in paths)
        )
    lines.append("")
    path.write_text("\n".join(lines), encoding="utf-8")
    return path
