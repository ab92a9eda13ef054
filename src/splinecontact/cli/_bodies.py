"""Bodies of the commands that take two profiles: body specs, reading them, checking grids.

It is imported by ``splinecontact --help``, so it must stay light: numpy, the readers, the
generator (numba) and the solvers are imported inside the functions that use them.

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

import difflib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from ..errors import GridMismatchError, ParameterError, ProfileReadError, SplineContactError
from ._reading import ProfileReading

if TYPE_CHECKING:
    from ..profile import Profile


__all__ = [
    "Bodies",
    "BodySpec",
    "body_files",
    "check_grids",
    "load_bodies",
    "parse_body_spec",
    "parse_generated_spec",
    "read_body",
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


def body_files(lower_text: str, upper_text: str) -> list[Path]:
    """The files named by the ``--lower`` and ``--upper`` specs: inputs no output may replace.

    Raises
    ------
    ParameterError, ProfileReadError
        As :func:`parse_body_spec` (``--lower`` checked first).
    """
    specs = (
        parse_body_spec(lower_text, option="--lower"),
        parse_body_spec(upper_text, option="--upper"),
    )
    return [s.path for s in specs if s.kind == "file"]


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
