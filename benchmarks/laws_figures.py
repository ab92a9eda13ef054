"""Figures of docs/contact-laws.md: adhesion and plasticity of rough pairs against D.

    python benchmarks/laws_figures.py [--overwrite] [--realizations 4] [--which study]

Writes into docs/figures/

* ``laws_pull_off_vs_D.png``: pull-off force and work of separation of a rough-on-flat contact
  against D, for 2D JKR, DMT and Maugis–Dugdale (mean ± standard error over realizations);
* ``laws_plastic_cycles.png``: F_N–δ_N over three load–unload cycles of the elastic–plastic
  law (one realization, D = 1.5), and the residual approach and the energy dissipated per
  cycle against D;
* ``laws_study_vs_D.png``: ``laws_study`` ensembles (rough on flat, ``weierstrass_mandelbrot_pair``
  defaults) for Hertz and every law: pull-off force, work of separation, residual approach and
  κ of eq. 15 fitted against F_N − F_0 (``adhesive_kappa``), means with 95 % Student-t bands.

Profiles: 2·10⁴ points over 2 µm (the paper's spacing, 0.1 nm), R_A = L/200, rough-on-flat,
E* = 10 GPa, μ0 = 0; each path loads to 0.1 × the peak-to-valley height.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from splinecontact import Segment, simulate, weierstrass_mandelbrot
from splinecontact.analysis.laws import cycle_energy, unloading
from splinecontact.analysis.laws_study import laws_study
from splinecontact.contact import make_law
from splinecontact.outputs import atomic_path, check_output_file
from splinecontact.plotting import plot_laws_study

FIGURES = Path(__file__).resolve().parent.parent / "docs" / "figures"
N_POINTS, LENGTH = 20_000, 2.0
DIMENSIONS = (1.2, 1.4, 1.6, 1.8)
ADHESIVE = {
    "jkr": {"work_of_adhesion": 0.1},
    "dmt": {"work_of_adhesion": 0.1, "cohesive_stress": 0.5},
    "maugis-dugdale": {"work_of_adhesion": 0.1, "cohesive_stress": 0.5},
}
PLASTIC = {"hardness": 2.0}


def _save(fig: Figure, name: str, overwrite: bool) -> None:
    path = check_output_file(FIGURES / name, overwrite=overwrite)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130)
    print(f"wrote {path}")


def _profile(dimension: float, seed: int):  # type: ignore[no-untyped-def]
    return weierstrass_mandelbrot(
        dimension, seed=seed, n_points=N_POINTS, length=LENGTH, wavelength=0.1 * LENGTH,
        ra=LENGTH / 200,
    )  # fmt: skip


def _cycles(depth: float, n: int, steps: int = 150) -> list[Segment]:
    path = [Segment(normal=-0.2 * depth, steps=1)]
    for _ in range(n):
        path += [Segment(normal=depth, steps=steps), Segment(normal=-0.2 * depth, steps=steps)]
    return path


def pull_off(realizations: int, overwrite: bool) -> None:
    fig = Figure(figsize=(10, 4), layout="constrained")
    ax_f, ax_w = fig.subplots(1, 2)
    for name, parameters in ADHESIVE.items():
        law = make_law(name, **parameters)
        forces, works = [], []
        for d in DIMENSIONS:
            f_d, w_d = [], []
            for seed in range(realizations):
                lower = _profile(d, seed)
                depth = 0.1 * lower.peak_to_valley
                r = simulate(lower, "flat", mu0=0.0, law=law, path=_cycles(depth, 1),
                             diagnostics=False)  # fmt: skip
                u = unloading(r, 151, 301)
                f_d.append(-u.pull_off_force)
                w_d.append(u.work_of_separation)
            forces.append((np.mean(f_d), np.std(f_d, ddof=1) / np.sqrt(realizations)))
            works.append((np.mean(w_d), np.std(w_d, ddof=1) / np.sqrt(realizations)))
        for ax, values in ((ax_f, forces), (ax_w, works)):
            mean, err = np.array(values).T
            ax.errorbar(DIMENSIONS, mean, yerr=err, marker="o", capsize=3, label=name)
    ax_f.set(xlabel="D", ylabel="pull-off force −min F_N [mN/µm]")
    ax_w.set(xlabel="D", ylabel="work of separation [mN·µm/µm]")
    for ax in (ax_f, ax_w):
        ax.set_ylim(bottom=0)
        ax.legend()
    fig.suptitle(
        f"Rough on flat, {N_POINTS} points over {LENGTH} µm, w = 0.1 J/m², σ0 = 0.5 GPa, "
        f"E* = 10 GPa; mean ± s.e. of {realizations} realizations"
    )
    _save(fig, "laws_pull_off_vs_D.png", overwrite)


def plastic(realizations: int, overwrite: bool) -> None:
    law = make_law("elastic-plastic", **PLASTIC)
    fig = Figure(figsize=(13, 4), layout="constrained")
    ax_c, ax_r, ax_e = fig.subplots(1, 3)
    lower = _profile(1.5, 0)
    depth = 0.1 * lower.peak_to_valley
    r = simulate(lower, "flat", mu0=0.0, law=law, path=_cycles(depth, 3), diagnostics=False)
    ax_c.plot(1e3 * r.displacement, r.normal_force, lw=1)
    ax_c.set(xlabel="δ_N [nm]", ylabel="F_N [mN/µm]", title="D = 1.5, three load–unload cycles")
    residual, energy = [], []
    for d in DIMENSIONS:
        res_d, en_d = [], []
        for seed in range(realizations):
            lower = _profile(d, seed)
            depth = 0.1 * lower.peak_to_valley
            r = simulate(lower, "flat", mu0=0.0, law=law, path=_cycles(depth, 3),
                         diagnostics=False)  # fmt: skip
            res_d.append([unloading(r, 151 + 300 * k, 301 + 300 * k).residual_displacement
                          / depth for k in range(3)])  # fmt: skip
            en_d.append([cycle_energy(r, 1 + 300 * k, 301 + 300 * k).work for k in range(3)])
        residual.append(np.nanmean(res_d, axis=0))
        energy.append(np.mean(en_d, axis=0))
    residual_a, energy_a = np.array(residual), np.array(energy)
    for k, (marker, size) in enumerate((("o", 9), ("s", 6), ("x", 6))):
        style = {"marker": marker, "markersize": size, "label": f"cycle {k + 1}"}
        ax_r.plot(DIMENSIONS, residual_a[:, k], **style)
        ax_e.plot(DIMENSIONS, energy_a[:, k], **style)
    ax_r.set(xlabel="D", ylabel="residual approach / maximum δ_N [1]")
    ax_e.set(xlabel="D", ylabel="energy dissipated per cycle [mN·µm/µm]")
    for ax in (ax_r, ax_e):
        ax.legend()
    fig.suptitle(
        f"Elastic–plastic law, H = {PLASTIC['hardness']} GPa, ν = 0.3, E* = 10 GPa, rough on flat; "
        f"mean of {realizations} realizations"
    )
    _save(fig, "laws_plastic_cycles.png", overwrite)


def study(realizations: int, overwrite: bool) -> None:
    laws: dict[str, dict[str, float]] = {"hertz": {}, **ADHESIVE, "elastic-plastic": PLASTIC}
    studies = {
        name: laws_study(DIMENSIONS, range(realizations), law=make_law(name, **parameters),
                         n_points=N_POINTS, length=LENGTH, steps=150)
        for name, parameters in laws.items()
    }  # fmt: skip
    fig = Figure(figsize=(11, 8), layout="constrained")
    axes = fig.subplots(2, 2).ravel()
    names = ("pull_off_force", "work_of_separation", "residual_fraction", "kappa")
    for ax, name in zip(axes, names, strict=True):
        plot_laws_study(studies, name, ax=ax)
    fig.suptitle(
        f"laws_study: rough on flat, {N_POINTS} points over {LENGTH} µm, to 0.1 × peak-to-valley "
        f"and back\nw = 0.1 J/m², σ0 = 0.5 GPa, H = 2 GPa, E* = 10 GPa; {realizations} "
        "realizations per D",
        fontsize="medium",
    )
    for name, ds in studies.items():
        for var in names:
            mean, ci = ds[f"{var}_mean"].values, ds[f"{var}_ci"].values
            cells = ", ".join(f"{m:.3g} ± {c:.2g}" for m, c in zip(mean, ci, strict=True))
            print(f"{name:16s} {var:20s} {cells}")
    _save(fig, "laws_study_vs_D.png", overwrite)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--overwrite", action="store_true")
    parser.add_argument("--realizations", type=int, default=4)
    parser.add_argument("--which", choices=("all", "pull-off", "plastic", "study"), default="all")
    args = parser.parse_args()
    if args.which in ("all", "pull-off"):
        pull_off(args.realizations, args.overwrite)
    if args.which in ("all", "plastic"):
        plastic(args.realizations, args.overwrite)
    if args.which in ("all", "study"):
        study(args.realizations, args.overwrite)


if __name__ == "__main__":
    main()
