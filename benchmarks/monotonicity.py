"""How often F_N(δ_N) steps down for fractal profiles at the paper's resolution.

    python benchmarks/monotonicity.py

Prints a Markdown table (the one in docs/conventions.md): for each D and contact type, the share
of the 1000 increments where F_N falls and the largest fall relative to the final F_N, over four
generated pairs (10⁶ points, default parameters).
"""

from __future__ import annotations

import numpy as np

import splinecontact as sc


def main() -> None:
    print("| D | contact | steps where F_N falls | largest drop / final F_N |")
    print("|---|---|---|---|")
    for dimension in (1.1, 1.3, 1.5, 1.7, 1.9):
        for kind in ("rough-on-rough", "rough-on-flat"):
            shares, drops = [], []
            for seed in range(4):
                lower, upper = sc.weierstrass_mandelbrot_pair(dimension, seed=100 + seed)
                result = sc.simulate(lower, upper if kind == "rough-on-rough" else "flat")
                force = result.normal_force
                change = np.diff(force)
                shares.append(np.mean(change < 0))
                drops.append(-change.min() / force[-1] if (change < 0).any() else 0.0)
            print(
                f"| {dimension} | {kind} | {100 * np.mean(shares):.1f} % | "
                f"{100 * np.max(drops):.2f} % |",
                flush=True,
            )


if __name__ == "__main__":
    main()
