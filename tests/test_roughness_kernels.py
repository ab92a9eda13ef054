"""The compiled one-pass roughness sums used for large profiles (splinecontact._roughness)."""

from __future__ import annotations

import numpy as np
import pytest

from splinecontact import Profile, fit_spline, weierstrass_mandelbrot_pair
from splinecontact import profile as profile_module
from splinecontact.profile import (
    rms_slope,
    roughness_average,
    roughness_rms,
    slope_rms,
    surface_statistics,
)

N = profile_module._COMPILED_MIN_POINTS + 1234


@pytest.fixture(scope="module")
def pair() -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(1.6, seed=21, n_points=N, length=N * 1e-4)


def test_compiled_sums_agree_with_numpy_formulas(pair: tuple[Profile, Profile]) -> None:
    lower, _ = pair
    z, dx = lower.z, lower.dx
    assert roughness_average(z) == pytest.approx(np.mean(np.abs(z - z.mean())), rel=1e-13)
    assert roughness_rms(z) == pytest.approx(np.sqrt(np.mean((z - z.mean()) ** 2)), rel=1e-13)
    assert rms_slope(z, dx) == pytest.approx(np.sqrt(np.mean((np.diff(z) / dx) ** 2)), rel=1e-13)
    slope = fit_spline(lower).slope
    assert slope_rms(slope) == pytest.approx(np.sqrt(np.mean(slope * slope)), rel=1e-13)
    # an offset does not change the deviations beyond rounding
    assert roughness_rms(z + 3.0) == pytest.approx(roughness_rms(z), rel=1e-9)


def test_statistics_of_sums_equal_those_of_the_sum_arrays(pair: tuple[Profile, Profile]) -> None:
    # surface_statistics sums z^l + z^u and f′^l + f′^u without forming them: bit-identical
    lower, upper = pair
    fit_l, fit_u = fit_spline(lower), fit_spline(upper)
    s = surface_statistics(lower, upper, fit_l.slope, fit_u.slope)
    assert s["ra_lower"] == lower.ra and s["ra_upper"] == upper.ra
    assert s["rq_lower"] == lower.rq and s["rsq_upper"] == upper.rsq
    assert s["rsq_gap"] == Profile(lower.x, lower.z + upper.z).rsq
    assert s["rsq_gap_spline"] == slope_rms(fit_l.slope + fit_u.slope)
    assert s["rsq_upper_spline"] == slope_rms(fit_u.slope)


def test_small_profiles_keep_numpy(pair: tuple[Profile, Profile]) -> None:
    z = pair[0].z[:1000]
    assert roughness_average(z) == float(np.mean(np.abs(z - z.mean())))
    assert rms_slope(z, 0.5) == float(np.sqrt(np.mean((np.diff(z) / 0.5) ** 2)))
