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


@pytest.mark.slow  # a process-level test (spawns Python)
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


# --- outputs of generate ----------------------------------------------------------------------


def test_generate_refuses_existing_files_and_replaces_with_overwrite(tmp_path: Path) -> None:
    out = tmp_path / "g.csv"
    out.write_text("precious", encoding="utf-8")
    args = ["generate", "-o", str(out), "--n-points", "500", "--seed", "2"]
    refused = runner.invoke(app, args)
    assert refused.exit_code == 1 and "--overwrite" in refused.output
    assert out.read_text(encoding="utf-8") == "precious"
    replaced = runner.invoke(app, [*args, "--overwrite"])
    assert replaced.exit_code == 0, replaced.output
    assert out.read_text(encoding="utf-8") != "precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.csv"]


def test_generate_pair_writes_both_or_nothing(tmp_path: Path) -> None:
    (tmp_path / "p-upper.npz").mkdir()  # the second file cannot be written
    result = runner.invoke(
        app, ["generate", "-o", str(tmp_path / "p.npz"), "--pair", "--n-points", "500"]
    )
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p-upper.npz"]


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--seed", "-1"], "0 ≤ seed < 2^63"),
        (["--seed", str(2**63)], "0 ≤ seed < 2^63"),
        (["-o", "g.json"], "unknown profile format"),
    ],
)
def test_generate_bad_options_are_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: list[str], fragment: str
) -> None:
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["generate", "-o", "g.npz", "--n-points", "100", *args])
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0], lines
    assert not list(tmp_path.iterdir())


def test_generate_without_seed_prints_and_stores_it(tmp_path: Path) -> None:
    import json
    import re

    out = tmp_path / "g.npz"
    result = runner.invoke(app, ["generate", "-o", str(out), "--n-points", "300"])
    assert result.exit_code == 0, result.output
    match = re.search(r"note: seed (\d+) \(drawn at random; --seed \1 repeats it\)", result.output)
    assert match, result.output
    with np.load(out) as data:
        stored = json.loads(str(data["metadata"]))
    assert stored["profile_metadata"]["seed_entropy"] == match.group(1)
    again = tmp_path / "again.npz"
    runner.invoke(
        app, ["generate", "-o", str(again), "--n-points", "300", "--seed", match.group(1)]
    )
    np.testing.assert_array_equal(np.load(out)["z"], np.load(again)["z"])


# --- --version, lazy imports, one line on stderr (processes) --------------------------------


def test_version() -> None:
    from splinecontact import __version__

    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0
    # issue 16: --version names the package version and the method's paper
    assert result.output.strip().startswith(f"splinecontact {__version__} ")
    assert "Hanaor" in result.output


@pytest.mark.slow  # a process-level test (spawns Python)
def test_help_and_option_errors_import_no_numerical_stack() -> None:
    code = (
        "import sys\n"
        "from typer.testing import CliRunner\n"
        "from splinecontact.cli import app\n"
        "r = CliRunner()\n"
        "assert r.invoke(app, ['--help']).exit_code == 0\n"
        "for cmd in ('simulate', 'compare', 'inspect', 'generate', 'plot', 'study'):\n"
        "    assert r.invoke(app, [cmd, '--help']).exit_code == 0, cmd\n"
        "assert r.invoke(app, ['simulate', '--steps', 'x']).exit_code == 2\n"
        "heavy = ('numba', 'scipy', 'matplotlib', 'xarray', 'numpy', 'splinecontact.bem',\n"
        "         'splinecontact.contact')\n"
        "print(sorted(m for m in sys.modules if m in heavy))\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=False
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


@pytest.mark.slow  # a process-level test (spawns Python)
def test_native_chatter_and_warnings_are_dropped_on_error(tmp_path: Path) -> None:
    # D18: what LAPACK/numba write on file descriptor 2 and the warnings raised before an
    # error never come before the one error line
    code = (
        "import os, sys, warnings\n"
        "import splinecontact.contact as c\n"
        "from splinecontact.errors import ParameterError\n"
        "def boom(*a, **k):\n"
        "    os.write(2, b' ** On entry to DLASCL parameter number 4 had an illegal value\\n')\n"
        "    warnings.warn('overflow encountered in multiply', RuntimeWarning)\n"
        "    raise ParameterError('boom')\n"
        "c.simulate = boom\n"
        "sys.argv = ['splinecontact', 'simulate', '--lower',\n"
        "            'generated:D=1.5,n_points=100,length=0.1,seed=1', '-o', 'x.nc']\n"
        "from splinecontact.cli import main\n"
        "main()\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
        check=False, cwd=tmp_path,
    )  # fmt: skip
    assert proc.returncode == 1
    assert proc.stderr.strip().splitlines() == ["error: ParameterError: boom"], proc.stderr
    assert not list(tmp_path.iterdir())
