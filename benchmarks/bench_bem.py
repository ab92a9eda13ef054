"""Benchmark of the boundary element reference solver.

100 load steps on a 2¹⁶-point self-affine profile (Hurst exponent 0.8) against a flat, up to about
10 % contact, each step warm-started from the previous one (``splinecontact.bem.load_path``).
The reference figure is 262 s for an established C++ BEM library on the same machine.

The profile comes from a small seeded FFT generator defined here: random phases, amplitudes
following the 1D power spectrum C(q) ∝ q^(−1−2H) from the longest wavelength L down to the grid
(no roll-off), scaled to an rms slope of 0.1. Periodic by construction.

Run::

    /work/venv/bin/python benchmarks/bench_bem.py               # the acceptance case
    /work/venv/bin/python benchmarks/bench_bem.py --tol 1e-8    # a looser tolerance

It prints the wall time, the iterations and the contact fraction reached.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np
import scipy.fft as sfft

from splinecontact import bem


def self_affine_heights(
    n_points: int, length: float, hurst: float, rms_slope: float, seed: int
) -> np.ndarray:
    """Periodic self-affine heights [µm] with PSD ∝ q^(−1−2H), scaled to a given rms slope."""
    rng = np.random.default_rng(seed)
    q = 2.0 * np.pi * np.arange(n_points // 2 + 1) / length
    amplitude = np.zeros_like(q)
    amplitude[1:] = q[1:] ** (-(1.0 + 2.0 * hurst) / 2.0)
    spectrum = amplitude * np.exp(2j * np.pi * rng.random(q.size))
    if n_points % 2 == 0:
        spectrum[-1] = spectrum[-1].real
    z = sfft.irfft(spectrum, n_points)
    dx = length / n_points
    slope = np.sqrt(np.mean((np.roll(z, -1) - z) ** 2)) / dx
    return np.asarray(z * rms_slope / slope, dtype=np.float64)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-points", type=int, default=2**16)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--hurst", type=float, default=0.8)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tol", type=float, default=bem.DEFAULT_TOLERANCE)
    parser.add_argument(
        "--max-load",
        type=float,
        default=0.048,
        help="largest mean pressure / (E* × rms slope); 0.048 gives about 10 %% contact",
    )
    args = parser.parse_args()

    length = 100.0  # µm
    e_star = 10.0  # GPa
    rms_slope = 0.1
    z = self_affine_heights(args.n_points, length, args.hurst, rms_slope, args.seed)
    problem = bem.contact_problem(z, e_star=e_star, dx=length / args.n_points)
    loads = args.max_load * e_star * rms_slope * np.arange(1, args.steps + 1) / args.steps

    start = time.perf_counter()
    path = bem.load_path(problem, loads, tol=args.tol)
    elapsed = time.perf_counter() - start

    fraction = path.column("contact_nodes") / problem.n_points
    iterations = path.column("iterations")
    print(f"machine: {platform.node()} {platform.processor() or platform.machine()}")
    print(
        f"profile: {args.n_points} points, H = {args.hurst}, seed {args.seed}, "
        f"rms slope {rms_slope}, L = {length} µm, E* = {e_star} GPa"
    )
    print(f"steps: {args.steps}, tol: {args.tol:g}, max mean pressure: {loads[-1]:.4g} GPa")
    print(f"contact fraction at the last step: {fraction[-1]:.4f}")
    print(
        f"iterations: total {int(iterations.sum())}, per step median {np.median(iterations):.0f},"
        f" max {int(iterations.max())}"
    )
    print(f"patches at the last step: {path.steps[-1].n_patches}")
    print(f"wall time: {elapsed:.2f} s ({elapsed / args.steps * 1e3:.1f} ms per step)")


if __name__ == "__main__":
    main()
