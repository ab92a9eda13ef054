"""Cost of interacting SAD with each contact law against the same path with the Hertz law.

A rough-on-flat Weierstrass–Mandelbrot profile (D = 1.5, seed 1, ``--points`` points over
``--length`` µm) loaded to ``--fraction`` (0.3) × its peak-to-valley height and unloaded to
−0.2 × that, in
``--steps`` steps each way, with ``interaction=True`` and each law (JKR and Maugis–Dugdale
w = 0.05 J/m², σ0 = 0.5 GPa; DMT the same; elastic–plastic S_y = 0.2 GPa). Each figure is the
CPU time of this process (``time.process_time``) beside the wall time of the ``simulate`` call,
after a warm-up call of every law on a small profile (compilation excluded) and a first,
unprinted pass over the laws on the full profile (the mesh kernels of its sizes are computed
on first use and cached; the first law would pay for them); the last columns
are the largest number of contacts, the total CG iterations and ∫F_N dδ_N over the path (the
energy dissipated: F_N vanishes at both ends).

Run::

    python benchmarks/bench_interaction_laws.py --points 100000 --steps 50
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from splinecontact import Segment, simulate
from splinecontact.contact import DMT, JKR, ElasticPlastic, Hertz, MaugisDugdale
from splinecontact.generate import weierstrass_mandelbrot

LAWS = (
    Hertz(),
    JKR(work_of_adhesion=0.05),
    DMT(work_of_adhesion=0.05, cohesive_stress=0.5),
    MaugisDugdale(work_of_adhesion=0.05, cohesive_stress=0.5),
    ElasticPlastic(yield_strength=0.2),
)


def _run(profile, path, law):  # type: ignore[no-untyped-def]
    cpu, wall = time.process_time(), time.perf_counter()
    result = simulate(profile, "flat", path=path, law=law, interaction=True, diagnostics=False)
    return result, time.process_time() - cpu, time.perf_counter() - wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=100_000)
    parser.add_argument("--length", type=float, default=10.0)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--fraction", type=float, default=0.3)
    args = parser.parse_args()
    small = weierstrass_mandelbrot(1.5, n_points=1024, length=1.0, seed=1)
    warm = [Segment(normal=0.02, steps=3), Segment(normal=-0.002, steps=3)]
    for law in LAWS:
        _run(small, warm, law)
    profile = weierstrass_mandelbrot(1.5, n_points=args.points, length=args.length, seed=1)
    top = args.fraction * profile.peak_to_valley
    path = [Segment(normal=top, steps=args.steps), Segment(normal=-0.2 * top, steps=args.steps)]
    print(f"{args.points} points, {args.steps} + {args.steps} steps, rough on flat")
    print("law              cpu [s]  wall [s]  ×Hertz(cpu)  contacts  CG its   ∫F dδ")
    for law in LAWS:
        _run(profile, path, law)
    base = None
    for law in LAWS:
        result, cpu, wall = _run(profile, path, law)
        base = cpu if base is None else base
        f, d = result.normal_force, result.displacement
        iterations = int(result.curves["interaction_iterations"].sum())
        work = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(d)))
        print(
            f"{law.name:16s} {cpu:7.2f}  {wall:8.2f}  {cpu / base:11.2f}  "
            f"{int(result.n_contacts.max()):8d}  {iterations:6d}"
            f"  {work:.3e}"
        )


if __name__ == "__main__":
    main()
