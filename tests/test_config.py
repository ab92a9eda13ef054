"""Study files: validation, one-line errors naming the key, resolved TOML."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.errors import StudyConfigError
from splinecontact.study.config import (
    PARAMETERS,
    StudyConfig,
    format_toml_value,
    load_study,
    parse_study,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

BASE = {"study": {"name": "t", "seed": 7, "realizations": 3}}


def study(**sections: object) -> dict[str, object]:
    return {**BASE, **sections}


def error_of(data: dict[str, object]) -> str:
    with pytest.raises(StudyConfigError) as info:
        parse_study(data, source="x.toml")
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith("study file x.toml: ")
    return message.removeprefix("study file x.toml: ")


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        (study(sweep={"dimension": [1.2, 1.5, 2.5]}), "sweep.dimension[2] = 2.5: must be ≤ 2"),
        (study(fixed={"dimension": 0.5}), "fixed.dimension = 0.5: must be ≥ 1"),
        (
            {"study": {"name": "t", "seed": 7, "realizations": -3}, "fixed": {"dimension": 1.5}},
            "study.realizations = -3: must be ≥ 1",
        ),
        (
            {"study": {"name": "t", "seed": 7, "realizations": 0}, "fixed": {"dimension": 1.5}},
            "study.realizations = 0: must be ≥ 1",
        ),
        (study(sweeep={"dimension": [1.2]}), "sweeep: unknown section; allowed: study, fixed"),
        (study(fixed={"dimension": 1.5, "e_sta": 3.0}), "fixed.e_sta = 3.0: unknown key"),
        (study(fixed={"dimension": 1.5, "alpha": 0.0}), "fixed.alpha = 0.0: must be > 0"),
        (study(fixed={"dimension": 1.5, "e_star": -10.0}), "fixed.e_star = -10.0: must be > 0"),
        (study(fixed={"dimension": 1.5, "steps": 0}), "fixed.steps = 0: must be ≥ 1"),
        (study(fixed={"dimension": 1.5, "n_points": 1e6}), "fixed.n_points = 1000000.0: must be"),
        (study(fixed={"dimension": "1.5"}), 'fixed.dimension = "1.5": must be a number'),
        (study(fixed={"dimension": 1.5, "g_star": -1.0}), "fixed.g_star = -1.0: must be > 0"),
        (
            study(fixed={"dimension": 1.5, "contact_type": "flat"}),
            "fixed.contact_type = \"flat\": must be one of 'rough-on-rough' or 'rough-on-flat'",
        ),
        (
            study(sweep={"contact_type": ["rough-on-flat", "rough"], "dimension": [1.5]}),
            'sweep.contact_type[1] = "rough": must be one of',
        ),
        (study(sweep={"dimension": 1.5}), "sweep.dimension = 1.5: must be a list"),
        (study(sweep={"dimension": []}), "sweep.dimension = []: must not be empty"),
        (study(sweep={"dimension": [1.2, 1.2]}), "sweep.dimension[1] = 1.2: duplicate value"),
        (
            study(fixed={"dimension": 1.5}, sweep={"dimension": [1.2]}),
            "fixed.dimension: also given in [sweep]",
        ),
        (study(), "fixed.dimension: required"),
        ({"fixed": {"dimension": 1.5}}, "study: required key is missing"),
        (study(fixed={"dimension": 1.5}, output={"batch_size": 0}), "output.batch_size = 0"),
        (study(fixed={"dimension": 1.5}, output={"bach_size": 2}), "output.bach_size = 2: unknown"),
        ({"study": {"name": "t", "seed": -1, "realizations": 3}}, "study.seed = -1: must be ≥ 0"),
    ],
)
def test_invalid_study_names_key_and_reason(data: dict[str, object], expected: str) -> None:
    assert error_of(data).startswith(expected)


def test_several_errors_are_reported_as_one_line_with_a_count() -> None:
    message = error_of(study(fixed={"dimension": 3.0, "alpha": -1.0}))
    assert message.endswith("(and 1 more)")


def test_sweep_order_follows_the_file_and_grid_is_the_product() -> None:
    cfg = parse_study(
        study(
            fixed={"e_star": 20},
            sweep={"contact_type": ["rough-on-flat", "rough-on-rough"], "dimension": [1.2, 1.5]},
        )
    )
    assert cfg.swept_names == ("contact_type", "dimension")
    assert cfg.grid_shape == (2, 2)
    assert list(cfg.grid_indices()) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    params = cfg.parameters_at((1, 0))
    assert params["contact_type"] == "rough-on-rough"
    assert params["dimension"] == 1.2
    assert params["e_star"] == 20.0  # an int in TOML is accepted as a float
    assert isinstance(params["e_star"], float)
    assert set(params) == set(PARAMETERS)
    # Unset parameters take the documented defaults.
    assert params["alpha"] == PARAMETERS["alpha"].default == 2.0
    assert params["g_star"] is None


def test_resolved_toml_round_trips_with_defaults_filled_in() -> None:
    cfg = parse_study(study(sweep={"alpha": [1.5, 2.5], "dimension": [1.1, 1.9]}))
    text = cfg.to_toml()
    data = tomllib.loads(text)
    assert data["fixed"]["n_points"] == 1_000_000
    assert "g_star" not in data["fixed"]  # engine default: absent
    assert list(data["sweep"]) == ["alpha", "dimension"]
    again = parse_study(data)
    assert again.identity() == cfg.identity()
    assert again.swept_names == cfg.swept_names
    assert again.to_toml() == text


def test_model_is_frozen_and_picklable() -> None:
    import pickle

    cfg = parse_study(study(sweep={"dimension": [1.2, 1.5]}))
    copy = pickle.loads(pickle.dumps(cfg))
    assert copy.swept == cfg.swept
    assert isinstance(copy, StudyConfig)


def test_load_study_file_errors(tmp_path: Path) -> None:
    with pytest.raises(StudyConfigError, match="no such file"):
        load_study(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[study\nname=", encoding="utf-8")
    with pytest.raises(StudyConfigError, match="not valid TOML"):
        load_study(bad)


@pytest.mark.parametrize("name", ["paper-study.toml", "quick-study.toml"])
def test_shipped_examples_are_valid(name: str) -> None:
    cfg = load_study(EXAMPLES / name)
    assert cfg.sweep.dimension is not None  # type: ignore[attr-defined]


def test_paper_study_is_the_papers_design() -> None:
    cfg = load_study(EXAMPLES / "paper-study.toml")
    swept = dict(cfg.swept)
    assert swept["dimension"] == pytest.approx([1.0 + 0.1 * i for i in range(10)])
    assert set(swept["contact_type"]) == {"rough-on-rough", "rough-on-flat"}
    assert cfg.study.realizations == 200
    fixed = cfg.fixed_parameters
    assert fixed["n_points"] == 1_000_000
    assert fixed["steps"] == 1000
    assert fixed["e_star"] == 10.0
    assert fixed["final_displacement_factor"] == 0.2


def test_every_parameter_is_documented() -> None:
    docs = (Path(__file__).resolve().parents[1] / "docs" / "studies.md").read_text(encoding="utf-8")
    for name, spec in PARAMETERS.items():
        assert f"| `{name}` |" in docs, name
        assert spec.description


finite = {"allow_nan": False, "allow_infinity": False}


@settings(max_examples=60, deadline=None)
@given(
    name=st.text(min_size=1, max_size=20),
    description=st.text(max_size=30),
    seed=st.integers(0, 2**63 - 1),
    dimensions=st.lists(st.floats(1.0, 2.0, **finite), min_size=1, max_size=4, unique=True),
    e_star=st.floats(1e-300, 1e300, **finite),
    ra=st.floats(min_value=5e-324, max_value=1e3, **finite).filter(lambda v: v > 0),
    steps=st.integers(1, 10**9),
)
def test_resolved_toml_round_trips_exactly(
    name: str,
    description: str,
    seed: int,
    dimensions: list[float],
    e_star: float,
    ra: float,
    steps: int,
) -> None:
    cfg = parse_study(
        {
            "study": {"name": name, "seed": seed, "realizations": 2, "description": description},
            "fixed": {"e_star": e_star, "ra": ra, "steps": steps},
            "sweep": {"dimension": dimensions},
        }
    )
    again = parse_study(tomllib.loads(cfg.to_toml()))
    assert again.identity() == cfg.identity()
    assert again.to_toml() == cfg.to_toml()


FLOATS = [
    name
    for name, spec in PARAMETERS.items()
    if isinstance(spec.default, float) or name in ("dimension", "g_star", "final_displacement")
]


@pytest.mark.parametrize("name", FLOATS)
@pytest.mark.parametrize("value", [float("inf"), float("-inf"), float("nan")])
def test_inf_and_nan_are_refused_for_every_number(name: str, value: float) -> None:
    fixed = {"dimension": 1.5, name: value}
    message = error_of(study(fixed=fixed))
    assert message.startswith(f"fixed.{name} = {format_toml_value(value)}: must be a finite")
    sweep = {"dimension": [1.5]} if name != "dimension" else {}
    swept = error_of(study(sweep={**sweep, name: [1.5, value]}))
    assert swept.startswith(f"sweep.{name}[1] = {format_toml_value(value)}: must be a finite")


def test_the_study_file_inf_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "inf.toml"
    path.write_text(
        '[study]\nname = "t"\nseed = 1\nrealizations = 2\n[fixed]\ndimension = 1.5\ne_star = inf\n',
        encoding="utf-8",
    )
    with pytest.raises(StudyConfigError, match=r"fixed\.e_star = inf: must be a finite number"):
        load_study(path)


@pytest.mark.parametrize(
    ("seed", "expected"),
    [
        (-1, "must be ≥ 0"),
        (2**63, "must be <"),
        (1.5, "must be an integer"),
        (True, "must be an integer"),
        ("abc", "must be an integer"),
    ],
)
def test_bad_seeds_are_refused(seed: object, expected: str) -> None:
    message = error_of({"study": {"name": "t", "seed": seed, "realizations": 2}})
    assert message.startswith("study.seed = ")
    assert expected in message


@pytest.mark.parametrize(
    ("fixed", "sweep"),
    [({"n_max": 2000}, {}), ({}, {"n_max": [5, 2000]}), ({"n_max": 100}, {"gamma": [1.5, 1e10]})],
)
def test_a_highest_frequency_beyond_float_range_is_refused(
    fixed: dict[str, object], sweep: dict[str, object]
) -> None:
    message = error_of(study(fixed={"dimension": 1.5, **fixed}, sweep=sweep))
    assert "n_max" in message and "overflows a float" in message


def test_deeply_nested_arrays_are_one_line(tmp_path: Path) -> None:
    path = tmp_path / "deep.toml"
    path.write_text(
        '[study]\nname = "t"\nseed = 1\nrealizations = 2\n[sweep]\nra = '
        + "[" * 5000
        + "]" * 5000
        + "\n",
        encoding="utf-8",
    )
    with pytest.raises(StudyConfigError, match="nested too deeply"):
        load_study(path)
    nested: list[object] = [1.0]
    for _ in range(5000):
        nested = [nested]
    with pytest.raises(StudyConfigError) as info:
        parse_study(study(fixed={"dimension": 1.5}, sweep={"ra": nested}), source="x.toml")
    assert "\n" not in str(info.value)
