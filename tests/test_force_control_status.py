"""The ``force_control`` output: how every step of a load path met its normal force.

Codes (``splinecontact.schema``, CF ``flag_values``/``flag_meanings``): 0 displacement-controlled,
1 F_N held on the contacts eq. 9 accepts at that δ_N, 2 F_N held with a contact set eq. 9 would
not accept as a whole (the target lies inside a jump of the free model), 3 the target lies inside
a jump and the nearer side was kept (F_N ≠ target). The oracle of codes 1 and 2 is independent
of the driver: with the Hertz law, eq. 9's accepted set at (u_T, δ_N) depends on the geometry
only, so a one-step displacement-controlled run to the same (u_T, δ_N) gives it.
"""

from __future__ import annotations

import csv
import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from splinecontact import Profile, Segment, schema, simulate
from splinecontact.analysis import (
    FrictionAnalysisError,
    dilatancy,
    force_control_counts,
    static_friction,
)
from splinecontact.cli import app
from splinecontact.cli._measured import write_result
from splinecontact.contact import JKR, loadpath
from splinecontact.contact import _force_status as fs
from splinecontact.generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair

from conftest import ANGSTROM, circle_cap, held_force_slide

E_STAR = 10.0


@pytest.fixture(scope="module")
def rough_run():  # type: ignore[no-untyped-def]
    """A 2000-point rough pair pressed in 20 steps, then slid 0.002 µm in 30 steps at half the
    force reached (its free F_N(δ_N) jumps across the target at about half the steps)."""
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=3, n_points=2000, length=0.2)
    d = 0.1 * lower.peak_to_valley
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the pair's form warning
        plain = simulate(lower, upper, steps=20, final_displacement=d, diagnostics=False)
        target = 0.5 * float(plain.normal_force[-1])
        path = [
            Segment(normal=d, steps=20),
            Segment(normal_force=target, tangential=0.002, steps=30),
        ]
        result = simulate(lower, upper, path=path, record_contacts="all", diagnostics=False)
    return lower, upper, path, result


def _points(result, step: int) -> np.ndarray:  # type: ignore[no-untyped-def]
    record = next((c for c in result.contacts if c.step == step), None)
    return np.zeros(0, np.int64) if record is None else np.sort(record.point)


def test_codes_of_a_rough_pair_match_the_contacts_eq9_accepts(rough_run) -> None:  # type: ignore[no-untyped-def]
    """Code 1 exactly where the step's contacts are those eq. 9 accepts at its (u_T, δ_N)
    (a separate one-step run there), code 2 elsewhere; F_N held to 1e−6 at both."""
    lower, upper, _, result = rough_run
    codes = result.force_control
    assert codes.dtype == np.int8 and codes.shape == result.displacement.shape
    assert np.all(codes[:21] == fs.DISPLACEMENT)
    assert set(codes[21:].tolist()) == {fs.HELD, fs.HELD_FIXED_SET}  # both occur on this pair
    target = result.normal_force_target[21:]
    assert np.all(np.abs(result.normal_force[21:] / target - 1) <= fs.HOLD_RTOL)
    for k in range(21, 51):
        step = [Segment(normal=float(result.displacement[k]),
                        tangential=float(result.tangential_displacement[k]), steps=1)]  # fmt: skip
        free = simulate(lower, upper, path=step, record_contacts=[1], diagnostics=False)
        same = np.array_equal(_points(free, 1), _points(result, k))
        assert same == (codes[k] == fs.HELD), (k, codes[k])
    assert force_control_counts(result) == {
        1: int(np.sum(codes == 1)),
        2: int(np.sum(codes == 2)),
        3: 0,
    }
    assert force_control_counts(result, segment=0) == {1: 0, 2: 0, 3: 0}


def test_displacement_controlled_steps_are_unchanged_and_code_zero(rough_run) -> None:  # type: ignore[no-untyped-def]
    """The new variable changes no other output: the pressing steps equal a displacement-only
    path to the bit, and a displacement-only path is all 0."""
    lower, upper, path, result = rough_run
    press = simulate(lower, upper, path=path[:1], diagnostics=False)
    assert np.all(press.force_control == fs.DISPLACEMENT)
    assert np.all(np.isnan(press.normal_force_target))
    for name in ("normal_force", "tangential_force", "contact_area", "n_contacts"):
        np.testing.assert_array_equal(press.curves[name], result.curves[name][:21])


def test_missed_steps_are_marked_and_warned(rough_run, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Where no held contact set carries the target (here forced: every attempt to hold one
    fails), the nearer side of the jump is kept: code 3, F_N off the target, one warning."""
    lower, upper, path, _ = rough_run

    def no_set(target, evaluate, state, bracket, d_miss, scale, window_of):  # type: ignore[no-untyped-def]
        return d_miss, None, None, fs.MISSED

    monkeypatch.setattr(loadpath, "_consistent_set", no_set)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        missed = simulate(lower, upper, path=path, diagnostics=False)
    codes = missed.force_control
    n_missed = int(np.sum(codes == fs.MISSED))
    assert n_missed > 0 and set(codes[21:].tolist()) <= {fs.HELD, fs.MISSED}
    miss = np.abs(missed.normal_force[21:] / missed.normal_force_target[21:] - 1)
    assert np.all(miss[codes[21:] == fs.MISSED] > loadpath.FORCE_RTOL)
    assert np.all(miss[codes[21:] == fs.HELD] <= loadpath.FORCE_RTOL)
    messages = [str(w.message) for w in caught if "could not be held" in str(w.message)]
    assert len(messages) == 1
    assert f"at {n_missed} of 30 " in messages[0] and "force_control = 3" in messages[0]


def test_elastic_plastic_sliding_holds_every_step_on_the_independent_path() -> None:
    """Sliding brings other summits onto a lower grid point whose elastic–plastic history
    (δ_max) another summit made. Before the history rule of ``contact/plasticity.py`` (the
    unloading line starts on the loading curve of the R_eff it is evaluated with) the force
    jumped at δ_max there, also with the step's contacts held, and 2 of these 42 held steps
    missed the target (code 3, F_N 0.006 % and 0.76 % off). Now F is continuous in δ and
    R_eff: every held step holds F_N to 1e−6 on eq. 9's set or a held set (codes 1 and 2
    only), and nothing warns."""
    from splinecontact.contact import ElasticPlastic

    lower = weierstrass_mandelbrot(1.5, n_points=1024, length=4.0, seed=1)
    upper = weierstrass_mandelbrot(1.3, n_points=1024, length=4.0, seed=6)
    top = 0.2 * (lower.peak_to_valley + upper.peak_to_valley)
    kwargs = {"e_star": E_STAR, "g_star": E_STAR / 2.6, "mu0": 0.3, "diagnostics": False,
              "law": ElasticPlastic(yield_strength=0.2)}  # fmt: skip
    loaded = simulate(lower, upper, path=[Segment(normal=top, steps=3)], **kwargs)
    target = 0.7 * float(loaded.normal_force[-1])
    path = [
        Segment(normal=top, steps=3),
        Segment(normal_force=target, steps=2),
        Segment(normal_force=target, tangential=0.04, steps=20),
        Segment(normal_force=target, tangential=-0.04, steps=20),
    ]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        result = simulate(lower, upper, path=path, **kwargs)
    codes = result.force_control
    assert np.all(codes[:4] == fs.DISPLACEMENT)
    assert set(codes[4:].tolist()) == {fs.HELD, fs.HELD_FIXED_SET}
    assert np.all(np.abs(result.normal_force[4:] / target - 1) <= fs.HOLD_RTOL)
    assert not [w for w in caught if "could not be held" in str(w.message)]


def _circle() -> Profile:
    x = np.arange(-400, 401) * 5 * ANGSTROM
    return Profile(x, circle_cap(x, 1.0))


@pytest.mark.parametrize("law", ["hertz", "jkr"])
@pytest.mark.parametrize("interaction", [False, True], ids=["independent", "interacting"])
def test_a_single_smooth_contact_is_held_at_every_step(law: str, interaction: bool) -> None:
    """One circle on the flat, pressed, held and slid in force: every held step is code 1 (one
    contact, F_N(δ_N) continuous). With JKR too: its jump-in at touching goes from 0 to a
    tensile force, so it never lies across a positive target (targets must be > 0)."""
    kwargs = {"e_star": E_STAR, "mu0": 0.3, "interaction": interaction, "diagnostics": False}
    if law == "jkr":
        kwargs["law"] = JKR(work_of_adhesion=0.05)
    path = [
        Segment(normal=2e-4, steps=3),
        Segment(normal_force=1e-3, steps=2),
        Segment(normal_force=1e-2, tangential=3e-3, steps=3),
        Segment(normal_force=1e-4, steps=2),
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        result = simulate(_circle(), "flat", path=path, **kwargs)
    assert result.force_control.tolist() == [0] * 4 + [1] * 7
    held = np.isfinite(result.normal_force_target)
    assert np.all(np.abs(result.normal_force[held] / result.normal_force_target[held] - 1) <= 1e-6)
    assert np.all(result.n_contacts[held] == 1)


def test_interacting_jkr_marks_the_step_inside_a_jump() -> None:
    """Interacting JKR on a rough pair: a held contact still jumps in at touching, and the
    target of the last step lies in that jump (nearer side kept): code 3 there and only where
    F_N misses by more than 1e−6; the warning counts the same steps."""
    lower = weierstrass_mandelbrot(1.5, n_points=1024, length=4.0, seed=3)
    upper = weierstrass_mandelbrot(1.3, n_points=1024, length=4.0, seed=8)
    top = 0.2 * (lower.peak_to_valley + upper.peak_to_valley)
    kwargs = {"e_star": E_STAR, "g_star": E_STAR / 2.6, "mu0": 0.3, "interaction": True,
              "diagnostics": False, "law": JKR(work_of_adhesion=0.05)}  # fmt: skip
    result, target, messages = held_force_slide(lower, upper, top, **kwargs)
    codes = result.force_control
    miss = np.abs(result.normal_force / target - 1)
    assert np.all(codes[:4] == fs.DISPLACEMENT)
    assert codes[-1] == fs.MISSED and miss[-1] > 1e-6
    assert np.all((codes[4:] == fs.MISSED) == (miss[4:] > 1e-6))
    assert np.all(np.isin(codes[4:], [fs.HELD, fs.HELD_FIXED_SET, fs.MISSED]))
    assert len(messages) == 1 and f"at {int(np.sum(codes == 3))} of 6 " in messages[0]
    # μ_s skips the missed step; dilatancy of the sliding segment uses its δ_N (the jump's)
    friction = static_friction(result)
    assert friction.skipped == 1 and friction.step != 9
    assert dilatancy(result, 2) == -(result.displacement[9] - result.displacement[5])


def _with_codes(result, codes, **curves):  # type: ignore[no-untyped-def]
    return dataclasses.replace(
        result, curves={**result.curves, "force_control": np.asarray(codes, np.int8), **curves}
    )


def test_static_friction_skips_missed_steps_and_says_so() -> None:
    """A step marked 3 carries an F_T/F_N of another load: μ_s leaves it out and counts it;
    with every loaded step marked, μ_s is refused."""
    path = [Segment(normal=2e-4, steps=3), Segment(normal_force=2e-3, tangential=3e-3, steps=6)]
    result = simulate(_circle(), "flat", e_star=E_STAR, mu0=0.3, path=path, diagnostics=False)
    base = static_friction(result)
    assert base.skipped == 0 and base.mu_s == pytest.approx(0.3, rel=1e-12)
    ft = np.array(result.tangential_force)
    ft[5] = 10.0 * float(result.normal_force[5])  # what a missed step could show
    codes = np.array(result.force_control)
    spiked = static_friction(_with_codes(result, codes, tangential_force=ft))
    assert spiked.mu_s == pytest.approx(10.0) and spiked.step == 5
    codes[5] = fs.MISSED
    marked = static_friction(_with_codes(result, codes, tangential_force=ft))
    assert marked.skipped == 1 and marked.mu_s == base.mu_s and marked.step != 5
    with pytest.raises(FrictionAnalysisError, match="missed its force target"):
        static_friction(_with_codes(result, [0] * 4 + [3] * 6, tangential_force=ft))


def test_finish_marks_misses_beyond_the_tolerance() -> None:
    target = np.array([np.nan, 1.0, 1.0, 1.0, 2.0, np.nan])
    force = np.array([0.5, 1.0 + 5e-7, 1.0 + 2e-6, 1.0, 2.0, 3.0])
    codes = np.array([1, 1, 2, 3, 2, 2], np.int8)  # a driver's code on a free step is ignored
    with pytest.warns(RuntimeWarning, match=r"at 2 of 4 .*force_control = 3.*the cause"):
        out = fs.finish(codes, force, target, cause="the cause", stacklevel=1)
    assert out.tolist() == [0, 1, 3, 3, 2, 0] and out.dtype == np.int8
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quiet = fs.finish(np.array([0, 1], np.int8), force[:2], target[:2], cause="", stacklevel=1)
    assert quiet.tolist() == [0, 1]


def test_codes_are_the_schema_flags() -> None:
    variable = schema.VARIABLES["force_control"]
    assert variable.table == "path_step" and variable.dtype == "int8" and variable.units == "1"
    assert [fs.DISPLACEMENT, fs.HELD, fs.HELD_FIXED_SET, fs.MISSED] == [0, 1, 2, 3]
    assert variable.flags == (
        "displacement_controlled",
        "held_accepted_set",
        "held_fixed_set",
        "missed_inside_jump",
    )


def test_dataset_netcdf_and_csv_keep_the_codes(rough_run, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    _, _, _, result = rough_run
    ds = result.to_xarray()
    assert ds["force_control"].dims == ("step",) and ds["force_control"].dtype == np.int8
    assert ds["force_control"].attrs["flag_meanings"].split() == list(
        schema.VARIABLES["force_control"].flags
    )
    np.testing.assert_array_equal(ds["force_control"].attrs["flag_values"], [0, 1, 2, 3])
    nc = write_result(result, tmp_path / "r.nc")
    with xr.open_dataset(nc) as back:
        np.testing.assert_array_equal(back["force_control"].values, result.force_control)
        assert (
            back["force_control"].attrs["flag_meanings"]
            == ds["force_control"].attrs["flag_meanings"]
        )
        np.testing.assert_array_equal(back["force_control"].attrs["flag_values"], [0, 1, 2, 3])
        np.testing.assert_array_equal(back["normal_force"].values, result.normal_force)
    path = write_result(result, tmp_path / "r.csv")
    lines = path.read_text(encoding="utf-8").splitlines()
    assert (
        "# force_control codes: 0 = displacement_controlled, 1 = held_accepted_set, "
        "2 = held_fixed_set, 3 = missed_inside_jump"
    ) in lines
    rows = list(csv.reader(line for line in lines if not line.startswith("#")))
    header, body = rows[0], rows[1:]
    assert "force_control [1]" in header and "normal_force_target [mN/µm]" in header
    column = [int(float(r[header.index("force_control [1]")])) for r in body]
    assert column == result.force_control.tolist()
    force = [float(r[header.index("normal_force [mN/µm]")]) for r in body]
    np.testing.assert_allclose(force, result.normal_force, rtol=1e-9)


def test_plain_simulate_csv_has_no_path_columns(tmp_path: Path) -> None:
    """A result without a load path keeps its CSV columns (no u_T, no force_control)."""
    result = simulate(_circle(), "flat", steps=3, final_displacement=1e-4, diagnostics=False)
    text = write_result(result, tmp_path / "p.csv").read_text(encoding="utf-8")
    assert "force_control" not in text and "tangential_displacement" not in text


def test_friction_command_prints_the_force_control_line(tmp_path: Path) -> None:
    args = [
        "friction", "--lower", "generated:D=1.5,seed=3,n_points=2000,length=0.2",
        "--upper", "generated:D=1.5,seed=4,n_points=2000,length=0.2",
        "--path", "normal=0.002,steps=10; force=0.01,tangential=0.002,steps=10",
        "-o", str(tmp_path / "f.nc"),
    ]  # fmt: skip
    run = CliRunner().invoke(app, args)
    assert run.exit_code == 0, run.output
    with xr.open_dataset(tmp_path / "f.nc") as ds:
        n = {c: int(np.sum(ds["force_control"].values == c)) for c in (1, 2, 3)}
    line = next(x for x in run.output.splitlines() if "force-controlled steps" in x)
    assert line.startswith(f"{n[1] + n[2]} of 10 force-controlled steps held F_N ({n[1]} ")
    assert f", {n[3]} missed it" in line
    plain = ["friction", "--lower", "generated:D=1.5,seed=3,n_points=2000,length=0.2",
             "--path", "normal=0.002,steps=5", "-o", str(tmp_path / "g.nc")]  # fmt: skip
    run = CliRunner().invoke(app, plain)
    assert run.exit_code == 0, run.output
    assert "force-controlled" not in run.output


def test_a_path_study_stores_the_codes_with_their_meanings(tmp_path: Path) -> None:
    """The study store keeps ``force_control`` (float64, NaN where not run) with the CF flags,
    equal to the codes of the same realization run directly."""
    from splinecontact.generate import weierstrass_mandelbrot_pair as pair
    from splinecontact.study import open_study, realization_seed, run_study
    from splinecontact.study.config import parse_study

    path = [{"normal": 0.004, "steps": 4}, {"normal_force": 0.02, "tangential": 0.01, "steps": 4}]
    config = parse_study(
        {
            "study": {"name": "fc", "seed": 7, "realizations": 1},
            "fixed": {"n_points": 1000, "dimension": 1.5},
            "path": path,
        }
    )
    run_study(config, tmp_path / "s.zarr", workers=1)
    ds = open_study(tmp_path / "s.zarr")
    stored = ds["force_control"]
    assert stored.attrs["flag_meanings"].split() == list(schema.VARIABLES["force_control"].flags)
    assert list(stored.attrs["flag_values"]) == [0.0, 1.0, 2.0, 3.0]
    params = config.parameters_at(())
    lower, upper = pair(
        1.5,
        seed=realization_seed(7, 0),
        **{k: params[k] for k in ("n_points", "length", "wavelength", "gamma", "directions",
                                  "n_max", "ra", "amplitude_law")},
    )  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        direct = simulate(lower, upper, path=[Segment(**s) for s in path])  # type: ignore[arg-type]
    values = stored.values.reshape(-1)
    np.testing.assert_array_equal(values, direct.force_control.astype(np.float64))
    assert np.all(values[:5] == 0) and np.all(np.isin(values[5:], [1, 2]))
