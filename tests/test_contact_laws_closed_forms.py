"""Local contact laws beyond Hertz: 2D JKR, DMT, Maugis–Dugdale and elastic–plastic.

Oracles: the closed forms of each law (line-contact JKR force–width relation and pull-off, DMT
pull-off, Green's yield onset) and independent quadratures of the Maugis–Dugdale pressure
distribution. Control mode: displacement (the overlap δ is prescribed step by step, as SAD moves
the upper body).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize

from splinecontact.contact import adhesion as ad
from splinecontact.contact import make_law
from splinecontact.contact import maugis_dugdale as md
from splinecontact.contact import plasticity as pl
from splinecontact.errors import (
    CohesiveStressError,
    ContactLawError,
    ParameterError,
    PoissonRatioError,
    SplineContactError,
    UnknownContactLawError,
    WorkOfAdhesionError,
    YieldStrengthError,
)

E_STAR = 10.0  # GPa
R_EFF = 2.0  # µm: a circle of radius 1 µm on the rigid flat
W = 1e-4  # mN/µm = 0.1 J/m²


def hertz(delta: float, r_eff: float = R_EFF) -> tuple[float, float]:
    return 0.25 * math.pi * E_STAR * delta, math.sqrt(delta * r_eff)


def jkr_path(deltas: np.ndarray, w: float = W) -> tuple[np.ndarray, np.ndarray]:
    branch = 0.0
    forces = []
    widths = []
    for d in deltas:
        f, width, branch = ad.jkr_evaluate(float(d), R_EFF, E_STAR, w, branch)
        forces.append(f)
        widths.append(width)
    return np.array(forces), np.array(widths)


def md_path(deltas: np.ndarray, w: float, sigma0: float) -> np.ndarray:
    state = np.zeros(md.N_STATE)
    forces = []
    for d in deltas:
        out = md.md_evaluate(float(d), R_EFF, E_STAR, w, sigma0, state)
        state[:5] = out[2:]
        forces.append(out[0])
    return np.array(forces)


def sigma_for(tabor: float, w: float = W) -> float:
    return tabor / 2.0 * (math.pi * w * E_STAR**2 / (0.5 * R_EFF)) ** (1.0 / 3.0)


# --- limits: every law is Hertz when its extra physics vanishes --------------------------------

DELTAS = np.array([1e-6, 1e-4, 3e-3, 0.05, 0.4])


@pytest.mark.parametrize("delta", DELTAS)
def test_zero_adhesion_is_hertz_exactly(delta: float) -> None:
    expected = hertz(delta)
    assert ad.jkr_evaluate(delta, R_EFF, E_STAR, 0.0, 0.0)[:2] == expected
    assert ad.dmt_evaluate(delta, R_EFF, E_STAR, 0.0, 1.0) == expected
    assert md.md_evaluate(delta, R_EFF, E_STAR, 0.0, 1.0, np.zeros(md.N_STATE))[:2] == expected


@pytest.mark.parametrize("delta", DELTAS[1:])
def test_vanishing_adhesion_tends_to_hertz(delta: float) -> None:
    f_h, a_h = hertz(delta)
    w = make_law("jkr", work_of_adhesion=1e-24).w
    f, width, _ = ad.jkr_evaluate(delta, R_EFF, E_STAR, w, 0.0)
    assert f == pytest.approx(f_h, rel=1e-9)
    assert width == pytest.approx(a_h, rel=1e-9)
    f, width = ad.dmt_evaluate(delta, R_EFF, E_STAR, w, 1.0)
    assert f == pytest.approx(f_h, rel=1e-9)
    assert width == pytest.approx(a_h, rel=1e-9)
    out = md.md_evaluate(delta, R_EFF, E_STAR, w, 1.0, np.zeros(md.N_STATE))
    assert out[0] == pytest.approx(f_h, rel=1e-9)
    assert out[1] == pytest.approx(a_h, rel=1e-9)


@pytest.mark.parametrize("delta", DELTAS)
def test_infinite_yield_strength_is_hertz_exactly(delta: float) -> None:
    law = make_law("elastic-plastic", yield_strength=1e50, poisson_ratio=0.3)
    out = pl.plastic_evaluate(delta, R_EFF, E_STAR, law.sy, law.h, 0.3, np.zeros(pl.N_STATE))
    assert out[:2] == hertz(delta)


# --- JKR -------------------------------------------------------------------------------------


def test_jkr_closed_forms_agree_with_the_force_width_relation() -> None:
    # Pull-off: the minimum of P(b) found numerically, independently of the closed forms.
    res = optimize.minimize_scalar(
        lambda b: ad.jkr_force(b, R_EFF, E_STAR, W),
        bounds=(1e-6, 1.0),
        method="bounded",
        options={"xatol": 1e-14},
    )
    assert res.fun == pytest.approx(ad.jkr_pull_off_force(R_EFF, E_STAR, W), rel=1e-9)
    assert res.x == pytest.approx(ad.jkr_pull_off_half_width(R_EFF, E_STAR, W), rel=1e-5)
    # Jump-out: the minimum of δ(b); jump-in: δ(b0) = 0 on the stable branch.
    res = optimize.minimize_scalar(
        lambda b: ad.jkr_approach(b, R_EFF, E_STAR, W),
        bounds=(1e-6, 1.0),
        method="bounded",
        options={"xatol": 1e-14},
    )
    assert res.x == pytest.approx(ad.jkr_jump_out_half_width(R_EFF, E_STAR, W), rel=1e-5)
    b0 = ad.jkr_jump_in_half_width(R_EFF, E_STAR, W)
    assert ad.jkr_approach(b0, R_EFF, E_STAR, W) == pytest.approx(0.0, abs=1e-15)


def test_jkr_loading_unloading_path_force_width_pairs_and_pull_off() -> None:
    b_c = ad.jkr_pull_off_half_width(R_EFF, E_STAR, W)
    b_m = ad.jkr_jump_out_half_width(R_EFF, E_STAR, W)
    d_c = ad.jkr_approach(b_c, R_EFF, E_STAR, W)
    d_m = ad.jkr_approach(b_m, R_EFF, E_STAR, W)
    load = np.linspace(-0.002, 0.01, 61)
    unload = np.concatenate([np.linspace(0.01, d_c, 50), [d_c], np.linspace(d_c, 1.02 * d_m, 30)])
    path = np.concatenate([load, unload])
    forces, widths = jkr_path(path)
    touching = widths > 0
    # Force–width pairs: the closed-form line-contact JKR relation.
    b = widths[touching] / math.sqrt(2.0)
    np.testing.assert_allclose(
        forces[touching], [ad.jkr_force(x, R_EFF, E_STAR, W) for x in b], rtol=1e-6, atol=0
    )
    np.testing.assert_allclose(
        [ad.jkr_approach(x, R_EFF, E_STAR, W) for x in b],
        path[touching],
        rtol=1e-6,
        atol=1e-12,
    )
    # No force before touching, a jump-in at δ = 0 (to b0, attractive), contact held below δ = 0
    # on unloading, then a jump-out at δ(b_m).
    assert np.all(forces[: np.searchsorted(load, 0.0)] == 0.0)
    first = np.argmax(touching)
    assert path[first] == pytest.approx(0.0, abs=1e-15)
    assert widths[first] / math.sqrt(2.0) == pytest.approx(
        ad.jkr_jump_in_half_width(R_EFF, E_STAR, W), rel=1e-9
    )
    assert forces[first] < 0.0
    assert np.all(touching[len(load) :][path[len(load) :] >= d_m])
    assert not touching[-1]
    # Minimum force under displacement control = the load-control pull-off (b_c is on the
    # stable branch because b_c > b_m).
    assert forces.min() == pytest.approx(ad.jkr_pull_off_force(R_EFF, E_STAR, W), rel=1e-4)


def test_jkr_loop_dissipates() -> None:
    d_m = ad.jkr_approach(ad.jkr_jump_out_half_width(R_EFF, E_STAR, W), R_EFF, E_STAR, W)
    path = np.concatenate([np.linspace(2 * d_m, 0.01, 400), np.linspace(0.01, 2 * d_m, 400)])
    forces, _ = jkr_path(path)
    work = np.sum(0.5 * (forces[1:] + forces[:-1]) * np.diff(path))
    assert work > 0.0


@settings(max_examples=30, deadline=None)
@given(
    r_eff=st.floats(1e-2, 1e3),
    e_star=st.floats(0.1, 500.0),
    w_jm2=st.floats(1e-3, 10.0),
    fraction=st.floats(1e-3, 3.0),  # away from the fold, where δ(b) is flat to rounding
)
def test_jkr_stable_branch_property(
    r_eff: float, e_star: float, w_jm2: float, fraction: float
) -> None:
    w = w_jm2 * 1e-3
    b_m = ad.jkr_jump_out_half_width(r_eff, e_star, w)
    b = b_m * (1.0 + fraction)
    delta = ad.jkr_approach(b, r_eff, e_star, w)
    f, width, branch = ad.jkr_evaluate(delta, r_eff, e_star, w, 2.0)
    assert branch == 2.0
    assert width / math.sqrt(2.0) == pytest.approx(b, rel=1e-6)
    assert f == pytest.approx(ad.jkr_force(b, r_eff, e_star, w), rel=1e-6, abs=1e-12 * abs(f))


# --- DMT -------------------------------------------------------------------------------------


def test_dmt_pull_off_and_attraction_at_a_gap() -> None:
    sigma0 = 0.2
    h0 = W / sigma0
    load = np.sort(np.concatenate([np.linspace(-2 * h0, 0.01, 101), [0.0]]))
    path = np.concatenate([load, load[::-1]])
    forces = np.array([ad.dmt_evaluate(d, R_EFF, E_STAR, W, sigma0)[0] for d in path])
    assert forces.min() == pytest.approx(ad.dmt_pull_off_force(R_EFF, W, sigma0), rel=1e-12)
    assert ad.dmt_evaluate(0.0, R_EFF, E_STAR, W, sigma0)[0] == pytest.approx(
        -2.0 * sigma0 * math.sqrt(2.0 * (R_EFF / 2) * h0), rel=1e-12
    )
    # Attracts at a gap below h0 (no contact width), nothing beyond.
    f, width = ad.dmt_evaluate(-0.5 * h0, R_EFF, E_STAR, W, sigma0)
    assert f < 0.0 and width == 0.0
    assert ad.dmt_evaluate(-1.01 * h0, R_EFF, E_STAR, W, sigma0) == (0.0, 0.0)
    # Single-valued: loading and unloading retrace, no dissipation.
    work = np.sum(0.5 * (forces[1:] + forces[:-1]) * np.diff(path))
    assert work == pytest.approx(0.0, abs=1e-15)


# --- Maugis–Dugdale --------------------------------------------------------------------------


def _adhesive_pressure(s: float, b: float, c: float) -> float:
    """p_A/σ0: the Dugdale tension with the bounded contact correction (closed form)."""
    s = abs(s)
    if s >= b:
        return -1.0
    return -2.0 / math.pi * math.atan(math.sqrt(c * c - b * b) / math.sqrt(b * b - s * s))


@pytest.mark.parametrize(("b", "c"), [(1.0, 1.3), (0.2, 1.0), (1.0, 4.0)])
def test_md_closed_forms_against_quadrature(b: float, c: float) -> None:
    """(MD-h) and (MD-δ) from quadratures of the half-plane Green's function (E* = σ0 = 1)."""
    r = 0.7
    breaks = [-c, -b, 0.0, b, c]

    def quad(f):
        return sum(
            integrate.quad(f, lo, hi, limit=400, epsabs=1e-13, epsrel=1e-12)[0]
            for lo, hi in itertools.pairwise(breaks)
        )

    # No displacement gradient inside the contact (the tension is balanced there).
    for x in (0.1 * b, 0.6 * b):
        pv = quad(
            lambda s, x=x: (_adhesive_pressure(s, b, c) - _adhesive_pressure(x, b, c)) / (x - s)
        )
        pv += _adhesive_pressure(x, b, c) * math.log((x + c) / (c - x))
        assert abs(pv) < 1e-9
    # Gap at x = c: Hertz part + the adhesive opening.
    opening = (
        -2
        / math.pi
        * quad(
            lambda s: _adhesive_pressure(s, b, c) * (math.log(abs(c - s)) - math.log(abs(b - s)))
        )
    )
    k = math.sqrt(c * c - b * b)
    hertz_gap = (c * k - b * b * math.acosh(c / b)) / (2 * r)
    t = k / b
    h0 = hertz_gap + opening
    assert md.md_gap_residual(b, t, 2 * r, 1.0, h0, 1.0) == pytest.approx(0.0, abs=1e-10)
    # Approach with the reference at distance βc (ln 2β = 3/2).
    u0 = (
        2
        / math.pi
        * quad(lambda s: _adhesive_pressure(s, b, c) * (1.5 + math.log(c / 2) - math.log(abs(s))))
    )
    assert md.md_approach(b, c, 2 * r, 1.0, 1.0) == pytest.approx(b * b / r + u0, rel=1e-9)
    assert md.md_force(b, c, 2 * r, 1.0, 1.0) == pytest.approx(
        math.pi * b * b / (4 * r) + quad(lambda s: _adhesive_pressure(s, b, c)), rel=1e-9
    )


def test_md_tends_to_jkr_at_large_tabor_parameter() -> None:
    b_c = ad.jkr_pull_off_half_width(R_EFF, E_STAR, W)
    errors = []
    for tabor in (100.0, 1000.0):
        sigma0 = sigma_for(tabor)
        assert md.tabor_parameter(R_EFF, E_STAR, W, sigma0) == pytest.approx(tabor)
        worst = 0.0
        for b in b_c * np.array([0.7, 1.0, 2.0, 5.0]):
            delta, force, outer = md.md_branch(b, R_EFF, E_STAR, W, sigma0)
            assert outer > b
            worst = max(
                worst,
                abs(delta - ad.jkr_approach(b, R_EFF, E_STAR, W))
                / abs(ad.jkr_approach(b_c, R_EFF, E_STAR, W)),
                abs(force - ad.jkr_force(b, R_EFF, E_STAR, W))
                / abs(ad.jkr_pull_off_force(R_EFF, E_STAR, W)),
            )
        errors.append(worst)
    assert errors[1] < 1e-4
    assert errors[1] < errors[0] / 50  # converges (as λ⁻²)
    # The fold (jump-out) tends to JKR's.
    b_f, _ = md.md_fold(R_EFF, E_STAR, W, sigma_for(1000.0))
    assert b_f == pytest.approx(ad.jkr_jump_out_half_width(R_EFF, E_STAR, W), rel=1e-4)


def test_md_tends_to_dmt_at_small_tabor_parameter() -> None:
    gaps = []
    for tabor in (0.1, 0.01):
        sigma0 = sigma_for(tabor)
        scale = math.sqrt(R_EFF * W / sigma0)
        forces = [
            md.md_branch(b, R_EFF, E_STAR, W, sigma0)[1]
            for b in np.geomspace(1e-8, 1.0, 400) * scale
        ]
        gaps.append(abs(min(forces) / ad.dmt_pull_off_force(R_EFF, W, sigma0) - 1.0))
        # Without contact the zone is the DMT (rigid) one as λ → 0.
        h0 = W / sigma0
        f_md, _, exists = md.md_noncontact(-0.5 * h0, R_EFF, E_STAR, W, sigma0)
        assert exists
        f_dmt = ad.dmt_evaluate(-0.5 * h0, R_EFF, E_STAR, W, sigma0)[0]
        assert f_md == pytest.approx(f_dmt, rel=3 * tabor)
    assert gaps[1] < 1e-3
    assert gaps[1] < gaps[0] / 10


@pytest.mark.parametrize("tabor", [0.3, 1.0, 3.0])
def test_md_path_is_continuous_on_branches_and_dissipates(tabor: float) -> None:
    sigma0 = sigma_for(tabor)
    h0 = W / sigma0
    top = 0.01
    path = np.concatenate(
        [np.linspace(-3 * h0 - 0.01, top, 300), np.linspace(top, -3 * h0 - 0.01, 300)]
    )
    forces = md_path(path, W, sigma0)
    assert forces[0] == 0.0 and forces[-1] == 0.0
    assert forces.min() < 0.0
    increments = 0.5 * (forces[1:] + forces[:-1]) * np.diff(path)
    assert np.sum(increments) >= -1e-12 * np.sum(np.abs(increments))  # ≥ 0 up to rounding
    # Loading retraced exactly where both directions are on the same (contact) branch.
    state = np.zeros(md.N_STATE)
    out = md.md_evaluate(top, R_EFF, E_STAR, W, sigma0, state)
    assert forces[299] == pytest.approx(out[0], rel=1e-12)


# --- elastic–plastic -------------------------------------------------------------------------

SY = 1.0  # GPa
NU = 0.3


def plastic_path(deltas: np.ndarray, sy: float = SY) -> tuple[np.ndarray, np.ndarray]:
    state = np.zeros(pl.N_STATE)
    forces = []
    widths = []
    for d in deltas:
        out = pl.plastic_evaluate(float(d), R_EFF, E_STAR, sy, pl.TABOR_FACTOR * sy, NU, state)
        state[:] = out[2:]
        forces.append(out[0])
        widths.append(out[1])
    return np.array(forces), np.array(widths)


def test_green_critical_values() -> None:
    c = pl.critical_pressure_coefficient(NU)
    assert c == pytest.approx(1.164 + 2.975 * 0.3 - 2.906 * 0.09)
    d_c = pl.critical_interference(R_EFF, E_STAR, SY, NU)
    b_c = pl.critical_half_width(R_EFF, E_STAR, SY, NU)
    # The Hertz peak pressure at δ_c is C S_y: p0 = E* b/(2R) with b² = R δ.
    assert E_STAR * math.sqrt(0.5 * R_EFF * d_c) / R_EFF == pytest.approx(c * SY, rel=1e-12)
    assert b_c == pytest.approx(math.sqrt(0.5 * R_EFF * d_c), rel=1e-12)
    assert pl.critical_force(R_EFF, E_STAR, SY, NU) == pytest.approx(
        math.pi * (R_EFF / 2) * (c * SY) ** 2 / E_STAR, rel=1e-12
    )


def _hertz_line_axis_stresses(z: np.ndarray, nu: float) -> tuple[np.ndarray, ...]:
    # McEwen (1949) plane-strain stresses under the Hertz line contact on the axis x = 0, in
    # units of p0, depth z in units of b (Johnson, Contact Mechanics, eq. 4.49); no shear there.
    s = np.sqrt(1.0 + z * z)
    sx = -((1.0 + 2.0 * z * z) / s - 2.0 * z)
    sz = -1.0 / s
    return sx, nu * (sx + sz), sz


@pytest.mark.parametrize("nu", [0.0, 0.05, 0.1, 0.15, 0.18, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.49])
def test_yield_onset_against_plane_strain_stress_field(nu: float) -> None:
    """C(ν) is p0/S_y at first von Mises yield of the elastic Hertz line contact: the largest
    von Mises stress on the axis (where it peaks) of the exact field, to 0.2 %."""
    z = np.linspace(0.0, 3.0, 300001)
    sx, sy, sz = _hertz_line_axis_stresses(z, nu)
    von_mises = np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2))
    assert pl.critical_pressure_coefficient(nu) == pytest.approx(1.0 / von_mises.max(), rel=2e-3)


def test_yield_onset_classical_cross_check() -> None:
    """At ν = 0.3 the classical line-contact values (Johnson, Contact Mechanics, sec. 4.2):
    Tresca τ_max = 0.30 p0 at z = 0.78 b, first yield at p0 = 3.3k = 1.67 Y; von Mises
    p0 = 1.79 Y. Through the package's Hertz convention δ_c = 4R (p0c/E*)² the critical
    interference for Y = 1 GPa, E* = 100 GPa, R = 1 µm is 4R (p0c/E*)² with the exact p0c."""
    z = np.linspace(0.0, 3.0, 300001)
    sx, sy, sz = _hertz_line_axis_stresses(z, 0.3)
    tau = np.abs(sx - sz) / 2.0
    assert tau.max() == pytest.approx(0.30, abs=5e-3)
    assert z[tau.argmax()] == pytest.approx(0.78, abs=1e-2)
    assert 1.0 / (2.0 * tau.max()) == pytest.approx(1.67, abs=5e-3)  # Tresca, Y = 2k
    c = pl.critical_pressure_coefficient(0.3)
    assert c == pytest.approx(1.79, abs=5e-3)  # von Mises
    assert c > 1.0 / (2.0 * tau.max())  # von Mises yields later than Tresca
    von_mises = np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2))
    p0c = 1.0 / von_mises.max()  # exact first yield [GPa] for Y = 1 GPa
    d_c = pl.critical_interference(2.0, 100.0, 1.0, 0.3)  # R_eff = 2R = 2 µm
    assert d_c == pytest.approx(4.0 * 1.0 * (p0c / 100.0) ** 2, rel=3e-3)


def test_plastic_below_critical_is_hertz() -> None:
    d_c = pl.critical_interference(R_EFF, E_STAR, SY, NU)
    deltas = d_c * np.array([1e-6, 0.1, 0.5, 0.999999, 1.0])
    forces, widths = plastic_path(deltas)
    for d, f, a in zip(deltas, forces, widths, strict=True):
        f_h, a_h = hertz(d)
        assert f == pytest.approx(f_h, rel=1e-12)
        assert a == pytest.approx(a_h, rel=1e-12)


def test_plastic_loading_is_continuous_at_yield_and_softer_beyond() -> None:
    d_c = pl.critical_interference(R_EFF, E_STAR, SY, NU)
    f_c = pl.critical_force(R_EFF, E_STAR, SY, NU)
    for eps in (1e-4, 1e-7, 1e-10):
        above = pl.plastic_loading(d_c * (1 + eps), R_EFF, E_STAR, SY, 2.8 * SY, NU)[0]
        assert abs(above - f_c) <= 2 * eps * f_c
    deltas = d_c * np.geomspace(1.0, 200.0, 300)
    forces = np.array([pl.plastic_loading(d, R_EFF, E_STAR, SY, 2.8 * SY, NU)[0] for d in deltas])
    assert np.all(np.diff(forces) > 0)
    assert np.all(forces[1:] < 0.25 * math.pi * E_STAR * deltas[1:])
    # Fully plastic: mean pressure = hardness over the truncated width 2√(2Rδ).
    d = 100 * d_c
    f, b = pl.plastic_loading(d, R_EFF, E_STAR, SY, 2.8 * SY, NU)
    assert b == pytest.approx(math.sqrt(R_EFF * d), rel=1e-12)
    assert f == pytest.approx(2 * b * 2.8 * SY, rel=1e-12)


def test_plastic_unloading_reloading_is_elastic_and_retraces() -> None:
    d_c = pl.critical_interference(R_EFF, E_STAR, SY, NU)
    d_max = 8 * d_c
    down = np.linspace(d_max, 0.0, 41)
    path = np.concatenate([np.linspace(0.0, d_max, 41), down[1:], down[::-1][1:]])
    forces, widths = plastic_path(path)
    f_max = forces[40]
    residual = pl.residual_interference(d_max, f_max, E_STAR)
    assert residual > 0.0
    unload = forces[40:81]
    reload = forces[80:][::-1]
    np.testing.assert_array_equal(unload, reload)  # retraces itself
    np.testing.assert_array_equal(widths[40:81], widths[80:][::-1])
    expected = np.maximum(0.25 * math.pi * E_STAR * (down - residual), 0.0)
    np.testing.assert_allclose(unload, expected, rtol=1e-12, atol=1e-15)
    # Below the loading curve, zero below the residual interference (starts later), stiffer.
    loading = forces[:41]
    assert np.all(unload[1:-1][::-1] <= loading[1:-1] + 1e-15)
    assert np.all(forces[path < residual][41:] == 0.0)
    # Beyond the previous maximum the loading curve continues.
    more = plastic_path(np.concatenate([path, [1.5 * d_max]]))[0][-1]
    assert more == pytest.approx(
        pl.plastic_loading(1.5 * d_max, R_EFF, E_STAR, SY, 2.8 * SY, NU)[0], rel=1e-12
    )
    work = np.sum(0.5 * (forces[1:81] + forces[:80]) * np.diff(path[:81]))
    assert work > 0.0


@settings(max_examples=40, deadline=None)
@given(nu=st.floats(0.0, 0.499), ratio=st.floats(1.0, 300.0))
def test_plastic_loading_never_stiffer_than_elastic(nu: float, ratio: float) -> None:
    d_c = pl.critical_interference(R_EFF, E_STAR, SY, nu)
    d = ratio * d_c
    f1 = pl.plastic_loading(d, R_EFF, E_STAR, SY, 2.8 * SY, nu)[0]
    f2 = pl.plastic_loading(d * (1 + 1e-6), R_EFF, E_STAR, SY, 2.8 * SY, nu)[0]
    assert 0.0 <= f2 - f1 <= 0.25 * math.pi * E_STAR * d * 1e-6 * (1 + 1e-6)


# --- parameters and their errors ---------------------------------------------------------------


def test_units_of_the_work_of_adhesion() -> None:
    assert make_law("jkr", work_of_adhesion=0.5).w == pytest.approx(5e-4)
    assert make_law("dmt", work_of_adhesion=0.5, cohesive_stress=2.0).range == pytest.approx(2.5e-4)


@pytest.mark.parametrize(
    ("name", "parameters", "error"),
    [
        ("jkr", {"work_of_adhesion": -0.1}, WorkOfAdhesionError),
        ("jkr", {"work_of_adhesion": float("nan")}, WorkOfAdhesionError),
        ("jkr", {"work_of_adhesion": "0.1"}, WorkOfAdhesionError),
        ("dmt", {"work_of_adhesion": -1.0}, WorkOfAdhesionError),
        ("dmt", {"cohesive_stress": 0.0}, CohesiveStressError),
        ("maugis-dugdale", {"cohesive_stress": -2.0}, CohesiveStressError),
        ("maugis-dugdale", {"work_of_adhesion": float("inf")}, WorkOfAdhesionError),
        ("elastic-plastic", {"hardness": 0.0}, YieldStrengthError),
        ("elastic-plastic", {"yield_strength": -1.0}, YieldStrengthError),
        ("elastic-plastic", {}, YieldStrengthError),
        ("elastic-plastic", {"hardness": 2.0, "yield_strength": 1.0}, YieldStrengthError),
        ("elastic-plastic", {"hardness": 2.0, "poisson_ratio": 0.5}, PoissonRatioError),
        ("elastic-plastic", {"hardness": 2.0, "poisson_ratio": -0.1}, PoissonRatioError),
        ("jkr", {"cohesive_stress": 1.0}, ContactLawError),
        ("hooke", {}, UnknownContactLawError),
        ("", {}, UnknownContactLawError),
    ],
)
def test_bad_parameters_give_specific_errors(name: str, parameters: dict, error: type) -> None:
    with pytest.raises(error) as info:
        make_law(name, **parameters)
    assert isinstance(info.value, ParameterError)
    assert isinstance(info.value, SplineContactError)
    assert str(info.value)


def test_unknown_law_lists_the_known_ones() -> None:
    with pytest.raises(UnknownContactLawError, match="maugis-dugdale"):
        make_law("jrk")


# --- analyses of a load–unload path -------------------------------------------------------------


def test_unloading_analysis_on_a_jkr_path() -> None:
    from splinecontact.analysis.laws import cycle_energy, unloading

    d_m = ad.jkr_approach(ad.jkr_jump_out_half_width(R_EFF, E_STAR, W), R_EFF, E_STAR, W)
    b_c = ad.jkr_pull_off_half_width(R_EFF, E_STAR, W)
    d_c = ad.jkr_approach(b_c, R_EFF, E_STAR, W)
    load = np.linspace(2 * d_m, 0.01, 200)
    unload = np.sort(np.concatenate([np.linspace(2 * d_m, 0.01, 200), [d_c]]))[::-1]
    path = np.concatenate([load, unload])
    forces, _ = jkr_path(path)
    curves = {"displacement": path, "normal_force": forces}
    res = unloading(curves, load.size, path.size - 1)
    assert res.pull_off_force == pytest.approx(ad.jkr_pull_off_force(R_EFF, E_STAR, W), rel=1e-9)
    assert res.pull_off_displacement == pytest.approx(d_c, rel=1e-12)
    # Work of separation: the tensile area under the unloading branch, quadrature of (J-F, J-δ).
    b = np.linspace(ad.jkr_jump_out_half_width(R_EFF, E_STAR, W), 0.2, 20001)
    p = np.array([ad.jkr_force(x, R_EFF, E_STAR, W) for x in b])
    dd = np.array([ad.jkr_approach(x, R_EFF, E_STAR, W) for x in b])
    exact = -np.trapezoid(np.minimum(p, 0.0), dd)
    assert res.work_of_separation == pytest.approx(exact, rel=2e-2)
    assert res.work_of_separation > 0
    assert cycle_energy(curves, 0, path.size - 1).work > 0
    with pytest.raises(ParameterError):
        unloading(curves, 0, load.size - 1)  # δ_N increases
    with pytest.raises(ParameterError):
        cycle_energy(curves, 5, 5)


def test_residual_displacement_of_a_plastic_unloading() -> None:
    from splinecontact.analysis.laws import unloading

    d_c = pl.critical_interference(R_EFF, E_STAR, SY, NU)
    path = np.concatenate([np.linspace(0, 10 * d_c, 51), np.linspace(10 * d_c, 0, 51)[1:]])
    forces, _ = plastic_path(path)
    res = unloading({"displacement": path, "normal_force": forces}, 50, path.size - 1)
    assert res.pull_off_force == 0.0 and res.work_of_separation == 0.0
    expected = pl.residual_interference(10 * d_c, forces[50], E_STAR)
    assert res.residual_displacement == pytest.approx(expected, rel=1e-9)


@settings(max_examples=25, deadline=None)
@example(tabor=0.5, r_eff=1.0, factor=2.0)  # δ within 1e-9 of the fold's: cond ~ 1e8
@example(tabor=0.5, r_eff=1.0, factor=1.05)  # δ within 2e-12 of the fold's: cond ~ 1e10
@example(tabor=0.46875, r_eff=0.25, factor=1.25)  # shallow fold (λ < 0.5): δ rises ~1e-11 |δ|
@example(tabor=0.45, r_eff=0.01, factor=1.25)  # δ flat to rounding over b(1 ± 1e-4)
@given(
    tabor=st.floats(0.05, 50.0),
    r_eff=st.floats(0.01, 100.0),
    factor=st.floats(1.05, 20.0),
)
def test_md_contact_state_round_trip(tabor: float, r_eff: float, factor: float) -> None:
    """The kernels' branch (parametrized by t, closed forms) returns the half-width whose
    δ and P the b-parametrized branch (MD-h solved for c) gives, on the stable side."""
    sigma0 = tabor / 2.0 * (math.pi * W * E_STAR**2 / (0.5 * r_eff)) ** (1.0 / 3.0)
    b_f, d_f = md.md_fold(r_eff, E_STAR, W, sigma0)
    b = max(b_f, 1e-6 * r_eff) * factor
    delta, force, _ = md.md_branch(b, r_eff, E_STAR, W, sigma0)
    assert delta > d_f
    state = np.zeros(md.N_STATE)
    state[0] = 2.0  # in contact
    out = md.md_evaluate(delta, r_eff, E_STAR, W, sigma0, state)
    assert out[2] == 2.0
    # Near the fold δ(b) is flat (δ − δ_f ∝ (b − b_f)²): δ, evaluated to ~1e-14 relative by the
    # closed forms, then fixes b only to 1e-14 × cond, cond = |δ| / |b dδ/db|. The half-width
    # is held to 1e-7 wherever that is attainable, and to the attainable bound otherwise.
    h = 1e-4
    d_plus, _, _ = md.md_branch(b * (1 + h), r_eff, E_STAR, W, sigma0)
    d_minus, _, _ = md.md_branch(b * (1 - h), r_eff, E_STAR, W, sigma0)
    slope = abs((d_plus - d_minus) / (2 * h))
    # δ flat to rounding over b(1 ± h) (right at a shallow fold): δ does not fix b at all
    cond = abs(delta) / slope if slope > 0.0 else math.inf
    assert out[1] / math.sqrt(2.0) == pytest.approx(b, rel=max(1e-7, 1e-14 * cond))
    assert out[0] == pytest.approx(
        force, rel=1e-6, abs=1e-9 * abs(ad.jkr_pull_off_force(r_eff, E_STAR, W))
    )
