"""Tests of splinecontact.plotting: every function draws on the given axes, labels its units."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from splinecontact import analysis, plotting
from splinecontact.errors import ParameterError
from test_analysis import make_study


@pytest.fixture(scope="module")
def study() -> xr.Dataset:
    return make_study(
        dimensions=(1.2, 1.5, 1.8), realizations=3, steps=80, noise=0.01, failed=((0, 0, 2),)
    )


def _axes() -> Axes:
    return Figure().add_subplot()


def _assert_labelled(ax: Axes) -> None:
    assert "[" in ax.get_xlabel() and "]" in ax.get_xlabel()
    assert "[" in ax.get_ylabel() and "]" in ax.get_ylabel()


def test_force_displacement_uses_given_axes(study: xr.Dataset) -> None:
    ens = analysis.ensemble_vs_displacement(study).sel(contact_type="rough-on-rough")
    ax = _axes()
    out = plotting.plot_force_displacement(ens, ax=ax)
    assert out is ax
    _assert_labelled(ax)
    assert "mN/µm" in ax.get_ylabel()
    assert "nm" in ax.get_xlabel()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["D = 1.2", "D = 1.5", "D = 1.8"]
    # the drawn curve is the ensemble mean, δ converted to nm
    line = ax.get_lines()[0]
    np.testing.assert_allclose(line.get_xdata(), ens.isel(dimension=0)["displacement"] * 1000)
    np.testing.assert_allclose(line.get_ydata(), ens.isel(dimension=0)["normal_force_mean"])


def test_force_figures_label_units(study: xr.Dataset) -> None:
    ens_f = analysis.ensemble_vs_force(study).sel(contact_type="rough-on-flat")
    ens_k = analysis.dimensionless_stiffness(study).sel(contact_type="rough-on-flat")
    for func, data in (
        (plotting.plot_separation_force, ens_f),
        (plotting.plot_area_force, ens_f),
        (plotting.plot_dimensionless_stiffness, ens_k),
    ):
        ax = _axes()
        assert func(data, ax=ax) is ax
        _assert_labelled(ax)
        assert len(ax.get_legend().get_texts()) == 3


def test_new_axes_when_none(study: xr.Dataset) -> None:
    ens = analysis.ensemble_vs_force(study).sel(contact_type="rough-on-flat")
    ax = plotting.plot_area_force(ens)
    assert isinstance(ax.figure, Figure)


def test_unselected_dimension_is_an_error(study: xr.Dataset) -> None:
    ens = analysis.ensemble_vs_displacement(study)
    with pytest.raises(ParameterError, match="contact_type"):
        plotting.plot_force_displacement(ens, ax=_axes())
    with pytest.raises(ParameterError, match="alpha"):
        plotting.plot_force_displacement(
            ens.sel(contact_type="rough-on-rough"), ax=_axes(), hue="alpha"
        )


def test_kappa_hurst_reference_lines(study: xr.Dataset) -> None:
    kap = analysis.kappa(study)
    kappas = {str(c): kap.sel(contact_type=c) for c in kap["contact_type"].values}
    ax = _axes()
    assert plotting.plot_kappa_hurst(kappas, ax=ax, measured_hurst={1.2: 0.8, 1.5: 0.5}) is ax
    _assert_labelled(ax)
    ys = {round(float(line.get_ydata()[0]), 4) for line in ax.get_lines()}
    assert round(analysis.PERSSON_KAPPA, 4) in ys
    assert round(analysis.BUSH_KAPPA, 4) in ys
    texts = " ".join(t.get_text() for t in ax.get_legend().get_texts())
    assert "Persson" in texts and "Bush" in texts and "rough-on-flat" in texts


@pytest.mark.slow  # renders and writes full figure sets (seconds each)
def test_make_study_figures_writes_png_and_svg(study: xr.Dataset, tmp_path: Path) -> None:
    written = plotting.make_study_figures(study, tmp_path)
    expected = {
        "fig10_rough-on-rough",
        "fig10_rough-on-flat",
        "fig11_rough-on-rough",
        "fig11_rough-on-flat",
        "fig12_kappa",
        "diag_force_split",
    }
    assert set(written) == expected
    for paths in written.values():
        assert sorted(p.suffix for p in paths) == [".png", ".svg"]
        for p in paths:
            assert p.stat().st_size > 1000
    assert (tmp_path / "fig12_kappa.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_profile_figures_draw(tmp_path: Path) -> None:
    from splinecontact.generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
    from splinecontact.spline import fit_spline

    small = {"n_points": 4000, "length": 4.0}
    profiles = [weierstrass_mandelbrot(d, seed=1, **small) for d in (1.2, 1.8)]
    ax = _axes()
    assert plotting.plot_profiles(profiles, labels=["a", "b"], ax=ax, xlim=(0, 2)) is ax
    _assert_labelled(ax)
    lower, upper = weierstrass_mandelbrot_pair(1.4, seed=2, **small)
    fits = [fit_spline(lower, alpha=a) for a in (1.0, 2.0)]
    ax = _axes()
    assert plotting.plot_spline_fits(lower, fits, ax=ax, xlim=(1.0, 1.1)) is ax
    assert [t.get_text() for t in ax.get_legend().get_texts()][1:] == [
        "spline, α = 1",
        "spline, α = 2",
    ]
    fit_l, fit_u = fit_spline(lower), fit_spline(upper)
    ax = _axes()
    assert plotting.plot_spheres(fit_l, upper_fit=fit_u, ax=ax, xlim=(1.0, 1.05)) is ax
    _assert_labelled(ax)
    ax = _axes()
    assert plotting.plot_first_contact(fit_l, fit_u, ax=ax) is ax
    _assert_labelled(ax)
    ax = _axes()
    assert plotting.plot_first_contact(fit_l, None, ax=ax) is ax


@pytest.mark.slow  # renders and writes full figure sets (seconds each)
def test_illustrative_figures_small(tmp_path: Path) -> None:
    from splinecontact.reproduce.figures import illustrative_inputs

    inputs = illustrative_inputs(
        dimensions=(1.2, 1.6),
        params={"n_points": 4000, "length": 4.0, "steps": 40},
        focus_dimension=1.4,
    )
    written = plotting.make_illustrative_figures(inputs, tmp_path)
    hurst = dict(zip(inputs.dimensions, analysis.measured_hurst(inputs.profiles), strict=True))
    assert set(written) == {
        "fig03_profiles",
        "fig04_spline_alpha",
        "fig05_spheres",
        "fig08_first_contact",
        "fig09_contact_zoom",
    }
    for paths in written.values():
        for p in paths:
            assert p.stat().st_size > 1000
    assert set(hurst) == {1.2, 1.6}
    assert hurst[1.2] > hurst[1.6]


def test_svg_files_are_reproducible_and_png_pixels_do_not_depend_on_compression(
    tmp_path: Path,
) -> None:
    """Same figure, same SVG bytes (no date); PNG written losslessly whatever the level."""
    from PIL import Image

    ax = plotting.new_axes(figsize=(2, 1.5))
    ax.plot([0, 1, 2], [0, 1, 0])
    fig = ax.figure
    assert isinstance(fig, Figure)
    first = plotting.save_figure(fig, tmp_path / "a")
    second = plotting.save_figure(fig, tmp_path / "b")
    assert first[1].read_bytes() == second[1].read_bytes()
    assert b"<dc:date>" not in first[1].read_bytes()
    fig.savefig(tmp_path / "c.png", dpi=150)  # matplotlib's default compression
    ours = np.asarray(Image.open(first[0]))
    default = np.asarray(Image.open(tmp_path / "c.png"))
    assert ours.shape == default.shape and (ours == default).all()


def test_decimate_keeps_extremes() -> None:
    x = np.linspace(0, 1, 100_000)
    z = np.sin(50 * x)
    z[12345] = 7.0
    xd, zd = plotting.decimate(x, z, max_points=1000)
    assert xd.size <= 1000
    assert zd.max() == 7.0
    assert zd.min() == pytest.approx(z.min())


@pytest.mark.slow  # a process-level test (spawns Python)
def test_importing_plotting_keeps_the_users_backend() -> None:
    """Importing the package's plotting module must not switch the matplotlib backend."""
    import os
    import subprocess
    import sys

    code = (
        "import matplotlib\n"
        "before = matplotlib.get_backend()\n"
        "import splinecontact.plotting\n"
        "import splinecontact.reproduce\n"
        "after = matplotlib.get_backend()\n"
        "assert before == after == 'pdf', (before, after)\n"
        "assert matplotlib.rcParams['backend'] == 'pdf'\n"
        "print('ok')\n"
    )
    env = {**os.environ, "MPLBACKEND": "pdf"}
    src = str(Path(__file__).resolve().parents[1] / "src")
    env["PYTHONPATH"] = src + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"


def _plotting_sources() -> dict[str, str]:
    folder = Path(plotting.__file__).parent
    return {p.name: p.read_text(encoding="utf-8") for p in sorted(folder.glob("*.py"))}


def test_plotting_module_does_not_call_matplotlib_use() -> None:
    sources = _plotting_sources()
    assert len(sources) > 1  # the package, not one file
    for name, source in sources.items():
        assert "matplotlib.use(" not in source, name
        assert "import matplotlib.pyplot" not in source, name
        assert "from matplotlib import pyplot" not in source, name


def test_plotting_never_generates_and_imports_nothing_above_it() -> None:
    """Plotting draws what it is given: no generation, fitting or simulation, no upward import."""
    import ast

    makers = {
        "weierstrass_mandelbrot",
        "weierstrass_mandelbrot_pair",
        "fit_spline",
        "simulate",
        "run_study",
        "study_hurst",
        "measured_hurst",
    }
    above = {"reproduce", "cli"}
    for name, source in _plotting_sources().items():
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.ImportFrom):
                parts = (node.module or "").split(".")
                module = parts[1] if node.level == 0 and parts[0] == "splinecontact" else parts[0]
                assert module not in above, f"plotting/{name} imports {module}"
                imported = {a.name for a in node.names}
                assert not imported & makers, f"plotting/{name} imports {imported & makers}"
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    parts = alias.name.split(".")
                    assert not (parts[0] == "splinecontact" and set(parts[1:2]) & above), name
            elif isinstance(node, ast.Attribute):
                assert node.attr not in makers, f"plotting/{name} calls .{node.attr}"


def test_write_figures_follows_the_output_rule(tmp_path: Path) -> None:
    from splinecontact.errors import OutputExistsError, UnsafeOutputError

    fig = Figure(figsize=(2, 2))
    fig.add_subplot().plot([0, 1], [1, 0])
    figures = {"fig12_kappa": fig}
    out = tmp_path / "figs"
    written = plotting.write_figures(figures, out)
    assert (out / "fig12_kappa.svg").is_file() and (out / "fig12_kappa.png").is_file()
    mine = out / "notes.txt"
    mine.write_bytes(b"my notes")
    with pytest.raises(OutputExistsError):
        plotting.write_figures(figures, out)
    again = plotting.write_figures(figures, out, overwrite=True)
    assert set(again) == set(written)
    assert mine.read_bytes() == b"my notes"
    user = tmp_path / "user"
    user.mkdir()
    (user / "data.csv").write_bytes(b"1,2\n")
    with pytest.raises(UnsafeOutputError):
        plotting.write_figures(figures, user, overwrite=True)
    assert sorted(p.name for p in user.iterdir()) == ["data.csv"]
    assert (user / "data.csv").read_bytes() == b"1,2\n"


def test_drawable_study_degenerate_cases(study: xr.Dataset) -> None:
    # one grid point without any successful realization: that D is left out, with a note
    ds = study.copy(deep=True)
    ds["status"].values[0, 1, :] = 2
    kept, notes = plotting.drawable_study(ds)
    assert list(kept["dimension"].values) == [1.5, 1.8]
    assert notes and "1.2" in notes[0]
    # non-finite curves count as failed
    ds = study.copy(deep=True)
    ds["displacement"].values[1, 0, 0, 5:] = np.inf
    kept, notes = plotting.drawable_study(ds)
    assert "non-finite" in notes[0]
    assert int(kept["status"].values[1, 0, 0]) == 2
    # nothing usable: one specific error
    ds = study.copy(deep=True)
    ds["status"].values[:] = 2
    with pytest.raises(analysis.AnalysisError, match="nothing to draw"):
        plotting.drawable_study(ds)
    # no sweep at all: a one-value dimension axis from the attribute
    single = study.isel(dimension=0, contact_type=0, drop=True)
    single.attrs["dimension"] = 1.2
    kept, _ = plotting.drawable_study(single)
    assert kept.sizes["dimension"] == 1
    figures = plotting.study_figures(kept)
    assert {"fig10", "fig11", "fig12_kappa", "diag_force_split"} <= set(figures)


# --- illustrative figures: profiles made once above, handed down -----------------------------

SMALL = {"n_points": 4000, "length": 4.0, "steps": 40}


@pytest.fixture(scope="module")
def counted_inputs() -> tuple[plotting.IllustrativeInputs, int]:
    import splinecontact.generate as generate
    from splinecontact.reproduce.figures import illustrative_inputs

    calls = 0
    original = generate.weierstrass_mandelbrot

    def counting(*args: object, **kwargs: object) -> object:
        nonlocal calls
        calls += 1
        return original(*args, **kwargs)  # type: ignore[arg-type]

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(generate, "weierstrass_mandelbrot", counting)
        inputs = illustrative_inputs(
            dimensions=(1.2, 1.4, 1.6), params=SMALL, seed=7, study_seed=True
        )
    return inputs, calls


def test_each_illustrative_profile_is_generated_once(
    counted_inputs: tuple[plotting.IllustrativeInputs, int],
) -> None:
    inputs, calls = counted_inputs
    # one lower profile per D (the one at the focus D is the pair's lower profile) + the upper
    assert calls == len(inputs.dimensions) + 1
    assert inputs.lower is inputs.profiles[inputs.dimensions.index(1.4)]
    assert [f.alpha for f in inputs.fits] == [1.0, 2.0, 3.0]
    assert inputs.lower_fit is inputs.fits[1]  # the simulation's α = 2 reused, not refitted
    assert inputs.record.step == 10 and inputs.displacement > 0


def test_illustrative_figures_draw_only_what_they_are_given(
    counted_inputs: tuple[plotting.IllustrativeInputs, int], monkeypatch: pytest.MonkeyPatch
) -> None:
    import splinecontact.contact as contact
    import splinecontact.generate as generate
    import splinecontact.spline as spline

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("plotting generated, fitted or simulated")

    for module, name in (
        (generate, "weierstrass_mandelbrot"),
        (spline, "fit_spline"),
        (contact, "simulate"),
    ):
        monkeypatch.setattr(module, name, refuse)
    inputs, _ = counted_inputs
    figures = plotting.illustrative_figures(inputs)
    assert set(figures) == {
        "fig03_profiles",
        "fig04_spline_alpha",
        "fig05_spheres",
        "fig08_first_contact",
        "fig09_contact_zoom",
    }
    assert all(isinstance(f, Figure) for f in figures.values())
    labels = [t.get_text() for t in figures["fig03_profiles"].axes[0].texts]
    assert labels == ["D = 1.2", "D = 1.4", "D = 1.6"]


def test_illustrative_inputs_need_one_profile_per_dimension(
    counted_inputs: tuple[plotting.IllustrativeInputs, int],
) -> None:
    import dataclasses

    inputs, _ = counted_inputs
    with pytest.raises(ParameterError, match="one profile per dimension"):
        dataclasses.replace(inputs, dimensions=(1.2, 1.4))
