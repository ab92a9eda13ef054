"""Large work arrays with the operating system's own page policy.

numpy asks the kernel for transparent huge pages on every array of 4 MiB or more
(``madvise(MADV_HUGEPAGE)``). On virtual machines whose host reclaims free guest memory in 2 MiB
blocks (free page reporting), every fresh huge page is such a reclaimed block, and touching it
costs a fault on the host: measured on this project's machine class, filling 800 MB of fresh
numpy arrays took 1.9 s of system time with the advice and 0.4–1.2 s without it. The arrays
here are anonymous memory maps without that advice, so the kernel's policy
(``/sys/kernel/mm/transparent_hugepage/enabled``) decides: on "always" they still get huge pages,
on "madvise" (the common default) small pages, which the guest can take from memory it already
holds.

Arrays below ``_MAPPED_BYTES`` come from numpy as usual: up to glibc's largest dynamic mmap
threshold (32 MiB) a freed block stays in the process's heap and the next realization reuses it
without any fault, which beats fresh small pages (measured at 10⁶ points: 9 ms of system time
for the two spline fits from numpy, 29 ms from fresh maps). Larger blocks are mapped afresh for
every allocation whatever the allocator, and there the small pages win. The arrays behave like
any numpy array (they own their memory through the map, which is unmapped when the last view
dies).
"""

from __future__ import annotations

import mmap

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["empty", "grid"]

#: Arrays of more than this many bytes are memory-mapped (glibc's largest dynamic mmap
#: threshold on 64-bit systems: smaller blocks are recycled inside the heap).
_MAPPED_BYTES = 32 << 20


def empty(n: int) -> NDArray[np.float64]:
    """An uninitialised float64 array of ``n`` values, large ones outside numpy's allocator."""
    nbytes = int(n) * 8
    if nbytes <= _MAPPED_BYTES:
        return np.empty(n)
    try:
        buffer = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    except (AttributeError, OSError, ValueError):  # pragma: no cover - not POSIX, or no memory
        return np.empty(n)
    return np.frombuffer(buffer, dtype=np.float64)


@numba.njit(cache=True, nogil=True)
def _count(out: NDArray[np.float64]) -> None:  # pragma: no cover - compiled
    for i in range(out.size):
        out[i] = float(i)


def grid(length: float, n: int) -> NDArray[np.float64]:
    """``numpy.linspace(0.0, length, n)`` bit for bit, in an array from :func:`empty`.

    The same operations in the same order as numpy's: 0, 1, …, n − 1 times the step
    length/(n − 1), plus the start, and the last value set to ``length`` exactly.
    """
    x = empty(n)
    _count(x)
    if n > 1:
        step = np.float64(length) / (n - 1)
        if step == 0.0:  # pragma: no cover - lengths are validated far above underflow
            return np.linspace(0.0, length, n)
        np.multiply(x, step, out=x)
    np.add(x, 0.0, out=x)
    if n > 1:
        x[-1] = length
    return x
