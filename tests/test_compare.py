"""``splinecontact compare``: SAD against the exact BEM on the same geometry (issue 7)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from splinecontact import Profile
from splinecontact.cli import app
from splinecontact.compare import COLUMNS, compare_profiles

runner = CliRunner()


def read_table(path: Path) -> tuple[list[str], np.ndarray]:
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if line[:1] != "#"]
    rows = list(csv.reader(lines))
    return rows[0], np.array(rows[1:], dtype=float)


def test_compare_generated_writes_table_and_figure(tmp_path: Path) -> None:
    out = tmp_path / "cmp.csv"
    result = runner.invoke(
        app,
        [
            "compare", "--lower", "generated", "--upper", "flat", "-D", "1.5",
            "--n-points", "2048", "--seed", "4", "--steps", "100", "--forces", "4",
            "-o", str(out),
        ],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "medians" in result.output
    header, data = read_table(out)
    assert header == [f"{name} [{unit}]" for name, (unit, _) in COLUMNS.items()]
    assert (tmp_path / "cmp.png").stat().st_size > 10_000
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
    out = tmp_path / "rr.csv"
    fig = tmp_path / "figs" / "rr.png"
    result = runner.invoke(
        app,
        [
            "compare", "--lower", str(tmp_path / "lower.npz"),
            "--upper", str(tmp_path / "upper.npz"), "--steps", "60", "--forces", "3",
            "-o", str(out), "--figure", str(fig),
        ],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert fig.exists()
    _, data = read_table(out)
    assert data.shape[0] >= 1 and np.all(np.isfinite(data[:, 0]))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--lower", "no-such-file.npz"], "error:"),
        (["--lower", "generated", "--amplitude-law", "printed"], "amplitude-law"),
        (["--lower", "generated", "--n-points", "512", "--forces", "0"], "n_forces"),
        (["--lower", "generated", "--n-points", "512", "-D", "2.5"], "error:"),
    ],
)
def test_compare_bad_input_is_one_line(tmp_path: Path, args: list[str], message: str) -> None:
    result = runner.invoke(app, ["compare", *args, "-o", str(tmp_path / "x.csv")])
    assert result.exit_code == 1
    assert message in result.output
    assert "Traceback" not in result.output


def test_compare_without_contact_force_is_an_error() -> None:
    from splinecontact.errors import ParameterError

    x = np.arange(256) * 0.01
    flat = Profile(x, np.zeros_like(x))
    with pytest.raises(ParameterError, match="no SAD step"):
        compare_profiles(flat, "flat", steps=10, final_displacement=1e-3)
