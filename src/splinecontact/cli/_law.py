"""Command-line options that select the local contact law (``simulate`` and ``friction``),
and the ``laws-study`` command (adhesion and plasticity of rough pairs against D)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ._errors import handle_errors
from ._reading import OverwriteOpt, QuietOpt

__all__ = [
    "LAWS_STUDY_FILES",
    "CohesiveStressOpt",
    "HardnessOpt",
    "LawOpt",
    "PoissonRatioOpt",
    "WorkOfAdhesionOpt",
    "YieldStrengthOpt",
    "law_from_options",
    "register",
]

#: What ``laws-study`` writes into its output folder (besides one figure per variable).
LAWS_STUDY_FILES = ("laws_study.nc", "laws_study.csv")

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


def _check_laws_output(output: Path, overwrite: bool, study_file: Path) -> None:
    """Refuse, before the study runs, an output folder the output rule would refuse later."""
    from ..errors import OutputExistsError, UnsafeOutputError

    if output.exists() and not output.is_dir():
        raise UnsafeOutputError(f"-o {output} is a file; give a folder name")
    if study_file.resolve().parent == output.resolve():
        raise UnsafeOutputError(f"-o {output} holds the study file {study_file}; choose another")
    if output.is_dir() and any(output.iterdir()) and not overwrite:
        raise OutputExistsError(
            f"-o {output} exists and is not empty; choose another folder or pass --overwrite "
            "(which replaces only what splinecontact wrote there)"
        )
    if not output.exists() and not output.parent.expanduser().resolve().is_dir():
        raise UnsafeOutputError(f"-o {output}: the folder {output.parent} does not exist")


def _means_table(ds: Any) -> str:
    """CSV of the ensemble means and confidence half-widths, units in the header."""
    from ..analysis import LAWS_STUDY_VARIABLES

    names = list(LAWS_STUDY_VARIABLES)
    header = ["law", "dimension [1]"] + [
        f"{n}_{part} [{LAWS_STUDY_VARIABLES[n]}]" for n in names for part in ("mean", "ci")
    ]
    rows = [",".join(header)]
    for law in ds["law"].values:
        for d in ds["dimension"].values:
            sel = {"law": law, "dimension": d}
            cells = [f'"{law}"', f"{float(d):.6g}"] + [
                f"{float(ds[f'{n}_{part}'].sel(sel)):.9g}" for n in names for part in ("mean", "ci")
            ]
            rows.append(",".join(cells))
    return "\n".join(rows) + "\n"


def register(app: typer.Typer) -> None:
    """Add ``laws-study`` to ``app``."""

    @app.command("laws-study")
    @handle_errors
    def laws_study_command(
        study_file: Annotated[
            Path, typer.Argument(help="Laws-study file (TOML: [laws_study] and [[law]] tables).")
        ],
        output: Annotated[
            Path,
            typer.Option(
                "-o", "--output", help="Output folder (netCDF, CSV, one PNG per variable)."
            ),
        ],
        quiet: QuietOpt = False,
        overwrite: OverwriteOpt = False,
    ) -> None:
        """Pull-off force, work of separation, residual approach, dissipation and κ against D,
        one load–unload cycle per realization under each [[law]] (docs/contact-laws.md).

        Writes laws_study.nc (every realization, with units), laws_study.csv (means and
        confidence half-widths) and one figure per variable. Progress goes to stderr (--quiet
        for none); a bad file or output is one line, and nothing is written.
        """
        from ..analysis import LAWS_STUDY_VARIABLES
        from ..analysis.laws_study_file import load_laws_study, run_laws_study
        from ..outputs import atomic_path, prepare_output_folder

        spec = load_laws_study(study_file)
        _check_laws_output(output, overwrite, study_file)

        def say(label: str, done: int, total: int) -> None:
            if not quiet:
                typer.echo(f"{label}: {done}/{total} realizations", err=True)

        ds = run_laws_study(spec, progress=say)
        from ..plotting import plot_laws_study

        folder = prepare_output_folder(output, overwrite=overwrite, command="laws-study")
        with atomic_path(folder.file(LAWS_STUDY_FILES[0])) as tmp:
            ds.to_netcdf(tmp, engine="h5netcdf")
        with atomic_path(folder.file(LAWS_STUDY_FILES[1])) as tmp:
            tmp.write_text(_means_table(ds), encoding="utf-8")
        studies = {str(law): ds.sel(law=law) for law in ds["law"].values}
        for name in LAWS_STUDY_VARIABLES:
            fig = plot_laws_study(studies, name).get_figure(root=True)
            assert fig is not None
            with atomic_path(folder.file(f"{name}.png")) as tmp:
                fig.savefig(tmp, dpi=150, format="png")
        lines = [f"{len(spec.laws)} laws × {spec.realizations} realizations -> {output}"]
        for law in ds["law"].values:
            sel = ds.sel(law=law)
            lines.append(
                f"{law}: pull-off {_fmt(sel['pull_off_force_mean'].values)} mN/µm, "
                f"residual δ_r/δ_max {_fmt(sel['residual_fraction_mean'].values)}, "
                f"κ {_fmt(sel['kappa_mean'].values)} at D = {_fmt(ds['dimension'].values)}"
            )
        typer.echo("\n".join(lines))


def _fmt(values: Any) -> str:
    return " / ".join(f"{float(v):.3g}" for v in values)
