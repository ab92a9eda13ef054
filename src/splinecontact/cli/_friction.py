"""``splinecontact friction``: move the upper body along a load path and report friction."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import typer

from ..errors import ParameterError
from ..profile import Profile
from ._common import handle_errors

__all__ = ["register"]


def _body(spec: str, *, role: str, other: Profile | None = None) -> Profile | Literal["flat"]:
    text = spec.strip()
    if text.lower() == "flat":
        if role == "lower":
            raise ParameterError("--lower flat: the lower body must be a rough profile")
        return "flat"
    if text.lower().startswith("generated"):
        from ..generate import weierstrass_mandelbrot
        from ._measured import parse_generated_spec

        kwargs: dict[str, Any] = parse_generated_spec(text)
        if other is not None and "n_points" not in kwargs and "length" not in kwargs:
            kwargs["n_points"] = other.n_points
            kwargs["length"] = other.length
        return weierstrass_mandelbrot(**kwargs)
    from ..io import read_profile

    return read_profile(Path(text))


def register(app: typer.Typer) -> None:
    """Add ``friction`` to ``app``."""

    @app.command()
    @handle_errors
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
        output: Annotated[Path, typer.Option("-o", "--output", help="Result file (.nc).")],
        upper: Annotated[
            str, typer.Option("--upper", help="Upper body: FILE, flat or generated:D=..,seed=..")
        ] = "flat",
        e_star: Annotated[
            float, typer.Option("--e-star", help="Effective modulus E* [GPa].")
        ] = 10.0,
        g_star: Annotated[
            float | None,
            typer.Option("--g-star", help="Effective shear modulus G* [GPa] (default E*/2.6)."),
        ] = None,
        mu0: Annotated[float, typer.Option("--mu0", help="Friction coefficient μ0 [1].")] = 0.3,
        alpha: Annotated[float, typer.Option("--alpha", help="Spline tightness α [1].")] = 2.0,
        x0: Annotated[float, typer.Option("--x0", help="Spline unit length x0 [µm].")] = 1.0,
        overwrite: Annotated[
            bool, typer.Option("--overwrite", help="Replace an existing output file.")
        ] = False,
    ) -> None:
        """Slide, press, unload or cycle the upper body along a load path (netCDF out).

        Prints μ_s, k_T and the dissipated work when the path moves the body tangentially.
        Nothing is written when anything fails.
        """
        from ..contact import simulate
        from ..friction import FrictionAnalysisError, static_friction, tangential_stiffness
        from ..loadpath import parse_path
        from ..outputs import atomic_path, check_output_file

        inputs = [p for p in (lower, upper) if Path(p).exists()]
        out = check_output_file(output, overwrite=overwrite, inputs=inputs, option="--output")
        segments = parse_path(path)
        lower_profile = _body(lower, role="lower")
        assert isinstance(lower_profile, Profile)
        upper_body = _body(upper, role="upper", other=lower_profile)
        result = simulate(
            lower_profile, upper_body, e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha,
            x0=x0, path=segments,
        )  # fmt: skip
        with atomic_path(out) as tmp:
            result.to_netcdf(tmp)
        c = result.curves
        line = (
            f"{len(c['displacement']) - 1} steps, "
            f"final δ_N {1e3 * float(c['displacement'][-1]):.4g} nm, "
            f"u_T {1e3 * float(c['tangential_displacement'][-1]):.4g} nm, "
            f"F_N {float(c['normal_force'][-1]):.4g} mN/µm, "
            f"F_T {float(c['tangential_force'][-1]):.4g} mN/µm, "
            f"dissipated {float(c['dissipated_work'][-1]):.4g} mN·µm/µm"
        )
        try:
            line += (
                f", μ_s {static_friction(result).mu_s:.4g}, "
                f"k_T {tangential_stiffness(result):.4g} GPa"
            )
        except FrictionAnalysisError:
            pass
        typer.echo(f"{line} -> {out}")
