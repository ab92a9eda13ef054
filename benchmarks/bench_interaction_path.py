"""Cost of interacting SAD along a sliding load path against the non-interacting path.

A rough-on-rough pair of Weierstrass–Mandelbrot profiles (D = 1.5 and 1.3, seeds 1 and 2,
``--points`` points over ``--length`` µm) pressed to 0.1 × the sum of the peak-to-valley heights
in ``--steps`` normal steps, then slid by ``--travel`` µm in ``--steps`` tangential steps; the
same path with a force-controlled sliding segment (``--force``) holds the normal force reached.
Each figure is CPU time of this process (``time.process_time``) beside wall time, after a
warm-up call on a small pair (compilation excluded); the per-step figures of the sliding and
the force-held sliding segments are the path's time less that of the normal loading alone,
over ``--steps``. ``--law`` runs the interacting paths with
a contact law (JKR and Maugis–Dugdale w = 0.05 J/m², σ0 = 0.5 GPa; DMT the same; elastic–plastic
S_y = 0.2 GPa, as ``bench_interaction_laws.py``).

Run::

    python benchmarks/bench_interaction_path.py --points 100000 --steps 100
    python benchmarks/bench_interaction_path.py --points 1000000 --steps 20 --length 100
    python benchmarks/bench_interaction_path.py --points 100000 --steps 20 --force --law jkr
"""

from __future__ import annotations

import argparse
import time

from splinecontact import Segment, simulate
from splinecontact.contact import DMT, JKR, ElasticPlastic, Hertz, MaugisDugdale
from splinecontact.generate import weierstrass_mandelbrot

LAWS = {
    "hertz": Hertz(),
    "jkr": JKR(work_of_adhesion=0.05),
    "dmt": DMT(work_of_adhesion=0.05, cohesive_stress=0.5),
    "md": MaugisDugdale(work_of_adhesion=0.05, cohesive_stress=0.5),
    "plastic": ElasticPlastic(yield_strength=0.2),
}


def _run(lower, upper, path, interaction, law=None):  # type: ignore[no-untyped-def]
    law = law if interaction else None
    cpu, wall = time.process_time(), time.perf_counter()
    result = simulate(lower, upper, path=path, interaction=interaction, diagnostics=False, law=law)
    return result, time.process_time() - cpu, time.perf_counter() - wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=100_000)
    parser.add_argument("--length", type=float, default=10.0)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--travel", type=float, default=0.05)
    parser.add_argument("--force", action="store_true", help="also a force-controlled slide")
    parser.add_argument("--law", choices=sorted(LAWS), default="hertz")
    args = parser.parse_args()
    law = LAWS[args.law]
    small = [weierstrass_mandelbrot(1.5, n_points=1024, length=1.0, seed=s) for s in (1, 2)]
    warm = [Segment(normal=0.001, steps=2), Segment(tangential=0.01, steps=2)]
    _run(*small, warm, True, law)
    _run(*small, [*warm, Segment(normal_force=0.01, steps=2)], True, law)
    lower = weierstrass_mandelbrot(1.5, n_points=args.points, length=args.length, seed=1)
    upper = weierstrass_mandelbrot(1.3, n_points=args.points, length=args.length, seed=2)
    top = 0.1 * (lower.peak_to_valley + upper.peak_to_valley)
    normal = [Segment(normal=top, steps=args.steps)]
    sliding = [*normal, Segment(tangential=args.travel, steps=args.steps)]
    rows = []
    for name, path, interaction in (
        ("plain path, normal", normal, False),
        ("plain path, normal + sliding", sliding, False),
        ("interacting, normal", normal, True),
        ("interacting, normal + sliding", sliding, True),
    ):
        result, cpu, wall = _run(lower, upper, path, interaction, law)
        rows.append((name, cpu, wall, int(result.n_contacts.max())))
        if name == "interacting, normal + sliding":
            target = float(result.normal_force[args.steps])
    if args.force:
        held = [*normal, Segment(normal_force=target, tangential=args.travel, steps=args.steps)]
        result, cpu, wall = _run(lower, upper, held, True, law)
        rows.append(("interacting, normal + force-held sliding", cpu, wall,
                     int(result.n_contacts.max())))  # fmt: skip
    print(f"{args.points} points, {args.steps} + {args.steps} steps, law {args.law}")
    for name, cpu, wall, contacts in rows:
        print(f"{name:44s} CPU {cpu:8.2f} s  wall {wall:8.2f} s  max contacts {contacts}")
    # per step of the second segment: the path's time less that of its normal loading
    base = {name: (cpu, wall) for name, cpu, wall, _ in rows}["interacting, normal"]
    for name, cpu, wall, _ in rows[3:]:
        step_cpu, step_wall = (cpu - base[0]) / args.steps, (wall - base[1]) / args.steps
        kind = "force-held sliding" if "force" in name else "sliding"
        print(f"per {kind} step{'':{26 - len(kind)}s} CPU {1e3 * step_cpu:8.1f} ms "
              f"wall {1e3 * step_wall:8.1f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
