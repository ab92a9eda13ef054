"""Shared parts of the command line: one error line, the profile-reading options, body specs.

Everything here is imported by ``splinecontact --help``, so it must stay light: numpy, the
readers, the generator (numba) and the solvers are imported inside the functions that use them.

Body specs (``--lower``, ``--upper``, ``inspect FILE``)
    ``FILE``
        A measured profile, read with the reading and preprocessing options below.
    ``flat``
        A rigid flat (upper body only).
    ``generated:D=1.5,seed=3,n_points=65536``
        A Weierstrass–Mandelbrot profile (eq. 1). Keys are the study-file parameter names:
        ``D`` (or ``dimension``), ``seed``, ``n_points``, ``length`` [µm], ``wavelength``
        [µm], ``gamma``, ``directions``, ``n_max``, ``ra`` [µm], ``amplitude_law``. Without a
        seed one is drawn, printed and stored with the result. Without ``n_points`` and
        ``length`` a generated body takes the grid of the other body when that is a file.
    ``generated`` (upper only, with a generated lower body)
        The lower body's parameters with the next seed (seed + 1): an independent profile.
"""

from __future__ import annotations

import contextlib
import difflib
import functools
import inspect
import io
import math
import os
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, ParamSpec, TypeVar

import typer

from ..errors import GridMismatchError, ParameterError, ProfileReadError, SplineContactError

if TYPE_CHECKING:
    from ..preprocess import Preprocessing
    from ..profile import Profile

P = ParamSpec("P")
T = TypeVar("T")

__all__ = [
    "Bodies",
    "BodySpec",
    "ProfileReading",
    "fail",
    "handle_errors",
    "load_bodies",
    "parse_body_spec",
    "parse_generated_spec",
    "profile_reading",
    "with_reading_options",
]

#: The body-spec grammar, shown under the options of every command that takes a body.
BODY_SPEC_HELP = (
    "Bodies: FILE (read with the options above), flat (upper only), or "
    "generated:D=1.5,seed=3,n_points=65536,length=100 (keys D, seed, n_points, length [µm], "
    "wavelength [µm], gamma, directions, n_max, ra [µm], amplitude_law: the study-file names; "
    "without a seed one is drawn, printed and stored; without n_points/length the grid of a "
    "FILE body is used). --upper generated: the lower's parameters with seed + 1."
)

#: Largest seed accepted (the study files' range: 0 ≤ seed < 2⁶³).
MAX_SEED = 2**63 - 1


# --- one error line -------------------------------------------------------------------------


def fail(message: str, code: int = 1) -> typer.Exit:
    """Print ``error: message`` on standard error and return the ``typer.Exit`` to raise."""
    typer.secho(f"error: {message}", err=True, fg=typer.colors.RED)
    return typer.Exit(code)


def warn(message: str) -> None:
    """Print ``warning: message`` on standard error."""
    typer.secho(f"warning: {message}", err=True, fg=typer.colors.YELLOW)


@contextlib.contextmanager
def _native_stderr_held() -> Iterator[list[bytes]]:
    """Send what native code (LAPACK, numba) writes to file descriptor 2 to a temporary file.

    Python's own ``sys.stderr`` keeps writing to the terminal (through a duplicate of the
    descriptor), so progress lines still appear at once. The held bytes are put in the yielded
    list when the block ends; the caller decides whether to show them (success) or not (an
    error, which must be one line). Does nothing when ``sys.stderr`` is not descriptor 2 (tests).
    """
    held: list[bytes] = []
    try:
        if sys.stderr is None or sys.stderr.fileno() != 2:
            raise ValueError
    except (AttributeError, ValueError, OSError, io.UnsupportedOperation):
        yield held
        return
    sys.stderr.flush()
    saved = os.dup(2)
    spool = tempfile.TemporaryFile()
    old_stderr = sys.stderr
    replacement = io.TextIOWrapper(
        open(os.dup(saved), "wb", buffering=0),  # closed with it in the finally below
        encoding=old_stderr.encoding or "utf-8",
        errors="backslashreplace",
        line_buffering=True,
        write_through=True,
    )
    os.dup2(spool.fileno(), 2)
    sys.stderr = replacement
    try:
        yield held
    finally:
        with contextlib.suppress(OSError, ValueError):
            replacement.flush()
        sys.stderr = old_stderr
        os.dup2(saved, 2)
        os.close(saved)
        replacement.close()
        spool.seek(0)
        held.append(spool.read())
        spool.close()


# The library's errors name its keyword arguments; on the command line the same ceilings are
# raised with options.
_CLI_HINTS = (
    ("pass a larger max_points= to read_profile", "pass a larger --max-points"),
    ("pass max_points= to allow more", "pass --max-points to allow more"),
    ("raise Preprocessing.max_points", "raise it with --max-points"),
    ("pass max_steps= to allow more", "pass --max-steps to allow more"),
)


def _cli_hints(text: str) -> str:
    for api, cli in _CLI_HINTS:
        text = text.replace(api, cli)
    return text


def handle_errors(func: Callable[P, T]) -> Callable[P, T]:
    """Decorate a command: expected errors become exactly one line on stderr and exit code 1.

    Expected errors are :class:`SplineContactError`, operating-system errors of file handling
    (missing file, permission denied, disk full) and running out of memory. Warnings and native
    library chatter raised before such an error are dropped, so the error line is the only
    line; on success they are shown (warnings as ``warning: ...`` lines). Anything else is a
    bug and keeps its traceback.
    """

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> T:
        message: str | None = None
        with (
            _native_stderr_held() as native,
            warnings.catch_warnings(record=True) as caught,
        ):
            warnings.simplefilter("default")
            try:
                result = func(*args, **kwargs)
            except SplineContactError as exc:
                message = f"{type(exc).__name__}: {_cli_hints(str(exc))}"
            except MemoryError:
                message = (
                    "MemoryError: out of memory; use fewer points (n_points=, --crop, "
                    "--resample-spacing) or fewer --steps; nothing was written"
                )
            except OSError as exc:
                message = f"{type(exc).__name__}: {exc}"
        if message is not None:
            raise fail(" ".join(message.split())) from None
        if native and native[0]:
            sys.stderr.write(native[0].decode("utf-8", "backslashreplace"))
        seen: set[tuple[type, str]] = set()
        for item in caught:
            key = (item.category, str(item.message))
            if key in seen:
                continue
            seen.add(key)
            from ..diagnostics import SimulationWarning

            text = str(item.message)
            if not issubclass(item.category, SimulationWarning):
                text = f"{item.category.__name__}: {text}"
            warn(text)
        return result

    return wrapper


# --- the reading and preprocessing options, defined once ------------------------------------

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


# --- body specs -----------------------------------------------------------------------------

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
_KEYWORDS = ("flat", "generated")


def _number(spec: str, name: str, text: str, kind: type) -> Any:
    value = text.strip()
    if kind is str:
        if value not in ("hurst", "as_printed"):
            raise ParameterError(f"{spec!r}: {name}={value!r}: use 'hurst' or 'as_printed'")
        return value
    digits = value.lstrip("+-")
    if kind is int and digits.isdigit() and digits.isascii():
        integer = int(value)  # exact, however large
        if abs(integer) > MAX_SEED:
            raise ParameterError(f"{spec!r}: {name}={value} is out of range (≥ 2^63)")
    else:
        try:
            number = float(value)
        except ValueError:
            raise ParameterError(
                f"{spec!r}: {name}={value!r} is not a valid {kind.__name__}"
            ) from None
        if not math.isfinite(number):
            raise ParameterError(f"{spec!r}: {name}={value!r} must be a finite number")
        if kind is float:
            return number
        if number != int(number) or abs(number) >= 2.0**63:
            raise ParameterError(f"{spec!r}: {name}={value!r} is not a valid int (whole number)")
        integer = int(number)
    if name == "seed" and not 0 <= integer <= MAX_SEED:
        raise ParameterError(f"{spec!r}: seed={value} must be an integer 0 ≤ seed < 2^63")
    if name != "seed" and integer < 0:
        raise ParameterError(f"{spec!r}: {name}={value} must not be negative")
    return integer


def parse_generated_spec(spec: str, *, require_dimension: bool = True) -> dict[str, Any]:
    """Keyword arguments of ``weierstrass_mandelbrot`` from ``generated:D=1.5,seed=3,...``.

    Parameters
    ----------
    spec : str
        The spec text.
    require_dimension : bool
        Whether ``D`` must be given.

    Raises
    ------
    ParameterError
        Unknown key, value of the wrong type, non-finite or negative values, a seed outside
        0 ≤ seed < 2⁶³, or no dimension.
    """
    head, _, body = spec.partition(":")
    if head.strip().lower() != "generated":
        raise ParameterError(f"{spec!r} is not generated:KEY=VALUE,...")
    kwargs: dict[str, Any] = {}
    for item in filter(None, (part.strip() for part in body.split(","))):
        key, eq, value = item.partition("=")
        key = key.strip()
        name = "dimension" if key in ("D", "d", "dimension") else key
        if not eq or name not in _GENERATED_KEYS:
            raise ParameterError(
                f"{spec!r}: {item!r} is not KEY=VALUE with KEY one of D, "
                f"{', '.join(k for k in _GENERATED_KEYS if k != 'dimension')}"
            )
        kwargs[name] = _number(spec, name, value, _GENERATED_KEYS[name])
    if require_dimension and "dimension" not in kwargs:
        raise ParameterError(f"{spec!r}: give the fractal dimension, e.g. generated:D=1.5,seed=3")
    return kwargs


def format_generated_spec(kwargs: dict[str, Any]) -> str:
    """The ``generated:`` spec text of keyword arguments (``D`` first, then ``seed``)."""
    parts = [f"D={kwargs['dimension']!r}"]
    parts += [f"{k}={kwargs[k]}" for k in _GENERATED_KEYS if k != "dimension" and k in kwargs]
    return "generated:" + ",".join(parts)


@dataclass(frozen=True)
class BodySpec:
    """A parsed body spec: a file, a rigid flat or a generated profile."""

    text: str
    kind: Literal["file", "flat", "generated"]
    generated: dict[str, Any] = field(default_factory=dict)

    @property
    def path(self) -> Path:
        """The file of a ``file`` spec."""
        return Path(self.text)


def parse_body_spec(text: str, *, option: str) -> BodySpec:
    """Parse ``FILE``, ``flat`` or ``generated[:...]`` for the option ``option``.

    Raises
    ------
    ParameterError
        ``flat`` for the lower body, a malformed ``generated:`` spec, or a name that is neither
        a file nor a keyword (with a "did you mean" hint when it is close to one).
    """
    stripped = text.strip()
    word = stripped.lower()
    if word == "flat":
        if option == "--lower":
            raise ParameterError("--lower flat: the lower body must be a rough profile")
        return BodySpec(stripped, "flat")
    if word == "generated" or word.startswith("generated:"):
        kwargs = parse_generated_spec(stripped, require_dimension=word != "generated")
        return BodySpec(stripped, "generated", kwargs)
    path = Path(stripped)
    if not path.exists():
        head = word.split(":", 1)[0]
        close = difflib.get_close_matches(head, _KEYWORDS, n=1, cutoff=0.6)
        choices = "flat, " if option != "--lower" else ""
        if close and (option != "--lower" or close[0] != "flat"):
            raise ParameterError(f"{option} {text!r}: no such file; did you mean `{close[0]}`?")
        raise ProfileReadError(
            f"{option} {text!r}: no such file (a body is a FILE, {choices}"
            "or generated:D=1.5,seed=3)"
        )
    if path.is_dir():
        raise ProfileReadError(f"{option} {text!r} is a folder; give a profile file")
    if not path.is_file():
        raise ProfileReadError(
            f"{option} {text!r} is not a regular file (a device or pipe); give a profile file"
        )
    return BodySpec(stripped, "file")


@dataclass(frozen=True)
class Bodies:
    """The two bodies of a run, with the spec of each as used (seeds filled in)."""

    lower: Profile
    upper: Profile | Literal["flat"]
    lower_spec: str
    upper_spec: str
    notes: tuple[str, ...] = ()
    inputs: tuple[Path, ...] = ()


def _draw_seed() -> int:
    import secrets

    return secrets.randbelow(2**32)


def _generate(kwargs: dict[str, Any], option: str, max_points: int | None = None) -> Profile:
    from ..generate import weierstrass_mandelbrot

    try:
        if max_points is not None:
            return weierstrass_mandelbrot(**kwargs, max_points=max_points)
        return weierstrass_mandelbrot(**kwargs)
    except SplineContactError:
        raise
    except (OverflowError, ValueError, TypeError, FloatingPointError, ZeroDivisionError) as exc:
        raise ParameterError(
            f"{option} {format_generated_spec(kwargs)}: these parameters cannot be generated "
            f"({type(exc).__name__}: {exc}); use smaller values"
        ) from None


def read_body(
    spec: BodySpec, reading: ProfileReading, *, upper: bool = False, two_files: bool = False
) -> Profile:
    """Read a ``file`` spec with the command's reading options.

    With two files, the reader's option hints name the option that reaches the body at hand
    (``--upper-line``/``--upper-unit`` for the upper file).
    """
    from ..errors import ReadOptionError
    from ..io import read_profile

    read = reading.upper_read if upper else reading.read
    preprocessing = reading.upper_preprocessing if upper else reading.preprocessing
    try:
        try:
            return read_profile(spec.path, preprocessing=preprocessing, **read)
        except ReadOptionError:
            # --line/--unit/--spacing are meant for the lower file: an upper file that states
            # its own units or is not areal is read without them
            if not (upper and reading.inherited):
                raise
            own = {**read, **{key: None for key in reading.inherited}}
            return read_profile(spec.path, preprocessing=preprocessing, **own)
    except ProfileReadError as exc:
        if not two_files:
            raise
        text = str(exc)
        if upper:
            text = text.replace("CLI --line", "CLI --upper-line").replace(
                "CLI --unit", "CLI --upper-unit"
            )
        if "line= is only for areal data" in text:
            text += (
                "; --line applies to both bodies: give the upper file its row with "
                "--upper-line instead"
                if not upper
                else "; drop --line and give the lower file its row with --line only if it "
                "is areal (--upper-line for the upper)"
            )
        if text == str(exc):
            raise
        raise type(exc)(text) from None


def load_bodies(
    lower_text: str,
    upper_text: str,
    reading: ProfileReading,
    *,
    default_n_points: int | None = None,
) -> Bodies:
    """Build both bodies of a command from their specs, under one grammar.

    Parameters
    ----------
    lower_text, upper_text : str
        The ``--lower`` and ``--upper`` specs.
    reading : ProfileReading
        From :func:`profile_reading`.
    default_n_points : int, optional
        Grid points of a generated body that gives neither ``n_points`` nor ``length`` and has
        no file to take its grid from (default: the generator's).

    Raises
    ------
    ParameterError
        A bare ``generated`` without a generated lower body, an upper body equal to the lower
        one, a spec that cannot be generated.
    GridMismatchError
        The two bodies do not share a grid.
    """
    lo = parse_body_spec(lower_text, option="--lower")
    up = parse_body_spec(upper_text, option="--upper")
    if lo.kind == "generated" and "dimension" not in lo.generated:
        raise ParameterError(
            "--lower generated: give the fractal dimension, e.g. generated:D=1.5,seed=3"
        )
    if up.kind != "file" and reading.upper_options:
        raise ParameterError(
            f"{reading.upper_options[0]} needs an upper FILE, not --upper {upper_text!r}"
        )
    notes: list[str] = []
    inputs = tuple(s.path for s in (lo, up) if s.kind == "file")
    two = lo.kind == "file" and up.kind == "file"
    lower_file = read_body(lo, reading, two_files=two) if lo.kind == "file" else None
    upper_file = read_body(up, reading, upper=True, two_files=two) if up.kind == "file" else None

    def resolve(spec: BodySpec, option: str, grid: Profile | None) -> dict[str, Any]:
        kwargs = dict(spec.generated)
        if "n_points" not in kwargs and "length" not in kwargs:
            if grid is not None:
                kwargs["n_points"], kwargs["length"] = grid.n_points, grid.length
            elif default_n_points is not None:
                kwargs["n_points"] = default_n_points
        if "seed" not in kwargs:
            kwargs["seed"] = _draw_seed()
            notes.append(
                f"{option} {format_generated_spec(kwargs)} (seed drawn at random; give it to "
                "repeat this run)"
            )
        return kwargs

    lower_kwargs: dict[str, Any] = {}
    if lo.kind == "generated":
        lower_kwargs = resolve(lo, "--lower", upper_file)
        lower: Profile = _generate(lower_kwargs, "--lower", reading.max_points)
        lower_spec = format_generated_spec(lower_kwargs)
    else:
        assert lower_file is not None
        lower, lower_spec = lower_file, lo.text

    upper_body: Profile | Literal["flat"]
    if up.kind == "flat":
        upper_body, upper_spec = "flat", "flat"
    elif up.kind == "file":
        assert upper_file is not None
        upper_body, upper_spec = upper_file, up.text
    else:
        if "dimension" not in up.generated:
            if lo.kind != "generated":
                raise ParameterError(
                    "--upper generated: give its fractal dimension, e.g. "
                    "--upper generated:D=1.5,seed=4 (a bare `generated` copies a generated "
                    "lower body's parameters with the next seed)"
                )
            kwargs = {**lower_kwargs, **up.generated}
            if "seed" not in up.generated:
                if lower_kwargs["seed"] >= MAX_SEED:
                    raise ParameterError("--lower seed 2^63 − 1 has no next seed for --upper")
                kwargs["seed"] = lower_kwargs["seed"] + 1
            upper_kwargs = kwargs
            notes.append(f"--upper {format_generated_spec(upper_kwargs)}")
        else:
            upper_kwargs = resolve(up, "--upper", lower)
        if lo.kind == "generated" and upper_kwargs == lower_kwargs:
            raise ParameterError(
                f"--upper {format_generated_spec(upper_kwargs)} is the same profile as --lower "
                "(same parameters and seed); give the upper body another seed"
            )
        upper_body = _generate(upper_kwargs, "--upper", reading.max_points)
        upper_spec = format_generated_spec(upper_kwargs)
    if not isinstance(upper_body, str):
        check_grids(lower, upper_body, lower_spec, upper_spec)
    return Bodies(lower, upper_body, lower_spec, upper_spec, tuple(notes), inputs)


def check_grids(lower: Profile, upper: Profile, lower_spec: str, upper_spec: str) -> None:
    """Refuse two bodies that do not share one grid (with the options that make them)."""
    from ..profile import UNIFORM_GRID_RTOL

    same_n = lower.n_points == upper.n_points
    same_dx = abs(lower.dx - upper.dx) <= UNIFORM_GRID_RTOL * lower.dx
    if same_n and same_dx:
        return
    raise GridMismatchError(
        f"the grids differ: lower {lower_spec} has {lower.n_points} points at dx = "
        f"{lower.dx:.6g} µm (length {lower.length:.6g} µm), upper {upper_spec} has "
        f"{upper.n_points} points at dx = {upper.dx:.6g} µm (length {upper.length:.6g} µm); "
        "make them share one grid: --nonuniform resample --resample-spacing DX, and "
        "--crop X_MIN,X_MAX for the lower, --upper-crop X_MIN,X_MAX for the upper (each in "
        "its file's own x, ranges of equal length)"
    )
