"""Load paths from text, the ``friction`` command and the friction figures."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from splinecontact import Segment, simulate
from splinecontact.cli import app
from splinecontact.contact import LoadPathError, parse_path
from splinecontact.plotting import plot_friction_loop, plot_path_history

from conftest import ANGSTROM, circle_cap


def test_parse_path_builds_segments() -> None:
    got = parse_path(" normal=0.001, steps=20 ; tangential=-0.02,steps=40;force=0.5,steps=3")
    assert got == (
        Segment(normal=0.001, steps=20),
        Segment(tangential=-0.02, steps=40),
        Segment(normal_force=0.5, steps=3),
    )


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", "is empty"),
        ("normal=0.001,steps=2;", "segment 1 is empty"),
        ("normal=0.001", "give steps=N"),
        ("normal=0.001,steps=2,normal=3", "normal given twice"),
        ("speed=3,steps=2", "'speed=3' is not key=value"),
        ("normal=abc,steps=2", "normal = 'abc' is not a number"),
        ("normal=0.1,steps=2.5", "steps = '2.5' is not an integer"),
        ("force=-1,steps=2", "must be > 0"),
    ],
)
def test_parse_path_refuses_bad_text(text: str, match: str) -> None:
    with pytest.raises(LoadPathError, match=match):
        parse_path(text)


def test_friction_command_writes_a_path_result(tmp_path: Path) -> None:
    out = tmp_path / "f.nc"
    args = [
        "friction", "--lower", "generated:D=1.5,seed=2,n_points=4000,length=0.4",
        "--path", "normal=0.001,steps=20; tangential=0.005,steps=30", "-o", str(out),
    ]  # fmt: skip
    run = CliRunner().invoke(app, args)
    assert run.exit_code == 0, run.output
    assert "μ_s 0.3" in run.output  # rough on a rigid flat: μ_s = μ0 once sliding
    with xr.open_dataset(out) as ds:
        assert ds.sizes["step"] == 51
        assert ds["tangential_displacement"].attrs["units"] == "µm"
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 1
    assert "OutputExistsError" in again.output


def test_friction_command_refuses_a_bad_path_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "f.nc"
    args = ["friction", "--lower", "generated:D=1.5,seed=2,n_points=4000,length=0.4",
            "--path", "normal=0.001,stepz=20", "-o", str(out)]  # fmt: skip
    run = CliRunner().invoke(app, args)
    assert run.exit_code == 1
    assert "LoadPathError" in run.output and "Traceback" not in run.output
    assert not out.exists()


def test_friction_figures_have_units() -> None:
    x = np.arange(-300, 301) * ANGSTROM
    from splinecontact import Profile

    lower = Profile(x, circle_cap(x, 1.0))
    result = simulate(
        lower,
        "flat",
        path=[
            Segment(normal=1e-3, steps=5),
            Segment(tangential=2e-3, steps=20),
            Segment(tangential=-2e-3, steps=40),
        ],
    )
    ax = plot_friction_loop(result, label="circle")
    assert "[nm]" in ax.get_xlabel() and "[mN/µm]" in ax.get_ylabel()
    assert len(ax.get_lines()[0].get_xdata()) == 66
    ax2 = plot_path_history(result)
    assert "[nm]" in ax2.get_ylabel()
