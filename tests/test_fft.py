"""The compiled circulant convolution of the BEM against numpy's FFT (rfft/irfft), any length."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact._fft import MIN_SIZE, CirculantConvolution, fast_size, transform_size
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


def _relative_error(response: np.ndarray, values: np.ndarray) -> float:
    n = values.size
    out = np.full(n, np.nan)
    CirculantConvolution(response, n)(values, out)
    expected = _reference(response, values)
    return float(np.max(np.abs(out - expected)) / np.max(np.abs(expected)))


@pytest.mark.parametrize(
    "n",
    [
        3 * 256, 2 * 3**5, 3 * 2**10, 9 * 2**9, 3 * 2**14, 2 * 3**9,  # factors three
        1000, 2 * 5**5, 10 * 2**12, 15 * 2**9, 10**5,  # factors five (and three)
    ],
)  # fmt: skip
def test_matches_numpy_at_sizes_with_factors_three_and_five(n: int) -> None:
    # n/2 = 2^a·3^b·5^c: transformed directly (radix-5 and radix-3 stages beside the radix-4
    # and radix-2 ones)
    assert fast_size(n) and transform_size(n) == n
    rng = np.random.default_rng(n)
    assert _relative_error(rng.random(n // 2 + 1), rng.standard_normal(n)) <= 1e-12


@pytest.mark.parametrize(
    "n",
    [
        8, 9, 15, 127, MIN_SIZE // 2, MIN_SIZE - 1, MIN_SIZE + 1,  # short and odd
        97, 1009, 4099, 65_537,  # primes
        2**12 + 2, 7 * 2**11, 2 * 1009, 6006, 2 * 7 * 10**4,  # even, other prime factors
    ],
)  # fmt: skip
def test_matches_numpy_at_other_sizes(n: int) -> None:
    # any other length is embedded in a fast size ≥ 2n − 1: the same product to 1e-12
    assert not fast_size(n)
    size = transform_size(n)
    assert fast_size(size) and size >= max(2 * n - 1, MIN_SIZE)
    assert size < 2.25 * n or size == MIN_SIZE
    rng = np.random.default_rng(n)
    assert _relative_error(rng.random(n // 2 + 1), rng.standard_normal(n)) <= 1e-12


@settings(max_examples=40, deadline=None)
@given(n=st.integers(2, 5000), seed=st.integers(0, 2**32 - 1), shift=st.integers(0, 5000))
def test_any_length_matches_numpy(n: int, seed: int, shift: int) -> None:
    # property: for every length (powers of two included) the product is numpy's
    # irfft(λ · rfft(v)) to 1e-12, and it commutes with a cyclic shift of v (a circulant)
    rng = np.random.default_rng(seed)
    response = rng.random(n // 2 + 1)
    values = rng.standard_normal(n)
    assert _relative_error(response, values) <= 1e-12
    op = CirculantConvolution(response, n)
    out = np.empty(n)
    shifted = np.empty(n)
    op(values, out)
    op(np.roll(values, shift), shifted)
    np.testing.assert_allclose(shifted, np.roll(out, shift), rtol=0, atol=1e-12 * np.abs(out).max())


def test_embedded_buffers_are_reused_without_drift() -> None:
    # the zero padding of the embedding must stay zero from call to call
    n = 1001
    rng = np.random.default_rng(5)
    op = CirculantConvolution(rng.random(n // 2 + 1), n)
    values = rng.standard_normal(n)
    first = np.empty(n)
    op(values, first)
    again = np.empty(n)
    op(rng.standard_normal(n), again)
    op(values, again)
    assert np.array_equal(first, again)


@pytest.mark.parametrize("n, modes", [(1, 1), (0, 1), (1000, 500), (1001, 502), (256, 128)])
def test_wrong_response_length_is_refused(n: int, modes: int) -> None:
    with pytest.raises(BEMError, match="response modes"):
        CirculantConvolution(np.ones(modes), n)
