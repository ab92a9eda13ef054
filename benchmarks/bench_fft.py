"""CPU time of one application of the BEM's elastic operator, u = irfft(λ · rfft(p)).

    python benchmarks/bench_fft.py                      # 2^14, 2^16, 3·2^14 and 10^5 points
    python benchmarks/bench_fft.py 4096 12288           # other grid sizes

Four ways, interleaved in rounds so that a drift of the machine hits all of them: scipy.fft
returning new arrays, scipy.fft with ``workers=2``, numpy.fft writing into preallocated buffers
(``out=``), and the package's compiled transform pair (``splinecontact._fft``), which the solver
uses on every grid (directly when n/2 = 2^a·3^b, zero-padded otherwise). Median CPU time
(``time.process_time``) per call over the rounds, wall time beside.
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np
import scipy.fft as sfft

from splinecontact._fft import CirculantConvolution


def main() -> None:
    sizes = [int(a) for a in sys.argv[1:]] or [2**14, 2**16, 3 * 2**14, 10**5]
    for n in sizes:
        _one_size(n)


def _one_size(n: int) -> None:
    rng = np.random.default_rng(0)
    p = rng.random(n)
    lam = rng.random(n // 2 + 1)
    spectrum = np.empty(n // 2 + 1, dtype=np.complex128)
    out = np.empty(n)

    def scipy_new() -> None:
        sfft.irfft(lam * sfft.rfft(p), n)

    def scipy_workers() -> None:
        sfft.irfft(lam * sfft.rfft(p, workers=2), n, workers=2)

    def numpy_out() -> None:
        np.fft.rfft(p, out=spectrum)
        np.multiply(spectrum, lam, out=spectrum)
        np.fft.irfft(spectrum, n, out=out)

    compiled = CirculantConvolution(lam, n)

    def compiled_pair() -> None:
        compiled(p, out)

    ways = {"scipy.fft": scipy_new, "scipy.fft workers=2": scipy_workers,
            "numpy.fft out=": numpy_out, "compiled pair": compiled_pair}  # fmt: skip
    calls = 200 if n <= 2**14 else 50
    cpu: dict[str, list[float]] = {k: [] for k in ways}
    wall: dict[str, list[float]] = {k: [] for k in ways}
    for fn in ways.values():
        fn()
    for _ in range(7):
        for name, fn in ways.items():
            c0, w0 = time.process_time(), time.perf_counter()
            for _ in range(calls):
                fn()
            cpu[name].append((time.process_time() - c0) / calls)
            wall[name].append((time.perf_counter() - w0) / calls)
    for name in ways:
        print(
            f"n={n:6d} {name:22s} cpu {statistics.median(cpu[name]) * 1e6:7.1f} µs  "
            f"wall {statistics.median(wall[name]) * 1e6:7.1f} µs"
        )


if __name__ == "__main__":
    main()
