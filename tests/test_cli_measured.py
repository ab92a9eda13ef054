"""`splinecontact simulate` and `splinecontact inspect` on measured profiles."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st
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
        reported = float(re.search(r"F_N ([-+0-9.e]+)", lines[-1]).group(1))  # type: ignore[union-attr]
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


@pytest.mark.slow  # a process-level test (spawns Python)
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


@pytest.mark.slow  # a process-level test (spawns Python)
def test_console_script_inspect(tmp_path: Path) -> None:
    proc = subprocess.run(
        [_console_script(), "inspect", str(DATA / "hfm-1.hfm")],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert _field(proc.stdout, "points") == "9600"
    assert "warning: the spacing 0.5 µm" in proc.stderr
    assert "warning: the profile is dominated by a tilt" in proc.stderr


# --- one grammar for every command that takes a body ------------------------------------------

READING_OPTIONS = {
    "--format", "--unit", "--height-unit", "--spacing", "--line", "--undefined", "--order",
    "--duplicates", "--nonuniform", "--resample-spacing", "--crop", "--zero-origin", "--detrend",
}  # fmt: skip


def _options(command: str) -> set[str]:
    import typer.main

    group = typer.main.get_command(app)
    cmd = group.commands[command]  # type: ignore[attr-defined]
    return {opt for param in cmd.params for opt in param.opts}


def test_every_body_command_takes_the_same_reading_options() -> None:
    for command in ("simulate", "compare", "inspect"):
        assert READING_OPTIONS <= _options(command), command
    for command in ("simulate", "compare"):
        assert {"--lower", "--upper", "--upper-line", "--upper-unit", "--overwrite"} <= _options(
            command
        )
    assert {"--tol", "--max-iterations", "--quiet"} <= _options("compare")


def test_generated_keys_are_the_study_parameter_names() -> None:
    from splinecontact.cli._common import _GENERATED_KEYS
    from splinecontact.parameters import PARAMETERS

    assert set(_GENERATED_KEYS) - {"seed"} <= set(PARAMETERS)


@pytest.mark.parametrize(
    ("spec", "fragment"),
    [
        ("generated:D=1.5,seed=-1", "0 ≤ seed < 2^63"),
        ("generated:D=1.5,seed=1.5", "not a valid int"),
        ("generated:D=1.5,seed=abc", "not a valid int"),
        ("generated:D=1.5,seed=99999999999999999999", "out of range"),
        ("generated:D=1.5,n_points=1e400", "finite"),
        ("generated:D=nan", "finite"),
        ("generated:D=1.5,ra=inf", "finite"),
        ("generated:D=1.5,n_points=-5", "negative"),
        ("generated:D=1.5,amplitude_law=printed", "hurst"),
        ("generated:seed=3", "fractal dimension"),
    ],
)
def test_bad_generated_specs_are_one_line(tmp_path: Path, spec: str, fragment: str) -> None:
    out = tmp_path / "out.nc"
    result = runner.invoke(app, ["simulate", "--lower", spec, "-o", str(out)])
    _assert_clean_failure(result, out, "ParameterError", fragment)


def test_unseeded_generated_body_gets_a_recorded_seed(tmp_path: Path) -> None:
    out = tmp_path / "g.nc"
    spec = "generated:D=1.5,n_points=2000,length=0.2"
    result = runner.invoke(app, ["simulate", "--lower", spec, "-o", str(out), "--steps", "10"])
    assert result.exit_code == 0, result.output
    match = re.search(r"note: --lower (generated:D=1.5,seed=(\d+),n_points=2000,length=0.2)",
                      result.output)  # fmt: skip
    assert match, result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.attrs["lower"] == match.group(1)
        first = ds["normal_force"].values.copy()
    # the recorded spec repeats the run exactly
    again = tmp_path / "again.nc"
    rerun = runner.invoke(
        app, ["simulate", "--lower", match.group(1), "-o", str(again), "--steps", "10"]
    )
    assert rerun.exit_code == 0, rerun.output
    assert "note:" not in rerun.output
    with xr.open_dataset(again, engine="h5netcdf") as ds:
        np.testing.assert_array_equal(ds["normal_force"].values, first)


def test_upper_generated_is_never_the_lower_body(tmp_path: Path) -> None:
    spec = "generated:D=1.5,n_points=2000,length=0.2,seed=3"
    out = tmp_path / "rr.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", spec, "--upper", "generated", "-o", str(out), "--steps", "10"]
    )
    assert result.exit_code == 0, result.output
    assert "note: --upper generated:D=1.5,seed=4,n_points=2000,length=0.2" in result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert float(ds["ra_upper"]) > 0
        assert ds.attrs["upper"] != ds.attrs["lower"]
    same = runner.invoke(
        app, ["simulate", "--lower", spec, "--upper", spec, "-o", str(tmp_path / "s.nc")]
    )
    _assert_clean_failure(same, tmp_path / "s.nc", "same profile as --lower")
    bare = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "--upper", "generated",
              "-o", str(tmp_path / "b.nc")],
    )  # fmt: skip
    _assert_clean_failure(bare, tmp_path / "b.nc", "give its fractal dimension")


@pytest.mark.parametrize(
    ("upper", "hint"), [("flatt", "did you mean `flat`?"), ("generatd:D=1.5", "`generated`")]
)
def test_typo_in_a_keyword_gets_a_hint(tmp_path: Path, upper: str, hint: str) -> None:
    out = tmp_path / "out.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "--upper", upper, "-o", str(out)]
    )
    _assert_clean_failure(result, out, hint)


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--resample-spacing", "1"], "--nonuniform resample"),
        (["--upper-line", "2"], "--upper-line 2 needs an upper FILE"),
        (["--upper-unit", "mm"], "--upper-unit mm needs an upper FILE"),
        (["--final-displacement", "1e308"], "--final-displacement"),
        (["--final-displacement", "nan"], "--final-displacement"),
    ],
)
def test_contradictory_or_overflowing_options_are_refused(
    tmp_path: Path, args: list[str], fragment: str
) -> None:
    out = tmp_path / "out.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "-o", str(out), *args]
    )
    _assert_clean_failure(result, out, fragment)


@pytest.mark.parametrize("alpha", ["3", "4", "0", "nan"])
def test_inspect_alpha_outside_its_range_is_one_line(tmp_path: Path, alpha: str) -> None:
    result = runner.invoke(
        app, ["inspect", str(DATA / "xy-4.txt"), "--unit", "mm", "--alpha", alpha,
              "--order", "sort", "--duplicates", "average"],
    )  # fmt: skip
    _assert_clean_failure(result, tmp_path / "none", "ParameterError", "--alpha")


# --- warnings of simulate (CLI and library) ---------------------------------------------------


def test_simulate_warns_about_tilt_and_near_full_contact_on_the_raw_scan(tmp_path: Path) -> None:
    out = tmp_path / "raw.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "-o", str(out), "--steps", "100"]
    )
    assert result.exit_code == 0, result.output
    warnings_ = [line for line in result.output.splitlines() if line.startswith("warning: ")]
    assert any("dominated by a tilt" in w and "--detrend tilt" in w for w in warnings_)
    assert any("A_S reaches 58 % of the profile length" in w for w in warnings_), warnings_
    assert any("coarse for the spline" in w for w in warnings_)
    detrended = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "-o", str(tmp_path / "d.nc"),
              "--steps", "100", "--detrend", "tilt"],
    )  # fmt: skip
    assert detrended.exit_code == 0, detrended.output
    assert "dominated by a tilt" not in detrended.output
    assert "A_S reaches" not in detrended.output


def test_library_simulate_issues_specific_warnings() -> None:
    from splinecontact import simulate
    from splinecontact.diagnostics import (
        CoarseGridWarning,
        FormWarning,
        LargeContactWarning,
        SimulationWarning,
    )
    from splinecontact.io import read_profile

    raw = read_profile(DATA / "hfm-1.hfm")
    with pytest.warns(SimulationWarning) as record:
        simulate(raw, "flat", steps=100)
    kinds = {w.category for w in record}
    assert {FormWarning, CoarseGridWarning, LargeContactWarning} <= kinds
    assert all(issubclass(k, UserWarning) for k in kinds)


def test_fine_generated_profile_gives_no_warning() -> None:
    import warnings

    from splinecontact import simulate, weierstrass_mandelbrot

    profile = weierstrass_mandelbrot(1.5, n_points=20_000, length=2.0, seed=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate(profile, "flat", steps=50)


def test_form_diagnostic_oracle() -> None:
    from splinecontact import Profile
    from splinecontact.diagnostics import FORM_VARIANCE_LIMIT, form_diagnostic

    x = np.linspace(0.0, 10.0, 1001)
    rough = 0.01 * np.sin(2 * np.pi * x * 7.3)  # variance 5e-5 µm²
    # a tilt of slope s over L=10 has variance s²L²/12: equal to the roughness at s ≈ 2.45e-3
    assert form_diagnostic(Profile(x, rough)) is None
    small = form_diagnostic(Profile(x, rough + 1e-3 * x))
    assert small is None
    big = form_diagnostic(Profile(x, rough + 1e-2 * x))
    assert big is not None and big.kind == "form" and big.value > FORM_VARIANCE_LIMIT
    assert "tilt" in big.message
    bowl = form_diagnostic(Profile(x, rough + 2e-3 * (x - 5.0) ** 2))
    assert bowl is not None and "curved form" in bowl.message and "poly2" in bowl.message


# --- outputs ----------------------------------------------------------------------------------


def test_simulate_csv_is_a_real_csv_with_units(tmp_path: Path) -> None:
    import csv

    out = tmp_path / "out.csv"
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "xy-4.txt"), "--unit", "um", "-o", str(out),
              "--steps", "20"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    text = out.read_text(encoding="utf-8")
    assert not text.startswith("\x89HDF")
    rows = list(csv.reader(line for line in text.splitlines() if not line.startswith("#")))
    assert rows[0][:4] == ["step [1]", "displacement [µm]", "normal_force [mN/µm]",
                           "tangential_force [mN/µm]"]  # fmt: skip
    data = np.array(rows[1:], dtype=float)
    assert data.shape[0] == 21 and np.all(np.isfinite(data))
    assert f"# lower = {DATA / 'xy-4.txt'}" in text


@pytest.mark.parametrize("name", ["out.json", "out.txt", "out"])
def test_unknown_result_extension_is_refused(tmp_path: Path, name: str) -> None:
    out = tmp_path / name
    result = runner.invoke(app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "-o", str(out)])
    _assert_clean_failure(result, out, "unknown result format", ".nc", ".csv")


def test_simulate_never_writes_over_inputs_or_existing_files(tmp_path: Path) -> None:
    from splinecontact.io import write_profile

    source = tmp_path / "small.csv"
    write_profile(
        __import__("splinecontact").weierstrass_mandelbrot(1.5, n_points=500, seed=1), source
    )
    before = source.read_bytes()
    for extra in ([], ["--overwrite"]):
        result = runner.invoke(
            app, ["simulate", "--lower", str(source), "-o", str(source), "--steps", "5", *extra]
        )
        assert result.exit_code == 1, result.output
        assert source.read_bytes() == before
    existing = tmp_path / "old.nc"
    existing.write_bytes(b"precious")
    refused = runner.invoke(
        app, ["simulate", "--lower", str(source), "-o", str(existing), "--steps", "5"]
    )
    assert refused.exit_code == 1 and "--overwrite" in refused.output
    assert existing.read_bytes() == b"precious"
    replaced = runner.invoke(
        app,
        ["simulate", "--lower", str(source), "-o", str(existing), "--steps", "5", "--overwrite"],
    )
    assert replaced.exit_code == 0, replaced.output
    assert existing.read_bytes()[:4] == b"\x89HDF"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.nc", "small.csv"]


@pytest.mark.slow  # renders and writes full figure sets (seconds each)
def test_plot_one_result(tmp_path: Path) -> None:
    result_file = tmp_path / "r.nc"
    made = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "x3p-2.x3p"), "--line", "0", "-o",
              str(result_file), "--steps", "40"],
    )  # fmt: skip
    assert made.exit_code == 0, made.output
    figs = tmp_path / "figs"
    drawn = runner.invoke(app, ["plot", str(result_file), "-o", str(figs)])
    assert drawn.exit_code == 0, drawn.output
    names = sorted(p.name for p in figs.iterdir() if not p.name.startswith("."))
    assert names == ["area_force.png", "normal_force_displacement.png",
                     "separation_force.png", "tangential_force_displacement.png"]  # fmt: skip
    assert all((figs / n).stat().st_size > 5_000 for n in names)
    again = runner.invoke(app, ["plot", str(result_file), "-o", str(figs)])
    assert again.exit_code == 1 and "--overwrite" in again.output
    mine = figs / "mine.txt"
    mine.write_text("keep", encoding="utf-8")
    replaced = runner.invoke(app, ["plot", str(result_file), "-o", str(figs), "--overwrite"])
    assert replaced.exit_code == 0, replaced.output
    assert mine.read_text(encoding="utf-8") == "keep"


def test_plot_of_a_file_that_is_not_a_result_is_one_line(tmp_path: Path) -> None:
    bogus = tmp_path / "bogus.nc"
    bogus.write_bytes(b"not netcdf")
    result = runner.invoke(app, ["plot", str(bogus), "-o", str(tmp_path / "figs")])
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "bogus.nc" in lines[0]
    assert not (tmp_path / "figs").exists()


# --- the error contract: MemoryError, OSError, warnings ---------------------------------------


@pytest.mark.parametrize(
    ("exc", "fragment"),
    [(MemoryError(), "out of memory"), (OSError(28, "No space left on device"), "No space left")],
)
def test_memory_and_os_errors_are_one_line_and_write_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, exc: BaseException, fragment: str
) -> None:
    import warnings

    import splinecontact.contact

    def explode(*args: object, **kwargs: object) -> None:
        warnings.warn("chatter before the failure", RuntimeWarning, stacklevel=1)
        raise exc

    monkeypatch.setattr(splinecontact.contact, "simulate", explode)
    out = tmp_path / "out.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "-o", str(out), "--detrend", "tilt"]
    )
    _assert_clean_failure(result, out, fragment)
    assert "chatter" not in result.output


# --- two measured files against each other ----------------------------------------------------

X3P_VS_HFM = [
    "--lower", str(DATA / "x3p-2.x3p"), "--line", "0", "--upper", str(DATA / "hfm-1.hfm"),
    "--nonuniform", "resample", "--resample-spacing", "0.5", "--crop", "77,157",
    "--upper-crop", "8680,8760", "--zero-origin", "--detrend", "tilt",
]  # fmt: skip


def test_two_different_files_on_one_grid(tmp_path: Path) -> None:
    # --line is for the areal lower file; the upper .hfm is read without it
    out = tmp_path / "xh.nc"
    result = runner.invoke(app, ["simulate", *X3P_VS_HFM, "-o", str(out), "--steps", "50"])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert int(ds.attrs["n_points"]) == 160
        assert float(ds["ra_upper"]) > 0


def test_upper_file_hints_name_the_upper_options(tmp_path: Path) -> None:
    out = tmp_path / "o.nc"
    result = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "--upper", str(DATA / "x3p-2.x3p"),
              "-o", str(out)],
    )  # fmt: skip
    _assert_clean_failure(result, out, "LineSelectionError", "--upper-line")
    mismatch = runner.invoke(
        app, ["simulate", "--lower", str(DATA / "hfm-1.hfm"), "--upper", str(DATA / "x3p-2.x3p"),
              "--upper-line", "0", "-o", str(out)],
    )  # fmt: skip
    _assert_clean_failure(mismatch, out, "GridMismatchError", "--upper-crop", "--resample-spacing")


# --- as a new user, from the console script ---------------------------------------------------


def _run(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "splinecontact", *args],
        capture_output=True, text=True, timeout=900, check=False, cwd=cwd,
    )  # fmt: skip


@pytest.mark.slow
def test_new_user_walkthrough_with_the_three_samples(tmp_path: Path) -> None:
    """inspect, simulate (flat and each other), compare and plot on tests/data, from a shell."""
    hfm, xy, x3p = (str(DATA / n) for n in ("hfm-1.hfm", "xy-4.txt", "x3p-2.x3p"))
    for args in ([hfm], [xy, "--unit", "um"], [x3p, "--line", "0"]):
        proc = _run("inspect", *args, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        assert "Traceback" not in proc.stderr
    # each sample against a flat: the refusal names the option, which then works
    refused = _run("simulate", "--lower", x3p, "-o", "x.nc", cwd=tmp_path)
    assert refused.returncode == 1 and "--line" in refused.stderr
    for name, args in (("h", [hfm, "--detrend", "tilt"]), ("y", [xy, "--unit", "um"]),
                       ("x", [x3p, "--line", "0"])):  # fmt: skip
        proc = _run(
            "simulate", "--lower", *args, "-o", f"{name}.nc", "--steps", "100", cwd=tmp_path
        )
        assert proc.returncode == 0, proc.stderr
        assert "Traceback" not in proc.stderr
    # against each other
    proc = _run("simulate", *X3P_VS_HFM, "-o", "xh.csv", "--steps", "100", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    # compare with the options its messages suggest
    refused = _run("compare", "--lower", x3p, "-o", "cmp", cwd=tmp_path)
    assert refused.returncode == 1 and "--line" in refused.stderr
    proc = _run("compare", "--lower", x3p, "--line", "0", "--detrend", "tilt", "--steps", "200",
                "--forces", "5", "-o", "cmp", cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "BEM force 5/5" in proc.stderr or "near full contact" in proc.stdout
    # plot one result
    proc = _run("plot", "h.nc", "-o", "figs", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert len(list((tmp_path / "figs").glob("*.png"))) == 4


def test_plot_of_a_study_export_says_what_plot_takes(tmp_path: Path) -> None:
    export = tmp_path / "export.nc"
    xr.Dataset(
        {"normal_force": (("realization", "step"), np.zeros((2, 3)), {"units": "mN/µm"})}
    ).to_netcdf(export, engine="h5netcdf")
    result = runner.invoke(app, ["plot", str(export), "-o", str(tmp_path / "figs")])
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "study export" in lines[0], lines
    assert not (tmp_path / "figs").exists()


@settings(max_examples=200, deadline=None)
@given(
    dimension=st.floats(1.0, 2.0),
    seed=st.integers(0, 2**63 - 1),
    n_points=st.integers(8, 10**7),
    ra=st.floats(1e-6, 1e3),
    amplitude_law=st.sampled_from(["hurst", "as_printed"]),
)
def test_generated_spec_round_trip(
    dimension: float, seed: int, n_points: int, ra: float, amplitude_law: str
) -> None:
    from splinecontact.cli._common import format_generated_spec

    kwargs = {"dimension": dimension, "seed": seed, "n_points": n_points, "ra": ra,
              "amplitude_law": amplitude_law}  # fmt: skip
    text = format_generated_spec(kwargs)
    parsed = parse_generated_spec(text)
    assert parsed["seed"] == seed and parsed["n_points"] == n_points
    assert parsed["amplitude_law"] == amplitude_law
    # the recorded spec repeats the run: every value read back exactly
    assert parsed == kwargs


@pytest.mark.parametrize("command", ["inspect", "simulate"])
def test_devices_and_folders_are_not_read(tmp_path: Path, command: str) -> None:
    for source, fragment in (("/dev/zero", "not a regular file"), (str(tmp_path), "folder")):
        args = [source] if command == "inspect" else ["--lower", source, "-o", "x.nc"]
        result = runner.invoke(app, [command, *args])
        assert result.exit_code == 1
        lines = result.output.strip().splitlines()
        assert len(lines) == 1 and fragment in lines[0], lines


def test_ceiling_errors_name_the_cli_options(tmp_path: Path) -> None:
    """The library's ceilings name keywords; the command line names the options that raise them."""
    out = tmp_path / "r.nc"
    result = runner.invoke(
        app,
        ["simulate", "--lower", "generated:D=1.5,seed=1,n_points=1000", "--steps", "2000000",
         "-o", str(out)],
    )  # fmt: skip
    assert result.exit_code == 1
    assert "--max-steps" in result.output and "max_steps=" not in result.output
    result = runner.invoke(
        app,
        ["simulate", "--lower", "generated:D=1.5,seed=1,n_points=30000000", "-o", str(out)],
    )
    assert result.exit_code == 1
    assert "--max-points" in result.output and "max_points=" not in result.output
    assert not out.exists()
    result = runner.invoke(
        app,
        ["simulate", "--lower", "generated:D=1.5,seed=1,n_points=2000,wavelength=0.1",
         "--steps", "20", "--max-steps", "10", "-o", str(out)],
    )  # fmt: skip
    assert result.exit_code == 1 and "ceiling 10" in result.output
