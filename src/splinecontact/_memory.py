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

import ctypes
import mmap
import sys

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["empty", "grid", "retain_freed_memory", "sparse_zeros"]

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


#: Zeroed arrays of at least this many bytes are memory-mapped (numpy's huge-page threshold).
_SPARSE_MAPPED_BYTES = 4 << 20


def sparse_zeros(rows: int, columns: int) -> NDArray[np.float64]:
    """A zeroed (rows, columns) float64 array for state of which few rows are ever touched.

    From 4 MiB it is a fresh anonymous map (zero pages from the kernel, small pages under the
    "madvise" policy): a row written costs one small page, where numpy's zeroed array (huge
    pages advised, or a recycled heap block zeroed whole) costs 2 MiB or the whole array.
    """
    nbytes = int(rows) * int(columns) * 8
    if nbytes < _SPARSE_MAPPED_BYTES:
        return np.zeros((rows, columns))
    try:
        buffer = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    except (AttributeError, OSError, ValueError):  # pragma: no cover - not POSIX, or no memory
        return np.zeros((rows, columns))
    return np.frombuffer(buffer, dtype=np.float64).reshape(rows, columns)


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


#: glibc's mallopt parameters (malloc.h).
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3

#: Freed heap memory a worker keeps instead of returning it to the kernel [bytes].
_RETAINED_BYTES = 1 << 30


def retain_freed_memory() -> bool:
    """Let this process reuse freed blocks up to ``_MAPPED_BYTES`` without new page faults.

    For processes the package starts itself (study workers), never for a caller's process:
    glibc then serves every block up to 32 MiB from its heap and keeps up to 1 GiB of freed
    heap instead of handing it back to the kernel, so the next realization's arrays reuse the
    previous one's pages (at 10⁶ points: 15–22 ms of system time per realization down to
    0.5 ms, measured). Returns whether the C library took the settings (False off glibc).
    """
    if not sys.platform.startswith("linux"):
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # pragma: no cover - no mallopt in this C library
        return False
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    mallopt.restype = ctypes.c_int
    mapped = mallopt(_M_MMAP_THRESHOLD, _MAPPED_BYTES)
    trimmed = mallopt(_M_TRIM_THRESHOLD, _RETAINED_BYTES)
    return bool(mapped == 1 and trimmed == 1)
