"""Large arrays outside numpy's huge-page allocator, and the grid built in one."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact._memory import _MAPPED_BYTES, empty, grid


@pytest.mark.parametrize("n", [1, 5, 1000, _MAPPED_BYTES // 8 - 1, _MAPPED_BYTES // 8 + 3])
def test_empty_gives_writable_float64_arrays_of_any_size(n: int) -> None:
    a = empty(n)
    assert a.shape == (n,) and a.dtype == np.float64 and a.flags.writeable
    assert a.flags.c_contiguous and a.flags.aligned
    a[:] = 2.5
    assert float(a.sum()) == 2.5 * n
    a.setflags(write=False)
    with pytest.raises(ValueError):
        a[0] = 1.0


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 5000),
    length=st.floats(1e-40, 1e40, allow_nan=False, allow_infinity=False),
)
def test_grid_is_numpy_linspace_bit_for_bit(n: int, length: float) -> None:
    assert np.array_equal(grid(length, n), np.linspace(0.0, length, n))


def test_grid_is_numpy_linspace_bit_for_bit_when_mapped() -> None:
    n = _MAPPED_BYTES // 8 + 12_345
    for length in (100.0, 0.3, 1234.5678):
        assert np.array_equal(grid(length, n), np.linspace(0.0, length, n))


@pytest.mark.slow
def test_retained_memory_is_reused_without_page_faults() -> None:
    # in a fresh process (the setting is process-wide): after retain_freed_memory, arrays of a
    # second realization-sized round reuse the first round's pages
    import subprocess
    import sys

    code = """
import resource, numpy as np
from splinecontact._memory import retain_freed_memory
assert retain_freed_memory()
def faults():
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt
def round_():
    arrays = [np.ones(1_000_000) for _ in range(12)]
    del arrays
round_()
before = faults()
round_()
print(faults() - before)
"""
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    # 12 arrays of 8 MB are ~24 000 fresh 4 KiB pages; reused ones fault (almost) never
    assert int(out.stdout.strip()) < 500
