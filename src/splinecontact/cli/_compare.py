"""``splinecontact compare``: SAD against the exact elastic reference (BEM) on one geometry.

The comparison itself lives in :mod:`splinecontact.compare`; this module reads the options.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import typer

from .. import bem
from ..compare import compare_profiles, write_figure, write_table
from ..errors import ParameterError
from ..profile import Profile
from ._common import handle_errors

__all__ = ["register"]


def _load_body(
    spec: str,
    *,
    dimension: float,
    seed: int | None,
    n_points: int,
    length: float,
    wavelength: float,
    ra: float,
    amplitude_law: str,
) -> Profile:
    from ..generate import weierstrass_mandelbrot

    if spec == "generated":
        return weierstrass_mandelbrot(
            dimension,
            n_points=n_points,
            length=length,
            wavelength=wavelength,
            ra=ra,
            amplitude_law=amplitude_law,  # type: ignore[arg-type]
            seed=seed,
        )
    return _read(Path(spec))


def _read(path: Path) -> Profile:
    try:
        from ..io import read_profile
    except ImportError:  # pragma: no cover - the reader ships with the package
        with np.load(path) as data:
            return Profile(data["x"], data["z"], metadata={"source": str(path)})
    return read_profile(path)


def register(app: typer.Typer) -> None:
    """Add ``compare`` to ``app``."""

    @app.command()
    @handle_errors
    def compare(
        lower: Annotated[
            str,
            typer.Option(help="Lower profile: a file, or 'generated' (Weierstrass–Mandelbrot)."),
        ],
        upper: Annotated[
            str,
            typer.Option(help="Upper body: 'flat', a file, or 'generated' (independent seed)."),
        ] = "flat",
        output: Annotated[
            Path, typer.Option("-o", "--output", help="Table to write (CSV, units in header).")
        ] = Path("compare.csv"),
        figure: Annotated[
            Path | None,
            typer.Option(help="Figure to write (PNG); default: the table's name with .png."),
        ] = None,
        e_star: Annotated[float, typer.Option(help="Effective modulus E* [GPa].")] = 10.0,
        steps: Annotated[int, typer.Option(help="SAD displacement steps.")] = 1000,
        final_displacement_factor: Annotated[
            float, typer.Option(help="SAD final displacement / peak-to-valley height.")
        ] = 0.2,
        alpha: Annotated[float, typer.Option(help="Spline tightness exponent α (eq. 3).")] = 2.0,
        x0: Annotated[float, typer.Option(help="Spline unit length x0 [µm] (eqs. 2–3).")] = 1.0,
        forces: Annotated[int, typer.Option(help="Number of forces compared.")] = 20,
        tol: Annotated[float, typer.Option(help="BEM tolerance.")] = bem.DEFAULT_TOLERANCE,
        dimension: Annotated[
            float, typer.Option("-D", "--dimension", help="Fractal dimension D (generated).")
        ] = 1.5,
        seed: Annotated[int | None, typer.Option(help="Seed (generated profiles).")] = None,
        n_points: Annotated[int, typer.Option(help="Grid points (generated).")] = 65_536,
        length: Annotated[float, typer.Option(help="Profile length L0 [µm] (generated).")] = 100.0,
        wavelength: Annotated[
            float, typer.Option(help="Stochastic length L [µm] (generated).")
        ] = 1.0,
        ra: Annotated[float, typer.Option(help="Mean roughness R_A [µm] (generated).")] = 0.005,
        amplitude_law: Annotated[
            str, typer.Option(help="'hurst' (H = 2 − D) or 'as_printed' (generated).")
        ] = "hurst",
    ) -> None:
        """Compare SAD with the exact elastic solution (BEM) on the same smoothed profile."""
        if amplitude_law not in ("hurst", "as_printed"):
            raise ParameterError(f"--amplitude-law {amplitude_law!r}: use 'hurst' or 'as_printed'")
        options: dict[str, Any] = {
            "dimension": dimension, "n_points": n_points, "length": length,
            "wavelength": wavelength, "ra": ra, "amplitude_law": amplitude_law,
        }  # fmt: skip
        if lower == "generated" and upper == "generated":
            from ..generate import weierstrass_mandelbrot_pair

            pair_options = {k: v for k, v in options.items() if k != "dimension"}
            lower_body, upper_p = weierstrass_mandelbrot_pair(dimension, seed=seed, **pair_options)
            upper_body: Profile | Literal["flat"] = upper_p
        else:
            lower_body = _load_body(lower, seed=seed, **options)
            if upper == "flat":
                upper_body = "flat"
            elif upper == "generated":
                upper_seed = None if seed is None else seed + 1
                upper_body = _load_body(upper, seed=upper_seed, **options)
            else:
                upper_body = _read(Path(upper))
        comparison = compare_profiles(
            lower_body,
            upper_body,
            e_star=e_star,
            steps=steps,
            final_displacement_factor=final_displacement_factor,
            alpha=alpha,
            x0=x0,
            n_forces=forces,
            tol=tol,
        )
        table = write_table(comparison, output)
        picture = write_figure(comparison, figure or output.with_suffix(".png"))
        for note in comparison.notes:
            typer.echo(f"note: {note}")
        typer.echo(
            f"compared at {comparison.columns['force'].size} forces; medians: "
            f"SAD width / exact {comparison.median('ratio_width'):.3g}, "
            f"A_S / exact {comparison.median('ratio_area'):.3g}, "
            f"mean gap error {comparison.median('mean_gap_error'):+.3g}, "
            f"approach exact / SAD {comparison.median('ratio_approach'):.3g}, "
            f"patches / SAD contacts {comparison.median('ratio_contacts'):.3g}"
        )
        typer.echo(f"wrote {table} and {picture}")
