"""``splinecontact compare``: SAD against the exact elastic reference (BEM) on one geometry.

The comparison itself lives in :mod:`splinecontact.compare`; this module reads the options.
Bodies are specs (FILE, ``flat``, ``generated:D=1.5,seed=3``) read with the shared options of
:mod:`splinecontact.cli._reading`, exactly as ``simulate`` reads them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ParameterError
from ._bodies import BODY_SPEC_HELP, body_files, load_bodies
from ._errors import handle_errors, note
from ._reading import EStarOpt, OverwriteOpt, ProfileReading, QuietOpt, with_reading_options

__all__ = ["register"]

#: Grid points of a generated body without n_points/length and no file to copy a grid from
#: (the BEM reference costs far more than SAD; 2¹⁶ points take seconds).
COMPARE_N_POINTS = 65_536

#: Defaults of the BEM reference (splinecontact.bem.DEFAULT_TOLERANCE and
#: splinecontact.compare.COMPARE_MAX_ITERATIONS, repeated so ``--help`` does not import them).
BEM_TOLERANCE = 1e-10
BEM_MAX_ITERATIONS = 5000


def _check_output_folder(output: Path, overwrite: bool, inputs: list[Path]) -> None:
    """Refuse, before any computation, an output folder the output rule would refuse later."""
    from ..errors import OutputExistsError, UnsafeOutputError

    if output.exists() and not output.is_dir():
        raise UnsafeOutputError(f"-o {output} is a file; give a folder name")
    written = {(output / name).resolve() for name in ("", "compare.csv", "compare.png")}
    for path in inputs:
        if path.resolve() in written:
            raise UnsafeOutputError(f"-o {output} would replace the input {path}")
    if output.is_dir() and any(output.iterdir()) and not overwrite:
        raise OutputExistsError(
            f"-o {output} exists and is not empty; choose another folder or pass --overwrite "
            "(which replaces only what splinecontact wrote there)"
        )


def register(app: typer.Typer) -> None:
    """Add ``compare`` to ``app``."""

    @app.command(epilog=BODY_SPEC_HELP)
    @handle_errors
    @with_reading_options(upper=True)
    def compare(
        lower: Annotated[
            str,
            typer.Option(
                "--lower",
                help="Lower body: FILE or generated:D=1.5,seed=3 (default n_points=65536).",
            ),
        ],
        upper: Annotated[
            str,
            typer.Option(
                "--upper",
                help="Upper body: flat, FILE, generated:D=..,seed=.. or generated (the "
                "lower's parameters, next seed).",
            ),
        ] = "flat",
        output: Annotated[
            Path,
            typer.Option(
                "-o", "--output", help="Folder to write compare.csv (units in header) and .png."
            ),
        ] = Path("compare"),
        e_star: EStarOpt = 10.0,
        steps: Annotated[int, typer.Option(help="SAD displacement steps.")] = 1000,
        final_displacement_factor: Annotated[
            float, typer.Option(help="SAD final displacement / peak-to-valley height.")
        ] = 0.2,
        alpha: Annotated[float, typer.Option(help="Spline tightness exponent α (eq. 3).")] = 2.0,
        x0: Annotated[float, typer.Option(help="Spline unit length x0 [µm] (eqs. 2–3).")] = 1.0,
        forces: Annotated[int, typer.Option(help="Number of forces compared.")] = 20,
        tol: Annotated[float, typer.Option(help="BEM tolerance [1].")] = BEM_TOLERANCE,
        max_iterations: Annotated[
            int,
            typer.Option(
                "--max-iterations",
                help="BEM iteration limit per solve (a force that fails is retried in "
                "smaller load steps).",
            ),
        ] = BEM_MAX_ITERATIONS,
        max_contact_fraction: Annotated[
            float,
            typer.Option(
                "--max-contact-fraction",
                help="Stop when the exact contact covers this share of the profile "
                "(near full contact).",
            ),
        ] = 0.9,
        interaction: Annotated[
            bool,
            typer.Option(
                "--interaction/--no-interaction",
                help="Also run interacting SAD (contacts coupled through the half-plane) and "
                "report it against the exact solution (int_* columns); it runs up to the "
                "largest compared force (docs/accuracy.md).",
            ),
        ] = False,
        quiet: QuietOpt = False,
        overwrite: OverwriteOpt = False,
        *,
        reading_options: Callable[[], ProfileReading],
    ) -> None:
        """Compare SAD with the exact elastic solution (BEM) on the same smoothed profile.

        Progress goes to stderr (one line per BEM force; --quiet for none). Stops with one
        line naming the force if the BEM does not converge, and reports no state at or near
        full contact.
        """
        from ..compare import compare_profiles, write_figure, write_table
        from ..outputs import atomic_path, prepare_output_folder

        if not (math.isfinite(tol) and tol > 0):
            raise ParameterError(f"--tol {tol!r} must be a positive number")
        if max_iterations < 1:
            raise ParameterError(f"--max-iterations {max_iterations} must be ≥ 1")
        if forces < 1:
            raise ParameterError(f"--forces {forces} must be ≥ 1")
        if not (math.isfinite(max_contact_fraction) and 0 < max_contact_fraction <= 1):
            raise ParameterError(
                f"--max-contact-fraction {max_contact_fraction!r} must be in (0, 1]"
            )
        reading = reading_options()
        _check_output_folder(output, overwrite, body_files(lower, upper))
        bodies = load_bodies(lower, upper, reading, default_n_points=COMPARE_N_POINTS)

        def say(text: str) -> None:
            if not quiet:
                typer.echo(text, err=True)

        note(*bodies.notes)
        comparison = compare_profiles(
            bodies.lower, bodies.upper, e_star=e_star, steps=steps,
            final_displacement_factor=final_displacement_factor, alpha=alpha, x0=x0,
            n_forces=forces, tol=tol, max_iterations=max_iterations,
            max_contact_fraction=max_contact_fraction, progress=say, interaction=interaction,
        )  # fmt: skip
        comparison.parameters["lower"] = bodies.lower_spec
        comparison.parameters["upper"] = bodies.upper_spec
        folder = prepare_output_folder(output, overwrite=overwrite, command="compare")
        table = folder.file("compare.csv")
        with atomic_path(table) as tmp:
            write_table(comparison, tmp)
        picture = folder.file("compare.png")
        with atomic_path(picture) as tmp:
            write_figure(comparison, tmp)
        for text in comparison.notes:
            typer.echo(f"note: {text}")
        typer.echo(
            f"compared at {comparison.columns['force'].size} forces; medians: "
            f"SAD width / exact {comparison.median('ratio_width'):.3g}, "
            f"A_S / exact {comparison.median('ratio_area'):.3g}, "
            f"mean gap error {comparison.median('mean_gap_error'):+.3g}, "
            f"approach exact / SAD {comparison.median('ratio_approach'):.3g}, "
            f"patches / SAD contacts {comparison.median('ratio_contacts'):.3g}"
        )
        if interaction:
            typer.echo(
                f"interacting SAD medians: contact length / exact "
                f"{comparison.median('ratio_length_int'):.3g}, mean gap error "
                f"{comparison.median('mean_gap_error_int'):+.3g}, approach exact / interacting "
                f"{comparison.median('ratio_approach_int'):.3g}, patches / interacting patches "
                f"{comparison.median('ratio_patches_int'):.3g}"
            )
        typer.echo(f"wrote {table} and {picture}")
