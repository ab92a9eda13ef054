"""Tests of splinecontact.analysis on synthetic study Datasets with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from splinecontact import analysis
from splinecontact.errors import ParameterError
from splinecontact.results import SCALAR_VARIABLES, STEP_VARIABLES

E_STAR = 10.0
LENGTH = 100.0


def make_study(
    *,
    dimensions: tuple[float, ...] = (1.2, 1.5, 1.8),
    contact_types: tuple[str, ...] = ("rough-on-rough", "rough-on-flat"),
    realizations: int = 4,
    steps: int = 200,
    exponent: float = 1.5,
    area_slope: float = 0.02,
    failed: tuple[tuple[int, int, int], ...] = ((0, 0, 3),),
    noise: float = 0.0,
    seed: int = 0,
) -> xr.Dataset:
    """A study Dataset following the study contract, with closed-form curves.

    Realization r of grid point (d, c) has final displacement δ_f = 0.01·(1 + 0.1 r)·(1 + d)
    [µm], F_N = C_d (1 + 0.05 r) δ^p with C_d = 100/(1 + d) (F_N falls as D rises),
    A_S = a_d F_N with a_d = area_slope/(1 + d) (lower for higher D), mean separation 0.02 − δ,
    R_Sq: gap 0.5 + d, lower 0.4 + d, spline variants one tenth of those.
    Realizations listed in ``failed`` (d, c, r) get status 2 and garbage curves.
    """
    rng = np.random.default_rng(seed)
    nd, nc, nr, ns = len(dimensions), len(contact_types), realizations, steps + 1
    shape = (nd, nc, nr, ns)
    disp = np.zeros(shape)
    force = np.zeros(shape)
    area = np.zeros(shape)
    for d in range(nd):
        for c in range(nc):
            for r in range(nr):
                final = 0.01 * (1 + 0.1 * r) * (1 + d)
                delta = np.linspace(0.0, final, ns)
                disp[d, c, r] = delta
                f = 100.0 / (1 + d) * (1 + 0.05 * r) * delta**exponent
                if noise:
                    f = np.maximum.accumulate(f * (1 + noise * rng.standard_normal(ns)))
                force[d, c, r] = f
                area[d, c, r] = area_slope / (1 + d) * f
    data: dict[str, xr.Variable] = {}
    dims4 = ("dimension", "contact_type", "realization", "step")
    dims3 = ("dimension", "contact_type", "realization")
    curves = {
        "displacement": disp,
        "normal_force": force,
        "tangential_force": 0.1 * force,
        "contact_area": area,
        "n_contacts": np.round(1000 * area),
        "mean_separation": 0.02 - disp,
        "normal_force_normal_part": 0.8 * force,
        "normal_force_tangential_part": 0.2 * force,
        "n_tilted_contacts": np.round(100 * area),
        "n_candidates": np.round(3000 * area),
    }
    for name, (units, desc) in STEP_VARIABLES.items():
        data[name] = xr.Variable(dims4, curves[name], {"units": units, "long_name": desc})
    dcol = np.arange(nd)[:, None, None] * np.ones((nd, nc, nr))
    scalars = {name: np.full((nd, nc, nr), 1.0) for name in SCALAR_VARIABLES}
    scalars["final_displacement"] = disp[..., -1]
    scalars["rsq_gap"] = 0.5 + dcol
    scalars["rsq_lower"] = 0.4 + dcol
    scalars["rsq_upper"] = 0.3 + dcol
    scalars["rsq_gap_spline"] = (0.5 + dcol) / 10
    scalars["rsq_lower_spline"] = (0.4 + dcol) / 10
    scalars["rsq_upper_spline"] = (0.3 + dcol) / 10
    for name, (units, desc) in SCALAR_VARIABLES.items():
        data[name] = xr.Variable(dims3, scalars[name], {"units": units, "long_name": desc})
    status = np.ones((nd, nc, nr), dtype=np.int8)
    for d, c, r in failed:
        status[d, c, r] = 2
        for name in STEP_VARIABLES:
            data[name].values[d, c, r] = 1e9 * rng.standard_normal(ns)
    data["status"] = xr.Variable(dims3, status, {"units": "1"})
    ds = xr.Dataset(
        data,
        coords={
            "dimension": ("dimension", np.array(dimensions), {"units": "1"}),
            "contact_type": ("contact_type", np.array(contact_types)),
            "realization": np.arange(nr),
            "step": np.arange(ns),
        },
        attrs={"e_star": E_STAR, "length": LENGTH, "n_points": 1000, "steps": steps},
    )
    return ds


@pytest.fixture(scope="module")
def study() -> xr.Dataset:
    return make_study()


def test_grid_dims_and_parameter(study: xr.Dataset) -> None:
    assert analysis.grid_dims(study) == ("dimension", "contact_type")
    assert analysis.parameter(study, "e_star") == E_STAR
    assert list(analysis.parameter(study, "dimension").values) == [1.2, 1.5, 1.8]
    assert analysis.parameter(study.drop_attrs(), "length") == 100.0
    with pytest.raises(analysis.AnalysisError, match="mu0"):
        analysis.parameter(study, "mu0")


def test_ensemble_vs_displacement_known_mean_and_ci() -> None:
    # F_N linear in δ: linear interpolation onto the common grid is exact
    study = make_study(exponent=1.0)
    ens = analysis.ensemble_vs_displacement(study, n_samples=41)
    # grid point (d=0, rough-on-rough): realization 3 failed, so 0..2 are averaged
    sub = ens.isel(dimension=0, contact_type=0)
    delta = sub["displacement"].values
    assert delta[0] == 0.0
    assert delta[-1] == pytest.approx(0.01)  # smallest final displacement (r = 0)
    factors = np.array([1.0, 1.05, 1.10])
    expected = 100.0 * factors[:, None] * delta[None, :]
    np.testing.assert_allclose(
        sub["normal_force_mean"].values, expected.mean(0), rtol=1e-9, atol=1e-15
    )
    std = expected.std(0, ddof=1)
    np.testing.assert_allclose(sub["normal_force_std"].values, std, rtol=1e-9, atol=1e-15)
    half = stats.t.ppf(0.975, 2) * std / math.sqrt(3)
    np.testing.assert_allclose(
        sub["normal_force_ci_high"].values - sub["normal_force_mean"].values,
        half,
        rtol=1e-9,
        atol=1e-15,
    )
    assert (sub["normal_force_count"].values == 3).all()
    assert ens["normal_force_mean"].attrs["units"] == "mN/µm"
    assert ens["displacement"].attrs["units"] == "µm"
    assert ens["contact_area_mean"].attrs["units"] == "µm"
    # the grid point with all four realizations
    assert (ens.isel(dimension=1)["normal_force_count"].values == 4).all()


def test_ensemble_vs_force_linear_relation_is_exact(study: xr.Dataset) -> None:
    ens = analysis.ensemble_vs_force(study, n_samples=33, end_quantile=0.0)
    for d in range(3):
        sub = ens.isel(dimension=d, contact_type=1)
        f = sub["normal_force"].values
        np.testing.assert_allclose(
            sub["contact_area_mean"].values, 0.02 / (1 + d) * f, rtol=1e-9, atol=1e-15
        )
        np.testing.assert_allclose(sub["contact_area_std"].values, 0.0, atol=1e-12)
        # upper end: the smallest final load among the realizations (r = 0)
        assert f[-1] == pytest.approx(100.0 / (1 + d) * (0.01 * (1 + d)) ** 1.5)
    assert ens["normal_force"].attrs["units"] == "mN/µm"


def test_force_plateaus_use_first_step_of_each_load() -> None:
    ds = make_study(dimensions=(1.5,), contact_types=("rough-on-rough",), realizations=2, failed=())
    f = ds["normal_force"].values.copy()
    f[..., :50] = 0.0  # a long initial plateau: no contact yet
    f[..., 100:120] = f[..., 100:101]  # a plateau later on
    sep = ds["mean_separation"].values
    ds["normal_force"].values[:] = f
    out = analysis.interpolate_realizations(ds, "normal_force", ["mean_separation"], n_samples=5)
    # at F = 0 the separation is that of the first step (δ = 0), not of step 49
    np.testing.assert_allclose(out["mean_separation"].values[0, 0, :, 0], sep[0, 0, :, 0])
    assert np.isfinite(out["mean_separation"].values).all()


def test_stiffness_of_power_law() -> None:
    steps = 1000
    ds = make_study(steps=steps, exponent=1.5, failed=((1, 1, 2),))
    k = analysis.stiffness(ds)
    assert k.attrs["units"] == "mN/µm²"
    assert k.attrs["window"] == 51
    delta = ds["displacement"].values
    expected = (
        1.5
        * 100.0
        / (1 + np.arange(3))[:, None, None, None]
        * (1 + 0.05 * np.arange(4))[None, None, :, None]
        * np.sqrt(np.abs(delta))
    )
    far = slice(100, None)  # away from δ = 0, where δ^0.5 has unbounded curvature
    got = k.values[..., far]
    ref = expected[..., far]
    ok = ds["status"].values == 1
    np.testing.assert_allclose(got[ok], ref[ok], rtol=2e-3)
    assert np.isnan(k.values[1, 1, 2]).all()  # the failed one


def test_stiffness_exact_for_quadratic() -> None:
    ds = make_study(steps=100, exponent=2.0, failed=())
    k = analysis.stiffness(ds, window=11)
    delta = ds["displacement"].values
    c = (
        100.0
        / (1 + np.arange(3))[:, None, None, None]
        * (1 + 0.05 * np.arange(4))[None, None, :, None]
    )
    np.testing.assert_allclose(k.values, 2 * c * delta, rtol=1e-8, atol=1e-9)


def test_stiffness_rejects_bad_window(study: xr.Dataset) -> None:
    with pytest.raises(ParameterError, match="window"):
        analysis.stiffness(study, window=10)
    with pytest.raises(ParameterError, match="window"):
        analysis.stiffness(study, window=100001)


def test_dimensionless_stiffness_of_power_law() -> None:
    ds = make_study(steps=1000, exponent=2.0, failed=())
    out = analysis.dimensionless_stiffness(ds, n_samples=50, end_quantile=0.0)
    # F = C δ² ⇒ k = 2 C δ = 2 √(C F): k/E* = 2 √(C F)/E*, independent of the realization only
    # through C; check grid point d = 0, whose C_r = 100 (1 + 0.05 r)
    sub = out.isel(dimension=0, contact_type=0)
    f = sub["normal_force"].values
    c = 100.0 * (1 + 0.05 * np.arange(4))
    expected = (2 * np.sqrt(c[:, None] * f[None, :]) / E_STAR).mean(0)
    np.testing.assert_allclose(
        sub["dimensionless_stiffness_mean"].values[5:], expected[5:], rtol=2e-3
    )
    np.testing.assert_allclose(sub["dimensionless_load"].values, f / (E_STAR * LENGTH))
    assert out["dimensionless_stiffness_mean"].attrs["units"] == "1"
    assert out["dimensionless_load"].attrs["units"] == "1"


def test_kappa_of_linear_area_load_relation(study: xr.Dataset) -> None:
    out = analysis.kappa(study)
    assert out.attrs["rsq_source"] == "auto"
    # rough-on-rough uses rsq_gap, rough-on-flat rsq_lower
    for d in range(3):
        slope = 0.02 / (1 + d)
        rr = out["kappa"].isel(dimension=d, contact_type=0).values
        rf = out["kappa"].isel(dimension=d, contact_type=1).values
        ok_rr = study["status"].isel(dimension=d, contact_type=0).values == 1
        np.testing.assert_allclose(rr[ok_rr], (0.5 + d) * E_STAR * slope, rtol=1e-12)
        np.testing.assert_allclose(rf, (0.4 + d) * E_STAR * slope, rtol=1e-12)
        assert out["kappa_mean"].isel(dimension=d, contact_type=1) == pytest.approx(
            (0.4 + d) * E_STAR * slope
        )
    assert np.isnan(out["kappa"].values[0, 0, 3])
    assert out["kappa_count"].values[0, 0] == 3
    assert out["kappa"].attrs["units"] == "1"
    spline = analysis.kappa(study, rsq_method="spline")
    np.testing.assert_allclose(spline["kappa_mean"].values, out["kappa_mean"].values / 10)
    gap = analysis.kappa(study, rsq_source="gap")
    np.testing.assert_allclose(
        gap["kappa_mean"].values[:, 1], out["kappa_mean"].values[:, 0], rtol=1e-12
    )


def test_kappa_uses_only_the_low_load_range() -> None:
    ds = make_study(failed=())
    f = ds["normal_force"].values
    fmax = f.max(axis=-1, keepdims=True)
    a = ds["contact_area"].values
    # beyond 30 % of the final load the area saturates: κ must not see it
    a_new = np.where(f <= 0.3 * fmax, a, a * 0 + (a.max(axis=-1, keepdims=True) * 0.1))
    ds["contact_area"].values[:] = a_new
    out = analysis.kappa(ds, fit_fraction=0.3)
    np.testing.assert_allclose(
        out["kappa"].isel(contact_type=1).values,
        ((0.4 + np.arange(3)) * E_STAR * 0.02 / (1 + np.arange(3)))[:, None] * np.ones((3, 4)),
        rtol=1e-12,
    )
    wide = analysis.kappa(ds, fit_fraction=1.0)
    assert (wide["kappa"].values < out["kappa"].values).all()


def test_kappa_alternatives_shape(study: xr.Dataset) -> None:
    alt = analysis.kappa_alternatives(study)
    assert alt["kappa_mean"].sizes["rsq_method"] == 2
    assert alt["kappa_mean"].sizes["fit_fraction"] == 3
    np.testing.assert_allclose(
        alt["kappa_mean"].sel(rsq_method="spline").values,
        alt["kappa_mean"].sel(rsq_method="grid").values / 10,
    )


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.5, float("nan")])
def test_kappa_rejects_bad_fit_fraction(study: xr.Dataset, bad: float) -> None:
    with pytest.raises(ParameterError, match="fit_fraction"):
        analysis.kappa(study, fit_fraction=bad)


def test_kappa_rejects_bad_rsq_choice(study: xr.Dataset) -> None:
    with pytest.raises(ParameterError, match="rsq_source"):
        analysis.kappa(study, rsq_source="middle")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="rsq_method"):
        analysis.kappa(study, rsq_method="fft")  # type: ignore[arg-type]


def test_reference_kappas() -> None:
    assert analysis.PERSSON_KAPPA == pytest.approx(1.5958, abs=1e-4)
    assert analysis.BUSH_KAPPA == pytest.approx(2.5066, abs=1e-4)


def test_force_split(study: xr.Dataset) -> None:
    split = analysis.force_split(study)
    ok = study["status"] == 1
    later = split.isel(step=slice(1, None)).where(ok)
    np.testing.assert_allclose(later["normal_part_fraction"].values[ok.values], 0.8)
    np.testing.assert_allclose(later["tangential_part_fraction"].values[ok.values], 0.2)
    assert np.isnan(split["normal_part_fraction"].isel(step=0)).all()  # F_N = 0
    assert np.isnan(split["tilted_fraction"].values[0, 0, 3]).all()  # failed
    assert split["tilted_fraction"].attrs["units"] == "1"
    tilted = study["n_tilted_contacts"] / study["n_contacts"]
    np.testing.assert_allclose(
        split["tilted_fraction"].isel(dimension=1).values[..., -1],
        tilted.isel(dimension=1).values[..., -1],
    )


def test_values_at(study: xr.Dataset) -> None:
    v = analysis.values_at(study, "displacement", "normal_force", 0.005)
    expected = 100.0 / (1 + np.arange(3))[:, None, None] * (1 + 0.05 * np.arange(4)) * 0.005**1.5
    ok = study["status"].values == 1
    np.testing.assert_allclose(v.values[ok], np.broadcast_to(expected, v.shape)[ok], rtol=1e-3)
    assert np.isnan(v.values[0, 0, 3])
    beyond = analysis.values_at(study, "displacement", "normal_force", 1.0)
    assert np.isnan(beyond.values).all()


def test_no_successful_realization_is_an_error() -> None:
    ds = make_study(failed=tuple((0, 1, r) for r in range(4)))
    with pytest.raises(analysis.AnalysisError, match="no successful realization"):
        analysis.ensemble_vs_displacement(ds)


def test_missing_variable_is_an_error(study: xr.Dataset) -> None:
    with pytest.raises(analysis.AnalysisError, match="contact_area"):
        analysis.kappa(study.drop_vars("contact_area"))


def test_confidence_halfwidth_matches_scipy() -> None:
    rng = np.random.default_rng(3)
    x = rng.normal(size=12)
    lo, hi = stats.t.interval(0.9, 11, loc=x.mean(), scale=stats.sem(x))
    half = analysis.confidence_halfwidth(x.std(ddof=1), 12, 0.9)
    assert x.mean() + half == pytest.approx(hi)
    assert x.mean() - half == pytest.approx(lo)
    assert np.isnan(analysis.confidence_halfwidth(1.0, 1))
    with pytest.raises(ParameterError, match="confidence"):
        analysis.confidence_halfwidth(1.0, 3, 1.5)


def test_power_law_exponent_and_linear_fit() -> None:
    x = np.linspace(0.1, 3, 50)
    assert analysis.power_law_exponent(x, 4 * x**1.3) == pytest.approx(1.3)
    assert analysis.linear_fit_through_origin(x, 2.5 * x) == pytest.approx(2.5)
    assert math.isnan(analysis.linear_fit_through_origin([0.0, 0.0], [1.0, 2.0]))


def test_nominal_hurst() -> None:
    np.testing.assert_allclose(analysis.nominal_hurst([1.0, 1.5, 1.9]), [1.0, 0.5, 0.1])


@settings(max_examples=25, deadline=None)
@given(
    slope=st.floats(1e-3, 1e2),
    rsq=st.floats(1e-2, 1e1),
    exponent=st.floats(1.0, 3.0),
    fraction=st.floats(0.05, 1.0),
)
def test_kappa_property_linear_area(
    slope: float, rsq: float, exponent: float, fraction: float
) -> None:
    """Any linear A = s·F gives κ = R_Sq·E*·s whatever F(δ) and the fit range."""
    ds = make_study(
        dimensions=(1.5,),
        contact_types=("rough-on-flat",),
        realizations=2,
        steps=50,
        exponent=exponent,
        failed=(),
    )
    ds["contact_area"].values[:] = slope * ds["normal_force"].values
    ds["rsq_lower"].values[:] = rsq
    out = analysis.kappa(ds, fit_fraction=fraction)
    np.testing.assert_allclose(out["kappa"].values, rsq * E_STAR * slope, rtol=1e-10)


def test_end_quantile_extends_range_and_counts_survivors() -> None:
    ds = make_study(dimensions=(1.5,), contact_types=("rough-on-flat",), realizations=5, failed=())
    finals = ds["normal_force"].isel(step=-1).values.ravel()
    ens = analysis.ensemble_vs_force(ds, ["contact_area"], end_quantile=0.5, n_samples=21)
    f = ens["normal_force"].values.ravel()
    assert f[-1] == pytest.approx(np.quantile(finals, 0.5))
    count = ens["contact_area_count"].values.ravel()
    # at each load, the realizations whose final load reaches it
    expected = (finals[None, :] >= f[:, None] * (1 - 1e-12)).sum(axis=1)
    np.testing.assert_array_equal(count, expected)
    assert count[-1] == 3 and count[0] == 5
    # the linear relation still holds exactly where fewer realizations contribute
    np.testing.assert_allclose(ens["contact_area_mean"].values.ravel(), 0.02 / 1 * f, rtol=1e-9)
    with pytest.raises(ParameterError, match="end_quantile"):
        analysis.ensemble_vs_force(ds, end_quantile=1.5)


def test_mean_curve_stiffness_matches_the_closed_form() -> None:
    """make_study: F_r = C (1 + 0.05 r) δ^1.5, so the mean curve is C̄ δ^1.5 and k̄ = 1.5 C̄ δ^0.5."""
    ds = make_study(
        dimensions=(1.5,), contact_types=("rough-on-flat",), realizations=4, steps=400, failed=()
    )
    c_bar = 100.0 * np.mean(1 + 0.05 * np.arange(4))
    delta_end = 0.01  # smallest final displacement (r = 0, d = 0)
    loads = c_bar * np.array([0.3, 0.8]) ** 1.5 * delta_end**1.5
    out = analysis.mean_curve_stiffness(ds, loads=loads, n_samples=401, n_boot=50)
    k = out["stiffness_at_load"].values.ravel()
    expected = 1.5 * c_bar ** (2 / 3) * loads ** (1 / 3)
    np.testing.assert_allclose(k, expected, rtol=2e-3)
    dimless = out["dimensionless_stiffness_mean"].isel(dimension=0, contact_type=0)
    assert (out["dimensionless_stiffness_ci_low"] <= out["dimensionless_stiffness_mean"]).all()
    assert dimless.attrs["units"] == "1"
    assert out["stiffness_at_load_boot"].sizes["boot"] == 50
    with pytest.raises(ParameterError, match="n_boot"):
        analysis.mean_curve_stiffness(ds, n_boot=1)
