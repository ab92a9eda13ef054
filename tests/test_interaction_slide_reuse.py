"""What the interacting sliding driver keeps between its coupled solves changes no result.

The driver (:mod:`splinecontact.contact.interaction_slide`) solves the first step of every
force trial (the committed δ_N from contact-free) once per shift and continues it, and lets
:func:`~splinecontact.contact.interaction.interacting_loading` keep the candidates' gap order,
slopes and quadratures between calls (``reuse``). Both must give, bit for bit, what a fresh
two-step solve of the same configuration gives.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from conftest import pressed_interacting_driver


@pytest.fixture(scope="module")
def driver():  # type: ignore[no-untyped-def]
    return pressed_interacting_driver()


def _geometry(driver, u: float, d: float):  # type: ignore[no-untyped-def]
    """The two-step geometry of a force trial at (u, d): the committed δ_N, then d."""
    from splinecontact.contact.geometry import ContactGeometry

    point, gap0, k_l, k_u, m_x, m_z, n_x, n_z = driver.columns(u, max(d, driver.d))
    index = point.astype(np.int64)
    return ContactGeometry(
        point=index, x=point * driver.dx, gap0=gap0, height_lower=driver.geo.surf.f_l[index],
        curvature_lower=k_l, curvature_upper=k_u, m_x=m_x, m_z=m_z, n_x=n_x, n_z=n_z,
        first_step_index=np.zeros(2, dtype=np.int64), displacement=np.array([driver.d, d]),
        dx=driver.dx, mean_gap0=0.0,
    )  # fmt: skip


def _fresh(driver, geometry, held=None, reuse=None):  # type: ignore[no-untyped-def]
    from splinecontact.contact.interaction import interacting_loading

    return interacting_loading(
        geometry, e_star=driver.e_star, g_star=0.0, mu0=0.0, n_points=driver.n,
        settings=dataclasses.replace(driver.given, tol=1e-11), record_steps=np.array([1]),
        contact_set=held, mesh=driver.mesh, reuse=reuse,
    )  # fmt: skip


def test_force_trials_continuing_the_cached_first_step_are_fresh_two_step_solves(
    driver,  # type: ignore[no-untyped-def]
) -> None:
    """Every force trial at one shift (free and with a held set, at rising δ_N so that the
    candidates grow) loads the same contacts with the same loads, bit for bit, as the two-step
    loading from contact-free solved afresh."""
    from splinecontact.contact.interaction_slide import _loaded

    made, top = driver
    u = 0.01
    for d in (0.6 * top, 0.8 * top, 1.3 * top, 0.55 * top):
        _, record = made.evaluate(u, d, False, 1e-11)
        _, contacts = _fresh(made, _geometry(made, u, d))
        assert record is not None and contacts
        assert np.array_equal(record.point, contacts[0].point)
        assert np.array_equal(record.normal_force, contacts[0].normal_force)
        assert np.array_equal(record.overlap, contacts[0].overlap)
        held = (_loaded(record)[::2], made.window(u, d))
        _, held_record = made.evaluate(u, d, False, 1e-11, held)
        geometry = _geometry(made, u, d)
        mask = np.isin(geometry.point, held[0])
        _, held_contacts = _fresh(made, geometry, held=mask)
        assert held_record is not None and held_contacts
        assert np.array_equal(held_record.point, held_contacts[0].point)
        assert np.array_equal(held_record.normal_force, held_contacts[0].normal_force)


def test_reuse_between_calls_changes_no_result(driver) -> None:  # type: ignore[no-untyped-def]
    """``interacting_loading`` with a ``reuse`` dict met again and again by the same candidates
    (and then by others) returns what it returns without one, bit for bit."""
    made, top = driver
    reuse: dict[str, object] = {}
    for u, d in ((0.02, 0.7 * top), (0.02, 0.6 * top), (0.02, 0.9 * top), (0.03, 0.7 * top)):
        geometry = _geometry(made, u, d)
        kept, kept_contacts = _fresh(made, geometry, reuse=reuse)
        plain, plain_contacts = _fresh(made, geometry)
        assert kept.keys() == plain.keys()
        for name in plain:
            assert np.array_equal(kept[name], plain[name], equal_nan=True), name
        for a, b in zip(kept_contacts, plain_contacts, strict=True):
            assert np.array_equal(a.point, b.point)
            assert np.array_equal(a.normal_force, b.normal_force)
    assert "fixed" in reuse
