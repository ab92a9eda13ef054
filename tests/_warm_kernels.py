"""Compile the package's numba kernels once before a parallel test run.

With an empty numba cache (a fresh clone, as in CI) every pytest-xdist worker would compile
the kernels its first tests use, and both workers compile the same ones at the same time. The
conftest runs this script as two processes, one per part, before the workers start, so that
each kernel is compiled once into numba's on-disk cache and the workers load it from there.
With a warm cache a part only loads its kernels (about a second). Test results never depend on
it: a kernel compiles on first use anyway.

    python tests/_warm_kernels.py PART     # PART: contact or paths
"""

from __future__ import annotations

import sys
import warnings

import numpy as np

PARTS = ("contact", "paths")


def _pair() -> tuple[object, object]:
    from splinecontact import weierstrass_mandelbrot_pair

    return weierstrass_mandelbrot_pair(1.5, seed=1, n_points=4000, length=4.0)


def _laws() -> list[object]:
    from splinecontact.contact import DMT, JKR, ElasticPlastic, MaugisDugdale

    return [
        JKR(work_of_adhesion=0.01),
        DMT(work_of_adhesion=0.01),
        MaugisDugdale(work_of_adhesion=0.01, cohesive_stress=1.0),
        ElasticPlastic(hardness=1.0),
    ]


def warm_contact() -> None:
    """Generation, spline, placement, the loading loop with every law, BEM and interaction."""
    from splinecontact import bem, simulate

    lower, upper = _pair()
    simulate(lower, upper, steps=5)
    simulate(lower, "flat", steps=5)
    for law in _laws():
        simulate(lower, upper, steps=5, law=law, diagnostics=False)
    simulate(lower, "flat", steps=5, interaction=True)
    for n in (256, 300):
        x = np.linspace(-0.5, 0.5, n, endpoint=False)
        heights = np.sqrt(1.0 - x**2) - 1.0
        problem = bem.contact_problem(heights, e_star=10.0, dx=1.0 / n, check_periodic=False)
        bem.solve_pressure(problem, 0.01)


def warm_paths() -> None:
    """The load-path kernels (normal, tangential, force control) with Hertz and every law."""
    from splinecontact import Segment, simulate

    lower, upper = _pair()
    path = [
        Segment(normal=0.002, steps=4),
        Segment(normal=0.002, tangential=0.05, steps=4),
        Segment(normal=0.0, steps=2),
    ]
    simulate(lower, upper, path=path)
    simulate(lower, "flat", path=path)
    for law in _laws():
        simulate(lower, upper, path=path, law=law)


def main(argv: list[str]) -> int:
    if len(argv) != 1 or argv[0] not in PARTS:
        print(f"usage: python tests/_warm_kernels.py {{{','.join(PARTS)}}}", file=sys.stderr)
        return 2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (warm_contact if argv[0] == "contact" else warm_paths)()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
