"""``splinecontact generate`` and the command line's error contract (issue 2)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from splinecontact.cli import app

runner = CliRunner()


def test_generate_writes_a_readable_profile(tmp_path: Path) -> None:
    out = tmp_path / "wm.npz"
    result = runner.invoke(
        app,
        [
            "generate",
            "-o",
            str(out),
            "-D",
            "1.3",
            "--n-points",
            "5000",
            "--length",
            "0.5",
            "--seed",
            "9",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "5000 points" in result.output
    from splinecontact.io import read_profile

    profile = read_profile(out)
    assert profile.n_points == 5000
    assert abs(profile.ra - 0.005) < 1e-12


def test_generate_pair(tmp_path: Path) -> None:
    out = tmp_path / "pair.npz"
    result = runner.invoke(
        app,
        [
            "generate",
            "-o",
            str(out),
            "--pair",
            "--n-points",
            "2000",
            "--length",
            "0.2",
            "--seed",
            "1",
        ],
    )
    assert result.exit_code == 0, result.output
    lower = np.load(tmp_path / "pair-lower.npz")["z"]
    upper = np.load(tmp_path / "pair-upper.npz")["z"]
    assert lower.shape == upper.shape and not np.array_equal(lower, upper)


def test_bad_dimension_is_one_clean_line(tmp_path: Path) -> None:
    out = tmp_path / "bad.npz"
    result = runner.invoke(app, ["generate", "-o", str(out), "-D", "2.5", "--n-points", "100"])
    assert result.exit_code == 1
    assert "outside [1, 2]" in result.output
    assert "Traceback" not in result.output
    assert not out.exists()


def test_console_script_error_has_no_traceback(tmp_path: Path) -> None:
    out = tmp_path / "bad.npz"
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "from splinecontact.cli import main; main()",
            "generate",
            "-o",
            str(out),
            "-D",
            "0.5",
            "--n-points",
            "100",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ParameterError")
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize(
    ("option", "fragment"),
    [
        (["--steps", "0"], "steps"),
        (["--e-star", "0"], "e_star"),
        (["--e-star", "-5"], "e_star"),
        (["--alpha", "0"], "alpha"),
        (["--alpha", "-1"], "alpha"),
    ],
)
def test_simulate_bad_parameters_are_one_line_and_write_nothing(
    tmp_path: Path, option: list[str], fragment: str
) -> None:
    lower = tmp_path / "lower.npz"
    runner.invoke(app, ["generate", "-o", str(lower), "--n-points", "2000", "--length", "0.2"])
    out = tmp_path / "out.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", str(lower), "--upper", "flat", "-o", str(out), *option]
    )
    assert result.exit_code != 0
    assert fragment in result.output
    assert "Traceback" not in result.output
    assert not out.exists()


def test_simulate_generated_dimension_out_of_range(tmp_path: Path) -> None:
    out = tmp_path / "out.nc"
    result = runner.invoke(
        app,
        [
            "simulate",
            "--lower",
            "generated:D=2.5,n_points=2000,length=0.2",
            "--upper",
            "flat",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code != 0
    assert "outside [1, 2]" in result.output
    assert not out.exists()
