"""The compiled circulant convolution of the BEM against numpy's FFT."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact._fft import MIN_SIZE, CirculantConvolution, fast_size
from splinecontact.errors import BEMError


def _reference(response: np.ndarray, values: np.ndarray) -> np.ndarray:
    return np.fft.irfft(response * np.fft.rfft(values), values.size)


@pytest.mark.parametrize("exponent", range(8, 18))
def test_matches_numpy_at_every_power_of_two(exponent: int) -> None:
    # odd and even powers of two: the four-step split and the radix-2 stage both get used
    n = 2**exponent
    rng = np.random.default_rng(exponent)
    response = rng.random(n // 2 + 1)
    values = rng.standard_normal(n)
    out = np.full(n, np.nan)
    CirculantConvolution(response, n)(values, out)
    expected = _reference(response, values)
    assert np.max(np.abs(out - expected)) <= 1e-14 * np.max(np.abs(expected))


@settings(max_examples=30, deadline=None)
@given(
    exponent=st.integers(8, 12),
    mode=st.integers(0, 2**12),
    seed=st.integers(0, 2**32 - 1),
)
def test_single_modes_and_point_loads(exponent: int, mode: int, seed: int) -> None:
    # a pure cosine is an eigenvector: λ_k times itself; a point load gives the kernel column
    n = 2**exponent
    k = mode % (n // 2 + 1)
    response = np.random.default_rng(seed).random(n // 2 + 1)
    op = CirculantConvolution(response, n)
    x = np.arange(n)
    out = np.empty(n)
    wave = np.cos(2 * np.pi * ((k * x) % n) / n)  # the angle reduced exactly
    op(wave, out)
    assert np.allclose(out, response[k] * wave, atol=1e-13, rtol=0)
    unit = np.zeros(n)
    unit[seed % n] = 1.0
    op(unit, out)
    assert np.allclose(out, _reference(response, unit), atol=1e-15, rtol=0)


def test_repeated_calls_reuse_buffers_without_drift() -> None:
    n = 2**12
    rng = np.random.default_rng(3)
    op = CirculantConvolution(rng.random(n // 2 + 1), n)
    values = rng.standard_normal(n)
    first = np.empty(n)
    op(values, first)
    again = np.empty(n)
    for _ in range(3):
        op(rng.standard_normal(n), again)
    op(values, again)
    assert np.array_equal(first, again)


@pytest.mark.parametrize("n", [MIN_SIZE // 2, 3 * 256, 1000, 2**12 + 2])
def test_other_sizes_are_not_fast_and_refused(n: int) -> None:
    assert not fast_size(n)
    with pytest.raises(BEMError, match="power of two"):
        CirculantConvolution(np.ones(n // 2 + 1), n)
