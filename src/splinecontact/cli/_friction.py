"""``splinecontact friction``: move the upper body along a load path and report friction."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer

from ._bodies import body_files, load_bodies
from ._errors import handle_errors, note
from ._law import (
    CohesiveStressOpt,
    HardnessOpt,
    LawOpt,
    PoissonRatioOpt,
    WorkOfAdhesionOpt,
    YieldStrengthOpt,
    law_from_options,
)
from ._reading import EStarOpt, GStarOpt, Mu0Opt, OverwriteOpt, ProfileReading, with_reading_options

__all__ = ["register"]


def register(app: typer.Typer) -> None:
    """Add ``friction`` to ``app``."""

    @app.command()
    @handle_errors
    @with_reading_options(upper=True)
    def friction(
        lower: Annotated[
            str, typer.Option("--lower", help="Lower body: FILE or generated:D=..,seed=..")
        ],
        path: Annotated[
            str,
            typer.Option(
                "--path",
                help=(
                    "Load path: segments separated by ';', each key=value pairs: normal [µm], "
                    "force [mN/µm], tangential [µm], steps, e.g. "
                    "'normal=0.001,steps=200; tangential=0.02,steps=400'."
                ),
            ),
        ],
        output: Annotated[
            Path,
            typer.Option(
                "-o", "--output", help="Result file: .nc (netCDF-4) or .csv (units in header)."
            ),
        ],
        upper: Annotated[
            str, typer.Option("--upper", help="Upper body: FILE, flat or generated:D=..,seed=..")
        ] = "flat",
        e_star: EStarOpt = 10.0,
        g_star: GStarOpt = None,
        mu0: Mu0Opt = 0.3,
        alpha: Annotated[float, typer.Option("--alpha", help="Spline tightness α [1].")] = 2.0,
        x0: Annotated[float, typer.Option("--x0", help="Spline unit length x0 [µm].")] = 1.0,
        overwrite: OverwriteOpt = False,
        interaction: Annotated[
            bool,
            typer.Option(
                "--interaction/--no-interaction",
                help="Couple the contacts through the elastic half-plane (interacting SAD).",
            ),
        ] = False,
        law: LawOpt = "hertz",
        work_of_adhesion: WorkOfAdhesionOpt = None,
        cohesive_stress: CohesiveStressOpt = None,
        yield_strength: YieldStrengthOpt = None,
        hardness: HardnessOpt = None,
        poisson_ratio: PoissonRatioOpt = None,
        *,
        reading_options: Callable[[], ProfileReading],
    ) -> None:
        """Slide, press, unload or cycle the upper body along a load path (netCDF out).

        Prints μ_s, k_T and the dissipated work when the path moves the body tangentially.
        Nothing is written when anything fails.
        """
        from ..analysis import FrictionAnalysisError, static_friction, tangential_stiffness
        from ..contact import parse_path, simulate
        from ..outputs import check_output_file
        from ._measured import _check_result_suffix, write_result

        _check_result_suffix(output)
        contact_law = law_from_options(
            law, work_of_adhesion=work_of_adhesion, cohesive_stress=cohesive_stress,
            yield_strength=yield_strength, hardness=hardness, poisson_ratio=poisson_ratio,
        )  # fmt: skip

        reading = reading_options()
        inputs = body_files(lower, upper)
        out = check_output_file(output, overwrite=overwrite, inputs=inputs, option="--output")
        segments = parse_path(path)
        bodies = load_bodies(lower, upper, reading)
        note(*bodies.notes)
        result = simulate(
            bodies.lower, bodies.upper, e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha,
            x0=x0, path=segments, law=contact_law, interaction=interaction,
        )  # fmt: skip
        write_result(result, out, header={"lower": bodies.lower_spec, "upper": bodies.upper_spec})
        c = result.curves
        summary = (
            f"{len(c['displacement']) - 1} steps, "
            f"final δ_N {1e3 * float(c['displacement'][-1]):.4g} nm, "
            f"u_T {1e3 * float(c['tangential_displacement'][-1]):.4g} nm, "
            f"F_N {float(c['normal_force'][-1]):.4g} mN/µm, "
            f"F_T {float(c['tangential_force'][-1]):.4g} mN/µm, "
            f"dissipated {float(c['dissipated_work'][-1]):.4g} mN·µm/µm"
        )
        try:
            summary += (
                f", μ_s {static_friction(result).mu_s:.4g}, "
                f"k_T {tangential_stiffness(result):.4g} GPa"
            )
        except FrictionAnalysisError:
            pass
        typer.echo(f"{summary} -> {out}")
        if (line := force_control_line(result)) is not None:
            typer.echo(line)


def force_control_line(result: Any) -> str | None:
    """One line on the force-controlled steps of a path (``None`` without any): how many met
    F_N on eq. 9's contacts, with a held contact set inside a jump, or missed it (codes 1–3 of
    the ``force_control`` output)."""
    from ..analysis import force_control_counts

    n = force_control_counts(result)
    total = sum(n.values())
    if total == 0:
        return None
    return (
        f"{n[1] + n[2]} of {total} force-controlled steps held F_N ({n[1]} on the contacts eq. 9 "
        f"accepts, {n[2]} with a held contact set inside a jump), {n[3]} missed it inside a jump "
        "(force_control = 3; normal_force − normal_force_target)"
    )
