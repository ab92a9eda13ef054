"""`splinecontact simulate` and `splinecontact inspect` on measured profiles."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from splinecontact import ParameterError
from splinecontact.cli import app
from splinecontact.cli._measured import parse_generated_spec
from test_io_malformed import MALFORMED

DATA = Path(__file__).parent / "data"
REAL = {
    "hfm-1.hfm": [],
    "xy-4.txt": ["--unit", "um"],
    "x3p-2.x3p": ["--line", "0"],
}
SUMMARY = re.compile(
    r"^final displacement [-+0-9.e]+ nm, F_N [-+0-9.e]+ mN/µm, A_S [-+0-9.e]+ µm, "
    r"\d+ contacts -> .+\.nc$"
)

runner = CliRunner()


def _field(output: str, name: str) -> str:
    match = re.search(rf"^{re.escape(name)}\s*: (.*)$", output, flags=re.MULTILINE)
    assert match, (name, output)
    return match.group(1)


# --- inspect ----------------------------------------------------------------------------------


def test_inspect_hfm() -> None:
    result = runner.invoke(app, ["inspect", str(DATA / "hfm-1.hfm"), "--detrend", "tilt"])
    assert result.exit_code == 0, result.output
    out = result.output
    assert _field(out, "points") == "9600"
    assert _field(out, "length") == "4799.5 µm"
    assert _field(out, "spacing") == "0.5 µm"
    assert _field(out, "R_q").startswith("0.2453")
    assert _field(out, "preprocessing") == "remove_tilt"
    assert "Hurst exponent" in out and "R_Sq" in out and "R_A" in out
    assert "2π(λ·dx)^¼ = 2.1 µm = 4.2 dx" in out
    # 0.5 µm spacing: the spline keeps 2.1 µm features with 4.2 points -> 20 % curvature bias
    assert "warning: the spacing 0.5 µm is coarse for the spline" in out
    assert "off by 20 %" in out and "--x0 ≥ 14.4 µm" in out


def test_inspect_x3p_row_and_fine_scan_without_warning() -> None:
    result = runner.invoke(app, ["inspect", str(DATA / "x3p-2.x3p"), "--line", "3"])
    assert result.exit_code == 0, result.output
    assert _field(result.output, "points") == "650"
    assert _field(result.output, "format") == "x3p, line 3"
    assert "off by 10 %" in result.output
    fine = runner.invoke(app, ["inspect", str(DATA / "xy-4.txt"), "--unit", "um"])
    assert fine.exit_code == 0, fine.output
    assert _field(fine.output, "points") == "10001"
    assert _field(fine.output, "preprocessing") == "regularize_grid"
    assert "35.4 dx" in fine.output
    assert "warning" not in fine.output


# --- simulate ---------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(REAL))
@pytest.mark.parametrize("upper", ["flat", "self"])
def test_simulate_real_files(tmp_path: Path, name: str, upper: str) -> None:
    out = tmp_path / "result.nc"
    upper_spec = "flat" if upper == "flat" else str(DATA / name)
    args = ["simulate", "--lower", str(DATA / name), "--upper", upper_spec, "-o", str(out)]
    args += [*REAL[name], "--steps", "50", "--detrend", "tilt"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    lines = result.output.strip().splitlines()
    assert SUMMARY.match(lines[-1]), lines
    assert all(line.startswith("warning: ") for line in lines[:-1]), lines
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["normal_force"].attrs["units"] == "mN/µm"
        assert ds["normal_force"].size == 51
        force = float(ds["normal_force"][-1])
        reported = float(re.search(r"F_N ([-+0-9.e]+)", lines[0]).group(1))  # type: ignore[union-attr]
        assert force == pytest.approx(reported, rel=1e-3)
    assert [p.name for p in tmp_path.iterdir()] == ["result.nc"]


def test_simulate_generated_upper_takes_the_file_grid(tmp_path: Path) -> None:
    out = tmp_path / "g.nc"
    args = ["simulate", "--lower", str(DATA / "x3p-2.x3p"), "--line", "0", "--upper",
            "generated:D=1.4,seed=3,ra=0.05", "-o", str(out), "--steps", "20"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert out.exists()


def test_parse_generated_spec() -> None:
    assert parse_generated_spec("generated:D=1.5,seed=3,n_points=1e5") == {
        "dimension": 1.5,
        "seed": 3,
        "n_points": 100000,
    }
    with pytest.raises(ParameterError, match="KEY=VALUE"):
        parse_generated_spec("generated:D=1.5,colour=red")
    with pytest.raises(ParameterError, match="fractal dimension"):
        parse_generated_spec("generated:seed=3")
    with pytest.raises(ParameterError, match="not a valid int"):
        parse_generated_spec("generated:D=1.5,seed=three")


def _assert_clean_failure(result, out: Path, *fragments: str) -> None:  # type: ignore[no-untyped-def]
    assert result.exit_code == 1, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, result.output
    assert lines[0].startswith("error: ")
    assert "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    assert not out.exists()
    assert not [p for p in out.parent.iterdir() if p.name.startswith(".")]


@pytest.mark.parametrize("name", sorted(MALFORMED))
def test_malformed_files_fail_cleanly_in_both_commands(tmp_path: Path, name: str) -> None:
    out = tmp_path / "out.nc"
    extra = ["--unit", "um"] if name == "tail-repeats.txt" else []
    error = MALFORMED[name][0].__name__
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / name), "-o", str(out), "--steps", "5", *extra]
    )
    _assert_clean_failure(result, out, error, name)
    result = runner.invoke(app, ["inspect", str(DATA / name), *extra])
    _assert_clean_failure(result, out, error, name)


def test_malformed_upper_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "out.nc"
    args = ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "--upper",
            str(DATA / "malformed-nan-rows.csv"), "-o", str(out)]  # fmt: skip
    _assert_clean_failure(runner.invoke(app, args), out, "UndefinedPointsError")


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--lower", "flat"], ("lower body must be a rough profile",)),
        (["--lower", str(DATA / "xy-4.txt"), "--unit", "um", "--upper", str(DATA / "hfm-1.hfm")],
         ("UnitError", "drop unit=")),
        (["--lower", str(DATA / "xy-4.txt"), "--unit", "um", "--upper", str(DATA / "hfm-1.hfm"),
          "--upper-unit", "mm"], ("GridMismatchError", "10001 points", "9600 points")),
        (["--lower", str(DATA / "x3p-2.x3p")], ("LineSelectionError", "--line")),
        (["--lower", "generated:D=1.5,foo=1"], ("ParameterError", "foo=1")),
        (["--lower", str(DATA / "hfm-1.hfm"), "--crop", "5,1"], ("x_min < x_max",)),
        (["--lower", str(DATA / "hfm-1.hfm"), "--crop", "abc"], ("X_MIN,X_MAX",)),
        (["--lower", str(DATA / "hfm-1.hfm"), "--detrend", "cubic"], ("polyN",)),
        (["--lower", str(DATA / "hfm-1.hfm"), "--undefined", "fill"], ("undefined='fill'",)),
        (["--lower", str(DATA / "missing.csv")], ("no such file", "missing.csv")),
        (["--lower", str(DATA / "hfm-1.hfm"), "--steps", "0"], ("steps",)),
    ],
)  # fmt: skip
def test_simulate_option_errors(tmp_path: Path, args: list[str], fragments: tuple[str]) -> None:
    out = tmp_path / "out.nc"
    result = runner.invoke(app, ["simulate", *args, "-o", str(out)])
    _assert_clean_failure(result, out, *fragments)


def test_output_directory_must_exist(tmp_path: Path) -> None:
    out = tmp_path / "no" / "out.nc"
    result = runner.invoke(app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "-o", str(out)])
    assert result.exit_code == 1
    assert "does not exist" in result.output
    assert not (tmp_path / "no").exists()


def test_undefined_points_interpolated_on_request(tmp_path: Path) -> None:
    out = tmp_path / "out.nc"
    args = ["simulate", "--lower", str(DATA / "stylus-invalid.hfm"), "-o", str(out),
            "--undefined", "interpolate", "--steps", "10"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert np.all(np.isfinite(ds["normal_force"].values))


# --- the installed console script -------------------------------------------------------------


def _console_script() -> str:
    script = Path(sys.executable).parent / "splinecontact"
    if not script.exists():
        pytest.skip("console script not installed next to the interpreter")
    return str(script)


def test_console_script_malformed_file(tmp_path: Path) -> None:
    out = tmp_path / "out.nc"
    proc = subprocess.run(
        [_console_script(), "simulate", "--lower", str(DATA / "malformed-descending-x.csv"),
         "-o", str(out)],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert proc.returncode == 1
    assert proc.stdout == ""
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: GridOrderError:"), proc.stderr
    assert "index 6 (line 8)" in lines[0]
    assert "Traceback" not in proc.stderr
    assert not list(tmp_path.iterdir())


def test_console_script_inspect(tmp_path: Path) -> None:
    proc = subprocess.run(
        [_console_script(), "inspect", str(DATA / "hfm-1.hfm")],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert _field(proc.stdout, "points") == "9600"
    assert "warning: the spacing 0.5 µm" in proc.stderr
    assert "warning: the profile is dominated by a tilt" in proc.stderr
