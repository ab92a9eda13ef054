"""Preprocessing policy: refusals, explicit corrections, their records, spline resolution."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.interpolate import make_smoothing_spline

from splinecontact import GridNotUniformError, Profile, TooFewPointsError
from splinecontact.preprocess import (
    CURVATURE_BIAS_LIMIT,
    CropError,
    DuplicatePositionError,
    GridOrderError,
    Preprocessing,
    PreprocessingOptionError,
    RawProfile,
    UndefinedPointsError,
    crop,
    detrend,
    detrend_degree,
    spline_resolution,
    to_profile,
)


def _raw(x, z, **kwargs) -> RawProfile:  # type: ignore[no-untyped-def]
    return RawProfile(x, z, metadata={"source": "test.csv"}, **kwargs)


def test_defaults_change_nothing() -> None:
    x = np.arange(10.0)
    z = np.sin(x)
    p = to_profile(_raw(x, z))
    np.testing.assert_array_equal(p.x, x)
    np.testing.assert_array_equal(p.z, z)
    assert p.metadata["preprocessing"] == []
    assert p.metadata["source"] == "test.csv"


# --- undefined points -------------------------------------------------------------------------


def test_undefined_refused_with_count_and_positions() -> None:
    z = np.arange(20.0)
    z[[2, 3, 11, 12, 13, 14, 15]] = np.nan
    with pytest.raises(UndefinedPointsError) as info:
        to_profile(_raw(np.arange(20.0), z, rows=np.arange(20) + 3))
    message = str(info.value)
    assert "test.csv: 7 undefined point(s) of 20" in message
    assert "index 2, line 5 (x=2 µm)" in message
    assert "and 2 more" in message  # lists five positions


def test_interpolation_is_exact_on_a_line_and_trims_ends() -> None:
    x = np.arange(12.0)
    z = 2.0 * x + 1.0
    z[[0, 4, 5, 8, 11]] = np.nan
    p = to_profile(_raw(x, z), Preprocessing(undefined="interpolate"))
    np.testing.assert_allclose(p.z, 2.0 * p.x + 1.0)
    assert p.x[0] == 1.0 and p.x[-1] == 10.0
    (step,) = p.metadata["preprocessing"]
    assert step == {
        "step": "interpolate_undefined",
        "method": "linear",
        "n_filled": 3,
        "n_trimmed_at_ends": 2,
    }


def test_undefined_positions_are_dropped() -> None:
    x = np.arange(10.0)
    x[9] = np.nan
    p = to_profile(_raw(x, np.ones(10)), Preprocessing(undefined="interpolate"))
    assert p.n_points == 9
    assert p.metadata["preprocessing"][0] == {"step": "drop_undefined_positions", "n_dropped": 1}


# --- order, duplicates ------------------------------------------------------------------------


def test_order_refused_then_sorted() -> None:
    x = np.array([0.0, 1.0, 2.0, 4.0, 3.0, 5.0, 6.0])
    z = x**2
    with pytest.raises(GridOrderError, match=r"index 4: x\[3\]=4 µm, x\[4\]=3 µm"):
        to_profile(_raw(x, z))
    p = to_profile(_raw(x, z), Preprocessing(order="sort"))
    np.testing.assert_array_equal(p.x, np.arange(7.0))
    np.testing.assert_array_equal(p.z, np.arange(7.0) ** 2)


def test_duplicates_refused_then_averaged() -> None:
    x = np.array([0.0, 1.0, 1.0, 1.0, 2.0, 3.0, 4.0])
    z = np.array([0.0, 1.0, 2.0, np.nan, 5.0, 6.0, 7.0])
    with pytest.raises(DuplicatePositionError, match="2 repeated position"):
        to_profile(_raw(x, z), Preprocessing(undefined="interpolate"))
    p = to_profile(_raw(x, z), Preprocessing(undefined="interpolate", duplicates="average"))
    np.testing.assert_array_equal(p.z, [0.0, 1.5, 5.0, 6.0, 7.0])  # NaN ignored in the mean
    assert p.metadata["preprocessing"] == [{"step": "average_duplicates", "n_merged": 2}]


# --- grid -------------------------------------------------------------------------------------


@settings(max_examples=50, deadline=None)
@example(n=10, step=2.0, start=0.005, decimals=2)  # on rounding ties: steps 1.99, 2.00, 2.01
@given(
    n=st.integers(10, 400),
    step=st.floats(0.013, 7.9),
    start=st.floats(-100.0, 100.0),
    decimals=st.integers(2, 6),
)
def test_printed_uniform_grid_is_regularised(
    n: int, step: float, start: float, decimals: int
) -> None:
    """A uniform grid rounded to d decimals is restored within 10^-d, heights untouched.

    Unless the print is so coarse (step < 1.5 × 10^-d) that a missing sample could not be told
    from rounding: then it is refused, never regularised silently.
    """
    exact = start + step * np.arange(n)
    printed = np.round(exact, decimals)
    if np.any(np.diff(printed) <= 0):
        return
    z = np.random.default_rng(n).normal(size=n)
    q = step / 10.0**-decimals
    if q < 1.49:
        if np.ptp(np.diff(printed)) > 1e-9:  # not already uniform as printed
            with pytest.raises(GridNotUniformError, match="cannot be told from rounding"):
                to_profile(_raw(printed, z, x_resolution=10.0**-decimals))
        return
    if q < 1.51:
        return  # the boundary: the fitted step decides
    p = to_profile(_raw(printed, z, x_resolution=10.0**-decimals))
    np.testing.assert_array_equal(p.z, z)
    assert np.max(np.abs(p.x - exact)) <= 10.0**-decimals
    assert p.dx == pytest.approx(step, abs=2 * 10.0**-decimals / (n - 1))


def test_real_non_uniformity_is_refused_then_resampled() -> None:
    x = np.array([0.0, 1.0, 2.0, 3.3, 4.0, 5.0, 6.0])
    z = 3.0 * x
    with pytest.raises(GridNotUniformError, match="resample"):
        to_profile(_raw(x, z, x_resolution=0.1))
    p = to_profile(_raw(x, z), Preprocessing(nonuniform="resample"))
    np.testing.assert_allclose(p.x, np.arange(7.0))
    np.testing.assert_allclose(p.z, 3.0 * p.x)  # linear data: interpolation exact
    q = to_profile(_raw(x, z), Preprocessing(nonuniform="resample", resample_spacing=0.25))
    assert q.n_points == 25 and q.dx == pytest.approx(0.25)


def test_exact_binary_grid_is_not_regularised() -> None:
    x = np.arange(10.0)
    x[5] += 1e-3
    with pytest.raises(GridNotUniformError):
        to_profile(_raw(x, np.zeros(10)))


# --- crop, origin, form removal ---------------------------------------------------------------


def test_crop_and_zero_origin() -> None:
    x = np.arange(100.0, 120.0)
    p = to_profile(_raw(x, x), Preprocessing(crop=(105.0, 110.0), zero_origin=True))
    np.testing.assert_array_equal(p.x, np.arange(6.0))
    np.testing.assert_array_equal(p.z, np.arange(105.0, 111.0))
    assert [s["step"] for s in p.metadata["preprocessing"]] == ["crop", "zero_origin"]
    with pytest.raises(CropError, match="keeps 2 point"):
        to_profile(_raw(x, x), Preprocessing(crop=(105.0, 106.5)))
    with pytest.raises(PreprocessingOptionError, match="x_min < x_max"):
        Preprocessing(crop=(5.0, 1.0))


@pytest.mark.parametrize("degree", [0, 1, 2, 3])
def test_polynomial_form_removed_exactly(degree: int) -> None:
    x = np.linspace(1000.0, 1100.0, 201)  # offset grid: conditioning matters
    rough = 1e-3 * np.sin(2 * np.pi * x / 7.3)
    coefficients = [5.0, -0.02, 3e-4, -1e-6][: degree + 1]
    form = np.polynomial.polynomial.polyval(x - 1050.0, coefficients)
    p = to_profile(_raw(x, form + rough), Preprocessing(detrend=degree))
    fitted_rough = rough - np.polynomial.Polynomial.fit(x, rough, degree)(x)
    np.testing.assert_allclose(p.z, fitted_rough, atol=1e-9)
    step = p.metadata["preprocessing"][-1]
    assert step["degree"] == degree


def test_detrend_options_and_profile_functions() -> None:
    assert detrend_degree("none") is None
    assert detrend_degree("mean") == 0
    assert detrend_degree("tilt") == 1
    assert detrend_degree("poly3") == 3
    with pytest.raises(PreprocessingOptionError, match="polyN"):
        detrend_degree("cubic")
    with pytest.raises(PreprocessingOptionError, match="0–10"):
        detrend_degree(11)
    p = Profile(np.arange(10.0), 0.5 * np.arange(10.0) + 2.0, metadata={"source": "s"})
    flat = detrend(p, "tilt")
    np.testing.assert_allclose(flat.z, 0.0, atol=1e-12)
    assert flat.metadata["preprocessing"][0]["coefficients"] == pytest.approx([2.0, 0.5])
    assert "preprocessing" not in p.metadata  # the input is unchanged
    short = crop(flat, 2.0, 7.0)
    assert short.n_points == 6
    assert [s["step"] for s in short.metadata["preprocessing"]] == ["remove_tilt", "crop"]
    with pytest.raises(CropError):
        crop(flat, 2.0, 3.0)


def test_option_validation() -> None:
    with pytest.raises(PreprocessingOptionError, match="undefined='fill'"):
        Preprocessing(undefined="fill")  # type: ignore[arg-type]
    with pytest.raises(PreprocessingOptionError, match="positive"):
        Preprocessing(resample_spacing=-1.0)


def test_too_few_points_after_preprocessing() -> None:
    with pytest.raises(TooFewPointsError):
        to_profile(_raw(np.arange(4.0), np.zeros(4)))


# --- spline resolution (eq. 3) ----------------------------------------------------------------


def test_cutoff_matches_the_paper_grids() -> None:
    """PHYSICS.md: about 3.5 nm at 10⁶ points over 100 µm, about 20 nm at 10⁵."""
    fine = spline_resolution(1e-4)
    assert fine.cutoff_wavelength == pytest.approx(3.53e-3, rel=1e-2)
    assert fine.points_per_cutoff == pytest.approx(35.3, rel=1e-2)
    assert not fine.coarse
    assert spline_resolution(1e-3).cutoff_wavelength == pytest.approx(19.9e-3, rel=1e-2)


@pytest.mark.parametrize("dx", [0.05, 0.5])
def test_cutoff_is_the_half_amplitude_wavelength_of_the_real_spline(dx: float) -> None:
    """A sinusoid of wavelength ℓ_c keeps half its amplitude in the eq. 2 spline."""
    res = spline_resolution(dx)
    x = np.arange(4000) * dx
    z = np.sin(2 * np.pi * x / res.cutoff_wavelength)
    f = make_smoothing_spline(x, z, lam=res.lam)(x)
    inner = slice(1000, 3000)
    gain = np.sum(f[inner] * z[inner]) / np.sum(z[inner] ** 2)
    assert gain == pytest.approx(0.5, abs=0.03)


def test_curvature_bias_formula_matches_spline_interpolation() -> None:
    """The bias is that of the interpolating cubic spline's f'' for N points per wavelength."""
    for points in (4.2, 5.9, 12.0):
        dx = 1.0
        x = np.arange(3000) * dx
        k = 2 * np.pi / (points * dx)
        spline = make_smoothing_spline(x, np.sin(k * x), lam=1e-12)
        second = spline.derivative(2)(x)[1000:2000]
        ratio = np.sum(second * -k * k * np.sin(k * x[1000:2000])) / np.sum(
            (k * k * np.sin(k * x[1000:2000])) ** 2
        )
        theta = k * dx
        predicted = 6 * (1 - np.cos(theta)) / (theta**2 * (2 + np.cos(theta)))
        assert ratio == pytest.approx(predicted, rel=1e-3)


def test_coarse_grids_are_flagged_with_a_remedy() -> None:
    hfm = spline_resolution(0.5)
    assert hfm.coarse and not hfm.interpolates
    assert hfm.points_per_cutoff == pytest.approx(4.2, abs=0.01)
    assert hfm.curvature_bias == pytest.approx(0.195, abs=0.005)
    better = spline_resolution(0.5, x0=hfm.x0_for_limit)  # the suggested x0 reaches the limit
    assert better.curvature_bias == pytest.approx(CURVATURE_BIAS_LIMIT, rel=1e-6)
    assert spline_resolution(200.0).interpolates


def test_explicit_resample_spacing_applies_after_grid_regularisation() -> None:
    """xy-4.txt prints x to 1e−6 µm and is regularised; an explicit resample spacing must still
    put it on the requested grid (to share another scan's grid), not be skipped."""
    from pathlib import Path

    from splinecontact.io import read_profile

    sample = Path(__file__).parent / "data" / "xy-4.txt"
    plain = read_profile(sample, unit="um")
    assert [s["step"] for s in plain.metadata["preprocessing"]] == ["regularize_grid"]
    resampled = read_profile(
        sample, unit="um", preprocessing=Preprocessing(nonuniform="resample", resample_spacing=2e-4)
    )
    assert resampled.dx == pytest.approx(2e-4, rel=1e-12)
    assert [s["step"] for s in resampled.metadata["preprocessing"]][-1] == "resample"
