"""``splinecontact generate``: write a Weierstrass–Mandelbrot profile (or a pair) to a file."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import ParameterError
from ..generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from ._common import handle_errors

__all__ = ["register"]


def _output_for_pair(path: Path) -> tuple[Path, Path]:
    return (
        path.with_name(f"{path.stem}-lower{path.suffix}"),
        path.with_name(f"{path.stem}-upper{path.suffix}"),
    )


def register(app: typer.Typer) -> None:
    """Add ``generate`` to ``app``."""

    @app.command()
    @handle_errors
    def generate(
        output: Annotated[
            Path, typer.Option("-o", "--output", help="Profile file to write (.npz, .csv, .txt).")
        ],
        dimension: Annotated[
            float, typer.Option("-D", "--dimension", help="Fractal dimension D, 1 ≤ D ≤ 2.")
        ] = 1.5,
        n_points: Annotated[int, typer.Option(help="Number of grid points.")] = 1_000_000,
        length: Annotated[float, typer.Option(help="Profile length L0 [µm].")] = 100.0,
        wavelength: Annotated[float, typer.Option(help="Stochastic length L [µm].")] = 1.0,
        gamma: Annotated[float, typer.Option(help="Frequency density γ.")] = 1.5,
        directions: Annotated[int, typer.Option(help="Number of directions M.")] = 20,
        n_max: Annotated[int, typer.Option(help="Highest frequency index n_max.")] = 20,
        ra: Annotated[float, typer.Option(help="Target mean roughness R_A [µm].")] = 0.005,
        amplitude_law: Annotated[
            str,
            typer.Option(help="'hurst' (H = 2 − D) or 'as_printed' (eq. 1 as printed)."),
        ] = "hurst",
        seed: Annotated[int | None, typer.Option(help="Seed of the random phases.")] = None,
        pair: Annotated[
            bool,
            typer.Option(
                "--pair",
                help="Write two independent profiles (spawned seeds) as NAME-lower / NAME-upper.",
            ),
        ] = False,
    ) -> None:
        """Generate a fractal profile by eq. 1 of the paper and write it to a file."""
        from ..io import write_profile

        if amplitude_law not in ("hurst", "as_printed"):
            raise ParameterError(f"--amplitude-law {amplitude_law!r}: use 'hurst' or 'as_printed'")
        options = {
            "n_points": n_points, "length": length, "wavelength": wavelength, "gamma": gamma,
            "directions": directions, "n_max": n_max, "ra": ra, "amplitude_law": amplitude_law,
        }  # fmt: skip
        if pair:
            lower, upper = weierstrass_mandelbrot_pair(dimension, seed=seed, **options)
            paths = _output_for_pair(output)
            for profile, path in zip((lower, upper), paths, strict=True):
                write_profile(profile, path)
            written = f"{paths[0]} and {paths[1]}"
            profile = lower
        else:
            profile = weierstrass_mandelbrot(dimension, seed=seed, **options)  # type: ignore[arg-type]
            write_profile(profile, output)
            written = str(output)
        dropped = profile.metadata["n_terms_dropped_above_nyquist"]
        note = f", {dropped} terms above Nyquist dropped" if dropped else ""
        typer.echo(
            f"wrote {written}: D = {dimension:g}, {profile.n_points} points, "
            f"dx = {profile.dx * 1e3:.4g} nm, R_A = {profile.ra * 1e3:.4g} nm, "
            f"peak-to-valley = {profile.peak_to_valley * 1e3:.4g} nm{note}"
        )
