"""Cost of a load path against a plain normal loading (10⁶ points, rough-on-rough, D = 1.5).

    python benchmarks/bench_friction.py [--travel 1.0] [--only normal|path]

Times (wall and CPU, best of 3 after a warm-up) the complete ``simulate`` call for

* a 1000-step normal loading to the default final displacement (0.2 × peak-to-valley), and
* the path: the same 1000 normal steps, then 1000 tangential steps of ``--travel`` µm at that δ_N,

and prints the ratio. Spline fits are included in both (they are the same work); the normal
loading runs with ``diagnostics=False``, as a load path runs none of those checks.

With ``--only normal`` or ``--only path`` one run of that case is made and nothing is timed:
for whole-process timing by an outside tool (e.g. ``/usr/bin/time -v``), which then also
counts the interpreter start, the imports and the generation of the pair.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable
from typing import Any

from splinecontact import Segment, simulate, weierstrass_mandelbrot_pair


def _time(run: Callable[[], Any], repeat: int = 3) -> tuple[float, float, Any]:
    result = run()  # warm-up (numba compilation is cached on disk)
    best = (float("inf"), float("inf"))
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        result = run()
        best = min(best, (time.perf_counter() - w0, time.process_time() - c0))
    return best[0], best[1], result


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--travel", type=float, default=1.0, help="tangential travel [µm]")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", choices=["normal", "path"], default=None)
    args = parser.parse_args()
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=args.seed)
    final = 0.2 * lower.peak_to_valley
    if args.only == "normal":
        simulate(lower, upper, steps=1000, diagnostics=False)
        return
    if args.only == "path":
        path = [Segment(normal=final, steps=1000), Segment(tangential=args.travel, steps=1000)]
        simulate(lower, upper, path=path)
        return
    wall_n, cpu_n, normal = _time(lambda: simulate(lower, upper, steps=1000, diagnostics=False))
    path = [Segment(normal=final, steps=1000), Segment(tangential=args.travel, steps=1000)]
    wall_p, cpu_p, moved = _time(lambda: simulate(lower, upper, path=path))
    print(f"load average: {os.getloadavg()}")
    print(f"points {lower.n_points}, final δ_N {final:.4g} µm, travel {args.travel} µm")
    print(f"contacts at full load: {int(normal.n_contacts[-1])}; after sliding: "
          f"{int(moved.n_contacts[-1])}")  # fmt: skip
    print("| run | wall [s] | CPU [s] |")
    print("|---|---|---|")
    print(f"| 1000-step normal loading | {wall_n:.2f} | {cpu_n:.2f} |")
    print(f"| 1000 normal + 1000 tangential | {wall_p:.2f} | {cpu_p:.2f} |")
    print(f"| ratio | {wall_p / wall_n:.2f} | {cpu_p / cpu_n:.2f} |")


if __name__ == "__main__":
    main()
