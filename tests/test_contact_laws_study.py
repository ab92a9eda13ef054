"""Contact laws selected from study files and from the command line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from splinecontact import Segment, simulate
from splinecontact.contact import make_law
from splinecontact.errors import StudyConfigError
from splinecontact.generate import weierstrass_mandelbrot_pair
from splinecontact.study import open_study, realization_seed, run_study
from splinecontact.study.config import parse_study

PATH = [{"normal": 0.004, "steps": 6}, {"normal": -0.002, "steps": 6}]
LAW = {"name": "jkr", "work_of_adhesion": 0.3}
STUDY: dict[str, Any] = {
    "study": {"name": "tiny-law", "seed": 5, "realizations": 1},
    "fixed": {"n_points": 1000, "mu0": 0.0, "dimension": 1.5},
    "path": PATH,
    "law": LAW,
}


def test_study_with_a_law_runs_the_law(tmp_path: Path) -> None:
    config = parse_study(STUDY)
    assert "[law]" in config.to_toml()
    assert parse_study(config.identity()).law == config.law
    store = tmp_path / "s.zarr"
    assert run_study(config, store, workers=1).complete
    ds = open_study(store)
    params = config.parameters_at(())
    lower, upper = weierstrass_mandelbrot_pair(
        1.5, seed=realization_seed(5, 0),
        **{k: params[k] for k in ("n_points", "length", "wavelength", "gamma", "directions",
                                  "n_max", "ra", "amplitude_law")},
    )  # fmt: skip
    law = make_law(**LAW)
    direct = simulate(lower, upper, mu0=0.0, path=[Segment(**s) for s in PATH], law=law)
    np.testing.assert_array_equal(ds["normal_force"].values.reshape(-1), direct.normal_force)
    assert direct.to_xarray().attrs["law"] == ds.attrs["law"] == "jkr"
    assert direct.to_xarray().attrs["law_work_of_adhesion"] == 0.3


@pytest.mark.parametrize(
    ("law", "message"),
    [
        ({"name": "hooke"}, "does not exist"),
        ({"name": "jkr", "work_of_adhesion": -1.0}, "work_of_adhesion"),
        ({"name": "elastic-plastic", "hardness": 0.0}, "hardness"),
        ({"name": "jkr", "hardness": 1.0}, "no parameter hardness"),
    ],
)
def test_bad_law_in_a_study_file_is_one_config_error(law: dict, message: str) -> None:
    with pytest.raises(StudyConfigError, match=message) as info:
        parse_study({**STUDY, "law": law})
    assert "\n" not in str(info.value)


@pytest.mark.slow
@pytest.mark.parametrize(
    "args",
    [
        ["--law", "hooke"],
        ["--law", "jkr", "--work-of-adhesion", "-0.1"],
        ["--law", "elastic-plastic", "--hardness", "0"],
        ["--law", "dmt", "--work-of-adhesion", "0.1", "--cohesive-stress", "0"],
    ],
)
def test_bad_law_on_the_command_line_is_one_line(tmp_path: Path, args: list[str]) -> None:
    out = tmp_path / "r.nc"
    for command in (
        ["simulate", "--lower", "generated:D=1.5,seed=1,n_points=1000"],
        ["friction", "--lower", "generated:D=1.5,seed=1,n_points=1000", "--path",
         "normal=0.001,steps=3"],
    ):  # fmt: skip
        proc = subprocess.run(
            [sys.executable, "-m", "splinecontact", *command, *args, "-o", str(out)],
            capture_output=True, text=True, check=False,
        )  # fmt: skip
        assert proc.returncode != 0
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1 and "Error" in lines[0], proc.stderr
        assert "Traceback" not in proc.stderr
        assert not out.exists()


def test_cli_selects_the_law_and_records_it(tmp_path: Path) -> None:
    import xarray as xr
    from typer.testing import CliRunner

    from splinecontact.cli import app

    lower = "generated:D=1.5,seed=2,n_points=2000,length=0.4"
    out = tmp_path / "f.nc"
    path = "normal=0.001,steps=10; normal=-0.001,steps=10"
    run = CliRunner().invoke(
        app,
        ["friction", "--lower", lower, "--path", path, "--law", "maugis-dugdale",
         "--work-of-adhesion", "0.2", "--cohesive-stress", "1.0", "-o", str(out)],
    )  # fmt: skip
    assert run.exit_code == 0, run.output
    with xr.open_dataset(out) as ds:
        assert ds.attrs["law"] == "maugis-dugdale"
        assert ds.attrs["law_work_of_adhesion"] == 0.2
        assert ds.attrs["law_cohesive_stress"] == 1.0
        assert float(ds["normal_force"].min()) < 0.0  # attraction on unloading
    out2 = tmp_path / "s.nc"
    run = CliRunner().invoke(
        app,
        ["simulate", "--lower", lower, "--steps", "10", "--law", "elastic-plastic",
         "--hardness", "2", "-o", str(out2)],
    )  # fmt: skip
    assert run.exit_code == 0, run.output
    with xr.open_dataset(out2) as ds:
        assert ds.attrs["law"] == "elastic-plastic"
        assert ds.attrs["law_hardness"] == 2.0
    bad = CliRunner().invoke(
        app, ["simulate", "--lower", lower, "--law", "jkr", "--hardness", "2", "-o",
              str(tmp_path / "x.nc")],
    )  # fmt: skip
    assert bad.exit_code == 1
    assert "no parameter hardness" in bad.output
    assert not (tmp_path / "x.nc").exists()
