"""The parameter registry is the one source of defaults and units.

The study files, the command-line options and the public function signatures are held to
:data:`splinecontact.parameters.PARAMETERS`: every default equal to the registry's, every unit
written in a docstring or an option's help (``[µm]``) equal to the registry's, every range of the
study files the registry's.
"""

from __future__ import annotations

import importlib
import inspect
import math
import pkgutil
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import typer
from pydantic import ConfigDict, TypeAdapter, ValidationError

import splinecontact
from splinecontact import simulate, weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from splinecontact.errors import ParameterError
from splinecontact.parameters import (
    CONTACT,
    GENERATOR,
    PARAMETERS,
    REQUIRED,
    STUDY,
    Parameter,
    default,
)
from splinecontact.study import config as study_config

NAMES = sorted(PARAMETERS)
UNIT = re.compile(r"\[([^\]]+)\]")


def _doc_units(func: Callable[..., Any]) -> dict[str, str | None]:
    """For each parameter of ``func``'s numpydoc section: the first ``[unit]`` (None: none)."""
    doc = inspect.getdoc(func) or ""
    if "Parameters\n----------\n" not in doc:
        return {}
    section = doc.split("Parameters\n----------\n", 1)[1]
    section = re.split(r"\n\n(?:Returns|Raises|Yields|Notes|Examples|See Also)\n-", section)[0]
    found: dict[tuple[str, ...], list[str]] = {}
    names: tuple[str, ...] = ()
    for line in section.splitlines():
        header = re.match(r"^(\w+(?:, \w+)*) : ", line)  # "alpha, x0 : float" too
        if header:
            names = tuple(header.group(1).split(", "))
            found[names] = []
        elif names:
            found[names] += UNIT.findall(line)
    units: dict[str, str | None] = {}
    for names, brackets in found.items():
        if len(names) > 1 and len(brackets) >= len(names):  # "α [1] and x0 [µm]": in order
            units.update(zip(names, brackets, strict=False))
        else:
            units.update(dict.fromkeys(names, brackets[0] if brackets else None))
    return units


# --- the registry itself ---------------------------------------------------------------------


def test_the_registry_is_complete_and_consistent() -> None:
    for name, parameter in PARAMETERS.items():
        assert parameter.name == name
        assert parameter.group in (GENERATOR, CONTACT, STUDY)
        assert parameter.description
        if parameter.kind is str:
            assert parameter.choices and parameter.unit == ""
            assert parameter.default in parameter.choices
        else:
            assert parameter.unit in ("1", "µm", "GPa", "mN/µm"), name
        if parameter.default not in (None, REQUIRED) and parameter.kind is not str:
            assert type(parameter.default) is parameter.kind, name
        assert (parameter.default is None) == parameter.optional, name


def test_default_returns_the_registry_value_and_refuses_unknown_names() -> None:
    assert default("e_star") == 10.0
    assert default("length") == 100.0
    assert default("g_star") is None
    with pytest.raises(ParameterError, match="'dimension' has no default"):
        default("dimension")
    with pytest.raises(ParameterError, match="'e_str' is not a model parameter"):
        default("e_str")


def test_the_groups_are_the_keywords_of_the_engine() -> None:
    from splinecontact.contact import SIMULATION_PARAMETERS
    from splinecontact.generate import GENERATOR_PARAMETERS

    contact = {n for n, p in PARAMETERS.items() if p.group == CONTACT}
    generator = {n for n, p in PARAMETERS.items() if p.group == GENERATOR}
    assert contact == set(SIMULATION_PARAMETERS)
    assert generator - {"dimension"} == set(GENERATOR_PARAMETERS)


# --- the study files -------------------------------------------------------------------------


@pytest.mark.parametrize("name", NAMES)
def test_study_config_takes_default_unit_and_meaning_from_the_registry(name: str) -> None:
    spec, parameter = study_config.PARAMETERS[name], PARAMETERS[name]
    assert spec.default == (None if parameter.required else parameter.default)
    assert spec.unit == parameter.unit
    assert spec.description == parameter.description
    assert list(study_config.PARAMETERS) == list(PARAMETERS)


def _boundary_cases(parameter: Parameter) -> Iterator[tuple[Any, bool]]:
    """(value, valid) pairs on each side of each bound, and the allowed words."""
    if parameter.choices is not None:
        yield from ((word, True) for word in parameter.choices)
        yield "something-else", False
        return
    step: Callable[[Any, float], Any]
    if parameter.kind is int:

        def step(v: Any, d: float) -> Any:
            return int(v + d)
    else:

        def step(v: Any, d: float) -> Any:
            return math.nextafter(float(v), math.copysign(math.inf, d))

    for key, bound in parameter.bounds.items():
        inward = 1.0 if key in ("gt", "ge") else -1.0
        yield step(bound, inward), True
        yield bound, key in ("ge", "le")
        yield step(bound, -inward), False
    if parameter.kind is float:
        yield math.inf, False
        yield math.nan, False
    if parameter.optional:
        yield None, True


@pytest.mark.parametrize("name", NAMES)
def test_study_config_ranges_are_the_registry_bounds(name: str) -> None:
    parameter = PARAMETERS[name]
    adapter = TypeAdapter(study_config.PARAMETERS[name].annotation, config=ConfigDict(strict=True))
    cases = list(_boundary_cases(parameter))
    assert cases
    for value, valid in cases:
        if valid:
            adapter.validate_python(value)
        else:
            with pytest.raises(ValidationError):
                adapter.validate_python(value)


# --- the function signatures and their docstrings --------------------------------------------

SIGNATURES: dict[str, tuple[Callable[..., Any], str]] = {
    "simulate": (simulate, CONTACT),
    "weierstrass_mandelbrot": (weierstrass_mandelbrot, GENERATOR),
}


@pytest.mark.parametrize("function", sorted(SIGNATURES))
def test_function_defaults_and_units_are_the_registry(function: str) -> None:
    func, group = SIGNATURES[function]
    signature = inspect.signature(func).parameters
    units = _doc_units(func)
    for name, parameter in PARAMETERS.items():
        if parameter.group != group:
            continue
        assert name in signature, f"{function} has no parameter {name}"
        given = signature[name].default
        if parameter.required:
            assert given is inspect.Parameter.empty, (function, name)
        else:
            assert given == parameter.default and type(given) is type(parameter.default), (
                function,
                name,
                given,
            )
        if parameter.unit:
            assert units.get(name) == parameter.unit, (function, name, units.get(name))


def test_the_pair_generator_takes_the_generator_parameters() -> None:
    signature = inspect.signature(weierstrass_mandelbrot_pair).parameters
    assert signature["dimension"].default is inspect.Parameter.empty
    assert any(p.kind is inspect.Parameter.VAR_KEYWORD for p in signature.values())
    assert _doc_units(weierstrass_mandelbrot_pair)["dimension"] == PARAMETERS["dimension"].unit


#: Parameters of public functions that share a registry name but not its meaning or default:
#: (function, parameter) -> why.
NOT_THE_MODEL_PARAMETER = {
    ("TrendTest", "alpha"): "significance level of a trend test, not the spline α",
    ("trend_test", "alpha"): "significance level of a trend test, not the spline α",
    ("trend_from_estimates", "alpha"): "significance level of a trend test, not the spline α",
    ("StudyLimits", "steps"): "a ceiling on steps, not the number of steps",
    ("friction_study", "n_points"): "the friction sweep's own small default profile",
    ("friction_study", "length"): "the friction sweep's own small default profile",
    ("laws_study", "n_points"): "the contact-law sweep's own small default profile",
    ("laws_study", "length"): "the contact-law sweep's own small default profile",
    ("laws_study", "steps"): "steps of each branch of the contact-law cycle, not of a study",
    ("LawsStudySpec", "n_points"): "the contact-law sweep's own small default profile",
    ("LawsStudySpec", "length"): "the contact-law sweep's own small default profile",
    ("LawsStudySpec", "steps"): "steps of each branch of the contact-law cycle, not of a study",
}


def _public_callables() -> Iterator[tuple[str, Callable[..., Any]]]:
    """Every public function, class and method of every public module of the package."""
    seen: set[int] = set()
    for info in pkgutil.walk_packages(splinecontact.__path__, "splinecontact."):
        if any(part.startswith("_") for part in info.name.split(".")) or ".cli" in info.name:
            continue
        module = importlib.import_module(info.name)
        for name in getattr(module, "__all__", ()):
            value = getattr(module, name)
            members = [(name, value)]
            if inspect.isclass(value):
                members += [
                    (f"{name}.{k}", v) for k, v in vars(value).items() if inspect.isfunction(v)
                ]
            for label, member in members:
                if callable(member) and id(member) not in seen:
                    seen.add(id(member))
                    yield label, member


def test_every_public_function_keeps_the_registry_defaults_and_units() -> None:
    """Any public function with a parameter of the registry's name has its default and unit."""
    checked = 0
    for function, func in _public_callables():
        try:
            signature = inspect.signature(func).parameters
        except (TypeError, ValueError):
            continue
        units = None
        for name, given in signature.items():
            parameter = PARAMETERS.get(name)
            if parameter is None or (function.split(".")[0], name) in NOT_THE_MODEL_PARAMETER:
                continue
            checked += 1
            if given.default is not inspect.Parameter.empty:
                assert not parameter.required, (function, name)
                assert given.default == parameter.default, (function, name, given.default)
            if parameter.unit and not inspect.isclass(func):
                units = _doc_units(func) if units is None else units
                if name in units:
                    assert units[name] == parameter.unit, (function, name, units[name])
    assert checked >= 40


# --- the command line ------------------------------------------------------------------------


def _commands() -> dict[str, Any]:
    """The click commands (typer's) of simulate, generate, friction and study's subcommands."""
    from splinecontact.cli import app

    root: Any = typer.main.get_command(app)
    out: dict[str, Any] = {}
    for name in ("simulate", "generate", "friction", "study"):
        command = root.commands[name]
        if hasattr(command, "commands"):  # a group
            out.update({f"{name} {sub}": c for sub, c in command.commands.items()})
        else:
            out[name] = command
    return out


COMMANDS = _commands()

#: Options whose CLI default is an example rather than a model default: the generator's
#: fractal dimension, which has no default in the API and the study files.
CLI_EXAMPLES = {("generate", "dimension")}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_cli_option_defaults_and_units_are_the_registry(command: str) -> None:
    for option in COMMANDS[command].params:
        parameter = PARAMETERS.get(option.name or "")
        if parameter is None or option.param_type_name != "option":
            continue
        assert f"--{parameter.name.replace('_', '-')}" in option.opts, (command, option.opts)
        if (command, parameter.name) not in CLI_EXAMPLES:
            expected = None if parameter.required else parameter.default
            assert option.default == expected, (command, parameter.name, option.default)
        unit = UNIT.search(option.help or "")
        if unit is not None:
            assert unit.group(1) == parameter.unit, (command, parameter.name, option.help)


def test_the_cli_exposes_the_model_parameters() -> None:
    """simulate and friction take every contact parameter they can; generate every generator one."""
    names = {c: {p.name for p in cmd.params} for c, cmd in COMMANDS.items()}
    generator = {n for n, p in PARAMETERS.items() if p.group == GENERATOR}
    assert generator <= names["generate"]
    for command in ("simulate", "friction"):
        assert {"e_star", "g_star", "mu0", "alpha", "x0"} <= names[command]


# --- the documentation -----------------------------------------------------------------------


def _docs_table() -> dict[str, list[str]]:
    path = Path(__file__).resolve().parents[1] / "docs" / "studies.md"
    rows: dict[str, list[str]] = {}
    text = path.read_text(encoding="utf-8")
    section = text.split("### Parameters\n", 1)[1].split("\n#", 1)[0]
    for line in section.splitlines():
        match = re.match(r"^\| `(\w+)` \|(.*)\|$", line)
        if match and match.group(1) in PARAMETERS:
            rows[match.group(1)] = [cell.strip() for cell in match.group(2).split("|")]
    return rows


def test_the_documented_parameter_table_is_the_registry() -> None:
    rows = _docs_table()
    assert list(rows) == list(PARAMETERS)
    for name, (shown, unit, _, _) in rows.items():
        parameter = PARAMETERS[name]
        assert unit == parameter.unit, (name, unit)
        if parameter.required:
            assert "required" in shown, name
        elif parameter.default is None:
            assert "(engine)" in shown, name
        else:
            value = shown.strip("`").replace(" ", "")
            expected = parameter.default
            assert (value.strip('"') if parameter.kind is str else parameter.kind(value)) == (
                expected
            ), (name, shown)
