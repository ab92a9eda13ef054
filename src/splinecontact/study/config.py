"""Study files: TOML descriptions of ensembles of SAD simulations, validated with pydantic.

A study file has four sections::

    [study]                     # required
    name = "paper"
    seed = 20150101             # entropy of numpy.random.SeedSequence (0 ≤ seed < 2⁶³)
    realizations = 200          # profile pairs per grid point

    [fixed]                     # parameters held constant (absent ones take their defaults)
    n_points = 1_000_000
    e_star = 10.0

    [sweep]                     # parameters swept; the grid is their Cartesian product,
    dimension = [1.0, 1.5]      # dimensions ordered as written here
    contact_type = ["rough-on-rough", "rough-on-flat"]

    [output]                    # how to run, not what: does not change the results
    batch_size = 4              # realizations per task (default: automatic)

An optional load path replaces ``steps`` and ``final_displacement`` by a sequence of segments
(the fields of :class:`splinecontact.Segment`), one ``[[path]]`` table each::

    [[path]]
    normal = 0.002              # δ_N [µm] at the segment's end (or normal_force [mN/µm])
    steps = 100
    [[path]]
    tangential = 0.5            # u_T [µm] at the segment's end
    steps = 100

Every parameter a study can fix or sweep is listed in :data:`PARAMETERS` (built from the
registry :data:`splinecontact.parameters.PARAMETERS`) with its type, range, default, unit and
meaning. Unknown keys, wrong types and out-of-range values are refused with a
:class:`~splinecontact.errors.StudyConfigError` whose one-line message names the key path and the
reason, for example ``sweep.dimension[2] = 2.5: must be ≤ 2``.
"""

from __future__ import annotations

import itertools
import json
import math
import tomllib
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    create_model,
    model_validator,
)

from ..errors import StudyConfigError
from ..parameters import PARAMETERS as MODEL_PARAMETERS
from ..parameters import Parameter

__all__ = [
    "PARAMETERS",
    "ParameterSpec",
    "PathSegmentSpec",
    "StudyConfig",
    "format_toml_value",
    "load_study",
    "parse_study",
]

_STRICT = ConfigDict(extra="forbid", strict=True, frozen=True)

#: Largest n_max · log10(γ): the highest frequency of eq. 1 is γ^n_max times the lowest.
_MAX_FREQUENCY_DECADES = 300

#: Floats are finite: ``inf`` and ``nan`` (valid TOML) are refused, as by the API.
Positive = Annotated[float, Field(gt=0.0, allow_inf_nan=False)]


def _annotation(parameter: Parameter) -> Any:
    """The pydantic type of one value of ``parameter`` (its kind, range and words)."""
    if parameter.choices is not None:
        annotation: Any = Literal[parameter.choices]
    elif parameter.kind is float:
        annotation = Annotated[float, Field(**parameter.bounds, allow_inf_nan=False)]
    elif parameter.kind is int:
        annotation = Annotated[int, Field(**parameter.bounds)]
    else:
        annotation = parameter.kind
    return annotation | None if parameter.optional else annotation


@dataclass(frozen=True)
class ParameterSpec:
    """One simulation parameter a study can fix or sweep (built from the parameter registry).

    Attributes
    ----------
    annotation : object
        The pydantic type of one value (with its range).
    default : object
        The value used when the study file neither fixes nor sweeps the parameter (``None``:
        the engine's own default, e.g. G* = E*/2.6, or a required parameter).
    unit : str
        Unit of the value (``"1"`` for dimensionless, ``""`` for words).
    description : str
        Meaning, with the paper's equation.
    """

    annotation: Any
    default: Any
    unit: str
    description: str


#: The simulation parameters of one realization, by name (the names are the study schema),
#: built from :data:`splinecontact.parameters.PARAMETERS`.
PARAMETERS: dict[str, ParameterSpec] = {
    name: ParameterSpec(
        _annotation(parameter),
        None if parameter.required else parameter.default,
        parameter.unit,
        parameter.description,
    )
    for name, parameter in MODEL_PARAMETERS.items()
}


def _fixed_field(spec: ParameterSpec) -> tuple[Any, Any]:
    return (spec.annotation | None, None)


def _sweep_field(spec: ParameterSpec) -> tuple[Any, Any]:
    return (Annotated[list[spec.annotation], Field(min_length=1)] | None, None)  # type: ignore[name-defined]


FixedParameters: type[BaseModel] = create_model(  # type: ignore[call-overload]
    "FixedParameters",
    __config__=_STRICT,
    **{name: _fixed_field(spec) for name, spec in PARAMETERS.items()},
)
SweptParameters: type[BaseModel] = create_model(  # type: ignore[call-overload]
    "SweptParameters",
    __config__=_STRICT,
    **{name: _sweep_field(spec) for name, spec in PARAMETERS.items()},
)


class StudySection(BaseModel):
    """The ``[study]`` section: name, seed and number of realizations per grid point."""

    model_config = _STRICT

    name: Annotated[str, Field(min_length=1)]
    seed: Annotated[int, Field(ge=0, lt=2**63)]
    realizations: Annotated[int, Field(ge=1)]
    description: str = ""


#: Parameters a load path replaces: a study with ``[[path]]`` may neither fix nor sweep them.
PATH_REPLACES = ("steps", "final_displacement", "final_displacement_factor")

Finite = Annotated[float, Field(allow_inf_nan=False)]


class PathSegmentSpec(BaseModel):
    """One ``[[path]]`` table: the fields of :class:`splinecontact.Segment`.

    ``normal`` is δ_N [µm] and ``normal_force`` F_N [mN/µm] at the segment's end (at most one),
    ``tangential`` u_T [µm] (absent: keep the current value), ``steps`` the increments [1].
    """

    model_config = _STRICT

    normal: Finite | None = None
    normal_force: Positive | None = None
    tangential: Finite | None = None
    steps: Annotated[int, Field(ge=1)]

    @model_validator(mode="after")
    def _one_normal(self) -> PathSegmentSpec:
        if self.normal is not None and self.normal_force is not None:
            raise ValueError(
                "give at most one of normal (δ_N [µm], displacement control) and normal_force "
                "(F_N [mN/µm], force control)"
            )
        return self

    def as_dict(self) -> dict[str, Any]:
        """The fields that are given (the keyword arguments of ``Segment``)."""
        return {k: v for k, v in self.model_dump().items() if v is not None}


class OutputSection(BaseModel):
    """The ``[output]`` section: how to run (does not change the stored results)."""

    model_config = _STRICT

    batch_size: Annotated[int, Field(ge=1)] | None = None


class StudyConfig(BaseModel):
    """A validated study: what to simulate, how often, with which seed.

    Build it with :func:`load_study` (from a TOML file) or :func:`parse_study` (from a mapping),
    which turn pydantic's errors into one-line :class:`StudyConfigError` messages.
    """

    model_config = _STRICT

    study: StudySection
    fixed: FixedParameters = Field(default_factory=FixedParameters)  # type: ignore[valid-type]
    sweep: SweptParameters = Field(default_factory=SweptParameters)  # type: ignore[valid-type]
    output: OutputSection = Field(default_factory=OutputSection)
    path: Annotated[list[PathSegmentSpec], Field(min_length=1)] | None = None

    _sweep_order: tuple[str, ...] = PrivateAttr(default=())

    @model_validator(mode="wrap")
    @classmethod
    def _remember_sweep_order(cls, data: Any, handler: Any) -> StudyConfig:
        model: StudyConfig = handler(data)
        order: tuple[str, ...] = ()
        if isinstance(data, Mapping) and isinstance(data.get("sweep"), Mapping):
            order = tuple(k for k in data["sweep"] if getattr(model.sweep, k, None) is not None)
        elif isinstance(data, StudyConfig):
            order = data._sweep_order
        if not order:
            order = tuple(k for k in PARAMETERS if getattr(model.sweep, k) is not None)
        model._sweep_order = order
        return model

    @model_validator(mode="after")
    def _check_consistency(self) -> StudyConfig:
        for name in self._swept_names_unordered():
            if getattr(self.fixed, name) is not None:
                raise ValueError(
                    f"fixed.{name}: also given in [sweep]; fix it or sweep it, not both"
                )
            values = getattr(self.sweep, name)
            seen: set[Any] = set()
            for i, value in enumerate(values):
                if value in seen:
                    raise ValueError(
                        f"sweep.{name}[{i}] = {format_toml_value(value)}: duplicate value; "
                        "each swept value must appear once"
                    )
                seen.add(value)
        if self.fixed.dimension is None and self.sweep.dimension is None:  # type: ignore[attr-defined]
            raise ValueError(
                "fixed.dimension: required; give the fractal dimension in [fixed] or [sweep]"
            )
        if self.path is not None:
            for name in PATH_REPLACES:
                for section in ("fixed", "sweep"):
                    if getattr(getattr(self, section), name) is not None:
                        raise ValueError(
                            f"{section}.{name}: not with [[path]]; the path's segments set the "
                            "steps and displacements, remove it"
                        )
        self._check_frequencies()
        self._check_spline_weight()
        return self

    def _check_spline_weight(self) -> None:
        """Every grid spacing, α and x0 of the study give a usable spline weight λ (eqs. 2–3).

        The same checks as :func:`splinecontact.fit_spline`, made before anything is written
        (otherwise every realization would fail with them).
        """
        from ..errors import ParameterError
        from ..spline import _MAX_GRID_LAMBDA, smoothing_parameter

        names = ("length", "n_points", "alpha", "x0")
        values = [sorted(set(self.parameter_values(name))) for name in names]
        if math.prod(len(v) for v in values) > 100_000:
            return  # the engine still checks each realization
        for length, n_points, alpha, x0 in itertools.product(*values):
            dx = length / (n_points - 1)
            try:
                lam = smoothing_parameter(dx, alpha=alpha, x0=x0)
            except ParameterError as exc:
                raise ValueError(f"x0 = {x0!r} with alpha = {alpha!r}: {exc}") from None
            if not lam / dx**3 <= _MAX_GRID_LAMBDA:
                raise ValueError(
                    f"x0 = {x0!r} with alpha = {alpha!r} and grid spacing {dx:.3g} µm: the "
                    f"spline weight λ/dx³ = {lam / dx**3:.3g} makes the spline a straight line; "
                    "use x0 of the order of 1 µm and alpha near 2"
                )

    def _check_frequencies(self) -> None:
        """γ^n_max (the highest frequency of eq. 1, relative to the lowest) must be a float."""
        gammas = self.parameter_values("gamma")
        n_maxes = self.parameter_values("n_max")
        gamma, n_max = max(gammas), max(n_maxes)
        if n_max * math.log10(gamma) > _MAX_FREQUENCY_DECADES:
            where_n = "sweep.n_max" if "n_max" in self._swept_names_unordered() else "fixed.n_max"
            raise ValueError(
                f"{where_n} = {n_max} with gamma = {gamma!r}: the highest frequency γ^n_max = "
                f"10^{n_max * math.log10(gamma):.0f} × the lowest overflows a float; keep "
                f"n_max · log10(γ) ≤ {_MAX_FREQUENCY_DECADES}"
            )

    def parameter_values(self, name: str) -> list[Any]:
        """The values parameter ``name`` takes in the study (its default if not given)."""
        swept = getattr(self.sweep, name)
        if swept is not None:
            return list(swept)
        value = getattr(self.fixed, name)
        return [PARAMETERS[name].default if value is None else value]

    def _swept_names_unordered(self) -> list[str]:
        return [k for k in PARAMETERS if getattr(self.sweep, k) is not None]

    # --- the grid ------------------------------------------------------------------------

    @property
    def swept(self) -> tuple[tuple[str, tuple[Any, ...]], ...]:
        """The swept parameters and their values, in the order of the study file."""
        return tuple((name, tuple(getattr(self.sweep, name))) for name in self._sweep_order)

    @property
    def swept_names(self) -> tuple[str, ...]:
        """Names of the swept parameters (the grid dimensions), in file order."""
        return self._sweep_order

    @property
    def grid_shape(self) -> tuple[int, ...]:
        """Number of values of each swept parameter."""
        return tuple(len(values) for _, values in self.swept)

    @property
    def n_grid_points(self) -> int:
        """Number of grid points (1 when nothing is swept)."""
        return math.prod(self.grid_shape)

    @property
    def fixed_parameters(self) -> dict[str, Any]:
        """Every parameter that is not swept, with its value (``None``: engine default)."""
        out: dict[str, Any] = {}
        for name, spec in PARAMETERS.items():
            if name in self._sweep_order:
                continue
            value = getattr(self.fixed, name)
            out[name] = spec.default if value is None else value
        if self.path is not None:
            out["steps"] = self.path_steps
            out["final_displacement"] = out["final_displacement_factor"] = None
        return out

    @property
    def path_steps(self) -> int:
        """Total number of steps of the load path (0 without a path)."""
        return sum(segment.steps for segment in self.path or ())

    @property
    def path_segments(self) -> tuple[dict[str, Any], ...] | None:
        """The load path as keyword arguments of ``Segment`` (None without a path)."""
        if self.path is None:
            return None
        return tuple(segment.as_dict() for segment in self.path)

    def grid_indices(self) -> Iterator[tuple[int, ...]]:
        """All grid indices, last swept parameter fastest."""
        return itertools.product(*(range(n) for n in self.grid_shape))

    def parameters_at(self, grid_index: Sequence[int]) -> dict[str, Any]:
        """The full parameter set of grid point ``grid_index`` (positions in the swept lists)."""
        params = self.fixed_parameters
        for (name, values), i in zip(self.swept, grid_index, strict=True):
            params[name] = values[i]
        out = {name: params[name] for name in PARAMETERS}
        if self.path is not None:
            out["path"] = self.path_segments
        return out

    @property
    def max_steps(self) -> int:
        """Largest number of steps over the grid (the length of the step dimension − 1)."""
        if "steps" in self._sweep_order:
            return int(max(self.sweep.steps))  # type: ignore[attr-defined]
        return int(self.fixed_parameters["steps"])

    # --- text form -----------------------------------------------------------------------

    def identity(self) -> dict[str, Any]:
        """What determines the results: everything but ``[output]``, defaults filled in."""
        fixed = self.fixed_parameters
        if self.path is not None:
            fixed = {k: v for k, v in fixed.items() if k not in PATH_REPLACES}
        ident: dict[str, Any] = {
            "study": self.study.model_dump(),
            "fixed": {k: v for k, v in fixed.items() if v is not None},
            "sweep": {name: list(values) for name, values in self.swept},
        }
        if self.path is not None:
            ident["path"] = [dict(segment) for segment in self.path_segments or ()]
        return ident

    def to_toml(self) -> str:
        """The resolved study file: every default filled in, swept parameters in file order."""
        ident = self.identity()
        lines = ["[study]"]
        lines += [f"{k} = {format_toml_value(v)}" for k, v in ident["study"].items()]
        lines += ["", "[fixed]"]
        lines += [f"{k} = {format_toml_value(v)}" for k, v in ident["fixed"].items()]
        lines += ["", "[sweep]"]
        lines += [f"{k} = {format_toml_value(v)}" for k, v in ident["sweep"].items()]
        lines += ["", "[output]"]
        lines += [
            f"{k} = {format_toml_value(v)}"
            for k, v in self.output.model_dump().items()
            if v is not None
        ]
        for segment in ident.get("path", ()):
            lines += ["", "[[path]]"]
            lines += [f"{k} = {format_toml_value(v)}" for k, v in segment.items()]
        return "\n".join(lines) + "\n"


# --- loading and error messages ---------------------------------------------------------------


def format_toml_value(value: Any) -> str:
    """Write a scalar or a list of scalars as TOML (floats keep their exact repr)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        if isinstance(value, float) and not math.isfinite(value):
            return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
        return repr(value)
    if isinstance(value, str):
        # JSON's escapes are valid TOML basic-string escapes; TOML also forbids a raw DEL.
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, list | tuple):
        return "[" + ", ".join(format_toml_value(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k} = {format_toml_value(v)}" for k, v in value.items()) + "}"
    return repr(value)


_SECTIONS: dict[str, type[BaseModel]] = {
    "study": StudySection,
    "fixed": FixedParameters,
    "sweep": SweptParameters,
    "output": OutputSection,
    "path": PathSegmentSpec,
}


def _key_path(loc: Sequence[int | str]) -> str:
    path = ""
    for part in loc:
        if isinstance(part, int):
            path += f"[{part}]"
        else:
            path += ("." if path else "") + str(part)
    return path


def _allowed_keys(loc: Sequence[int | str]) -> list[str]:
    if len(loc) == 1:
        return list(_SECTIONS)
    model = _SECTIONS.get(str(loc[0]))
    return list(model.model_fields) if model is not None else []


def _reason(error: Mapping[str, Any]) -> str:
    kind = error["type"]
    ctx = error.get("ctx") or {}
    loc = error["loc"]
    if kind == "extra_forbidden":
        allowed = ", ".join(_allowed_keys(loc))
        where = "section" if len(loc) == 1 else "key"
        return f"unknown {where}; allowed: {allowed}"
    if kind == "missing":
        return "required key is missing"
    bounds = {
        "less_than_equal": ("≤", "le"),
        "less_than": ("<", "lt"),
        "greater_than_equal": ("≥", "ge"),
        "greater_than": (">", "gt"),
    }
    if kind in bounds:
        symbol, key = bounds[kind]
        bound = ctx.get(key)
        shown = f"{bound:g}" if isinstance(bound, float) else str(bound)
        return f"must be {symbol} {shown}"
    if kind == "int_type":
        return "must be an integer (write 1_000_000, not 1e6)"
    if kind == "float_type":
        return "must be a number"
    if kind == "finite_number":
        return "must be a finite number (inf and nan are not parameter values)"
    if kind == "string_type":
        return "must be a string"
    if kind == "literal_error":
        return f"must be one of {ctx.get('expected')}"
    if kind == "list_type" and tuple(loc) == ("path",):
        return "must be an array of tables, one [[path]] per segment"
    if kind in ("list_type",):
        return "must be a list of values, e.g. [1.2, 1.5]"
    if kind == "too_short":
        return "must not be empty"
    if kind in ("model_type", "dict_type", "model_attributes_type"):
        return "must be a table (a [section])"
    if kind == "string_too_short":
        return "must not be empty"
    return str(error["msg"]).removeprefix("Value error, ")


def _format_error(error: Mapping[str, Any]) -> str:
    loc = error["loc"]
    if not loc:
        msg = str(error["msg"])
        return msg.removeprefix("Value error, ")
    # pydantic names the branch of a union (e.g. "float" in "g_star.float"): drop it.
    loc = tuple(p for p in loc if not (isinstance(p, str) and p in ("float", "int", "str", "none")))
    text = _key_path(loc)
    value = error.get("input")
    if error["type"] != "missing" and not isinstance(value, Mapping):
        text += f" = {format_toml_value(value)}"
    return f"{text}: {_reason(error)}"


def parse_study(data: Mapping[str, Any], *, source: str = "<mapping>") -> StudyConfig:
    """Validate a study given as a mapping (as read from TOML).

    Parameters
    ----------
    data : mapping
        Sections ``study``, ``fixed``, ``sweep`` and ``output`` (see the module docstring).
    source : str
        Where the data came from, for the error message.

    Raises
    ------
    StudyConfigError
        With one line: ``study file SOURCE: key.path = value: reason``.
    """
    try:
        return StudyConfig.model_validate(dict(data))
    except RecursionError:
        raise StudyConfigError(
            f"study file {source}: not a study (arrays or tables nested too deeply)"
        ) from None
    except ValidationError as exc:
        errors = exc.errors()
        try:
            first = _format_error(errors[0])
        except RecursionError:
            first = f"{_key_path(errors[0]['loc'])}: nested too deeply; must be a value"
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        raise StudyConfigError(f"study file {source}: {first}{more}") from None


def load_study(path: str | Path) -> StudyConfig:
    """Read and validate a TOML study file.

    Raises
    ------
    StudyConfigError
        If the file is missing, is not TOML, or is not a valid study (one line naming the key).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise StudyConfigError(f"study file {path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise StudyConfigError(f"study file {path}: cannot be read ({exc})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise StudyConfigError(f"study file {path}: not valid TOML: {exc}") from None
    except RecursionError:
        raise StudyConfigError(
            f"study file {path}: not a study file (arrays or tables nested too deeply)"
        ) from None
    return parse_study(data, source=str(path))
