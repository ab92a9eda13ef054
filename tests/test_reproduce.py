"""Tests of splinecontact.reproduce: findings on synthetic studies, and the tiny end-to-end run."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from splinecontact import reproduce
from splinecontact.cli import app
from splinecontact.errors import ParameterError
from splinecontact.study.config import parse_study
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
    for estimator in ("mean_curve", "per_realization"):
        numbers = found["b"].numbers["rough-on-rough"][estimator]
        assert numbers["falls"] == "reproduced"
        assert numbers["converges"] == "not reproduced"
    assert "paper" in found["b"].numbers["rough-on-rough"]["estimator_for_verdict"]
    assert "mean curve" in found["b"].test and "per realization" in found["b"].test.lower()
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


def _u_shaped_area(levels: list[float]) -> xr.Dataset:
    """Study whose A_S at any load is levels[d] · F_N (1 % scatter between realizations)."""
    ds = make_study(dimensions=DIMS, realizations=8, steps=150, noise=0.02, failed=())
    rng = np.random.default_rng(7)
    for i, level in enumerate(levels):
        scatter = 1 + 0.01 * rng.standard_normal(ds.sizes["realization"])
        ds["contact_area"].values[i] = (
            0.01 * level * scatter[None, :, None] * ds["normal_force"].values[i]
        )
    return ds


def test_u_shaped_area_is_never_reported_as_falling() -> None:
    # falls, then rises at the last D: ρ strongly negative but not monotone
    found = _by_key(reproduce.evaluate_findings(_u_shaped_area([6, 5, 4, 3, 2, 2.5])))
    c = found["c"]
    assert c.numbers["rough-on-rough"]["shape"] == "not monotone"
    assert c.numbers["rough-on-rough"]["lower_for_higher_d"] == "partly reproduced"
    assert c.verdict == "partly reproduced"
    assert "not monotone" in c.summary and "↑ 1.8→1.9" in c.summary
    # the quick study's shape: minimum in the middle
    found = _by_key(reproduce.evaluate_findings(_u_shaped_area([6.9, 4.5, 3.0, 3.0, 3.6, 4.2])))
    assert found["c"].verdict in ("partly reproduced", "not reproduced")
    assert found["c"].numbers["rough-on-rough"]["shape"] == "not monotone"
    # a clean monotone fall is reproduced
    found = _by_key(reproduce.evaluate_findings(_u_shaped_area([6, 5, 4, 3, 2, 1])))
    assert found["c"].numbers["rough-on-rough"]["lower_for_higher_d"] == "reproduced"
    assert found["c"].verdict == "reproduced"


def test_every_printed_estimate_lies_in_its_interval() -> None:
    kappa = {1.2: 1.8, 1.4: 2.0, 1.6: 2.2, 1.7: 3.0, 1.8: 4.0, 1.9: 5.0}
    import re

    number = r"([-+\d.e]+)%?"
    checked = 0
    for f in reproduce.evaluate_findings(_study_with_kappa(kappa), seed=1):
        for _, _, rows in f.tables:
            for row in rows:
                # "estimate [low, high]" in one cell, or "estimate" | "[low, high]" side by side
                pairs = [(c, "") for c in row] + list(itertools.pairwise(row))
                for cell, following in pairs:
                    text = f"{cell} {following}".strip()
                    m = re.fullmatch(rf"{number} \[{number}, {number}\].*", text)
                    if m:
                        value, low, high = (float(g) for g in m.groups())
                        assert low <= value <= high, (f.key, text)
                        checked += 1
    assert checked > 50
    assert all(
        f.verdict in reproduce.VERDICTS
        for f in reproduce.evaluate_findings(_study_with_kappa(kappa), seed=1)
    )


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
    # the same command again continues (here: finds the study complete) and keeps user files
    (out / "my-notes.md").write_bytes(b"notes")
    (out / "figures" / "extra.png").write_bytes(b"mine")
    store_files = _snapshot(out / "study.zarr")
    again = CliRunner().invoke(
        app, ["reproduce", "--scale", "tiny", "-o", str(out), "--workers", "1", "--quiet"]
    )
    assert again.exit_code == 0, again.output
    assert (out / "my-notes.md").read_bytes() == b"notes"
    assert (out / "figures" / "extra.png").read_bytes() == b"mine"
    assert (out / "report.md").is_file() and (out / "figures" / "fig12_kappa.svg").is_file()
    assert _snapshot(out / "study.zarr").keys() == store_files.keys()
    # another scale in the same folder: refused before anything is touched
    before = _snapshot(out)
    other = CliRunner().invoke(app, ["reproduce", "--scale", "quick", "-o", str(out), "--quiet"])
    assert other.exit_code == 1 and "--overwrite" in other.output
    assert _snapshot(out) == before


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
    from splinecontact.reproduce import trend_test

    a = trend_test(np.arange(5.0), groups)
    b = trend_test(np.arange(5.0), groups)
    assert (a.rho, a.p_value, a.shape) == (b.rho, b.p_value, b.shape)


# --- the output rule and degenerate stores (plot, reproduce) ---------------------------------


def _small_study(sweep: dict[str, object] | None, realizations: int = 2) -> dict[str, object]:
    fixed: dict[str, object] = {"n_points": 2000, "length": 2.0, "steps": 30}
    if not sweep:
        fixed["dimension"] = 1.5
    return {
        "study": {"name": "small", "seed": 5, "realizations": realizations},
        "fixed": fixed,
        **({"sweep": sweep} if sweep else {}),
    }


def _failing_realization(parameters: object, seed: object) -> object:
    raise RuntimeError("this realization always fails")


def _nonfinite_realization(parameters: object, seed: object) -> object:
    import dataclasses

    from splinecontact.study import simulate_realization

    result = simulate_realization(parameters, seed)  # type: ignore[arg-type]
    curves = dict(result.curves)
    curves["displacement"] = np.full_like(curves["displacement"], np.inf)
    curves["normal_force"] = np.zeros_like(curves["normal_force"])
    return dataclasses.replace(result, curves=curves)


@pytest.fixture(scope="module")
def stores(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    from splinecontact.study import run_study

    root = tmp_path_factory.mktemp("stores")
    out = {}
    cases = {
        "sweep": (_small_study({"dimension": [1.2, 1.5, 1.8]}), None),
        "single": (_small_study(None), None),
        "one_realization": (_small_study({"dimension": [1.2, 1.8]}, realizations=1), None),
        "failed": (_small_study({"dimension": [1.2, 1.8]}), _failing_realization),
        "nonfinite": (_small_study(None), _nonfinite_realization),
    }
    for name, (mapping, func) in cases.items():
        out[name] = root / f"{name}.zarr"
        run_study(
            parse_study(mapping), out[name], workers=1, progress=False, realization_function=func
        )
    return out


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def _plot(*args: str) -> object:
    return CliRunner().invoke(app, ["plot", *args, "--no-illustrative"])


@pytest.mark.slow  # renders and writes full figure sets (seconds each)
def test_plot_refuses_user_folders_and_leaves_them_identical(
    stores: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    user = tmp_path / "work"
    user.mkdir()
    (user / "thesis.tex").write_bytes(b"\\documentclass{article}")
    (user / "sub").mkdir()
    (user / "sub" / "data.csv").write_bytes(b"1,2\n")
    before = _snapshot(user)
    for extra in ([], ["--overwrite"]):
        result = _plot(str(stores["sweep"]), "-o", str(user), *extra)
        assert result.exit_code == 1, result.output
        assert "error:" in result.output and "Traceback" not in result.output
        assert _snapshot(user) == before
    # plot -o . never removes anything
    monkeypatch.chdir(user)
    for extra in ([], ["--overwrite"]):
        result = _plot(str(stores["sweep"]), "-o", ".", *extra)
        assert result.exit_code == 1, result.output
        assert _snapshot(user) == before


@pytest.mark.slow  # renders and writes full figure sets (seconds each)
def test_plot_reuses_its_own_folder_only_with_overwrite(
    stores: dict[str, Path], tmp_path: Path
) -> None:
    figs = tmp_path / "figs"
    result = _plot(str(stores["sweep"]), "-o", str(figs))
    assert result.exit_code == 0, result.output
    assert (figs / "fig12_kappa.png").is_file()
    (figs / "my-notes.txt").write_bytes(b"keep me")
    result = _plot(str(stores["sweep"]), "-o", str(figs))
    assert result.exit_code == 1 and "--overwrite" in result.output
    result = _plot(str(stores["sweep"]), "-o", str(figs), "--overwrite")
    assert result.exit_code == 0, result.output
    assert (figs / "my-notes.txt").read_bytes() == b"keep me"
    assert (figs / "fig12_kappa.svg").is_file()


@pytest.mark.slow  # renders and writes full figure sets (seconds each)
@pytest.mark.parametrize("case", ["single", "one_realization", "nonfinite", "failed"])
def test_plot_degenerate_stores(stores: dict[str, Path], tmp_path: Path, case: str) -> None:
    figs = tmp_path / "figs"
    result = _plot(str(stores[case]), "-o", str(figs))
    assert "Traceback" not in result.output
    if case in ("nonfinite", "failed"):
        # nothing usable: one line, and no folder left behind
        assert result.exit_code == 1, result.output
        lines = [line for line in result.output.splitlines() if line.strip()]
        assert len(lines) == 1 and lines[0].startswith("error:")
        assert "nothing to draw" in lines[0]
        assert not figs.exists()
    else:
        assert result.exit_code == 0, result.output
        assert (figs / "fig10.png").is_file() or (figs / "fig10_rough-on-rough.png").is_file()
        assert (figs / "fig12_kappa.svg").is_file()


@pytest.mark.parametrize("fraction", ["-1", "nan", "0", "1.5"])
def test_plot_bad_fit_fraction_writes_nothing(
    stores: dict[str, Path], tmp_path: Path, fraction: str
) -> None:
    figs = tmp_path / "figs"
    result = _plot(str(stores["sweep"]), "-o", str(figs), "--fit-fraction", fraction)
    assert result.exit_code == 1
    assert "fit-fraction" in result.output and "Traceback" not in result.output
    assert not figs.exists()


def test_reproduce_refuses_a_user_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    user = tmp_path / "mine"
    user.mkdir()
    (user / "results.txt").write_bytes(b"precious")
    (user / "study.zarr").mkdir()  # looks like a store, but no splinecontact marker
    (user / "study.zarr" / "x").write_bytes(b"z")
    before = _snapshot(user)
    for target in (str(user), "."):
        monkeypatch.chdir(user if target == "." else tmp_path)
        for extra in ([], ["--overwrite"]):
            result = CliRunner().invoke(
                app, ["reproduce", "--scale", "tiny", "-o", target, "--quiet", *extra]
            )
            assert result.exit_code == 1, result.output
            assert "Traceback" not in result.output
            assert _snapshot(user) == before


def test_reproduce_study_with_progress_draws_a_bar_and_prints_the_summary(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``reproduce(progress=True)`` (the CLI's default) supplies the bar: the runner prints
    nothing and refuses ``progress=True`` itself."""
    from splinecontact.reproduce.run import _run_reproduce_study
    from splinecontact.study import open_study, parse_study

    config = parse_study(
        {
            "study": {"name": "tiny", "seed": 1, "realizations": 2},
            "fixed": {"n_points": 2048, "length": 10.0, "steps": 20},
            "sweep": {"dimension": [1.3, 1.7]},
        }
    )
    store = tmp_path / "tiny.zarr"
    _run_reproduce_study(config, store, workers=1, progress=True, overwrite=False)
    assert dict(open_study(store).sizes)["realization"] == 2
    out = " ".join(capsys.readouterr().out.split())
    assert "study complete: 4 ok, 0 failed, 0 not run, of 4 realizations" in out
