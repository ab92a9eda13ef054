"""k_T/k_N of rough pairs: the finite-difference ratio against the interface stiffness.

    python benchmarks/friction_stiffness.py

For D = 1.3, 1.5, 1.7 and seeds 1…8 (10⁵ points over 10 µm, E* = 10 GPa, G* = E*/2.6, μ0 = 0.3):
press to 0.1 × the lower peak-to-valley height in 200 steps, then one tangential increment of
0.05 nm. Prints, per D and contact type, the mean, standard deviation and range over the seeds of

* the finite-difference ratio: ``tangential_stiffness`` (first increment) over
  ``normal_stiffness`` (least squares over the last 20 normal increments), and
* the interface ratio ``interface_stiffness(...).ratio`` at the start of the slide,

and how many seeds give a negative value. The table in docs/friction.md comes from this script.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from splinecontact import Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.analysis import interface_stiffness, normal_stiffness, tangential_stiffness


def _row(label: str, values: list[float]) -> str:
    v = np.asarray(values)
    return (
        f"{label}: {v.mean():.3g} ± {v.std(ddof=1):.2g} (range {v.min():.3g} … {v.max():.3g}, "
        f"{int(np.sum(v < 0))} of {v.size} negative)"
    )


def main() -> None:
    cpu0, wall0 = time.process_time(), time.perf_counter()
    print("| D | contact | finite-difference k_T/k_N | interface k_T/k_N |")
    print("|---|---|---|---|")
    for dimension in (1.3, 1.5, 1.7):
        for flat in (False, True):
            fd: list[float] = []
            iface: list[float] = []
            for seed in range(1, 9):
                lower, upper = weierstrass_mandelbrot_pair(
                    dimension, seed=seed, n_points=100_000, length=10.0
                )
                d = 0.1 * lower.peak_to_valley
                path = [Segment(normal=d, steps=200), Segment(tangential=5e-5, steps=1)]
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result = simulate(
                        lower, "flat" if flat else upper, mu0=0.3, path=path, record_contacts=[200]
                    )
                if result.n_contacts[200] == 0:
                    continue
                fd.append(tangential_stiffness(result) / normal_stiffness(result, increments=20))
                iface.append(interface_stiffness(result).ratio)
            kind = "rough-on-flat" if flat else "rough-on-rough"
            print(f"| {dimension} | {kind} | {_row('fd', fd)} | {_row('interface', iface)} |")
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    print(f"CPU {cpu:.1f} s, wall {wall:.1f} s")


if __name__ == "__main__":
    main()
