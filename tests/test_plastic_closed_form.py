"""The elastic–plastic line contact against its documented closed form (``docs/contact-laws.md``).

Each value is recomputed here from the stated equations, independently of the kernel: Green's
yield onset, the mean pressure interpolated in ln ω from (π/4) p0c at ω = 1 to H at ω_p = 54,
the half-width blended from b² = Rδ to b² = 2Rδ, and elastic unloading to the residual
interference δ_r = δ_max − 4 F_max/(π E*).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact.contact import plasticity as pl

E_STAR = 10.0  # GPa
R_EFF = 2.0  # µm (R = 1 µm)
SY = 0.5  # GPa


def _loading(delta: float, nu: float, hardness: float) -> tuple[float, float]:
    r = R_EFF / 2.0
    c = min(1.164 + 2.975 * nu - 2.906 * nu**2, 1.0 / (1.0 - 2.0 * nu))
    p0c = c * SY
    delta_c = 4.0 * r * (p0c / E_STAR) ** 2
    hertz = math.pi / 4.0 * E_STAR * delta
    if delta <= delta_c:
        return hertz, math.sqrt(R_EFF * delta)
    omega = delta / delta_c
    x = min((omega - 1.0) / 53.0, 1.0)
    half = math.sqrt(r * delta * (1.0 + x * x * (3.0 - 2.0 * x)))
    p_m = hardness
    if omega < 54.0:
        p_m = hardness - (hardness - math.pi / 4.0 * p0c) * math.log(54.0 / omega) / math.log(54.0)
    return min(2.0 * half * p_m, hertz), math.sqrt(2.0) * half


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.3, 0.45])
@pytest.mark.parametrize("omega", [0.5, 1.5, 4.0, 20.0, 53.0, 54.0, 120.0])
def test_loading_curve_equals_its_closed_form(nu: float, omega: float) -> None:
    hardness = 2.8 * SY
    delta = omega * pl.critical_interference(R_EFF, E_STAR, SY, nu)
    state = np.zeros(pl.N_STATE)
    force, width, d_max, f_max, _ = pl.plastic_evaluate(
        delta, R_EFF, E_STAR, SY, hardness, nu, state
    )
    expected_force, expected_width = _loading(delta, nu, hardness)
    assert force == pytest.approx(expected_force, rel=1e-12)
    assert width == pytest.approx(expected_width, rel=1e-12)
    assert (d_max, f_max) == (delta, force)


@pytest.mark.parametrize("omega", [3.0, 30.0, 80.0])
def test_unloading_line_equals_its_closed_form(omega: float) -> None:
    nu = 0.3
    hardness = 2.8 * SY
    d_max = omega * pl.critical_interference(R_EFF, E_STAR, SY, nu)
    f_max, w_max = _loading(d_max, nu, hardness)
    residual = d_max - 4.0 * f_max / (math.pi * E_STAR)
    state = np.zeros(pl.N_STATE)
    out = pl.plastic_evaluate(d_max, R_EFF, E_STAR, SY, hardness, nu, state)
    state[:] = out[2:]
    for fraction in (0.99, 0.5, 0.1):
        delta = residual + fraction * (d_max - residual)
        force, width, *_ = pl.plastic_evaluate(delta, R_EFF, E_STAR, SY, hardness, nu, state)
        assert force == pytest.approx(math.pi / 4.0 * E_STAR * (delta - residual), rel=1e-12)
        assert width == pytest.approx(w_max * math.sqrt(fraction), rel=1e-12)
    below = pl.plastic_evaluate(0.5 * residual, R_EFF, E_STAR, SY, hardness, nu, state)
    assert below[:2] == (0.0, 0.0)


@pytest.mark.parametrize(("nu", "hardness_ratio"), [(0.3, 2.8), (0.45, 2.8), (0.3, 4.0)])
def test_slope_just_beyond_yield(nu: float, hardness_ratio: float) -> None:
    # Continuous force, not slope: dF/dδ drops from (π/4)E* to (π/4)E* [1/2 + (H/p_mc − 1)/ln 54].
    hardness = hardness_ratio * SY
    d_c = pl.critical_interference(R_EFF, E_STAR, SY, nu)
    p_mc = math.pi / 4.0 * pl.critical_pressure_coefficient(nu) * SY
    h = 1e-7 * d_c
    f1 = pl.plastic_loading(d_c + h, R_EFF, E_STAR, SY, hardness, nu)[0]
    f2 = pl.plastic_loading(d_c + 2 * h, R_EFF, E_STAR, SY, hardness, nu)[0]
    ratio = (f2 - f1) / h / (math.pi / 4.0 * E_STAR)
    expected = min(0.5 + (hardness / p_mc - 1.0) / math.log(54.0), 1.0)
    assert ratio == pytest.approx(expected, rel=1e-5)
