"""Commands for measured profiles: ``simulate`` and ``inspect``; the single-result plot.

Bodies are given as specs (a FILE, ``flat`` or ``generated:D=1.5,seed=3,...``) read with the
shared reading and preprocessing options: see :mod:`splinecontact.cli._reading`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from ..errors import OutputWriteError, ParameterError, ProfileReadError
from ._bodies import (
    BODY_SPEC_HELP,
    BodySpec,
    body_files,
    load_bodies,
    parse_generated_spec,
    read_body,
)
from ._errors import handle_errors, note, warn
from ._law import (
    CohesiveStressOpt,
    HardnessOpt,
    LawOpt,
    PoissonRatioOpt,
    WorkOfAdhesionOpt,
    YieldStrengthOpt,
    law_from_options,
)
from ._reading import (
    EStarOpt,
    GStarOpt,
    Mu0Opt,
    OverwriteOpt,
    ProfileReading,
    X0Opt,
    with_reading_options,
)

if TYPE_CHECKING:
    from ..profile import Profile
    from ..results import SimulationResult

__all__ = [
    "RESULT_SUFFIXES",
    "OutputWriteError",
    "parse_generated_spec",
    "plot_result",
    "register",
    "write_result",
]

#: Result file formats of ``simulate -o``, by extension.
RESULT_SUFFIXES = {".nc": "netCDF-4", ".csv": "CSV, units in the header"}


def _check_result_suffix(output: Path) -> None:
    if output.suffix.lower() not in RESULT_SUFFIXES:
        known = ", ".join(f"{k} ({v})" for k, v in RESULT_SUFFIXES.items())
        raise OutputWriteError(
            f"-o {output}: unknown result format {output.suffix or '(no extension)'!r}; use {known}"
        )


def _write_csv(result: SimulationResult, path: Path, header: dict[str, Any]) -> None:
    import csv

    import numpy as np

    from .. import schema
    from ..results import PATH_STEP_VARIABLES, STEP_VARIABLES

    with path.open("w", newline="", encoding="utf-8") as handle:
        for key, value in header.items():
            handle.write(f"# {key} = {value}\n")
        for key, value in result.parameters.items():
            handle.write(f"# {key} = {value}\n")
        from ..results import SCALAR_VARIABLES

        for key, (units, _) in SCALAR_VARIABLES.items():
            handle.write(f"# {key} [{units}] = {float(result.scalars[key]):.10g}\n")
        writer = csv.writer(handle)
        table = dict(STEP_VARIABLES)
        if "path" in result.parameters:  # a load path: u_T, slip, work, F_N target, force_control
            table.update((n, u) for n, u in PATH_STEP_VARIABLES.items() if n in result.curves)
        names = list(table)
        for name in names:  # the meaning of each code of a coded column (CF flag_meanings)
            if flags := schema.VARIABLES[name].flags:
                codes = ", ".join(f"{code} = {meaning}" for code, meaning in enumerate(flags))
                handle.write(f"# {name} codes: {codes}\n")
        writer.writerow(["step [1]", *(f"{n} [{table[n][0]}]" for n in names)])
        columns = [np.asarray(result.curves[n]) for n in names]
        for i in range(len(columns[0])):
            writer.writerow([i, *(f"{c[i]:.10g}" for c in columns)])


def write_result(
    result: SimulationResult, output: Path, *, header: dict[str, Any] | None = None
) -> Path:
    """Write a result atomically as netCDF-4 (``.nc``) or CSV (``.csv``), by extension.

    Parameters
    ----------
    result : SimulationResult
        What to write.
    output : Path
        The file; checked beforehand with :func:`splinecontact.outputs.check_output_file`.
    header : dict, optional
        Extra ``# key = value`` lines of a CSV file (the body specs); netCDF stores them as
        attributes.

    Raises
    ------
    OutputWriteError
        Unknown extension or a missing netCDF backend.
    """
    from ..outputs import atomic_path

    _check_result_suffix(output)
    header = header or {}
    with atomic_path(output) as tmp:
        if output.suffix.lower() == ".csv":
            _write_csv(result, tmp, header)
        else:
            try:
                ds = result.to_xarray()
                ds.attrs.update({k: str(v) for k, v in header.items()})
                ds.to_netcdf(tmp, engine="h5netcdf")
            except ImportError as exc:
                raise OutputWriteError(
                    f"cannot write {output}: netCDF-4 writing needs h5netcdf ({exc}); install "
                    "it with `pip install h5netcdf`, or write .csv"
                ) from None
    return output


@handle_errors
@with_reading_options(upper=True)
def simulate_command(
    lower: Annotated[
        str, typer.Option("--lower", help="Lower body: FILE or generated:D=..,seed=..")
    ],
    output: Annotated[
        Path,
        typer.Option(
            "--output", "-o", help="Result file: .nc (netCDF-4) or .csv (units in header)."
        ),
    ],
    upper: Annotated[
        str,
        typer.Option(
            "--upper",
            help="Upper body: FILE, flat, generated:D=..,seed=.. or generated (the lower's "
            "parameters, next seed).",
        ),
    ] = "flat",
    steps: Annotated[int, typer.Option("--steps", help="Displacement increments [1].")] = 1000,
    max_steps: Annotated[
        int,
        typer.Option("--max-steps", min=1, help="Raise the ceiling on --steps [1]."),
    ] = 1_000_000,
    final_displacement: Annotated[
        float | None,
        typer.Option(
            "--final-displacement",
            help="Final displacement [µm] (default: 0.2 × the lower peak-to-valley height).",
        ),
    ] = None,
    e_star: EStarOpt = 10.0,
    g_star: GStarOpt = None,
    mu0: Mu0Opt = 0.3,
    alpha: Annotated[float, typer.Option("--alpha", help="Spline tightness α [1] (eq. 3).")] = 2.0,
    x0: X0Opt = 1.0,
    overwrite: OverwriteOpt = False,
    law: LawOpt = "hertz",
    work_of_adhesion: WorkOfAdhesionOpt = None,
    cohesive_stress: CohesiveStressOpt = None,
    yield_strength: YieldStrengthOpt = None,
    hardness: HardnessOpt = None,
    poisson_ratio: PoissonRatioOpt = None,
    *,
    reading_options: Callable[[], ProfileReading],
) -> None:
    """Press two measured (or generated) profiles together, or one against a rigid flat.

    Writes every per-step curve to OUTPUT (.nc or .csv, with units) and prints one summary
    line; warns when a body is dominated by tilt or form, the grid is too coarse for the
    spline, or the load nears full contact. Nothing is written when anything fails.
    """
    import warnings

    from ..contact import simulate
    from ..outputs import check_output_file

    _check_result_suffix(output)
    contact_law = law_from_options(
        law, work_of_adhesion=work_of_adhesion, cohesive_stress=cohesive_stress,
        yield_strength=yield_strength, hardness=hardness, poisson_ratio=poisson_ratio,
    )  # fmt: skip
    if final_displacement is not None and not (
        math.isfinite(final_displacement) and 0 < final_displacement < 1e100
    ):
        raise ParameterError(
            f"--final-displacement {final_displacement!r} must be a positive finite length in µm"
        )
    reading = reading_options()
    check_output_file(output, overwrite=overwrite, inputs=body_files(lower, upper))
    bodies = load_bodies(lower, upper, reading)
    note(*bodies.notes)
    with warnings.catch_warnings():
        # the diagnostics are printed once below (and simulate issues them for scripts)
        from ..diagnostics import SimulationWarning, simulation_diagnostics

        warnings.simplefilter("ignore", SimulationWarning)
        result = simulate(
            bodies.lower, bodies.upper, steps=steps, final_displacement=final_displacement,
            e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, max_steps=max_steps,
            law=contact_law,
        )  # fmt: skip
    for item in simulation_diagnostics(
        bodies.lower, bodies.upper, result.curves, alpha=alpha, x0=x0
    ):
        warn(item.message)
    write_result(result, output, header={"lower": bodies.lower_spec, "upper": bodies.upper_spec})
    curves = result.curves
    typer.echo(
        f"final displacement {float(curves['displacement'][-1]) * 1e3:.4g} nm, "
        f"F_N {float(curves['normal_force'][-1]):.4g} mN/µm, "
        f"A_S {float(curves['contact_area'][-1]):.4g} µm, "
        f"{int(curves['n_contacts'][-1])} contacts -> {output}"
    )


def _fmt(value: float, unit: str = "") -> str:
    text = f"{value:.6g}"
    return f"{text} {unit}".rstrip()


@handle_errors
@with_reading_options(upper=False)
def inspect_command(
    file: Annotated[Path, typer.Argument(help="Measured profile file.")],
    alpha: Annotated[
        float, typer.Option("--alpha", help="Spline tightness α [1] (eq. 3), 0 < α < 3.")
    ] = 2.0,
    x0: X0Opt = 1.0,
    *,
    reading_options: Callable[[], ProfileReading],
) -> None:
    """Print size, roughness and Hurst exponent of a profile; warn about form and coarse grids.

    The grid warning compares the spline's smoothing wavelength 2π(λ·dx)^¼ (eq. 3) with the
    grid spacing: see docs/measured-profiles.md.
    """
    from ..diagnostics import form_diagnostic, grid_diagnostic
    from ..preprocess import spline_resolution

    if not (math.isfinite(alpha) and 0 < alpha < 3):
        raise ParameterError(
            f"--alpha {alpha:g}: the spline tightness exponent must satisfy 0 < α < 3 "
            "(eq. 3; paper: 2)"
        )
    if not (math.isfinite(x0) and x0 > 0):
        raise ParameterError(f"--x0 {x0:g} must be a positive length in µm")
    reading = reading_options()
    if not file.is_file():
        what = (
            "no such file"
            if not file.exists()
            else "is a folder"
            if file.is_dir()
            else "is not a regular file (a device or pipe)"
        )
        raise ProfileReadError(f"{file}: {what}; give a profile file")
    profile = read_body(BodySpec(str(file), "file"), reading)
    meta = profile.metadata
    units = meta.get("units", {})
    rows = [
        ("file", str(file)),
        (
            "format",
            str(meta.get("format", "?")) + (f", line {meta['line']}" if "line" in meta else ""),
        ),
        (
            "units in file",
            f"x {units.get('x', '?')} ({units.get('x_from', '?')}), "
            f"z {units.get('z', '?')} ({units.get('z_from', '?')})",
        ),
        ("points", str(profile.n_points)),
        ("length", _fmt(profile.length, "µm")),
        ("spacing", _fmt(profile.dx, "µm")),
        ("x range", f"{profile.x[0]:.6g} … {profile.x[-1]:.6g} µm"),
        ("R_A", _fmt(profile.ra, "µm")),
        ("R_q", _fmt(profile.rq, "µm")),
        ("R_Sq", _fmt(profile.rsq) + " (rms slope, grid differences, eq. 15)"),
        ("peak-to-valley", _fmt(profile.peak_to_valley, "µm")),
        ("Hurst exponent", _hurst_text(profile)),
    ]
    steps = meta.get("preprocessing", [])
    rows.append(("preprocessing", ", ".join(s["step"] for s in steps) if steps else "none"))
    res = spline_resolution(profile.dx, alpha=alpha, x0=x0)
    rows.append(
        (
            "spline (eq. 3)",
            f"α = {alpha:g}, x0 = {x0:g} µm: λ = {res.lam:.3g} µm³, smoothing wavelength "
            f"2π(λ·dx)^¼ = {res.cutoff_wavelength:.3g} µm = {res.points_per_cutoff:.3g} dx",
        )
    )
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        typer.echo(f"{name:<{width}} : {value}")
    for item in (form_diagnostic(profile), grid_diagnostic(profile.dx, alpha=alpha, x0=x0)):
        if item is not None:
            warn(item.message)


def _hurst_text(profile: Profile) -> str:
    from ..spectra import hurst_exponent

    try:
        h = float(hurst_exponent(profile))
    except (ParameterError, ValueError) as exc:
        return f"n/a ({exc})"
    if not math.isfinite(h):
        return "n/a"
    text = f"{h:.3g} (PSD slope; profile dimension D = 2 − H = {2 - h:.3g})"
    if not 0.0 <= h <= 1.0:
        text += "; outside 0–1: not self-affine in the fitted band (noise, form or steps?)"
    return text


def plot_result(result_file: Path, out_dir: Path, *, overwrite: bool) -> list[Path]:
    """Draw the curves of one ``simulate`` result (.nc) into ``out_dir`` (PNG), atomically.

    The result is read and checked before the folder is touched; the folder follows
    :func:`splinecontact.outputs.prepare_output_folder`.
    """
    from ..outputs import atomic_path, prepare_output_folder

    try:
        import xarray as xr

        ds = xr.open_dataset(result_file, engine="h5netcdf").load()
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ParameterError(
            f"{result_file}: not a readable netCDF result of `splinecontact simulate` "
            f"({type(exc).__name__}: {exc})"
        ) from None
    force = ds.variables.get("normal_force")
    if force is not None and force.dims != ("step",):
        raise ParameterError(
            f"{result_file} holds curves over {', '.join(map(str, force.dims))} (a study "
            "export?); `plot FILE.nc` draws one `simulate` result, `plot STORE` a study store"
        )
    from ..plotting import result_figures

    figures = result_figures(ds, title=result_file.name)
    folder = prepare_output_folder(out_dir, overwrite=overwrite, command="plot")
    written = []
    for stem, fig in figures.items():
        target = folder.file(f"{stem}.png")
        with atomic_path(target) as tmp:
            fig.savefig(tmp, dpi=150, format="png")
        written.append(target)
    return written


def register(app: typer.Typer) -> None:
    """Add ``simulate`` and ``inspect`` to ``app``."""
    app.command("simulate", epilog=BODY_SPEC_HELP)(simulate_command)
    app.command("inspect")(inspect_command)
