"""Friction quantities of rough pairs at the paper's spacing (the table in docs/friction.md).

    python benchmarks/friction_table.py

10⁵ points over 10 µm, seed 7, D = 1.3, 1.5, 1.7, rough-on-rough and rough-on-flat: press to
0.1 × the lower peak-to-valley height in 200 steps, then hold F_N while sliding +50 nm, −50 nm,
+50 nm. k_T/k_N from a separate displacement-controlled first increment of 0.01 nm.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from splinecontact import Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.friction import (
    dilatancy,
    dissipated_energy,
    normal_stiffness,
    segment_steps,
    static_friction,
    tangential_stiffness,
)

HEADER = (
    "| D | contact | contacts | μ_s | k_T/k_N | dissipation per cycle [mN·µm/µm] "
    "| dilatancy [nm] | steps with F_N held to 1e−6 |"
)


def main() -> None:
    warnings.simplefilter("ignore")  # force-control misses are counted in the table
    print(HEADER)
    print("|---|---|---|---|---|---|---|---|")
    cpu0, wall0 = time.process_time(), time.perf_counter()
    travel = 0.05
    for dimension in (1.3, 1.5, 1.7):
        lower, upper = weierstrass_mandelbrot_pair(dimension, seed=7, n_points=100_000, length=10.0)
        d = 0.1 * lower.peak_to_valley
        for up in (upper, "flat"):
            plain = simulate(lower, up, steps=200, final_displacement=d)
            force = float(plain.normal_force[-1])
            path = [
                Segment(normal=d, steps=200),
                Segment(normal_force=force, tangential=travel, steps=250),
                Segment(normal_force=force, tangential=-travel, steps=500),
                Segment(normal_force=force, tangential=travel, steps=500),
            ]
            result = simulate(lower, up, path=path)
            bounds = segment_steps(result)
            first = simulate(
                lower, up, path=[Segment(normal=d, steps=200), Segment(tangential=1e-5, steps=1)]
            )
            ratio = tangential_stiffness(first) / normal_stiffness(first)
            held = np.isfinite(result.normal_force_target)
            ok = np.mean(np.abs(result.normal_force[held] / force - 1) <= 1e-6)
            kind = "rough-on-flat" if up == "flat" else "rough-on-rough"
            cycle = dissipated_energy(result, bounds[1][1], bounds[3][1])
            print(
                f"| {dimension} | {kind} | {int(plain.n_contacts[-1])} "
                f"| {static_friction(result).mu_s:.3f} | {ratio:.3f} | {cycle:.3e} "
                f"| {1e3 * dilatancy(result, 1):.3f} | {100 * ok:.0f} % |"
            )
    print(f"CPU {time.process_time() - cpu0:.1f} s, wall {time.perf_counter() - wall0:.1f} s")


if __name__ == "__main__":
    main()
