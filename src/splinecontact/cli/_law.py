"""Command-line options that select the local contact law (``simulate`` and ``friction``)."""

from __future__ import annotations

from typing import Annotated, Any

import typer

__all__ = [
    "CohesiveStressOpt",
    "HardnessOpt",
    "LawOpt",
    "PoissonRatioOpt",
    "WorkOfAdhesionOpt",
    "YieldStrengthOpt",
    "law_from_options",
]

PANEL_LAW = "Contact law"

LawOpt = Annotated[
    str,
    typer.Option(
        "--law",
        help="Local contact law: hertz, jkr, dmt, maugis-dugdale or elastic-plastic.",
        rich_help_panel=PANEL_LAW,
    ),
]
WorkOfAdhesionOpt = Annotated[
    float | None,
    typer.Option(
        "--work-of-adhesion",
        help="Work of adhesion w [J/m²] (jkr, dmt, maugis-dugdale; typical 0.01–1).",
        rich_help_panel=PANEL_LAW,
    ),
]
CohesiveStressOpt = Annotated[
    float | None,
    typer.Option(
        "--cohesive-stress",
        help="Dugdale stress σ0 [GPa] (dmt, maugis-dugdale).",
        rich_help_panel=PANEL_LAW,
    ),
]
YieldStrengthOpt = Annotated[
    float | None,
    typer.Option(
        "--yield-strength",
        help="Yield strength S_y [GPa] (elastic-plastic; or give --hardness).",
        rich_help_panel=PANEL_LAW,
    ),
]
HardnessOpt = Annotated[
    float | None,
    typer.Option(
        "--hardness",
        help="Hardness H [GPa] (elastic-plastic; or give --yield-strength).",
        rich_help_panel=PANEL_LAW,
    ),
]
PoissonRatioOpt = Annotated[
    float | None,
    typer.Option(
        "--poisson-ratio",
        help="Poisson's ratio ν [1] (elastic-plastic; default 0.3).",
        rich_help_panel=PANEL_LAW,
    ),
]


def law_from_options(name: str, **options: float | None) -> Any:
    """The validated law ``name`` with the options that were given (``None`` = not given).

    Raises
    ------
    UnknownContactLawError, ContactLawError
        Unknown name, an option the law does not take, or a bad value (one line on the CLI).
    """
    from ..contact import make_law

    return make_law(name, **{k: v for k, v in options.items() if v is not None})
