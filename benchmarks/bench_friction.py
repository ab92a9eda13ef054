"""Cost of a load path against a plain normal loading (10⁶ points, rough-on-rough, D = 1.5).

    python benchmarks/bench_friction.py [--travel 1.0] [--only normal|path]

Times (wall and CPU after a warm-up; the two cases run alternately, ``--repeat`` times each, so
that a drift of the machine's speed hits both) the complete ``simulate`` call for

* a 1000-step normal loading to the default final displacement (0.2 × peak-to-valley), and
* the path: the same 1000 normal steps, then 1000 tangential steps of ``--travel`` µm at that δ_N,

and prints the best and the median of each and their ratios. Spline fits are included in both
(they are the same work); the normal loading runs with ``diagnostics=False``, as a load path
runs none of those checks.

With ``--only normal`` or ``--only path`` one run of that case is made and nothing is timed:
for whole-process timing by an outside tool (e.g. ``/usr/bin/time -v``), which then also
counts the interpreter start, the imports and the generation of the pair.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable
from typing import Any

from splinecontact import Segment, simulate, weierstrass_mandelbrot_pair


def _time(run: Callable[[], Any]) -> tuple[float, float, Any]:
    w0, c0 = time.perf_counter(), time.process_time()
    result = run()
    return time.perf_counter() - w0, time.process_time() - c0, result


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--travel", type=float, default=1.0, help="tangential travel [µm]")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", choices=["normal", "path"], default=None)
    parser.add_argument("--repeat", type=int, default=7, help="timed runs of each case")
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
    path = [Segment(normal=final, steps=1000), Segment(tangential=args.travel, steps=1000)]
    runs: dict[str, list[tuple[float, float]]] = {"normal": [], "path": []}
    normal = simulate(lower, upper, steps=1000, diagnostics=False)  # warm-up (numba cache)
    moved = simulate(lower, upper, path=path)
    for _ in range(args.repeat):
        wall, cpu, normal = _time(lambda: simulate(lower, upper, steps=1000, diagnostics=False))
        runs["normal"].append((wall, cpu))
        wall, cpu, moved = _time(lambda: simulate(lower, upper, path=path))
        runs["path"].append((wall, cpu))
    print(f"load average: {os.getloadavg()}")
    print(f"points {lower.n_points}, final δ_N {final:.4g} µm, travel {args.travel} µm")
    print(f"contacts at full load: {int(normal.n_contacts[-1])}; after sliding: "
          f"{int(moved.n_contacts[-1])}")  # fmt: skip
    stats = {
        key: [(min(v[k] for v in val), statistics.median(v[k] for v in val)) for k in (0, 1)]
        for key, val in runs.items()
    }
    (wn, wn_med), (cn, cn_med) = stats["normal"]
    (wp, wp_med), (cp, cp_med) = stats["path"]
    print(
        f"| run ({args.repeat} each, alternated) | wall best / median [s] | CPU best / median [s] |"
    )
    print("|---|---|---|")
    print(f"| 1000-step normal loading | {wn:.3f} / {wn_med:.3f} | {cn:.3f} / {cn_med:.3f} |")
    print(f"| 1000 normal + 1000 tangential | {wp:.3f} / {wp_med:.3f} | {cp:.3f} / {cp_med:.3f} |")
    print(
        f"| ratio | {wp / wn:.2f} / {wp_med / wn_med:.2f} | {cp / cn:.2f} / {cp_med / cn_med:.2f} |"
    )


if __name__ == "__main__":
    main()
