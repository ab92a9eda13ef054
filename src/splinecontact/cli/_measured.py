"""Commands for measured profiles: ``simulate`` (files, flats, generated profiles) and ``inspect``.

A profile SPEC is a file path, ``flat`` (upper body only: a rigid flat), or a generated
Weierstrass–Mandelbrot profile ``generated:D=1.5,seed=3,n_points=100000`` (keys: ``D`` or
``dimension``, ``seed``, ``n_points``, ``length`` [µm], ``wavelength`` [µm], ``gamma``,
``directions``, ``n_max``, ``ra`` [µm], ``amplitude_law``). A generated profile without
``n_points`` and ``length`` takes the grid of the other body when that is a file.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Annotated, Any, Literal

import typer

from ..errors import GridMismatchError, ParameterError, SplineContactError
from ..io import read_profile
from ..preprocess import Preprocessing, PreprocessingOptionError, spline_resolution
from ..profile import UNIFORM_GRID_RTOL, Profile
from ._common import handle_errors

__all__ = ["OutputWriteError", "parse_generated_spec", "register"]

_PANEL_READ = "Reading files"
_PANEL_PRE = "Preprocessing (applied to every file read)"

FormatOpt = Annotated[
    str | None,
    typer.Option(
        "--format",
        help="table, dektak, x3p, npy, npz or surfacetopography "
        "(default: from extension, else content).",
        rich_help_panel=_PANEL_READ,
    ),
]
UnitOpt = Annotated[
    str | None,
    typer.Option(
        "--unit",
        help="Unit of the file's values when its header gives none (um, nm, mm, m, A).",
        rich_help_panel=_PANEL_READ,
    ),
]
HeightUnitOpt = Annotated[
    str | None,
    typer.Option(
        "--height-unit",
        help="Unit of the heights if it differs from --unit.",
        rich_help_panel=_PANEL_READ,
    ),
]
SpacingOpt = Annotated[
    float | None,
    typer.Option(
        "--spacing",
        help="Grid spacing [µm] for files of heights only.",
        rich_help_panel=_PANEL_READ,
    ),
]
LineOpt = Annotated[
    int | None,
    typer.Option(
        "--line",
        help="Row (0-based) of areal data (X3P, 2-D .npy) to use.",
        rich_help_panel=_PANEL_READ,
    ),
]
UndefinedOpt = Annotated[
    str,
    typer.Option(
        "--undefined",
        help="Undefined points (NaN, invalid flags): refuse or interpolate.",
        rich_help_panel=_PANEL_PRE,
    ),
]
OrderOpt = Annotated[
    str,
    typer.Option("--order", help="x stepping back: refuse or sort.", rich_help_panel=_PANEL_PRE),
]
DuplicatesOpt = Annotated[
    str,
    typer.Option("--duplicates", help="Repeated x: refuse or average.", rich_help_panel=_PANEL_PRE),
]
NonuniformOpt = Annotated[
    str,
    typer.Option(
        "--nonuniform",
        help="Non-uniform grid: refuse or resample (linear).",
        rich_help_panel=_PANEL_PRE,
    ),
]
ResampleSpacingOpt = Annotated[
    float | None,
    typer.Option(
        "--resample-spacing",
        help="Spacing [µm] of the resampled grid (with --nonuniform resample).",
        rich_help_panel=_PANEL_PRE,
    ),
]
CropOpt = Annotated[
    str | None,
    typer.Option(
        "--crop",
        help="Keep X_MIN,X_MAX [µm] (positions in µm after unit conversion).",
        rich_help_panel=_PANEL_PRE,
    ),
]
ZeroOriginOpt = Annotated[
    bool,
    typer.Option("--zero-origin", help="Shift x to start at 0 µm.", rich_help_panel=_PANEL_PRE),
]
DetrendOpt = Annotated[
    str,
    typer.Option(
        "--detrend", help="Form removal: none, mean, tilt or polyN.", rich_help_panel=_PANEL_PRE
    ),
]

_GENERATED_KEYS: dict[str, type] = {
    "dimension": float,
    "seed": int,
    "n_points": int,
    "length": float,
    "wavelength": float,
    "gamma": float,
    "directions": int,
    "n_max": int,
    "ra": float,
    "amplitude_law": str,
}


def parse_generated_spec(spec: str) -> dict[str, Any]:
    """Keyword arguments of ``weierstrass_mandelbrot`` from ``generated:D=1.5,seed=3,...``.

    Raises
    ------
    ParameterError
        Unknown key, value of the wrong type, or no dimension.
    """
    body = spec.split(":", 1)[1] if ":" in spec else ""
    kwargs: dict[str, Any] = {}
    for item in filter(None, (part.strip() for part in body.split(","))):
        key, sep, value = item.partition("=")
        key = key.strip()
        name = "dimension" if key in ("D", "d", "dimension") else key
        if not sep or name not in _GENERATED_KEYS:
            raise ParameterError(
                f"{spec!r}: {item!r} is not KEY=VALUE with KEY one of D, "
                f"{', '.join(k for k in _GENERATED_KEYS if k != 'dimension')}"
            )
        kind = _GENERATED_KEYS[name]
        try:
            kwargs[name] = kind(float(value) if kind is int and "e" in value.lower() else value)
        except ValueError:
            raise ParameterError(
                f"{spec!r}: {name}={value!r} is not a valid {kind.__name__}"
            ) from None
    if "dimension" not in kwargs:
        raise ParameterError(f"{spec!r}: give the fractal dimension, e.g. generated:D=1.5,seed=3")
    return kwargs


def _preprocessing(
    undefined: str,
    order: str,
    duplicates: str,
    nonuniform: str,
    resample_spacing: float | None,
    crop: str | None,
    zero_origin: bool,
    detrend: str,
) -> Preprocessing:
    crop_range = None
    if crop is not None:
        parts = crop.replace(":", ",").split(",")
        try:
            lo, hi = (float(p) for p in parts)
        except ValueError:
            raise PreprocessingOptionError(
                f"--crop {crop!r} is not X_MIN,X_MAX in µm (e.g. --crop 100,2000)"
            ) from None
        crop_range = (lo, hi)
    return Preprocessing(
        undefined=undefined,  # type: ignore[arg-type]  # validated by Preprocessing
        order=order,  # type: ignore[arg-type]
        duplicates=duplicates,  # type: ignore[arg-type]
        nonuniform=nonuniform,  # type: ignore[arg-type]
        resample_spacing=resample_spacing,
        crop=crop_range,
        zero_origin=zero_origin,
        detrend=detrend,
    )


def _load(
    spec: str,
    *,
    role: str,
    read: dict[str, Any],
    preprocessing: Preprocessing,
    other: Profile | None = None,
) -> Profile | Literal["flat"]:
    text = spec.strip()
    if text.lower() == "flat":
        if role == "lower":
            raise ParameterError("--lower flat: the lower body must be a rough profile")
        return "flat"
    if text.lower().startswith("generated"):
        from ..generate import weierstrass_mandelbrot

        kwargs = parse_generated_spec(text)
        if other is not None and "n_points" not in kwargs and "length" not in kwargs:
            kwargs["n_points"] = other.n_points
            kwargs["length"] = other.length
        return weierstrass_mandelbrot(**kwargs)
    return read_profile(Path(text), preprocessing=preprocessing, **read)


def _is_generated(spec: str) -> bool:
    return spec.strip().lower().startswith("generated")


def _check_grids(lower: Profile, upper: Profile, lower_spec: str, upper_spec: str) -> None:
    same_n = lower.n_points == upper.n_points
    same_dx = abs(lower.dx - upper.dx) <= UNIFORM_GRID_RTOL * lower.dx
    if same_n and same_dx:
        return
    raise GridMismatchError(
        f"the grids differ: lower {lower_spec} has {lower.n_points} points at dx = "
        f"{lower.dx:.6g} µm (length {lower.length:.6g} µm), upper {upper_spec} has "
        f"{upper.n_points} points at dx = {upper.dx:.6g} µm (length {upper.length:.6g} µm); "
        "make them share one grid, e.g. --nonuniform resample --resample-spacing DX and "
        "--crop X_MIN,X_MAX (with --zero-origin)"
    )


class OutputWriteError(SplineContactError):
    """The result file cannot be written (e.g. the netCDF-4 backend is missing)."""


def _write_atomically(result: Any, output: Path) -> None:
    """Write ``result`` to a temporary name and rename it: a failure leaves nothing behind."""
    tmp = output.with_name(f".{output.name}.tmp-{os.getpid()}.nc")
    try:
        result.to_netcdf(tmp)
        os.replace(tmp, output)
    except ImportError as exc:
        raise OutputWriteError(
            f"cannot write {output}: netCDF-4 writing needs h5py ({exc}); install it with "
            "`pip install h5py`"
        ) from None
    finally:
        if tmp.exists():
            tmp.unlink()


@handle_errors
def simulate_command(
    lower: Annotated[
        str, typer.Option("--lower", help="Lower body: FILE or generated:D=..,seed=..")
    ],
    output: Annotated[Path, typer.Option("--output", "-o", help="Result file (netCDF, .nc).")],
    upper: Annotated[
        str, typer.Option("--upper", help="Upper body: FILE, flat or generated:D=..,seed=..")
    ] = "flat",
    steps: Annotated[int, typer.Option("--steps", help="Displacement increments [1].")] = 1000,
    final_displacement: Annotated[
        float | None,
        typer.Option(
            "--final-displacement",
            help="Final displacement [µm] (default: 0.2 × the lower peak-to-valley height).",
        ),
    ] = None,
    e_star: Annotated[float, typer.Option("--e-star", help="Effective modulus E* [GPa].")] = 10.0,
    g_star: Annotated[
        float | None,
        typer.Option("--g-star", help="Effective shear modulus G* [GPa] (default E*/2.6)."),
    ] = None,
    mu0: Annotated[float, typer.Option("--mu0", help="Friction coefficient μ0 [1].")] = 0.3,
    alpha: Annotated[float, typer.Option("--alpha", help="Spline tightness α [1] (eq. 3).")] = 2.0,
    x0: Annotated[float, typer.Option("--x0", help="Spline unit length x0 [µm] (eq. 3).")] = 1.0,
    file_format: FormatOpt = None,
    unit: UnitOpt = None,
    height_unit: HeightUnitOpt = None,
    spacing: SpacingOpt = None,
    line: LineOpt = None,
    upper_line: Annotated[
        int | None,
        typer.Option(
            "--upper-line",
            help="Row of areal data for the upper body (default: --line).",
            rich_help_panel=_PANEL_READ,
        ),
    ] = None,
    upper_unit: Annotated[
        str | None,
        typer.Option(
            "--upper-unit",
            help="Unit of the upper file's values if it differs from --unit.",
            rich_help_panel=_PANEL_READ,
        ),
    ] = None,
    undefined: UndefinedOpt = "refuse",
    order: OrderOpt = "refuse",
    duplicates: DuplicatesOpt = "refuse",
    nonuniform: NonuniformOpt = "refuse",
    resample_spacing: ResampleSpacingOpt = None,
    crop: CropOpt = None,
    zero_origin: ZeroOriginOpt = False,
    detrend: DetrendOpt = "none",
) -> None:
    """Press two measured (or generated) profiles together, or one against a rigid flat.

    Writes every per-step curve to OUTPUT (netCDF, with units) and prints one summary line.
    Nothing is written when anything fails.
    """
    from ..contact import simulate

    if output.exists() and output.is_dir():
        raise ParameterError(f"--output {output} is a directory; give a file name such as out.nc")
    if not output.parent.exists():
        raise ParameterError(f"--output {output}: the directory {output.parent} does not exist")
    preprocessing = _preprocessing(
        undefined, order, duplicates, nonuniform, resample_spacing, crop, zero_origin, detrend
    )
    read = {
        "format": file_format,
        "unit": unit,
        "height_unit": height_unit,
        "spacing": spacing,
        "line": line,
    }
    upper_read = {**read, "line": line if upper_line is None else upper_line}
    if upper_unit is not None:
        upper_read.update(unit=upper_unit, height_unit=None)
    if _is_generated(lower) and not _is_generated(upper) and upper.strip().lower() != "flat":
        upper_profile = _load(upper, role="upper", read=upper_read, preprocessing=preprocessing)
        assert isinstance(upper_profile, Profile)
        lower_profile = _load(
            lower, role="lower", read=read, preprocessing=preprocessing, other=upper_profile
        )
    else:
        lower_profile = _load(lower, role="lower", read=read, preprocessing=preprocessing)
        assert isinstance(lower_profile, Profile)
        upper_profile = _load(
            upper, role="upper", read=upper_read, preprocessing=preprocessing, other=lower_profile
        )
    assert isinstance(lower_profile, Profile)
    if isinstance(upper_profile, Profile):
        _check_grids(lower_profile, upper_profile, lower, upper)
    result = simulate(
        lower_profile,
        upper_profile,
        steps=steps,
        final_displacement=final_displacement,
        e_star=e_star,
        g_star=g_star,
        mu0=mu0,
        alpha=alpha,
        x0=x0,
    )
    _write_atomically(result, output)
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
def inspect_command(
    file: Annotated[Path, typer.Argument(help="Measured profile file.")],
    alpha: Annotated[float, typer.Option("--alpha", help="Spline tightness α [1] (eq. 3).")] = 2.0,
    x0: Annotated[float, typer.Option("--x0", help="Spline unit length x0 [µm] (eq. 3).")] = 1.0,
    file_format: FormatOpt = None,
    unit: UnitOpt = None,
    height_unit: HeightUnitOpt = None,
    spacing: SpacingOpt = None,
    line: LineOpt = None,
    undefined: UndefinedOpt = "refuse",
    order: OrderOpt = "refuse",
    duplicates: DuplicatesOpt = "refuse",
    nonuniform: NonuniformOpt = "refuse",
    resample_spacing: ResampleSpacingOpt = None,
    crop: CropOpt = None,
    zero_origin: ZeroOriginOpt = False,
    detrend: DetrendOpt = "none",
) -> None:
    """Print size, roughness and Hurst exponent of a profile; warn if its grid is too coarse.

    The warning compares the spline's smoothing wavelength 2π(λ·dx)^¼ (eq. 3) with the grid
    spacing: see docs/measured-profiles.md.
    """
    preprocessing = _preprocessing(
        undefined, order, duplicates, nonuniform, resample_spacing, crop, zero_origin, detrend
    )
    profile = read_profile(
        file, format=file_format, unit=unit, height_unit=height_unit, spacing=spacing,
        line=line, preprocessing=preprocessing,
    )  # fmt: skip
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
    if res.interpolates:
        typer.secho(
            f"warning: the spacing {profile.dx:.3g} µm is coarser than the spline's smoothing "
            f"wavelength ({res.cutoff_wavelength:.3g} µm < 2 dx): the spline passes through "
            "every measured point, noise included, and the sphere radii (eq. 5) come from "
            f"point-to-point curvature; raise --x0 to ≥ {res.x0_for_limit:.3g} µm "
            "or use a finer scan",
            err=True,
            fg=typer.colors.YELLOW,
        )
    elif res.coarse:
        hint = (
            f"; to smooth at ≤ {100 * 0.05:.0f} % bias use --x0 ≥ {res.x0_for_limit:.3g} µm "
            "or a finer scan"
            if res.x0_for_limit is not None
            else "; use a finer scan"
        )
        typer.secho(
            f"warning: the spacing {profile.dx:.3g} µm is coarse for the spline: the shortest "
            f"feature it keeps ({res.cutoff_wavelength:.3g} µm) spans only "
            f"{res.points_per_cutoff:.2g} grid points (paper: 35), so its curvature and the "
            f"sphere radii of eq. 5 are off by {100 * res.curvature_bias:.0f} %{hint}",
            err=True,
            fg=typer.colors.YELLOW,
        )


def _hurst_text(profile: Profile) -> str:
    try:
        from ..spectra import hurst_exponent
    except ImportError:  # pragma: no cover - the spectra module is part of the package
        return "unavailable (splinecontact.spectra missing)"
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


def register(app: typer.Typer) -> None:
    """Add ``simulate`` and ``inspect`` to ``app``."""
    app.command("simulate")(simulate_command)
    app.command("inspect")(inspect_command)
