"""Tests of splinecontact.reproduce: findings on synthetic studies, and the tiny end-to-end run."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from splinecontact import reproduce
from splinecontact.cli import app
from splinecontact.config import parse_study
from splinecontact.errors import ParameterError
from test_analysis import E_STAR, make_study

DIMS = (1.2, 1.4, 1.6, 1.7, 1.8, 1.9)


def _study_with_kappa(
    kappa_of_d: dict[float, float], *, rf_factor: float = 1.0, reverse: bool = False
) -> xr.Dataset:
    """Synthetic study whose κ per D is known: R_Sq set so that R_Sq·E*·(A/F) = κ(D).

    ``reverse`` reverses the curves along D, so that F_N rises with D.
    """
    ds = make_study(dimensions=DIMS, realizations=6, steps=150, noise=0.02, failed=())
    if reverse:
        for name in ("normal_force", "contact_area", "tangential_force", "displacement"):
            ds[name].values[:] = ds[name].values[::-1].copy()
    for i, d in enumerate(DIMS):
        j = len(DIMS) - 1 - i if reverse else i
        slope = 0.02 / (1 + j)  # A_S = slope · F_N (make_study)
        rsq = kappa_of_d[d] / (E_STAR * slope)
        ds["rsq_gap"].values[i] = rsq
        ds["rsq_lower"].values[i] = rsq * rf_factor
    return ds


def _by_key(findings: list[reproduce.Finding]) -> dict[str, reproduce.Finding]:
    return {f.key: f for f in findings}


def test_findings_on_a_study_that_follows_the_paper() -> None:
    kappa = {1.2: 1.8, 1.4: 2.0, 1.6: 2.2, 1.7: 3.0, 1.8: 4.0, 1.9: 5.0}
    found = _by_key(reproduce.evaluate_findings(_study_with_kappa(kappa), seed=1))
    # make_study: F_N = C_d δ^1.5 with C_d falling with D, A_S ∝ F_N with a falling slope
    assert found["a"].verdict == "reproduced"
    assert found["c"].verdict == "reproduced"
    assert found["d"].verdict == "reproduced"
    assert found["e"].verdict == "reproduced"
    # a power law with one exponent: log k curves are parallel, they never converge
    assert found["b"].verdict == "partly reproduced"
    assert found["b"].numbers["rough-on-rough"]["falls"] is True
    assert found["b"].numbers["rough-on-rough"]["converges"] is False
    for f in found.values():
        assert f.summary and f.test and f.tables


def test_findings_that_do_not_hold_are_reported() -> None:
    # κ out of band and falling; rough-on-flat κ half of rough-on-rough
    kappa = {1.2: 5.0, 1.4: 4.5, 1.6: 4.0, 1.7: 3.5, 1.8: 3.0, 1.9: 2.5}
    # F_N rising with D instead of falling
    ds = _study_with_kappa(kappa, rf_factor=0.5, reverse=True)
    found = _by_key(reproduce.evaluate_findings(ds, seed=1))
    assert found["a"].verdict == "not reproduced"
    assert found["d"].verdict == "not reproduced"
    assert found["d"].numbers["rough-on-rough"]["in_band_d_le_1_6"] == "0/3"
    assert found["e"].verdict == "not reproduced"
    assert all(not a for a in found["e"].numbers["agree"])


def test_undetermined_with_too_few_dimensions() -> None:
    ds = make_study(dimensions=(1.3, 1.7), realizations=3, failed=())
    found = _by_key(reproduce.evaluate_findings(ds))
    assert found["a"].verdict == "undetermined"


def test_study_mappings_are_valid_and_keep_the_paper_resolution() -> None:
    for scale in reproduce.SCALES:
        config = parse_study(reproduce.study_mapping(scale))  # type: ignore[arg-type]
        assert dict(config.swept)["contact_type"] == ("rough-on-rough", "rough-on-flat")
    quick = parse_study(reproduce.study_mapping("quick"))
    fixed = quick.fixed_parameters
    assert fixed["n_points"] == 1_000_000 and fixed["steps"] == 1000
    assert dict(quick.swept)["dimension"] == (1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8, 1.9)
    paper = parse_study(reproduce.study_mapping("paper"))
    assert paper.study.realizations == 200
    assert len(dict(paper.swept)["dimension"]) == 10
    with pytest.raises(ParameterError, match="scale"):
        reproduce.study_mapping("huge")  # type: ignore[arg-type]


FIGURES = [
    "fig03_profiles",
    "fig04_spline_alpha",
    "fig05_spheres",
    "fig08_first_contact",
    "fig09_contact_zoom",
    "fig10_rough-on-rough",
    "fig10_rough-on-flat",
    "fig11_rough-on-rough",
    "fig11_rough-on-flat",
    "fig12_kappa",
    "diag_force_split",
]


@pytest.mark.slow
def test_reproduce_tiny_writes_every_promised_file(tmp_path: Path) -> None:
    out = tmp_path / "run"
    result = CliRunner().invoke(
        app, ["reproduce", "--scale", "tiny", "-o", str(out), "--workers", "1", "--quiet"]
    )
    assert result.exit_code == 0, result.output
    for key in "abcde":
        assert f"({key})" in result.output
    promised = [out / "study.toml", out / "report.md", out / "findings.json"]
    promised += [out / "figures" / f"{name}.{ext}" for name in FIGURES for ext in ("png", "svg")]
    for path in promised:
        assert path.is_file(), path
        assert path.stat().st_size > 0, path
    assert (out / "study.zarr").is_dir()
    report = (out / "report.md").read_text(encoding="utf-8")
    for key in "abcde":
        assert f"## ({key})" in report
    assert "R_Sq source" in report and "fit" in report
    # every embedded figure exists
    for link in [line for line in report.splitlines() if line.startswith("![")]:
        target = link.split("(", 1)[1].rstrip(")")
        assert (out / target).is_file(), target
    data = json.loads((out / "findings.json").read_text(encoding="utf-8"))
    assert [f["key"] for f in data["findings"]] == list("abcde")
    verdicts = {"reproduced", "partly reproduced", "not reproduced", "undetermined"}
    assert {f["verdict"] for f in data["findings"]} <= verdicts
    # `plot` redraws the study figures from the store, with the alternative κ choices
    figs = tmp_path / "figs"
    result = CliRunner().invoke(
        app,
        [
            "plot",
            str(out / "study.zarr"),
            "-o",
            str(figs),
            "--no-illustrative",
            "--rsq-method",
            "spline",
            "--fit-fraction",
            "0.1",
        ],
    )
    assert result.exit_code == 0, result.output
    for name in FIGURES[5:]:
        assert (figs / f"{name}.png").stat().st_size > 0
        assert (figs / f"{name}.svg").stat().st_size > 0


def test_reproduce_rejects_unknown_scale(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["reproduce", "--scale", "huge", "-o", str(tmp_path)])
    assert result.exit_code == 1
    assert "error:" in result.output and "huge" in result.output


def test_plot_command_on_a_missing_store(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["plot", str(tmp_path / "nothing"), "-o", str(tmp_path)])
    assert result.exit_code == 1
    assert "error:" in result.output
    assert "Traceback" not in result.output


def test_trend_of_means_is_reproducible() -> None:
    rng = np.random.default_rng(0)
    groups = [rng.normal(5 - i, 1, 10) for i in range(5)]
    from splinecontact.analysis import trend_test

    a = trend_test(np.arange(5.0), groups, seed=3)
    b = trend_test(np.arange(5.0), groups, seed=3)
    assert (a.rho_low, a.rho_high) == (b.rho_low, b.rho_high)
