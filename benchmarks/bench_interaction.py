"""Cost of interacting SAD against plain SAD and the exact BEM on one profile.

One Weierstrass–Mandelbrot profile (default 10⁶ points over 100 µm, D = 1.5, seed 1) against a
flat, 1000 displacement steps to 0.2 × the peak-to-valley height:

* plain SAD: spline fit, geometry and loading loop (``contact_geometry`` + ``run_loading``);
* interacting SAD: spline fit, extended geometry and the interacting loop;
* the BEM (``--bem``): the exact contact of the mirrored smoothed profile at ``--forces`` forces
  evenly spaced up to the interacting variant's largest force, warm-started along the path as
  ``splinecontact compare`` does (``--bem-forces K`` solves only the first K of them and
  reports the time per force as well).

Each figure is CPU time of this process (``time.process_time``) beside wall time; with
``--repeat N`` both SAD variants run N times, alternated, and the smallest and median times are
printed (the ratio is of the smallest CPU times, the least disturbed by other jobs).

Run::

    python benchmarks/bench_interaction.py                       # SAD variants only
    python benchmarks/bench_interaction.py --bem                 # and the BEM at 20 forces
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from splinecontact import Profile, bem
from splinecontact.compare import _solve_in_substeps
from splinecontact.contact import contact_geometry, run_loading
from splinecontact.contact.interaction import extended_geometry, interacting_loading
from splinecontact.generate import weierstrass_mandelbrot
from splinecontact.spline import fit_spline

E_STAR = 10.0


def clock() -> tuple[float, float]:
    return time.process_time(), time.perf_counter()


def since(start: tuple[float, float]) -> tuple[float, float]:
    cpu, wall = clock()
    return cpu - start[0], wall - start[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-points", type=int, default=1_000_000)
    parser.add_argument("--dimension", type=float, default=1.5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--bem", action="store_true")
    parser.add_argument("--forces", type=int, default=20)
    parser.add_argument("--bem-forces", type=int, default=None)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    profile = weierstrass_mandelbrot(args.dimension, n_points=args.n_points, seed=args.seed)
    kwargs = dict(
        steps=args.steps, final_displacement=None, final_displacement_factor=0.2, alpha=2.0, x0=1.0
    )
    # compile both kernels on a small profile first
    small = weierstrass_mandelbrot(args.dimension, n_points=4096, seed=args.seed)
    g = extended_geometry(small, "flat", **kwargs)  # type: ignore[arg-type]
    interacting_loading(g, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3, n_points=4096)
    g = contact_geometry(small, "flat", **kwargs)  # type: ignore[arg-type]
    run_loading(g, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3)

    plain_times = []
    inter_times = []
    for _ in range(max(args.repeat, 1)):
        start = clock()
        geometry = contact_geometry(profile, "flat", **kwargs)  # type: ignore[arg-type]
        plain = run_loading(geometry, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3).curves
        plain_times.append(since(start))
        n_plain = (geometry.gap0.size, plain["n_contacts"].max())
        start = clock()
        geometry = extended_geometry(profile, "flat", **kwargs)  # type: ignore[arg-type]
        inter, _ = interacting_loading(
            geometry, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3, n_points=profile.n_points
        )
        inter_times.append(since(start))
    cpu_sad, wall_sad = (min(t[k] for t in plain_times) for k in (0, 1))
    cpu_int, wall_int = (min(t[k] for t in inter_times) for k in (0, 1))
    med = [float(np.median([t[k] for t in times])) for times in (plain_times, inter_times)
           for k in (0, 1)]  # fmt: skip
    print(
        f"plain SAD: CPU {cpu_sad:.3f} s, wall {wall_sad:.3f} s (median {med[0]:.3f}, "
        f"{med[1]:.3f}); {n_plain[0]} candidates, {n_plain[1]} contacts at most"
    )
    print(
        f"interacting SAD: CPU {cpu_int:.3f} s, wall {wall_int:.3f} s (median {med[2]:.3f}, "
        f"{med[3]:.3f}; {cpu_int / cpu_sad:.1f}× plain SAD CPU); {geometry.gap0.size} "
        f"candidates, {inter['n_contacts'].max()} contacts at most, "
        f"{inter['interaction_iterations'].sum()} CG iterations"
    )
    if not args.bem:
        return
    forces = float(inter["normal_force"].max()) * np.arange(1, args.forces + 1) / args.forces
    solve = forces[: args.bem_forces] if args.bem_forces else forces
    start = clock()
    f = fit_spline(profile, alpha=2.0, x0=1.0).f
    problem = bem.contact_problem(bem.mirror_extend(Profile(profile.x, f)), e_star=E_STAR)
    previous = None
    previous_load = 0.0
    for k, force in enumerate(solve):
        load = force / profile.length
        state = _solve_in_substeps(problem, load, previous, previous_load, 1e-10, 5000)
        previous, previous_load = state.pressure, load
        cpu, wall = since(start)
        print(
            f"  BEM force {k + 1}/{solve.size}: {state.iterations} iterations, "
            f"CPU {cpu:.1f} s, wall {wall:.1f} s so far",
            flush=True,
        )
    cpu_bem, wall_bem = since(start)
    print(
        f"BEM at {solve.size} of {forces.size} forces: CPU {cpu_bem:.1f} s, wall {wall_bem:.1f} s "
        f"({cpu_bem / cpu_int:.1f}× interacting SAD CPU)"
    )


if __name__ == "__main__":
    main()
