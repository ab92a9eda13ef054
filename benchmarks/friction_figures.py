"""Figures of docs/friction.md: F_T–u_T loops, μ_s against D, k_T/k_N against load.

    python benchmarks/friction_figures.py [--overwrite]

Writes docs/figures/friction_loop.png, friction_mu_vs_D.png and friction_ratio_vs_load.png
(10⁵ points over 10 µm, the paper's spacing; E* = 10 GPa, G* = E*/2.6, μ0 = 0.3).
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from splinecontact import Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.analysis import (
    friction_study,
    mindlin_stiffness_ratio,
    normal_stiffness,
    spring_slider_stiffness_ratio,
    tangential_stiffness,
)
from splinecontact.outputs import atomic_path, check_output_file
from splinecontact.plotting import plot_friction_loop, plot_study_vs_dimension

FIGURES = Path(__file__).resolve().parent.parent / "docs" / "figures"
N_POINTS, LENGTH = 100_000, 10.0


def _save(fig: Figure, name: str, overwrite: bool) -> None:
    path = check_output_file(FIGURES / name, overwrite=overwrite)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130)
    print(f"wrote {path}")


def loops(overwrite: bool) -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=7, n_points=N_POINTS, length=LENGTH)
    d = 0.1 * lower.peak_to_valley
    fig = Figure(figsize=(10, 4), layout="constrained")
    axes = fig.subplots(1, 2)
    for ax, body, title in ((axes[0], upper, "rough-on-rough"), (axes[1], "flat", "rough-on-flat")):
        force = float(simulate(lower, body, steps=200, final_displacement=d).normal_force[-1])
        path = [
            Segment(normal=d, steps=200),
            Segment(normal_force=force, tangential=0.05, steps=250),
            Segment(normal_force=force, tangential=-0.05, steps=500),
            Segment(normal_force=force, tangential=0.05, steps=500),
        ]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            result = simulate(lower, body, path=path)
        plot_friction_loop(result, ax=ax, lw=0.8)
        ax.set_title(f"{title}, D = 1.5, F_N = {force:.3g} mN/µm held")
    _save(fig, "friction_loop.png", overwrite)


def mu_vs_dimension(overwrite: bool) -> None:
    dims, seeds = [1.2, 1.4, 1.6, 1.8], [1, 2, 3, 4]
    studies = {
        "rough-on-rough": friction_study(dims, seeds, n_points=N_POINTS, length=LENGTH),
        "rough-on-flat": friction_study(dims, seeds, flat=True, n_points=N_POINTS, length=LENGTH),
    }
    for label, ds in studies.items():
        print(
            label,
            "μ_s",
            np.round(ds["mu_s_mean"].values, 3),
            "±",
            np.round(ds["mu_s_ci"].values, 3),
        )
        print(label, "k_T/k_N", np.round(ds["stiffness_ratio_mean"].values, 3))
        print(label, "F_N held", np.round(ds["force_held_mean"].values, 2))
    fig = Figure(figsize=(10, 4), layout="constrained")
    axes = fig.subplots(1, 2)
    plot_study_vs_dimension(studies, "mu_s", ax=axes[0])
    plot_study_vs_dimension(studies, "dissipation", ax=axes[1])
    _save(fig, "friction_mu_vs_D.png", overwrite)


def ratio_vs_load(overwrite: bool) -> None:
    fractions = [0.02, 0.05, 0.1, 0.15, 0.2]
    fig = Figure(figsize=(6.4, 4.6), layout="constrained")
    ax = fig.subplots()
    for flat in (False, True):
        rows = []
        for fraction in fractions:
            ratios = []
            for seed in (1, 2, 3, 4):
                lower, upper = weierstrass_mandelbrot_pair(
                    1.5, seed=seed, n_points=N_POINTS, length=LENGTH
                )
                d = fraction * lower.peak_to_valley
                path = [Segment(normal=d, steps=200), Segment(tangential=5e-5, steps=1)]
                r = simulate(lower, "flat" if flat else upper, path=path)
                k_t = tangential_stiffness(r)
                ratios.append(k_t / normal_stiffness(r, increments=20))
            rows.append((np.mean(ratios), np.std(ratios, ddof=1)))
        mean = np.array([m for m, _ in rows])
        std = np.array([s for _, s in rows])
        label = "rough-on-flat" if flat else "rough-on-rough"
        print(label, "k_T/k_N vs load", np.round(mean, 3))
        ax.errorbar(fractions, mean, yerr=std, marker="o", capsize=3, label=f"{label}, D = 1.5")
    ax.axhline(spring_slider_stiffness_ratio(10.0, 10.0 / 2.6), color="0.5", ls="--",
               label="one stuck SAD contact: G*/((π/4)E*)")  # fmt: skip
    ax.axhline(mindlin_stiffness_ratio(0.3), color="0.5", ls=":", label="Mindlin, ν = 0.3")
    ax.set_xlabel("δ_N / lower peak-to-valley height [1]")
    ax.set_ylabel("k_T / k_N [1]  (error bar: std of 4 pairs)")
    ax.legend()
    _save(fig, "friction_ratio_vs_load.png", overwrite)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--overwrite", action="store_true")
    args = parser.parse_args()
    cpu, wall = time.process_time(), time.perf_counter()
    loops(args.overwrite)
    mu_vs_dimension(args.overwrite)
    ratio_vs_load(args.overwrite)
    print(f"CPU {time.process_time() - cpu:.1f} s, wall {time.perf_counter() - wall:.1f} s")


if __name__ == "__main__":
    main()
