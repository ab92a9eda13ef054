"""Profile construction and validation (issue 2, item 2)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from splinecontact import Profile
from splinecontact.errors import (
    GridNotIncreasingError,
    GridNotUniformError,
    NonFiniteValueError,
    ProfileError,
    ProfileShapeError,
    SplineContactError,
    TooFewPointsError,
)


def test_valid_profile_properties() -> None:
    x = np.linspace(0.0, 1.0, 11)
    z = np.array([0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0], dtype=float) * 1e-3
    p = Profile(x, z, metadata={"source": "test"})
    assert p.n_points == 11
    assert p.dx == pytest.approx(0.1)
    assert p.length == pytest.approx(1.0)
    assert p.peak_to_valley == pytest.approx(2e-3)
    assert p.ra == pytest.approx(np.mean(np.abs(z - z.mean())))
    assert p.rsq == pytest.approx(np.sqrt(np.mean((np.diff(z) / 0.1) ** 2)))
    assert "n_points=11" in repr(p)


def test_profile_is_immutable_copy() -> None:
    x = np.linspace(0.0, 1.0, 6)
    z = np.zeros(6)
    p = Profile(x, z)
    z[0] = 5.0
    assert p.z[0] == 0.0
    with pytest.raises(ValueError):
        p.z[0] = 1.0
    with pytest.raises(AttributeError):
        p.x = x  # type: ignore[misc]


@pytest.mark.parametrize(
    ("x", "z", "error", "fragment"),
    [
        (np.zeros((2, 3)), np.zeros((2, 3)), ProfileShapeError, "one-dimensional"),
        (np.linspace(0, 1, 6), np.zeros(5), ProfileShapeError, "same length"),
        (np.linspace(0, 1, 4), np.zeros(4), TooFewPointsError, "at least 5"),
        (np.linspace(0, 1, 6), [0, 0, np.nan, 0, 0, 0], NonFiniteValueError, "z[2]"),
        ([0, 0.1, 0.2, np.inf, 0.4, 0.5], np.zeros(6), NonFiniteValueError, "x[3]"),
        ([0, 0.1, 0.2, 0.2, 0.4, 0.5], np.zeros(6), GridNotIncreasingError, "index 3"),
        ([0.5, 0.4, 0.3, 0.2, 0.1, 0.0], np.zeros(6), GridNotIncreasingError, "index 1"),
        ([0, 0.1, 0.2, 0.31, 0.4, 0.5], np.zeros(6), GridNotUniformError, "step 2→3"),
    ],
)
def test_bad_profiles_raise_specific_errors(x, z, error, fragment) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(error, match=re.escape(fragment)) as info:
        Profile(x, z)
    assert isinstance(info.value, ProfileError)
    assert isinstance(info.value, SplineContactError)


def test_uniform_tolerance_accepts_linspace_rounding() -> None:
    x = np.linspace(0.0, 100.0, 1_000_001)
    Profile(x, np.zeros_like(x))
