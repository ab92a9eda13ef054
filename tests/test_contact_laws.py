"""The local contact-law interface (Hertz today) and the shared tangential spring."""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact import Profile, Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.contact import ContactLaw, Hertz
from splinecontact.contact.laws import (
    HERTZ,
    _evaluate,
    _evaluate_hertz,
    _evaluate_typed,
    check_law,
    commit_law,
    kernel_material,
    law_step,
    make_law,
    new_law_state,
    normal_law,
    tangential_spring,
)
from splinecontact.errors import ParameterError


def test_hertz_is_a_contact_law_without_parameters_reach_or_state() -> None:
    law = Hertz()
    assert isinstance(law, ContactLaw)
    assert law.code == HERTZ
    assert law.name == "hertz"
    assert law.reach == 0.0
    assert law.n_state == 0
    assert law.parameters().shape == (0,)
    np.testing.assert_array_equal(law.kernel_parameters(10.0), [10.0])
    assert check_law(law) is law
    assert new_law_state(law, 7).shape == (7, 0)


@pytest.mark.parametrize("delta", [1e-9, 1e-4, 0.3])
@pytest.mark.parametrize("r_eff", [1e-3, 1.0, 250.0])
def test_hertz_law_is_eq_10_with_a_squared_equal_delta_r(delta: float, r_eff: float) -> None:
    state = new_law_state(Hertz(), 3)
    params = Hertz().kernel_parameters(7.5)
    force, width = normal_law(HERTZ, params, delta, r_eff, state, 1)
    assert force == 0.25 * math.pi * 7.5 * delta
    assert width == math.sqrt(delta * r_eff)
    commit_law(HERTZ, params, delta, r_eff, state, 1)  # no history: nothing to change
    assert state.shape == (3, 0)


@pytest.mark.parametrize("delta", [1e-9, 1e-4, 0.3])
@pytest.mark.parametrize("r_eff", [1e-3, 1.0, 250.0])
def test_hertz_alone_form_is_bit_identical(delta: float, r_eff: float) -> None:
    # The 1-tuple (E*,) of the loading loop and the array of the other kernels: the same bits.
    state = new_law_state(Hertz(), 3)
    array = Hertz().kernel_parameters(7.5)
    alone = kernel_material(
        Hertz(), e_star=7.5, g_star=3.0, mu0=0.5, n_points=3, hertz_alone=True
    ).law_params
    assert alone == (7.5,)
    for fn in (normal_law, law_step):
        assert fn(HERTZ, alone, delta, r_eff, state, 1) == fn(HERTZ, array, delta, r_eff, state, 1)
    commit_law(HERTZ, alone, delta, r_eff, state, 1)
    assert state.shape == (3, 0)


def test_hertz_alone_form_compiles_no_other_law() -> None:
    # The form is chosen by the type of the parameters when a kernel is typed: a 1-tuple gets
    # the Hertz form, which names no other law; an array gets the form with every law.
    from numba.core import types

    args = (types.int64, types.float64, types.float64, types.float64[:, :], types.int64)
    tuple_params = types.UniTuple(types.float64, 1)
    assert _evaluate_typed(args[0], tuple_params, *args[1:], types.int64) is _evaluate_hertz
    assert _evaluate_typed(args[0], types.float64[:], *args[1:], types.int64) is _evaluate
    names = set(_evaluate_hertz.__code__.co_names)
    assert not names & {"dmt_evaluate", "_history_law", "_store", "md_evaluate"}
    assert {"dmt_evaluate", "_history_law"} <= set(_evaluate.__code__.co_names)
    # Only Hertz gets it; the load-path kernel (no hertz_alone) gets an array for Hertz too.
    for law in (make_law("jkr", work_of_adhesion=0.1), make_law("elastic-plastic", hardness=2)):
        material = kernel_material(
            law, e_star=10.0, g_star=4.0, mu0=0.5, n_points=2, hertz_alone=True
        )
        assert isinstance(material.law_params, np.ndarray)
    material = kernel_material(Hertz(), e_star=10.0, g_star=4.0, mu0=0.5, n_points=2)
    assert isinstance(material.law_params, np.ndarray)


@pytest.mark.parametrize(
    ("previous", "increment", "normal", "expected", "slipping"),
    [  # binary-exact values, μ0 = 0.5
        (0.0, -0.125, 1.0, 0.125, False),  # elastic: F = previous − G*Δu
        (0.25, 0.125, 1.0, 0.125, False),
        (0.25, -0.25, 1.0, 0.5, False),  # exactly at the cap μ0 F^n: not slipping
        (0.25, -0.5, 1.0, 0.5, True),  # capped at +μ0 F^n (eq. 13)
        (-0.25, 0.5, 1.0, -0.5, True),  # capped at −μ0 F^n, sign kept
        (0.125, 0.0, 0.0, 0.0, True),  # no normal force: no tangential force
    ],
)
def test_tangential_spring_is_eqs_11_to_13(
    previous: float, increment: float, normal: float, expected: float, slipping: bool
) -> None:
    force, slip, trial = tangential_spring(previous, increment, 0.5, normal)
    assert force == expected
    assert slip is slipping
    assert trial == previous - increment


@pytest.mark.parametrize("bad", ["hertz", Hertz, 1, None])
def test_a_law_that_is_not_a_contact_law_is_refused(bad: object) -> None:
    pair = weierstrass_mandelbrot_pair(1.5, seed=1, n_points=64, length=0.1)
    if bad is None:  # None means the default law
        simulate(*pair, steps=2, law=None, diagnostics=False)
        return
    with pytest.raises(ParameterError, match="is not a contact law"):
        simulate(*pair, steps=2, law=bad, diagnostics=False)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def pair() -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(1.5, seed=11, n_points=1024, length=1.0)


@pytest.mark.parametrize("kind", ["flat", "rough"])
def test_explicit_hertz_is_bit_identical_to_the_default(
    pair: tuple[Profile, Profile], kind: str
) -> None:
    lower, upper = pair[0], "flat" if kind == "flat" else pair[1]
    a = simulate(lower, upper, steps=50, record_contacts="last", diagnostics=False)
    b = simulate(lower, upper, steps=50, record_contacts="last", diagnostics=False, law=Hertz())
    for name in ("normal_force", "tangential_force", "contact_area", "n_contacts"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    np.testing.assert_array_equal(a.contacts[0].overlap, b.contacts[0].overlap)
    path = [Segment(normal=float(a.displacement[-1]), steps=10), Segment(tangential=0.01, steps=10)]
    c = simulate(lower, upper, path=path)
    d = simulate(lower, upper, path=path, law=Hertz())
    for name in ("normal_force", "tangential_force", "contact_area", "dissipated_work"):
        np.testing.assert_array_equal(getattr(c, name), getattr(d, name))


@pytest.mark.parametrize("reach", [0.0, 2e-4, 1e-3])
def test_reach_makes_points_candidates_at_gap_reach(reach: float) -> None:
    from splinecontact import fit_spline
    from splinecontact.contact import contact_geometry

    from conftest import circle_cap

    x = np.linspace(-0.5, 0.5, 201)
    ball = Profile(x, circle_cap(x, 1.0))
    steps, final = 10, 1e-3
    geometry = contact_geometry(
        ball, "flat", steps=steps, final_displacement=final, final_displacement_factor=0.2,
        alpha=2.0, x0=1.0, reach=reach,
    )  # fmt: skip
    f = fit_spline(ball).f
    gap0 = f.max() - f
    for k, d in enumerate(geometry.displacement):
        active = set(geometry.point[: geometry.first_step_index[k]].tolist())
        assert active == set(np.flatnonzero(gap0 - reach <= d).tolist())


def test_negative_reach_is_refused() -> None:
    from splinecontact.contact import contact_geometry

    x = np.linspace(0.0, 1.0, 11)
    with pytest.raises(ParameterError, match="reach"):
        contact_geometry(
            Profile(x, np.sin(x)), "flat", steps=2, final_displacement=1e-3,
            final_displacement_factor=0.2, alpha=2.0, x0=1.0, reach=-1e-3,
        )  # fmt: skip


def test_load_path_errors_live_in_errors_and_stay_importable() -> None:
    import splinecontact
    import splinecontact.contact
    import splinecontact.errors

    for name in ("LoadPathError", "ForceControlError"):
        cls = getattr(splinecontact.errors, name)
        assert getattr(splinecontact, name) is cls
        assert getattr(splinecontact.contact, name) is cls
        assert issubclass(cls, ParameterError)
    assert issubclass(splinecontact.ForceControlError, splinecontact.LoadPathError)
