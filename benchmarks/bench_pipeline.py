"""Per-stage timings and peak memory of one SAD realization.

    python benchmarks/bench_pipeline.py [--sizes 1e4 1e5 1e6 1e7] [--repeats 5]
                                        [--realizations 100]

For each size, a fresh subprocess runs one warm-up realization and then ``--repeats`` timed ones
(two generated profiles, two spline fits, spheres + placement, 1000 loading steps, rough-on-rough,
tangential forces on) and reports the median time of every stage and the process's peak RSS
(``resource.getrusage``). Then it times ``--realizations`` realizations at 10⁶ points in one
process, and the first-call overhead of a fresh process with a cold and with a warm numba cache.
Only public tools: ``time.perf_counter`` and ``resource``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time


def _one_realization(n_points: int, seed: int) -> dict[str, float]:
    import numpy as np  # noqa: F401

    from splinecontact import fit_spline, weierstrass_mandelbrot_pair
    from splinecontact.contact import contact_geometry, run_loading

    t0 = time.perf_counter()
    lower, upper = weierstrass_mandelbrot_pair(
        1.5, seed=seed, n_points=n_points, length=100.0 * n_points / 1_000_000
    )
    t1 = time.perf_counter()
    fits = (fit_spline(lower), fit_spline(upper))
    t2 = time.perf_counter()
    geometry = contact_geometry(
        lower,
        upper,
        steps=1000,
        final_displacement=None,
        final_displacement_factor=0.2,
        alpha=2.0,
        x0=1.0,
        fits=fits,
    )
    t3 = time.perf_counter()
    run_loading(geometry, e_star=10.0, g_star=10.0 / 2.6, mu0=0.3)
    t4 = time.perf_counter()
    return {
        "generate (2 profiles)": t1 - t0,
        "spline (2 fits)": t2 - t1,
        "spheres + placement": t3 - t2,
        "1000 loading steps": t4 - t3,
        "total": t4 - t0,
        "candidates": float(geometry.point.size),
        "visits": float(geometry.first_step_index.sum()),
    }


def _child(n_points: int, repeats: int) -> None:
    _one_realization(n_points, seed=0)  # warm-up (JIT from the on-disk cache)
    runs = [_one_realization(n_points, seed=1 + r) for r in range(repeats)]
    median = {key: statistics.median(run[key] for run in runs) for key in runs[0]}
    median["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(median))


def _first_call(cache_dir: str) -> float:
    code = (
        "import time; t0 = time.perf_counter();"
        "from splinecontact import simulate, weierstrass_mandelbrot_pair;"
        "a, b = weierstrass_mandelbrot_pair(1.5, seed=0, n_points=10_000, length=1.0);"
        "simulate(a, b, steps=100);"
        "print(time.perf_counter() - t0)"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True
    )
    return float(out.stdout.strip())


def _many(realizations: int) -> float:
    code = (
        "import time;"
        "from splinecontact import simulate, weierstrass_mandelbrot_pair;"
        "t0 = time.perf_counter();"
        f"[simulate(*weierstrass_mandelbrot_pair(1.5, seed=s)) for s in range({realizations})];"
        "print(time.perf_counter() - t0)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.strip())


def _study_command(realizations: int) -> float | None:
    """Wall time of ``splinecontact study run`` on benchmarks/study-100.toml (all local cores)."""
    if realizations != 100:
        return None
    here = os.path.dirname(os.path.abspath(__file__))
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "splinecontact", "study", "run",
             os.path.join(here, "study-100.toml"),
             "-o", os.path.join(tmp, "s.zarr"), "--quiet"],
            check=True, capture_output=True,
        )  # fmt: skip
        return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", type=float, default=[1e4, 1e5, 1e6, 1e7])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--realizations", type=int, default=100)
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(args.child, args.repeats)
        return

    stages = ["generate (2 profiles)", "spline (2 fits)", "spheres + placement",
              "1000 loading steps", "total"]  # fmt: skip
    print(f"# SAD pipeline, rough-on-rough, D = 1.5, median of {args.repeats} after warm-up\n")
    print("| points | " + " | ".join(f"{s} [ms]" for s in stages)
          + " | closed-gap points | Σ visits | peak RSS [MB] |")  # fmt: skip
    print("|---" * (len(stages) + 4) + "|")
    for size in args.sizes:
        n = int(size)
        out = subprocess.run(
            [sys.executable, __file__, "--child", str(n), "--repeats", str(args.repeats)],
            capture_output=True,
            text=True,
            check=True,
        )
        row = json.loads(out.stdout.strip().splitlines()[-1])
        cells = " | ".join(f"{1e3 * row[s]:.1f}" for s in stages)
        print(f"| {n:.0e} | {cells} | {row['candidates']:.0f} | {row['visits']:.3g} | "
              f"{row['peak_rss_mb']:.0f} |", flush=True)  # fmt: skip

    with tempfile.TemporaryDirectory() as cache:
        cold = _first_call(cache)
        warm = _first_call(cache)
    print(f"\nfresh process, import + first small simulation: cold numba cache {cold:.2f} s, "
          f"warm cache {warm:.2f} s")  # fmt: skip
    if args.realizations:
        wall = _many(args.realizations)
        print(f"{args.realizations} realizations at 10⁶ points, one process: {wall:.1f} s "
              f"({wall / args.realizations:.3f} s each; paper: ~216 s each)")  # fmt: skip
        study = _study_command(args.realizations)
        if study is not None:
            print(f"`splinecontact study run benchmarks/study-100.toml` ({os.cpu_count()} cores):"
                  f" {study:.1f} s wall")  # fmt: skip


if __name__ == "__main__":
    main()
