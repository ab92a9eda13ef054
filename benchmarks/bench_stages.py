"""CPU, system and wall time of each stage of one SAD realization, in one process.

    python benchmarks/bench_stages.py --n-points 1000000 --repeats 5

Rough-on-rough, D = 1.5, 1000 loading steps: generation of the pair, the two spline fits, the
geometry pass (spheres and placement) and the loading loop. Each stage is timed with
``time.process_time`` (CPU), ``resource.getrusage`` (user and system separately) and
``time.perf_counter`` (wall); the median over the repeats after one warm-up is printed, with the
process's peak RSS. Run it with two versions of the package (``PYTHONPATH``) to compare them.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import time
from collections.abc import Callable
from typing import Any


def _timed(fn: Callable[[], Any]) -> tuple[Any, dict[str, float]]:
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    c0, w0 = time.process_time(), time.perf_counter()
    result = fn()
    c1, w1 = time.process_time(), time.perf_counter()
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    return result, {
        "cpu": c1 - c0,
        "sys": r1.ru_stime - r0.ru_stime,
        "wall": w1 - w0,
    }


def one(n_points: int, seed: int) -> dict[str, dict[str, float]]:
    from splinecontact import fit_spline, weierstrass_mandelbrot_pair
    from splinecontact.contact import contact_geometry, run_loading

    length = 100.0 * n_points / 1_000_000
    times: dict[str, dict[str, float]] = {}
    (lower, upper), times["generate"] = _timed(
        lambda: weierstrass_mandelbrot_pair(1.5, seed=seed, n_points=n_points, length=length)
    )
    fits, times["spline"] = _timed(lambda: (fit_spline(lower), fit_spline(upper)))
    geometry, times["geometry"] = _timed(
        lambda: contact_geometry(
            lower,
            upper,
            steps=1000,
            final_displacement=None,
            final_displacement_factor=0.2,
            alpha=2.0,
            x0=1.0,
            fits=fits,
        )
    )
    _, times["loop"] = _timed(
        lambda: run_loading(geometry, e_star=10.0, g_star=10.0 / 2.6, mu0=0.3)
    )
    times["total"] = {k: sum(t[k] for t in times.values()) for k in ("cpu", "sys", "wall")}
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-points", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    one(min(args.n_points, 10_000), seed=0)  # warm-up: JIT from the cache
    runs = [one(args.n_points, seed=1 + r) for r in range(args.repeats)]
    print(f"n_points={args.n_points} repeats={args.repeats} (median) [ms]")
    for stage in runs[0]:
        cells = "  ".join(
            f"{k} {1e3 * statistics.median(run[stage][k] for run in runs):8.1f}"
            for k in ("cpu", "sys", "wall")
        )
        print(f"{stage:9s} {cells}")
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak RSS {rss:.0f} MB")


if __name__ == "__main__":
    main()
