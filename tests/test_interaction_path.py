"""Interacting SAD along normal load paths, the stop force and what stays refused."""

from __future__ import annotations

import numpy as np
import pytest

from splinecontact import Segment, simulate
from splinecontact.contact import InteractionSettings
from splinecontact.contact.interaction_path import normal_path_displacements
from splinecontact.contact.laws import make_law
from splinecontact.errors import LoadPathError, ParameterError
from splinecontact.generate import weierstrass_mandelbrot

E_STAR = 10.0

#: Converged widths at every step (no lag), so the normal state depends on δ_N only.
TIGHT = InteractionSettings(width="hertz", width_iterations=100, tol=1e-12, width_tol=1e-13)


@pytest.fixture(scope="module")
def profile():  # type: ignore[no-untyped-def]
    return weierstrass_mandelbrot(1.5, n_points=2048, length=5.0, seed=4)


def test_path_displacements() -> None:
    d = normal_path_displacements(
        [Segment(normal=2e-3, steps=4), Segment(steps=2), Segment(normal=-1e-3, steps=3)]
    )
    np.testing.assert_allclose(
        d, [0, 5e-4, 1e-3, 1.5e-3, 2e-3, 2e-3, 2e-3, 1e-3, 0.0, -1e-3], atol=1e-18
    )


def test_monotone_path_is_the_interacting_loading(profile) -> None:  # type: ignore[no-untyped-def]
    top = 0.2 * profile.peak_to_valley
    path = simulate(
        profile, "flat", path=[Segment(normal=top, steps=20)], interaction=True,
        diagnostics=False,
    )  # fmt: skip
    plain = simulate(
        profile, "flat", steps=20, final_displacement=top, interaction=True, diagnostics=False
    )
    np.testing.assert_array_equal(path.normal_force, plain.normal_force)
    np.testing.assert_array_equal(path.coalesced_contact_length, plain.coalesced_contact_length)
    assert path.parameters["path_segment_end"] == [20]


def test_unloading_retraces_loading_and_dissipates_nothing(profile) -> None:  # type: ignore[no-untyped-def]
    top = 0.2 * profile.peak_to_valley
    result = simulate(
        profile, "flat", diagnostics=False, interaction=TIGHT,
        path=[Segment(normal=top, steps=20), Segment(normal=0.0, steps=20),
              Segment(normal=top, steps=20)],
    )  # fmt: skip
    f = result.normal_force
    d = result.displacement
    assert f.size == 61
    scale = f.max()
    assert result.n_contacts[20] > 3  # several coupled contacts
    np.testing.assert_allclose(f[20::-1], f[20:41], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(f[:21], f[40:], rtol=0, atol=1e-9 * scale)
    # work of the normal force over the cycle (trapezoids): elastic, so ≥ 0 and ≈ 0
    cycle = np.sum(0.5 * (f[1:41] + f[:40]) * np.diff(d[:41]))
    assert cycle >= -1e-9 * scale * d.max()
    assert abs(cycle) <= 1e-9 * scale * d.max()


def test_separation_unloads_everything(profile) -> None:  # type: ignore[no-untyped-def]
    top = 0.2 * profile.peak_to_valley
    result = simulate(
        profile, "flat", diagnostics=False, interaction=True,
        path=[Segment(normal=top, steps=10), Segment(normal=-0.5 * top, steps=10)],
    )  # fmt: skip
    assert result.normal_force[10] > 0
    assert result.normal_force[-1] == 0.0
    assert result.n_contacts[-1] == 0
    assert result.tangential_force[-1] == 0.0


def test_stop_force_ends_the_loading(profile) -> None:  # type: ignore[no-untyped-def]
    top = 0.2 * profile.peak_to_valley
    full = simulate(
        profile, "flat", steps=30, final_displacement=top, interaction=True, diagnostics=False
    )
    target = 0.5 * float(full.normal_force[-1])
    first = int(np.argmax(full.normal_force >= target))
    short = simulate(
        profile, "flat", steps=30, final_displacement=top, diagnostics=False,
        interaction=InteractionSettings(stop_force=target), record_contacts="all",
    )  # fmt: skip
    assert short.normal_force.size == first + 1
    np.testing.assert_array_equal(short.normal_force, full.normal_force[: first + 1])
    assert short.normal_force[-1] >= target > short.normal_force[-2]
    assert max(c.step for c in short.contacts) <= first


def test_path_refuses_steps_and_final_displacement(profile) -> None:  # type: ignore[no-untyped-def]
    path = [Segment(normal=1e-3, steps=5)]
    with pytest.raises(LoadPathError, match="steps"):
        simulate(profile, "flat", interaction=True, path=path, steps=10)
    with pytest.raises(LoadPathError, match="final_displacement"):
        simulate(profile, "flat", interaction=True, path=path, final_displacement=1e-3)


@pytest.mark.parametrize("law", ["jkr", "dmt", "maugis-dugdale", "elastic-plastic"])
def test_other_laws_run_by_name_on_sliding_paths(profile, law) -> None:  # type: ignore[no-untyped-def]
    """Every law runs interacting normal paths (tests/test_interaction_laws.py) and paths that
    slide (tests/test_interaction_laws_slide.py), chosen by name; the result records it."""
    parameters = {
        "jkr": {"work_of_adhesion": 1e-4},
        "dmt": {"work_of_adhesion": 1e-4},
        "maugis-dugdale": {"work_of_adhesion": 1e-4, "cohesive_stress": 1.0},
        "elastic-plastic": {"hardness": 1.0},
    }[law]
    try:
        chosen = make_law(law, **parameters)
    except ParameterError as exc:  # pragma: no cover - parameter names of another stream
        pytest.skip(f"law parameters changed: {exc}")
    path = [Segment(normal=1e-3, steps=2), Segment(tangential=1e-3, steps=2)]
    result = simulate(profile, "flat", path=path, interaction=True, law=chosen, diagnostics=False)
    assert result.to_xarray().attrs["law"] == chosen.name
    assert result.tangential_displacement[-1] == 1e-3 and result.normal_force[-1] > 0.0


@pytest.mark.parametrize(
    ("field", "value"), [("stop_force", -1.0), ("stop_force", float("nan")), ("width_tol", 0.0)]
)
def test_bad_settings_are_refused(profile, field, value) -> None:  # type: ignore[no-untyped-def]
    settings = InteractionSettings(**{field: value})
    with pytest.raises(ParameterError, match=field):
        simulate(profile, "flat", steps=5, interaction=settings, diagnostics=False)


def test_single_asperity_unloading_keeps_the_hertz_width() -> None:
    """One circular asperity loaded and unloaded: on both branches its coupled contact width
    is Hertz's 2√(4PR/(πE*)) at its own force (SAD's single contact is exact there)."""
    from splinecontact import Profile

    n, dx, radius = 2048, 0.01, 200.0
    x = np.arange(n) * dx
    s = np.clip(x - n // 2 * dx, -radius, radius)
    profile = Profile(x, -(s * s) / (radius + np.sqrt(radius * radius - s * s)))
    converged = InteractionSettings(width_iterations=100, width_tol=1e-10, tol=1e-12)
    result = simulate(
        profile, "flat", diagnostics=False, interaction=converged,
        path=[Segment(normal=4e-3, steps=40), Segment(normal=1e-3, steps=30)],
    )  # fmt: skip
    steps = np.array([20, 40, 55, 70])
    force = result.normal_force[steps]
    assert np.all(result.n_contacts[steps] == 1)
    hertz = 2.0 * np.sqrt(4.0 * force * radius / (np.pi * E_STAR))
    np.testing.assert_allclose(result.coalesced_contact_length[steps], hertz, rtol=2e-3)
    # unloading to δ_N = 1e-3 lands where loading passed it (step 10), to the tolerance of
    # the punch widths (their load matches to 1e-6, from a start that depends on the path)
    np.testing.assert_allclose(result.normal_force[70], result.normal_force[10], rtol=1e-6)
