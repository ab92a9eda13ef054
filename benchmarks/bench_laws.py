"""Cost of each contact law against Hertz on the same load path (rough-on-rough, D = 1.5).

    python benchmarks/bench_laws.py [--points 1000000] [--pairs 3] [--laws jkr,dmt,...]
    python benchmarks/bench_laws.py --single jkr --paths loading   # one run, whole process

For every law and every path (a 1000-step loading; loading then unloading, 2 × 500 steps; two
load–unload cycles, 4 × 250 steps) the complete ``simulate`` call is timed alternately with Hertz
and with the law (H, L, H, L, ...: paired, so a drift of the shared machine hits both), after a
warm-up of each (numba compilation is cached on disk). Printed: the median paired ratio
law/Hertz of wall and of CPU time, and the medians of the wall and CPU times themselves.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from typing import Any

from splinecontact import Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.contact import make_law

LAWS: dict[str, dict[str, float]] = {
    "jkr": {"work_of_adhesion": 0.1},
    "dmt": {"work_of_adhesion": 0.1, "cohesive_stress": 0.5},
    "maugis-dugdale": {"work_of_adhesion": 0.1, "cohesive_stress": 0.5},
    "elastic-plastic": {"hardness": 2.0},
}


def _paths(final: float) -> dict[str, list[Segment]]:
    return {
        "loading": [Segment(normal=final, steps=1000)],
        "load-unload": [Segment(normal=final, steps=500), Segment(normal=-0.1 * final, steps=500)],
        "2 cycles": [
            Segment(normal=final, steps=250),
            Segment(normal=-0.1 * final, steps=250),
            Segment(normal=final, steps=250),
            Segment(normal=-0.1 * final, steps=250),
        ],
    }


def _timed(run: Any) -> tuple[float, float]:
    w0, c0 = time.perf_counter(), time.process_time()
    run()
    return time.perf_counter() - w0, time.process_time() - c0


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--pairs", type=int, default=3, help="paired runs per law and path")
    parser.add_argument("--laws", default=",".join(LAWS))
    parser.add_argument("--paths", default="loading,load-unload,2 cycles")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument(
        "--single", help="run one law (or hertz) once on the first of --paths, for a "
        "whole-process comparison",
    )  # fmt: skip
    args = parser.parse_args()
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=args.seed, n_points=args.points)
    final = 0.2 * lower.peak_to_valley
    paths = _paths(final)
    if args.single:
        law = make_law(args.single, **LAWS.get(args.single, {}))
        path = paths[args.paths.split(",")[0]]
        wall, cpu = _timed(lambda: simulate(lower, upper, path=path, law=law, diagnostics=False))
        print(f"{args.single}: wall {wall:.3f} s, CPU {cpu:.3f} s")
        return
    print(f"load average before: {os.getloadavg()}")
    print(f"points {lower.n_points}, final δ_N {final:.4g} µm, E* = 10 GPa")
    print(
        "| law | path | Hertz wall [s] | law wall [s] | Hertz CPU [s] | law CPU [s] | wall ratio "
        "| CPU ratio |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name in args.laws.split(","):
        law = make_law(name, **LAWS[name])
        for label in args.paths.split(","):
            path = paths[label]

            def hertz(path: list[Segment] = path) -> Any:
                return simulate(lower, upper, path=path, diagnostics=False)

            def other(path: list[Segment] = path, law: Any = law) -> Any:
                return simulate(lower, upper, path=path, law=law, diagnostics=False)

            hertz()
            other()
            walls: list[tuple[float, float]] = []
            cpus: list[tuple[float, float]] = []
            for _ in range(args.pairs):
                wh, ch = _timed(hertz)
                wl, cl = _timed(other)
                walls.append((wh, wl))
                cpus.append((ch, cl))
            wall_ratio = statistics.median(b / a for a, b in walls)
            cpu_ratio = statistics.median(b / a for a, b in cpus)
            print(
                f"| {name} | {label} | {statistics.median(a for a, _ in walls):.2f} | "
                f"{statistics.median(b for _, b in walls):.2f} | "
                f"{statistics.median(a for a, _ in cpus):.3f} | "
                f"{statistics.median(b for _, b in cpus):.3f} | {wall_ratio:.2f} | "
                f"{cpu_ratio:.2f} |",
                flush=True,
            )
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
