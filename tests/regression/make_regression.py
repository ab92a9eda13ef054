"""Regenerate the fixed-seed regression curves (run only after an intended change of results).

    python tests/regression/make_regression.py

Writes ``sad_curves.npz``: per case the per-step F_N, F_T [mN/µm], A_S [µm] and contact counts
of ``simulate`` on Weierstrass–Mandelbrot pairs (2·10⁴ points at the paper's spacing 1e−4 µm).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from splinecontact import simulate, weierstrass_mandelbrot_pair

CASES = [(d, kind) for d in (1.3, 1.6, 1.9) for kind in ("rough", "flat")]


def compute() -> dict[str, np.ndarray]:
    out: dict[str, np.ndarray] = {}
    for dimension, kind in CASES:
        lower, upper = weierstrass_mandelbrot_pair(
            dimension, seed=2015, n_points=20_000, length=2.0
        )
        result = simulate(lower, "flat" if kind == "flat" else upper, steps=50)
        key = f"D{dimension}_{kind}"
        for name in ("normal_force", "tangential_force", "contact_area", "n_contacts"):
            out[f"{key}/{name}"] = np.asarray(result.curves[name])
    return out


if __name__ == "__main__":
    np.savez_compressed(Path(__file__).with_name("sad_curves.npz"), **compute())
