"""CPU time of one realization: the package against the plain-numba floor prototype.

    python benchmarks/bench_floor.py --n-points 1000000 --repeats 7

Both run in this process, alternately (package, prototype, package, ...), after a warm-up, so a
drift of the machine's speed hits both; the median CPU time (``time.process_time``) of each and
the median of the pair-by-pair ratios are printed, wall time beside.
"""

from __future__ import annotations

import argparse
import statistics
import time

from floor_prototype import realization as floor_realization


def package_realization(n_points: int, seed: int) -> object:
    from splinecontact import simulate, weierstrass_mandelbrot_pair

    lower, upper = weierstrass_mandelbrot_pair(
        1.5, seed=seed, n_points=n_points, length=100.0 * n_points / 1_000_000
    )
    return simulate(lower, upper, steps=1000)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-points", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    package_realization(10_000, 0)
    floor_realization(10_000, 0)
    rows = []
    for r in range(args.repeats):
        row = []
        for fn in (package_realization, floor_realization):
            c0, w0 = time.process_time(), time.perf_counter()
            fn(args.n_points, 1 + r)
            row.append((time.process_time() - c0, time.perf_counter() - w0))
        rows.append(row)
    pkg_cpu = statistics.median(r[0][0] for r in rows)
    flo_cpu = statistics.median(r[1][0] for r in rows)
    pkg_wall = statistics.median(r[0][1] for r in rows)
    flo_wall = statistics.median(r[1][1] for r in rows)
    ratios = [r[0][0] / r[1][0] for r in rows]
    print(f"n_points={args.n_points} repeats={args.repeats}")
    print(f"package   cpu {pkg_cpu * 1e3:8.1f} ms  wall {pkg_wall * 1e3:8.1f} ms")
    print(f"prototype cpu {flo_cpu * 1e3:8.1f} ms  wall {flo_wall * 1e3:8.1f} ms")
    print(
        f"CPU ratio package/prototype: median {statistics.median(ratios):.2f} "
        f"(min {min(ratios):.2f}, max {max(ratios):.2f})"
    )


if __name__ == "__main__":
    main()
