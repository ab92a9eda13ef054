"""``splinecontact reproduce``: run the paper's study, draw its figures, check its findings.

One call runs the study of the paper's Section 3 at a chosen scale (:data:`SCALES`), writes every
figure (PNG and SVG) and a ``report.md`` that checks, with numbers, each finding the paper states:

(a) at a given displacement F_N falls as D rises;
(b) at a given load the stiffness falls as D rises, and the curves converge at higher load;
(c) A_S grows near-linearly with F_N, and is lower for higher D;
(d) κ lies between the Persson and Bush values for D ≤ 1.6 and rises beyond;
(e) rough-on-rough and rough-on-flat κ agree.

Each finding is reported as reproduced, partly reproduced, not reproduced or undetermined (too
few data), with its numbers and the figure behind it. The statistical tests are described in
``docs/analysis.md`` and in :func:`evaluate_findings`.

Output directory layout::

    OUT/study.toml        the study that was run (resolved, every default filled in)
    OUT/study.zarr/       the study store (resumable: run the same command again)
    OUT/figures/*.png     every figure, also as .svg
    OUT/findings.json     the verdicts and numbers, machine-readable
    OUT/report.md         the report, figures embedded

Modules
-------
* :mod:`~splinecontact.reproduce.run` — the embedded studies and the command (:func:`reproduce`).
* :mod:`~splinecontact.reproduce.findings` — the findings (a)–(e) and their verdicts.
* :mod:`~splinecontact.reproduce.report` — ``report.md``.
* :mod:`~splinecontact.reproduce.statistics` — the trend tests and bootstrap intervals.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .findings import KAPPA_AGREEMENT_TOLERANCE as KAPPA_AGREEMENT_TOLERANCE
    from .findings import LINEAR_EXPONENT_RANGE as LINEAR_EXPONENT_RANGE
    from .findings import LOAD_QUANTILE as LOAD_QUANTILE
    from .findings import VERDICTS, Finding, evaluate_findings
    from .report import write_report
    from .run import CONTACT_TYPES as CONTACT_TYPES
    from .run import SCALES, ReproduceResult, reproduce, study_mapping
    from .run import STUDY_SEED as STUDY_SEED
    from .statistics import (
        TrendTest,
        bootstrap_means,
        spearman_pvalue,
        trend_from_estimates,
        trend_test,
    )

#: Where each public name lives; imported on first use, so that ``reproduce`` starts its
#: worker processes before this process loads the statistics and plotting libraries.
_HOMES: dict[str, str] = {
    "KAPPA_AGREEMENT_TOLERANCE": "findings",
    "LINEAR_EXPONENT_RANGE": "findings",
    "LOAD_QUANTILE": "findings",
    "VERDICTS": "findings",
    "Finding": "findings",
    "evaluate_findings": "findings",
    "write_report": "report",
    "CONTACT_TYPES": "run",
    "SCALES": "run",
    "STUDY_SEED": "run",
    "ReproduceResult": "run",
    "reproduce": "run",
    "study_mapping": "run",
    "TrendTest": "statistics",
    "bootstrap_means": "statistics",
    "spearman_pvalue": "statistics",
    "trend_from_estimates": "statistics",
    "trend_test": "statistics",
}


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{home}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_HOMES})


__all__ = [
    "SCALES",
    "VERDICTS",
    "Finding",
    "ReproduceResult",
    "TrendTest",
    "bootstrap_means",
    "evaluate_findings",
    "reproduce",
    "spearman_pvalue",
    "study_mapping",
    "trend_from_estimates",
    "trend_test",
    "write_report",
]
