"""The reading and preprocessing options, declared once, and the option aliases shared by
several commands: :func:`profile_reading`, :func:`with_reading_options`.

It is imported by ``splinecontact --help``, so it must stay light: numpy, the readers, the
generator (numba) and the solvers are imported inside the functions that use them.
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from ..errors import ParameterError

if TYPE_CHECKING:
    from ..preprocess import Preprocessing

T = TypeVar("T")

__all__ = ["ProfileReading", "profile_reading", "with_reading_options"]

PANEL_READ = "Reading files"
PANEL_PRE = "Preprocessing (applied to every file read)"

FormatOpt = Annotated[
    str | None,
    typer.Option(
        "--format",
        help="table, dektak, x3p, npy, npz or surfacetopography "
        "(default: from extension, else content).",
        rich_help_panel=PANEL_READ,
    ),
]
UnitOpt = Annotated[
    str | None,
    typer.Option(
        "--unit",
        help="Unit of the file's values when its header gives none (um, nm, mm, m, A).",
        rich_help_panel=PANEL_READ,
    ),
]
HeightUnitOpt = Annotated[
    str | None,
    typer.Option(
        "--height-unit",
        help="Unit of the heights if it differs from --unit.",
        rich_help_panel=PANEL_READ,
    ),
]
SpacingOpt = Annotated[
    float | None,
    typer.Option(
        "--spacing", help="Grid spacing [µm] for files of heights only.", rich_help_panel=PANEL_READ
    ),
]
LineOpt = Annotated[
    int | None,
    typer.Option(
        "--line",
        help="Row (0-based) of areal data (X3P, 2-D .npy) to use.",
        rich_help_panel=PANEL_READ,
    ),
]
UpperLineOpt = Annotated[
    int | None,
    typer.Option(
        "--upper-line",
        help="Row of areal data for the upper body (default: --line).",
        rich_help_panel=PANEL_READ,
    ),
]
UpperUnitOpt = Annotated[
    str | None,
    typer.Option(
        "--upper-unit",
        help="Unit of the upper file's values if it differs from --unit.",
        rich_help_panel=PANEL_READ,
    ),
]
UndefinedOpt = Annotated[
    str,
    typer.Option(
        "--undefined",
        help="Undefined points (NaN, invalid flags): refuse or interpolate.",
        rich_help_panel=PANEL_PRE,
    ),
]
OrderOpt = Annotated[
    str, typer.Option("--order", help="x stepping back: refuse or sort.", rich_help_panel=PANEL_PRE)
]
DuplicatesOpt = Annotated[
    str,
    typer.Option("--duplicates", help="Repeated x: refuse or average.", rich_help_panel=PANEL_PRE),
]
NonuniformOpt = Annotated[
    str,
    typer.Option(
        "--nonuniform",
        help="Non-uniform grid: refuse or resample (linear).",
        rich_help_panel=PANEL_PRE,
    ),
]
ResampleSpacingOpt = Annotated[
    float | None,
    typer.Option(
        "--resample-spacing",
        help="Spacing [µm] of the resampled grid (needs --nonuniform resample).",
        rich_help_panel=PANEL_PRE,
    ),
]
CropOpt = Annotated[
    str | None,
    typer.Option(
        "--crop",
        help="Keep X_MIN,X_MAX [µm] (positions in µm after unit conversion).",
        rich_help_panel=PANEL_PRE,
    ),
]
UpperCropOpt = Annotated[
    str | None,
    typer.Option(
        "--upper-crop",
        help="Keep X_MIN,X_MAX [µm] of the upper file (default: --crop).",
        rich_help_panel=PANEL_PRE,
    ),
]
ZeroOriginOpt = Annotated[
    bool, typer.Option("--zero-origin", help="Shift x to start at 0 µm.", rich_help_panel=PANEL_PRE)
]
DetrendOpt = Annotated[
    str,
    typer.Option(
        "--detrend", help="Form removal: none, mean, tilt or polyN.", rich_help_panel=PANEL_PRE
    ),
]
MaxPointsOpt = Annotated[
    int | None,
    typer.Option(
        "--max-points",
        min=1,
        help="Raise the ceiling on points per file read, resampled or generated (defaults: "
        "10⁸ read, the resampling and generator ceilings otherwise).",
        rich_help_panel=PANEL_READ,
    ),
]
#: Model parameters that several commands take with the same name and help.
EStarOpt = Annotated[float, typer.Option("--e-star", help="Effective modulus E* [GPa].")]
GStarOpt = Annotated[
    float | None,
    typer.Option("--g-star", help="Effective shear modulus G* [GPa] (default E*/2.6)."),
]
Mu0Opt = Annotated[float, typer.Option("--mu0", help="Friction coefficient μ0 [1].")]
X0Opt = Annotated[float, typer.Option("--x0", help="Spline unit length x0 [µm] (eq. 3).")]
OverwriteOpt = Annotated[
    bool,
    typer.Option("--overwrite", help="Replace an existing output (never an input)."),
]
QuietOpt = Annotated[bool, typer.Option("--quiet", "-q", help="No progress lines.")]


@dataclass(frozen=True)
class ProfileReading:
    """How every file of one command is read: reader keywords and the preprocessing."""

    read: dict[str, Any]
    upper_read: dict[str, Any]
    preprocessing: Preprocessing
    upper_preprocessing: Preprocessing
    upper_options: tuple[str, ...] = ()
    inherited: tuple[str, ...] = ()
    max_points: int | None = None


def profile_reading(
    *,
    file_format: str | None = None,
    unit: str | None = None,
    height_unit: str | None = None,
    spacing: float | None = None,
    line: int | None = None,
    upper_line: int | None = None,
    upper_unit: str | None = None,
    undefined: str = "refuse",
    order: str = "refuse",
    duplicates: str = "refuse",
    nonuniform: str = "refuse",
    resample_spacing: float | None = None,
    crop: str | None = None,
    upper_crop: str | None = None,
    zero_origin: bool = False,
    detrend: str = "none",
    max_points: int | None = None,
) -> ProfileReading:
    """Turn the shared reading options into the reader keywords and a ``Preprocessing``.

    Raises
    ------
    ParameterError
        Contradictory options (``--resample-spacing`` without ``--nonuniform resample``,
        ``--height-unit`` with ``--upper-unit`` ambiguity), a malformed ``--crop``, a negative
        ``--line``.
    PreprocessingOptionError
        A value ``Preprocessing`` refuses (unknown ``--detrend``, ...).
    """
    from ..preprocess import Preprocessing, PreprocessingOptionError

    if resample_spacing is not None and nonuniform != "resample":
        raise ParameterError(
            f"--resample-spacing {resample_spacing:g} has no effect without --nonuniform "
            "resample; add --nonuniform resample or drop --resample-spacing"
        )
    for name, value in (("--line", line), ("--upper-line", upper_line)):
        if value is not None and value < 0:
            raise ParameterError(f"{name} {value} must be a row number ≥ 0")
    for name, number in (("--spacing", spacing), ("--resample-spacing", resample_spacing)):
        if number is not None and not (math.isfinite(number) and number > 0):
            raise ParameterError(f"{name} {number!r} must be a positive length in µm")

    def crop_range(option: str, text: str | None) -> tuple[float, float] | None:
        if text is None:
            return None
        parts = text.replace(":", ",").split(",")
        try:
            lo, hi = (float(p) for p in parts)
        except ValueError:
            raise PreprocessingOptionError(
                f"{option} {text!r} is not X_MIN,X_MAX in µm (e.g. {option} 100,2000)"
            ) from None
        return (lo, hi)

    def preprocessing_with(window: tuple[float, float] | None) -> Preprocessing:
        return Preprocessing(
            undefined=undefined,  # type: ignore[arg-type]  # validated by Preprocessing
            order=order,  # type: ignore[arg-type]
            duplicates=duplicates,  # type: ignore[arg-type]
            nonuniform=nonuniform,  # type: ignore[arg-type]
            resample_spacing=resample_spacing,
            crop=window,
            zero_origin=zero_origin,
            detrend=detrend,
            **({} if max_points is None else {"max_points": max_points}),
        )

    preprocessing = preprocessing_with(crop_range("--crop", crop))
    upper_preprocessing = (
        preprocessing
        if upper_crop is None
        else preprocessing_with(crop_range("--upper-crop", upper_crop))
    )
    read = {
        "format": file_format,
        "unit": unit,
        "height_unit": height_unit,
        "spacing": spacing,
        "line": line,
        **({} if max_points is None else {"max_points": max_points}),
    }
    upper_read = {**read, "line": line if upper_line is None else upper_line}
    if upper_unit is not None:
        upper_read.update(unit=upper_unit, height_unit=None)
    given = (
        ("--upper-line", upper_line),
        ("--upper-unit", upper_unit),
        ("--upper-crop", upper_crop),
    )
    upper_options = tuple(f"{name} {value}" for name, value in given if value is not None)
    # reader options the upper file takes from the shared ones (dropped if it refuses them)
    inherited = tuple(
        key
        for key, own in (("line", upper_line), ("unit", upper_unit),
                         ("height_unit", upper_unit), ("spacing", upper_unit))
        if own is None and read[key] is not None
    )  # fmt: skip
    return ProfileReading(
        read, upper_read, preprocessing, upper_preprocessing, upper_options, inherited, max_points
    )


#: The option alias of each keyword of :func:`profile_reading` (its signature gives the order
#: and the defaults of the options a command gets from :func:`with_reading_options`).
_READING_OPTIONS: dict[str, Any] = {
    "file_format": FormatOpt,
    "unit": UnitOpt,
    "height_unit": HeightUnitOpt,
    "spacing": SpacingOpt,
    "line": LineOpt,
    "upper_line": UpperLineOpt,
    "upper_unit": UpperUnitOpt,
    "undefined": UndefinedOpt,
    "order": OrderOpt,
    "duplicates": DuplicatesOpt,
    "nonuniform": NonuniformOpt,
    "resample_spacing": ResampleSpacingOpt,
    "crop": CropOpt,
    "upper_crop": UpperCropOpt,
    "zero_origin": ZeroOriginOpt,
    "detrend": DetrendOpt,
    "max_points": MaxPointsOpt,
}


def with_reading_options(*, upper: bool) -> Callable[[Callable[..., T]], Callable[..., T]]:
    """Give a command the shared reading and preprocessing options, declared once.

    The command declares a last parameter ``reading_options: Callable[[], ProfileReading]``.
    In its place the options of :func:`profile_reading` (without the ``--upper-*`` ones unless
    ``upper``) are appended to the command's signature, so ``--help`` lists them after the
    command's own, in one order for every command. ``reading_options()`` calls
    :func:`profile_reading` with their values: the command calls it where its own checks want
    it, so errors keep their order.
    """
    defaults = inspect.signature(profile_reading).parameters
    names = [name for name in defaults if upper or not name.startswith("upper_")]
    added = [
        inspect.Parameter(
            name,
            inspect.Parameter.POSITIONAL_OR_KEYWORD,
            default=defaults[name].default,
            annotation=_READING_OPTIONS[name],
        )
        for name in names
    ]

    def decorate(func: Callable[..., T]) -> Callable[..., T]:
        signature = inspect.signature(func, eval_str=True)
        own = [p for p in signature.parameters.values() if p.name != "reading_options"]
        if len(own) == len(signature.parameters):
            raise TypeError(f"{func.__name__} has no parameter reading_options")

        @functools.wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> T:
            given = {name: kwargs.pop(name, defaults[name].default) for name in names}
            reading = functools.partial(profile_reading, **given)
            return func(*args, reading_options=reading, **kwargs)

        parameters = [*own, *added]
        wrapper.__signature__ = signature.replace(parameters=parameters)  # type: ignore[attr-defined]
        wrapper.__annotations__ = {p.name: p.annotation for p in parameters}
        wrapper.__annotations__["return"] = signature.return_annotation
        return wrapper

    return decorate
