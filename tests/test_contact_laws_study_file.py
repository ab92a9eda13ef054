"""The laws study from a study file (``[laws_study]``, ``[[law]]``) and the ``laws-study`` command."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from splinecontact.analysis import LAWS_STUDY_VARIABLES, laws_study
from splinecontact.analysis.laws_study_file import (
    load_laws_study,
    parse_laws_study,
    run_laws_study,
)
from splinecontact.contact import make_law
from splinecontact.errors import StudyConfigError

TINY: dict[str, Any] = {
    "laws_study": {"dimensions": [1.4], "seeds": [0, 1], "n_points": 1000, "steps": 8},
    "law": [
        {"name": "hertz"},
        {"name": "jkr", "work_of_adhesion": 0.1, "label": "JKR 0.1"},
    ],
}

TOML = """
[laws_study]
dimensions = [1.4]
seeds = [0, 1]
n_points = 1000
steps = 8

[[law]]
name = "hertz"
[[law]]
name = "elastic-plastic"
hardness = 0.5
"""


def test_laws_study_file_runs_each_law_as_the_api_does() -> None:
    spec = parse_laws_study(TINY)
    assert spec.flat and spec.e_star == 10.0 and spec.realizations == 2
    calls: list[tuple[str, int, int]] = []
    ds = run_laws_study(spec, progress=lambda *a: calls.append(a))
    assert list(ds["law"].values) == ["hertz", "JKR 0.1"]
    assert calls[-1] == ("JKR 0.1", 2, 2) and len(calls) == 4
    direct = laws_study(
        [1.4], [0, 1], law=make_law("jkr", work_of_adhesion=0.1), n_points=1000, steps=8
    )
    for name, units in LAWS_STUDY_VARIABLES.items():
        np.testing.assert_array_equal(ds[name].sel(law="JKR 0.1").values, direct[name].values)
        assert ds[name].attrs["units"] == units
    assert ds.attrs["law_1"] == "jkr" and ds.attrs["law_1_work_of_adhesion"] == 0.1
    assert np.all(ds["pull_off_force"].sel(law="hertz").values == 0.0)
    assert np.all(ds["pull_off_force"].sel(law="JKR 0.1").values > 0.0)


def test_laws_study_file_defaults_and_reading(tmp_path: Path) -> None:
    file = tmp_path / "laws.toml"
    file.write_text(TOML, encoding="utf-8")
    spec = load_laws_study(file)
    assert spec.laws == (("hertz", "hertz", {}), ("elastic-plastic", "elastic-plastic",
                                                  {"hardness": 0.5}))  # fmt: skip
    assert (spec.load_fraction, spec.fit_fraction, spec.confidence) == (0.1, 0.3, 0.95)
    only = parse_laws_study({"laws_study": {"dimensions": [1.5], "seeds": [3]}})
    assert only.laws == (("hertz", "hertz", {}),) and only.n_points == 20_000


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"laws_study": {"seeds": [0]}}, "laws_study.dimensions is missing"),
        ({"laws_study": {"dimensions": [1.5, 2.5], "seeds": [0]}}, r"dimensions\[1\] = 2.5"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [-1]}}, r"seeds\[0\] = -1"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [0], "steps": 2}}, "steps = 2"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [0], "n_points": 1.5}}, "whole number"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [0], "confidence": 1.0}}, "confidence"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [0], "e_star": -1.0}}, "e_star"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [0], "contact_type": "flat"}}, "contact"),
        ({"laws_study": {"dimensions": [1.5], "seeds": [0], "dimension": 1.5}}, "not a key"),
        ({"study": {}}, "unknown section 'study'"),
        ({"law": [{"name": "hooke"}]}, r"law\[0\]: .*does not exist"),
        ({"law": [{"name": "jkr", "work_of_adhesion": -1.0}]}, r"law\[0\]: .*work_of_adhesion"),
        ({"law": [{"name": "elastic-plastic", "hardness": 0.0}]}, "hardness"),
        ({"law": [{"name": "jkr", "hardness": 1.0}]}, "no parameter hardness"),
        ({"law": [{"name": "hertz"}, {"name": "hertz"}]}, "distinct label"),
        ({"law": [{"work_of_adhesion": 0.1}]}, r"law\[0\].name"),
        ({"law": []}, "one or more"),
    ],
)
def test_bad_laws_study_file_is_one_config_error(change: dict, message: str) -> None:
    data = {**TINY, **change}
    with pytest.raises(StudyConfigError, match=message) as info:
        parse_laws_study(data)
    assert "\n" not in str(info.value)


def test_unreadable_laws_study_file(tmp_path: Path) -> None:
    with pytest.raises(StudyConfigError, match="cannot read"):
        load_laws_study(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[laws_study\n", encoding="utf-8")
    with pytest.raises(StudyConfigError, match="not valid TOML"):
        load_laws_study(bad)
    deep = tmp_path / "deep.toml"
    deep.write_text("dimensions = " + "[" * 5000 + "]" * 5000 + "\n", encoding="utf-8")
    with pytest.raises(StudyConfigError, match="nested too deeply"):
        load_laws_study(deep)


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "splinecontact", "laws-study", *args],
        capture_output=True, text=True, check=False,
    )  # fmt: skip


@pytest.mark.slow
def test_laws_study_command_writes_data_table_and_figures(tmp_path: Path) -> None:
    import xarray as xr

    file = tmp_path / "laws.toml"
    file.write_text(TOML, encoding="utf-8")
    out = tmp_path / "out"
    proc = _cli(str(file), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "elastic-plastic: 2/2 realizations" in proc.stderr
    assert "elastic-plastic: pull-off" in proc.stdout
    names = {p.name for p in out.iterdir()}
    assert {"laws_study.nc", "laws_study.csv"} | {f"{n}.png" for n in LAWS_STUDY_VARIABLES} <= names
    with xr.open_dataset(out / "laws_study.nc", engine="h5netcdf") as ds:
        assert list(ds["law"].values) == ["hertz", "elastic-plastic"]
        assert ds["residual_fraction"].attrs["units"] == "1"
        assert float(ds["dissipated_energy"].sel(law="elastic-plastic").min()) > 0.0
    header = (out / "laws_study.csv").read_text(encoding="utf-8").splitlines()[0]
    assert "pull_off_force_mean [mN/µm]" in header
    # the output rule: an existing folder is refused without --overwrite, nothing touched
    before = (out / "laws_study.csv").stat().st_mtime_ns
    again = _cli(str(file), "-o", str(out), "-q")
    assert again.returncode != 0 and "--overwrite" in again.stderr
    assert len(again.stderr.strip().splitlines()) == 1 and "Traceback" not in again.stderr
    assert (out / "laws_study.csv").stat().st_mtime_ns == before
    redo = _cli(str(file), "-o", str(out), "-q", "--overwrite")
    assert redo.returncode == 0 and redo.stderr == ""


@pytest.mark.slow
def test_bad_laws_study_file_on_the_command_line_is_one_line(tmp_path: Path) -> None:
    file = tmp_path / "laws.toml"
    file.write_text(TOML.replace("hardness = 0.5", "hardness = 0.0"), encoding="utf-8")
    out = tmp_path / "out"
    proc = _cli(str(file), "-o", str(out))
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode != 0 and len(lines) == 1, proc.stderr
    assert "StudyConfigError" in lines[0] and "hardness" in lines[0]
    assert not out.exists()


def test_a_laws_study_file_and_laws_study_share_their_defaults() -> None:
    """Every key a file may omit defaults to what :func:`laws_study` takes when omitted."""
    import dataclasses
    import inspect

    from splinecontact.analysis.laws_study_file import LawsStudySpec

    arguments = inspect.signature(laws_study).parameters
    shared = [
        f
        for f in dataclasses.fields(LawsStudySpec)
        if f.name in arguments and f.default is not dataclasses.MISSING
    ]
    assert {f.name for f in shared} >= {"flat", "n_points", "length", "steps", "e_star"}
    for field in shared:
        assert field.default == arguments[field.name].default, field.name
    only = parse_laws_study({"laws_study": {"dimensions": [1.5], "seeds": [3]}})
    for field in shared:
        assert getattr(only, field.name) == arguments[field.name].default, field.name
