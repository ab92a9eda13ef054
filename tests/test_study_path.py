"""Study files with a load path: schema, validation and the stored path variables."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from splinecontact import Segment, simulate
from splinecontact.errors import StudyConfigError
from splinecontact.generate import weierstrass_mandelbrot_pair
from splinecontact.results import PATH_STEP_VARIABLES, STEP_VARIABLES
from splinecontact.study import open_study, realization_seed, run_study
from splinecontact.study.config import load_study, parse_study

PATH = [
    {"normal": 0.004, "steps": 6},
    {"tangential": 0.05, "steps": 5},
    {"tangential": 0.0, "steps": 3},
]

TINY_PATH: dict[str, Any] = {
    "study": {"name": "tiny-path", "seed": 7, "realizations": 2},
    "fixed": {"n_points": 1000, "mu0": 0.2},
    "sweep": {"dimension": [1.4, 1.6]},
    "path": PATH,
}


def test_path_study_runs_and_stores_path_variables(tmp_path: Path) -> None:
    config = parse_study(TINY_PATH)
    assert config.max_steps == 14
    store = tmp_path / "s.zarr"
    summary = run_study(config, store, workers=1)
    assert summary.complete
    ds = open_study(store)
    for name in (*STEP_VARIABLES, *PATH_STEP_VARIABLES):
        assert name in ds.data_vars, name
        assert ds[name].attrs["units"] == {**STEP_VARIABLES, **PATH_STEP_VARIABLES}[name][0]
    assert ds.sizes["step"] == 15
    assert (ds["status"].values == 1).all()
    u = ds["tangential_displacement"].values
    np.testing.assert_allclose(u[..., 6], 0.0, atol=0)
    np.testing.assert_allclose(u[..., 11], 0.05, rtol=1e-12)
    assert np.isfinite(ds["n_slipping"].values).all()
    assert (ds["dissipated_work"].values >= 0).all()
    # The stored values are those of simulate(path=...) on the same realization.
    d = float(ds["dimension"].values[1])
    params = config.parameters_at((1,))
    lower, upper = weierstrass_mandelbrot_pair(
        d,
        seed=realization_seed(7, 1),
        **{k: params[k] for k in ("n_points", "length", "wavelength", "gamma", "directions",
                                  "n_max", "ra", "amplitude_law")},
    )  # fmt: skip
    direct = simulate(lower, upper, mu0=0.2, path=[Segment(**s) for s in PATH])
    for name in ("normal_force", "tangential_force", "dissipated_work", "n_slipping"):
        np.testing.assert_array_equal(ds[name].values[1, 1], direct.curves[name])
    # The stored study file round-trips, path included.
    stored = parse_study(tomllib.loads(ds.attrs["study_toml"]))
    assert stored.identity() == config.identity()
    assert "steps" not in stored.identity()["fixed"]


def test_study_without_path_keeps_its_layout(tmp_path: Path) -> None:
    data = {k: v for k, v in TINY_PATH.items() if k != "path"}
    data["fixed"] = {"n_points": 1000, "steps": 5}
    store = tmp_path / "s.zarr"
    run_study(parse_study(data), store, workers=1)
    ds = open_study(store)
    for name in PATH_STEP_VARIABLES:
        assert name not in ds.data_vars
    assert "path" not in parse_study(data).identity()


def test_path_study_toml_file(tmp_path: Path) -> None:
    file = tmp_path / "p.toml"
    file.write_text(
        '[study]\nname = "p"\nseed = 1\nrealizations = 1\n[fixed]\ndimension = 1.5\n'
        "[[path]]\nnormal = 0.01\nsteps = 4\n[[path]]\nnormal_force = 0.5\ntangential = 0.1\n"
        "steps = 2\n",
        encoding="utf-8",
    )
    config = load_study(file)
    assert config.path_segments == (
        {"normal": 0.01, "steps": 4},
        {"normal_force": 0.5, "tangential": 0.1, "steps": 2},
    )
    assert config.max_steps == 6
    assert config.parameters_at(())["path"] == config.path_segments
    assert parse_study(tomllib.loads(config.to_toml())).identity() == config.identity()


@pytest.mark.parametrize(
    ("path", "fixed", "message"),
    [
        ([], {}, "path = []: must not be empty"),
        ([{"normal": 0.1}], {}, "path[0].steps: required key is missing"),
        ([{"normal": 0.1, "steps": 0}], {}, "path[0].steps = 0: must be ≥ 1"),
        ([{"normal": 0.1, "steps": 2.5}], {}, "path[0].steps = 2.5: must be an integer"),
        ([{"normal": float("nan"), "steps": 2}], {}, "path[0].normal = nan: must be a finite"),
        ([{"normal_force": -1.0, "steps": 2}], {}, "path[0].normal_force = -1.0: must be > 0"),
        ([{"steps": 2, "speed": 1.0}], {}, "path[0].speed = 1.0: unknown key; allowed: normal"),
        (
            [{"normal": 0.1, "normal_force": 1.0, "steps": 2}],
            {},
            "path[0]: give at most one of normal",
        ),
        ([{"normal": 0.1, "steps": 2}], {"steps": 10}, "fixed.steps: not with [[path]]"),
        (
            [{"normal": 0.1, "steps": 2}],
            {"final_displacement": 0.1},
            "fixed.final_displacement: not with [[path]]",
        ),
        ({"normal": 0.1, "steps": 2}, {}, "path: must be an array of tables, one [[path]]"),
    ],
)
def test_bad_path_is_refused_with_one_line(path: Any, fixed: dict[str, Any], message: str) -> None:
    data = {
        "study": {"name": "bad", "seed": 1, "realizations": 1},
        "fixed": {"dimension": 1.5, **fixed},
        "path": path,
    }
    with pytest.raises(StudyConfigError) as info:
        parse_study(data, source="x.toml")
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith("study file x.toml: ")
    assert message in text, text


def test_swept_steps_with_path_is_refused() -> None:
    data = {
        "study": {"name": "bad", "seed": 1, "realizations": 1},
        "fixed": {"dimension": 1.5},
        "sweep": {"final_displacement_factor": [0.1, 0.2]},
        "path": [{"normal": 0.1, "steps": 2}],
    }
    with pytest.raises(StudyConfigError, match=r"sweep.final_displacement_factor: not with"):
        parse_study(data)
