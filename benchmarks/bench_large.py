"""One large rough-on-rough realization, whole-array or streamed: CPU, system, wall, peak RSS.

    python benchmarks/bench_large.py --n-points 100000000 --mode streamed
    python benchmarks/bench_large.py --n-points 10000000 --mode whole --compare

D = 1.5, 1000 loading steps, the profile length 100 µm per 10⁶ points (the paper's grid).
``whole``: ``weierstrass_mandelbrot_pair`` then ``simulate`` (every array of n points made);
``streamed``: ``splinecontact.contact.streamed.simulate_generated`` (chunks, no array of n
points). A 10⁴-point warm-up loads the compiled kernels first; the realization's own CPU, user,
system and wall time come from ``resource.getrusage`` and ``time.perf_counter``, the peak RSS
of the process from ``ru_maxrss`` (run it under ``/usr/bin/time -v`` for the whole process).
``--compare`` runs both modes in this process on the same seed (smaller sizes only) and prints
the largest relative deviation of the curves and scalars.
"""

from __future__ import annotations

import argparse
import resource
import time
from typing import Any


def _realization(mode: str, n_points: int, seed: int, chunk: int | None) -> Any:
    gen = {
        "n_points": n_points,
        "length": 100.0 * n_points / 1_000_000,
        "max_points": max(n_points, 20_000_000),
        "max_work": max(n_points * 420, 10_000_000_000),
    }
    if mode == "streamed":
        from splinecontact.contact.streamed import simulate_generated

        return simulate_generated(1.5, seed=seed, generator=gen, steps=1000, chunk_points=chunk)
    from splinecontact import simulate, weierstrass_mandelbrot_pair
    from splinecontact.contact.streamed import STREAM_MIN_POINTS

    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=seed, **gen)
    if n_points >= STREAM_MIN_POINTS:  # simulate would stream the fits: the whole-array path
        from splinecontact.contact.geometry import contact_geometry
        from splinecontact.contact.kernel import run_loading
        from splinecontact.spline import fit_spline_pair

        fits = fit_spline_pair(lower, upper)
        geometry = contact_geometry(
            lower, upper, steps=1000, final_displacement=None, final_displacement_factor=0.2,
            alpha=2.0, x0=1.0, fits=fits,
        )  # fmt: skip
        return run_loading(geometry, e_star=10.0, g_star=10.0 / 2.6, mu0=0.3)
    return simulate(lower, upper, steps=1000, diagnostics=False)


def _timed(mode: str, n_points: int, seed: int, chunk: int | None) -> tuple[Any, dict[str, float]]:
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    w0 = time.perf_counter()
    result = _realization(mode, n_points, seed, chunk)
    w1 = time.perf_counter()
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    user, system = r1.ru_utime - r0.ru_utime, r1.ru_stime - r0.ru_stime
    return result, {"cpu": user + system, "user": user, "sys": system, "wall": w1 - w0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-points", type=int, default=10_000_000)
    parser.add_argument("--mode", choices=("whole", "streamed"), default="streamed")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--chunk", type=int, default=None)
    parser.add_argument("--compare", action="store_true")
    args = parser.parse_args()
    for mode in ("whole", "streamed"):  # warm-up: load the compiled kernels
        _realization(mode, 10_000, 0, None)
    result, t = _timed(args.mode, args.n_points, args.seed, args.chunk)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"{args.mode} n_points={args.n_points}: cpu {t['cpu']:.2f} s (user {t['user']:.2f}, "
        f"system {t['sys']:.2f} = {100 * t['sys'] / t['cpu']:.0f} %), wall {t['wall']:.2f} s, "
        f"peak RSS {rss:.0f} MB, final F_N {result.curves['normal_force'][-1]:.6g} mN/µm"
    )
    if args.compare:
        import numpy as np

        other, _ = _timed("whole" if args.mode == "streamed" else "streamed", args.n_points,
                          args.seed, args.chunk)  # fmt: skip
        worst = 0.0
        for name, values in result.curves.items():
            ref = np.asarray(other.curves[name], dtype=float)
            scale = np.maximum(np.abs(ref), 1e-300)
            worst = max(worst, float(np.max(np.abs(np.asarray(values, float) - ref) / scale)))
        print(f"largest relative deviation of the curves, streamed vs whole: {worst:.2e}")


if __name__ == "__main__":
    main()
