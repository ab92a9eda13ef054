"""``splinecontact compare``: SAD against the exact BEM on the same geometry (issue 7)."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from splinecontact import Profile
from splinecontact.cli import app
from splinecontact.compare import COLUMNS, compare_profiles

# Single asperities and small profiles pressed to large contact are a curved form or near full
# contact by construction: simulate()'s diagnostics on them are true and irrelevant to the
# comparison; the diagnostics themselves are tested in tests/test_cli_measured.py.
pytestmark = pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")

runner = CliRunner()
DATA = Path(__file__).parent / "data"


def read_table(path: Path) -> tuple[list[str], np.ndarray]:
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if line[:1] != "#"]
    rows = list(csv.reader(lines))
    return rows[0], np.array(rows[1:], dtype=float)


def test_compare_generated_writes_table_and_figure(tmp_path: Path) -> None:
    out = tmp_path / "cmp"
    result = runner.invoke(
        app,
        [
            "compare", "--lower", "generated:D=1.5,n_points=2048,seed=4", "--upper", "flat",
            "--steps", "100", "--forces", "4", "-o", str(out),
        ],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "medians" in result.output
    # progress on stderr: one line per BEM force
    assert len(re.findall(r"^BEM force \d/4: ", result.output, flags=re.MULTILINE)) == 4
    header, data = read_table(out / "compare.csv")
    assert header == [f"{name} [{unit}]" for name, (unit, _) in COLUMNS.items()]
    text = (out / "compare.csv").read_text(encoding="utf-8")
    assert "# lower = generated:D=1.5,seed=4,n_points=2048" in text
    assert (out / "compare.png").stat().st_size > 10_000
    assert data.shape == (4, len(COLUMNS))
    col = {name: data[:, i] for i, name in enumerate(COLUMNS)}
    # both methods start from the same first-contact geometry (same smoothed profile):
    # mean separation + displacement = mean gap + approach = max f − mean f
    np.testing.assert_allclose(
        col["sad_mean_separation"] + col["sad_displacement"],
        col["bem_mean_gap"] + col["bem_approach"],
        rtol=1e-9,
    )
    np.testing.assert_allclose(col["ratio_width"], np.sqrt(2) * col["ratio_area"], rtol=1e-8)
    assert np.all(np.diff(col["force"]) > 0)
    assert np.all(col["bem_contact_length_subgrid"] > 0)


def test_single_asperity_sad_matches_exact(tmp_path: Path) -> None:
    # One smooth circular asperity: SAD's independent Hertz contact is exact up to the
    # discretisation, so its contact width equals the BEM contact length.
    n, dx, radius = 4096, 0.01, 200.0
    x = np.arange(n) * dx
    s = x - x[n // 2]
    z = -(s * s) / (radius + np.sqrt(radius * radius - s * s))
    comparison = compare_profiles(
        Profile(x, z), "flat", steps=200, final_displacement=6e-3, n_forces=6
    )
    c = comparison.columns
    assert np.all(c["sad_n_contacts"] == 1)
    assert np.all(c["bem_n_patches"] == 1)
    wide = c["bem_contact_length"] >= 100 * dx
    assert wide.sum() >= 4
    np.testing.assert_allclose(c["ratio_width"][wide], 1.0, rtol=0.01)


def test_compare_reads_files_rough_on_rough(tmp_path: Path) -> None:
    from splinecontact.generate import weierstrass_mandelbrot_pair
    from splinecontact.io import write_profile

    lower, upper = weierstrass_mandelbrot_pair(1.4, seed=11, n_points=1024)
    write_profile(lower, tmp_path / "lower.npz")
    write_profile(upper, tmp_path / "upper.npz")
    out = tmp_path / "rr"
    result = runner.invoke(
        app,
        [
            "compare", "--lower", str(tmp_path / "lower.npz"),
            "--upper", str(tmp_path / "upper.npz"), "--steps", "60", "--forces", "3",
            "-o", str(out), "--quiet",
        ],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "BEM force" not in result.output  # --quiet
    assert (out / "compare.png").exists()
    _, data = read_table(out / "compare.csv")
    assert data.shape[0] >= 1 and np.all(np.isfinite(data[:, 0]))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--lower", "no-such-file.npz"], "no such file"),
        (["--lower", "generated:D=1.5,amplitude_law=printed"], "amplitude_law"),
        (["--lower", "generated:D=1.5,n_points=512", "--forces", "0"], "--forces 0"),
        (["--lower", "generated:D=2.5,n_points=512"], "error:"),
        (["--lower", "generated:D=1.5,n_points=512", "--tol", "0"], "--tol"),
        (["--lower", "generated:D=1.5,n_points=512", "--max-iterations", "0"], "--max-iter"),
        (["--lower", "generated:D=1.5,n_points=512", "--upper", "flatt"], "did you mean `flat`"),
        (["--lower", "generated:D=1.5,n_points=512,seed=3",
          "--upper", "generated:D=1.5,n_points=512,seed=3"], "same profile as --lower"),
        (["--lower", "generated:D=1.5,n_points=512", "--resample-spacing", "1"],
         "--nonuniform resample"),
    ],
)  # fmt: skip
def test_compare_bad_input_is_one_line(tmp_path: Path, args: list[str], message: str) -> None:
    out = tmp_path / "x"
    result = runner.invoke(app, ["compare", *args, "-o", str(out)])
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), lines
    assert message in lines[0]
    assert not out.exists()


def test_compare_takes_the_reading_options_its_errors_name(tmp_path: Path) -> None:
    # the x3p sample is areal: compare needs --line, as its error says, and then works
    source = str(DATA / "x3p-2.x3p")
    refused = runner.invoke(app, ["compare", "--lower", source, "-o", str(tmp_path / "a")])
    assert refused.exit_code == 1 and "--line" in refused.output
    out = tmp_path / "b"
    result = runner.invoke(
        app,
        ["compare", "--lower", source, "--line", "0", "--detrend", "tilt", "--steps", "100",
         "--forces", "3", "-o", str(out), "-q"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (out / "compare.csv").exists()
    # the folder is the one output: refused without --overwrite, replaced with it
    again = runner.invoke(
        app, ["compare", "--lower", source, "--line", "0", "--steps", "50", "-o", str(out)]
    )
    assert again.exit_code == 1 and "--overwrite" in again.output
    user_file = out / "notes.txt"
    user_file.write_text("mine", encoding="utf-8")
    replaced = runner.invoke(
        app,
        ["compare", "--lower", source, "--line", "0", "--steps", "50", "--forces", "2",
         "-o", str(out), "--overwrite", "-q"],
    )  # fmt: skip
    assert replaced.exit_code == 0, replaced.output
    assert user_file.read_text(encoding="utf-8") == "mine"


def test_compare_never_writes_over_an_input(tmp_path: Path) -> None:
    from splinecontact.generate import weierstrass_mandelbrot
    from splinecontact.io import write_profile

    folder = tmp_path / "out"
    folder.mkdir()
    source = folder / "compare.csv"
    write_profile(weierstrass_mandelbrot(1.5, n_points=512, seed=1), source)
    before = source.read_bytes()
    result = runner.invoke(
        app, ["compare", "--lower", str(source), "-o", str(folder), "--overwrite"]
    )
    assert result.exit_code == 1 and "input" in result.output
    assert source.read_bytes() == before


def _cycling_profile() -> Profile:
    """The detrended hfm-1 sample's spline: warm-started BEM cycles at its third force."""
    from splinecontact.io import read_profile
    from splinecontact.preprocess import Preprocessing

    return read_profile(DATA / "hfm-1.hfm", preprocessing=Preprocessing(detrend="tilt"))


def test_bem_that_cycles_is_approached_in_smaller_steps() -> None:
    # warm-started from the second force, the third does not converge in 500 iterations;
    # halving the load step does, so the comparison finishes
    progress: list[str] = []
    comparison = compare_profiles(
        _cycling_profile(), "flat", steps=1000, n_forces=20, max_iterations=500,
        progress=progress.append,
    )  # fmt: skip
    assert comparison.columns["force"].size >= 5
    assert any(line.startswith("BEM force 3/") for line in progress)
    assert np.all(np.isfinite(comparison.columns["bem_mean_gap"]))


def test_bem_failure_names_the_force_and_what_to_change() -> None:
    from splinecontact.errors import NoConvergenceError

    with pytest.raises(NoConvergenceError) as info:
        compare_profiles(_cycling_profile(), "flat", steps=1000, n_forces=20, max_iterations=1)
    text = str(info.value)
    assert "force 1 of" in text or "force 2 of" in text or "force 3 of" in text
    assert "--max-iterations" in text and "--tol" in text


def test_no_state_near_full_contact_is_reported() -> None:
    # a shallow profile pressed far: the exact contact covers the whole profile long before
    # SAD's last step; the comparison stops with a note instead of reporting mean-gap ratios
    x = np.arange(1024) * 0.01
    z = 1e-3 * np.sin(2 * np.pi * x / x[-1] * 4)
    comparison = compare_profiles(
        Profile(x, z), "flat", steps=200, final_displacement_factor=0.9, n_forces=10,
        max_contact_fraction=0.3,
    )  # fmt: skip
    assert any("near full contact" in note for note in comparison.notes)
    n_points = 2 * x.size
    length = comparison.columns["bem_contact_length"]
    assert 1 <= length.size < 10
    assert np.all(length / (x.size * 0.01) < 0.3 + 1.0 / n_points)


def test_compare_without_contact_force_is_an_error() -> None:
    from splinecontact.errors import ParameterError

    x = np.arange(256) * 0.01
    flat = Profile(x, np.zeros_like(x))
    with pytest.raises(ParameterError, match="no SAD step"):
        compare_profiles(flat, "flat", steps=10, final_displacement=1e-3)
