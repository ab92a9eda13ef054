"""Cost of the loading loop against the number of steps (linear in Σ closed-gap visits).

    python benchmarks/bench_steps.py

One 10⁶-point rough-on-rough pair (D = 1.5); the geometry is prepared for each step count and
the loop timed (median of 5). The loop's cost follows Σ_k c_k, the number of (point, step)
visits, not points × steps.
"""

from __future__ import annotations

import statistics
import time

from splinecontact import weierstrass_mandelbrot_pair
from splinecontact.contact import contact_geometry, run_loading


def main() -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=1)
    print("| steps | Σ visits | loop [ms] | ns per visit | points × steps |")
    print("|---|---|---|---|---|")
    for steps in (100, 1000, 10_000, 100_000):
        geometry = contact_geometry(
            lower, upper, steps=steps, final_displacement=None, final_displacement_factor=0.2,
            alpha=2.0, x0=1.0,
        )  # fmt: skip
        run_loading(geometry, e_star=10.0, g_star=10.0 / 2.6, mu0=0.3)
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            run_loading(geometry, e_star=10.0, g_star=10.0 / 2.6, mu0=0.3)
            times.append(time.perf_counter() - t0)
        loop = statistics.median(times)
        visits = int(geometry.first_step_index.sum())
        print(f"| {steps} | {visits:.3g} | {1e3 * loop:.1f} | {1e9 * loop / visits:.1f} | "
              f"{lower.n_points * steps:.0e} |")  # fmt: skip


if __name__ == "__main__":
    main()
