"""Number formatting and Markdown tables of the report."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from .statistics import TrendTest


def _fmt(x: float, digits: int = 3) -> str:
    if x is None or not math.isfinite(float(x)):
        return "–"
    return f"{float(x):.{digits}g}"


def _table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


_TREND_HEADER = ["trend", "ρ", "exact p", "adjacent steps ↓ / ↑ / unresolved"]


def _trend_row(t: TrendTest) -> list[str]:
    down = int((t.step_sign == -1).sum())
    up = int((t.step_sign == 1).sum())
    return [
        t.shape,
        _fmt(t.rho, 2),
        _fmt(t.p_value, 2),
        f"{down} / {up} / {int(t.step_sign.size) - down - up}",
    ]


def _steps_table(caption: str, t: TrendTest, unit: str) -> tuple[str, list[str], list[list[str]]]:
    rows = []
    for (a, b), d, lo, hi, s in zip(
        t.step_x, t.step_diff, t.step_low, t.step_high, t.step_sign, strict=True
    ):
        rows.append(
            [
                f"{a:g} → {b:g}",
                f"{_fmt(d)} [{_fmt(lo)}, {_fmt(hi)}]",
                {-1: "↓", 1: "↑"}.get(int(s), "–"),
            ]
        )
    header = ["D", f"difference [{unit}] [simultaneous {t.confidence:.0%} CI]", "step"]
    return caption, header, rows


def _means_table(
    caption: str, tests: Mapping[str, TrendTest], unit: str
) -> tuple[str, list[str], list[list[str]]]:
    names = list(tests)
    first = tests[names[0]]
    header = ["D", *[f"{n} [{unit}]" for n in names]]
    rows = []
    for i, d in enumerate(first.x):
        row = [f"{d:g}"]
        for n in names:
            t = tests[n]
            row.append(
                f"{_fmt(t.means[i])} [{_fmt(t.ci_low[i])}, {_fmt(t.ci_high[i])}] (n={t.counts[i]})"
            )
        rows.append(row)
    return caption, header, rows
