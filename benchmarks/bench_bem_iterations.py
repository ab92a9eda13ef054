"""CPU time per conjugate-gradient iteration of the boundary element solver.

The acceptance case: 20 load steps up to about 10 % contact on a periodic self-affine profile
(Hurst exponent 0.8, rms slope 0.1, L = 100 µm, E* = 10 GPa, seeded FFT generator of
``bench_bem.py``) against a flat, tolerance 1e−10, each step warm-started from the previous one
(``splinecontact.bem.load_path``). The solve is repeated and the fastest repeat is reported;
CPU time (``time.process_time``) is printed beside wall time.

Run::

    python benchmarks/bench_bem_iterations.py --n-points 65536 --repeats 3
    python benchmarks/bench_bem_iterations.py --n-points 16384 --repeats 5

The last line gives the iteration count, the contact fraction, the mean gap and a checksum of
the final contact set, so two versions of the solver can be compared run against run.
"""

from __future__ import annotations

import argparse
import hashlib
import time

import numpy as np

from splinecontact import bem

try:  # run as a script from the repository root or from benchmarks/
    from bench_bem import self_affine_heights
except ImportError:  # pragma: no cover
    from benchmarks.bench_bem import self_affine_heights


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-points", type=int, default=2**16)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--tol", type=float, default=1e-10)
    parser.add_argument("--max-load", type=float, default=0.048)
    args = parser.parse_args()

    length, e_star, rms_slope = 100.0, 10.0, 0.1
    z = self_affine_heights(args.n_points, length, 0.8, rms_slope, 1)
    problem = bem.contact_problem(z, e_star=e_star, dx=length / args.n_points)
    loads = args.max_load * e_star * rms_slope * np.arange(1, args.steps + 1) / args.steps
    bem.load_path(problem, loads[:1], tol=1e-6)  # warm-up (JIT, FFT plans)

    best_cpu = best_wall = np.inf
    path = None
    for _ in range(args.repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        path = bem.load_path(problem, loads, tol=args.tol, fields=True)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        best_cpu, best_wall = min(best_cpu, cpu), min(best_wall, wall)
    assert path is not None
    iterations = int(path.column("iterations").sum())
    last = path.steps[-1]
    assert last.pressure is not None
    digest = hashlib.sha1(np.flatnonzero(last.pressure > 0.0).tobytes()).hexdigest()[:12]
    print(
        f"n={args.n_points} steps={args.steps} tol={args.tol:g} iterations={iterations} "
        f"contact={last.contact_nodes / problem.n_points:.4f} mean_gap={last.mean_gap:.12e} "
        f"contact_set={digest}"
    )
    print(
        f"best of {args.repeats}: cpu {best_cpu:.3f} s, wall {best_wall:.3f} s, "
        f"cpu per iteration {best_cpu / iterations * 1e3:.3f} ms, "
        f"wall per iteration {best_wall / iterations * 1e3:.3f} ms"
    )


if __name__ == "__main__":
    main()
