"""``splinecontact generate``: write a Weierstrass–Mandelbrot profile (or a pair) to a file."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ..errors import ParameterError
from ._bodies import MAX_SEED
from ._errors import handle_errors
from ._reading import OverwriteOpt

if TYPE_CHECKING:
    from ..profile import Profile

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
        seed: Annotated[
            int | None,
            typer.Option(
                help="Seed of the random phases, 0 ≤ seed < 2^63 (default: drawn, printed and "
                "stored in the file)."
            ),
        ] = None,
        pair: Annotated[
            bool,
            typer.Option(
                "--pair",
                help="Write two independent profiles (spawned seeds) as NAME-lower / NAME-upper.",
            ),
        ] = False,
        overwrite: OverwriteOpt = False,
    ) -> None:
        """Generate a fractal profile by eq. 1 of the paper and write it to a file."""
        import contextlib
        import secrets

        from ..generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
        from ..io import write_profile
        from ..outputs import atomic_path, check_output_file

        if amplitude_law not in ("hurst", "as_printed"):
            raise ParameterError(f"--amplitude-law {amplitude_law!r}: use 'hurst' or 'as_printed'")
        if seed is not None and not 0 <= seed <= MAX_SEED:
            raise ParameterError(f"--seed {seed} must be an integer 0 ≤ seed < 2^63")
        if output.suffix.lower() not in (".npz", ".csv", ".txt"):
            raise ParameterError(
                f"-o {output}: unknown profile format {output.suffix or '(no extension)'!r}; "
                "use .npz, .csv or .txt"
            )
        targets = _output_for_pair(output) if pair else (output,)
        for target in targets:
            check_output_file(target, overwrite=overwrite)
        drawn = seed is None
        if seed is None:
            seed = secrets.randbelow(2**32)
        options = {
            "n_points": n_points, "length": length, "wavelength": wavelength, "gamma": gamma,
            "directions": directions, "n_max": n_max, "ra": ra, "amplitude_law": amplitude_law,
        }  # fmt: skip
        profiles: tuple[Profile, ...]
        try:
            if pair:
                profiles = weierstrass_mandelbrot_pair(dimension, seed=seed, **options)
            else:
                profiles = (weierstrass_mandelbrot(dimension, seed=seed, **options),)  # type: ignore[arg-type]
        except (OverflowError, FloatingPointError, ZeroDivisionError) as exc:
            raise ParameterError(
                f"these parameters cannot be generated ({type(exc).__name__}: {exc}); use "
                "smaller values"
            ) from None
        with contextlib.ExitStack() as stack:
            # every file to a temporary name first: all are renamed only if all were written
            for profile, target in zip(profiles, targets, strict=True):
                write_profile(profile, stack.enter_context(atomic_path(target)))
        written = " and ".join(str(t) for t in targets)
        profile = profiles[0]
        if drawn:
            typer.echo(f"note: seed {seed} (drawn at random; --seed {seed} repeats it)", err=True)
        dropped = profile.metadata["n_terms_dropped_above_nyquist"]
        note = f", {dropped} terms above Nyquist dropped" if dropped else ""
        typer.echo(
            f"wrote {written}: D = {dimension:g}, {profile.n_points} points, "
            f"dx = {profile.dx * 1e3:.4g} nm, R_A = {profile.ra * 1e3:.4g} nm, "
            f"peak-to-valley = {profile.peak_to_valley * 1e3:.4g} nm{note}"
        )
