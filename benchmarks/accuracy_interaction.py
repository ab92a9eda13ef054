"""Accuracy of independent and interacting SAD against the exact BEM on the docs ensemble.

For each realization (Weierstrass–Mandelbrot, 2¹⁶ points over 100 µm, package defaults) SAD runs
its 1000 displacement steps twice, independent (the paper's eq. 10) and interacting
(:mod:`splinecontact.contact.interaction`); 20 forces evenly spaced up to the interacting variant's
largest force are solved exactly by the BEM on the mirrored smoothed composite profile (as
``splinecontact compare`` does), and both variants are read at those forces by linear
interpolation between their steps. The BEM states are cached per realization in ``--cache`` so
that a change of the interacting model does not re-run the BEM.

Run::

    python benchmarks/accuracy_interaction.py --dims 1.5 --seeds 1          # one realization
    python benchmarks/accuracy_interaction.py                                # the ensemble
    python benchmarks/accuracy_interaction.py --pair --dims 1.3 1.5 1.7      # rough on rough

Prints per realization the medians of contact length / exact and mean gap / exact, and at the end
the medians and 5th–95th percentiles over all forces per D.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from splinecontact import Profile, bem
from splinecontact.compare import _solve_in_substeps
from splinecontact.contact import contact_geometry, run_loading
from splinecontact.contact.interaction import (
    InteractionSettings,
    extended_geometry,
    interacting_loading,
)
from splinecontact.generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from splinecontact.spline import fit_spline

E_STAR = 10.0


def interpolate(curve_f: np.ndarray, values: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Values of a per-step curve at given forces (force increasing along the path)."""
    force = np.maximum.accumulate(curve_f)
    keep = np.concatenate([[True], np.diff(force) > 0])
    return np.interp(forces, force[keep], values[keep])


def bem_states(
    lower: Profile, upper: Profile | str, forces: np.ndarray, cache: Path, tag: str
) -> dict[str, np.ndarray]:
    path = cache / f"{tag}.npz"
    if path.exists():
        data = dict(np.load(path))
        if data["force"].shape == forces.shape and np.allclose(data["force"], forces, rtol=1e-12):
            return data
    n = lower.n_points
    composite = fit_spline(lower, alpha=2.0, x0=1.0).f
    if not isinstance(upper, str):
        composite = composite + fit_spline(upper, alpha=2.0, x0=1.0).f
    problem = bem.contact_problem(bem.mirror_extend(Profile(lower.x, composite)), e_star=E_STAR)
    segment = n * lower.dx
    previous = None
    previous_load = 0.0
    out: dict[str, list[float]] = {"length": [], "gap": [], "patches": [], "approach": []}
    for force in forces:
        state = _solve_in_substeps(problem, force / segment, previous, previous_load, 1e-10, 5000)
        stats = bem.contact_statistics(state.pressure[:n], lower.dx, periodic=False)
        out["length"].append(stats.contact_length_subgrid)
        out["gap"].append(state.mean_gap)
        out["patches"].append(stats.n_patches)
        out["approach"].append(state.approach)
        previous, previous_load = state.pressure, force / segment
    data = {k: np.asarray(v) for k, v in out.items()}
    data["force"] = forces
    cache.mkdir(parents=True, exist_ok=True)
    np.savez(path, **data)
    return data


def realization(
    d: float, seed: int, pair: bool, cache: Path, n_points: int, mesh: int | None
) -> dict[str, np.ndarray]:
    if pair:
        lower, upper_p = weierstrass_mandelbrot_pair(d, n_points=n_points, seed=seed)
        upper: Profile | str = upper_p
    else:
        lower = weierstrass_mandelbrot(d, n_points=n_points, seed=seed)
        upper = "flat"
    geo = contact_geometry(
        lower,
        upper,
        steps=1000,
        final_displacement=None,
        final_displacement_factor=0.2,
        alpha=2.0,
        x0=1.0,
    )
    t0 = time.process_time()
    sad = run_loading(geo, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3).curves
    t1 = time.process_time()
    geo_x = extended_geometry(
        lower,
        upper,
        steps=1000,
        final_displacement=None,
        final_displacement_factor=0.2,
        alpha=2.0,
        x0=1.0,
    )
    inter, _ = interacting_loading(
        geo_x,
        e_star=E_STAR,
        g_star=E_STAR / 2.6,
        mu0=0.3,
        n_points=lower.n_points,
        settings=InteractionSettings(mesh_cells=mesh),
    )
    t2 = time.process_time()
    top = float(inter["normal_force"].max())
    forces = top * np.arange(1, 21) / 20
    tag = f"{'pair' if pair else 'flat'}-D{d}-s{seed}-n{n_points}"
    exact = bem_states(lower, upper, forces, cache, tag)
    t3 = time.process_time()
    res = {
        "force": forces,
        "sad_width": interpolate(sad["normal_force"], np.sqrt(2) * sad["contact_area"], forces),
        "sad_sep": interpolate(sad["normal_force"], sad["mean_separation"], forces),
        "sad_n": interpolate(sad["normal_force"], sad["n_contacts"].astype(float), forces),
        "int_length": interpolate(inter["normal_force"], inter["coalesced_contact_length"], forces),
        "int_width": interpolate(inter["normal_force"], np.sqrt(2) * inter["contact_area"], forces),
        "int_sep": interpolate(inter["normal_force"], inter["mean_separation"], forces),
        "int_n": interpolate(inter["normal_force"], inter["n_contacts"].astype(float), forces),
        "int_patches": interpolate(
            inter["normal_force"], inter["n_contact_patches"].astype(float), forces
        ),
        "bem_length": exact["length"],
        "bem_gap": exact["gap"],
        "bem_patches": exact["patches"],
        "reach_exceeded": np.array(int(inter["reach_exceeded"].sum())),
        "cpu_sad": np.array(t1 - t0),
        "cpu_int": np.array(t2 - t1),
        "cpu_bem": np.array(t3 - t2),
    }
    return res


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dims", type=float, nargs="+", default=[1.1, 1.3, 1.5, 1.7, 1.9])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--pair", action="store_true", help="rough on rough")
    parser.add_argument("--n-points", type=int, default=2**16)
    parser.add_argument("--mesh", type=int, default=None)
    parser.add_argument("--cache", type=Path, default=Path("accuracy-cache"))
    parser.add_argument("--json", type=Path, default=None, help="write the per-force ratios")
    args = parser.parse_args()
    table: dict[str, dict[str, list[float]]] = {}
    for d in args.dims:
        rows = table.setdefault(str(d), {"len": [], "gap": [], "sadlen": [], "sadgap": [], "n": []})
        for seed in args.seeds:
            r = realization(d, seed, args.pair, args.cache, args.n_points, args.mesh)
            length = r["int_length"] / r["bem_length"]
            gap = r["int_sep"] / r["bem_gap"]
            rows["len"] += length.tolist()
            rows["gap"] += gap.tolist()
            rows["sadlen"] += (r["sad_width"] / r["bem_length"]).tolist()
            rows["sadgap"] += (r["sad_sep"] / r["bem_gap"]).tolist()
            rows["n"] += (r["bem_patches"] / np.maximum(r["int_patches"], 1)).tolist()
            print(
                f"D={d} seed={seed}: interacting length/exact {np.median(length):.3f} "
                f"({length.min():.3f}–{length.max():.3f}), mean gap/exact {np.median(gap):.4f} "
                f"({gap.min():.4f}–{gap.max():.4f}); Σ2a/exact {np.median(r['int_width'] / r['bem_length']):.3f}; "
                f"independent length {np.median(r['sad_width'] / r['bem_length']):.3f}, gap "
                f"{np.median(r['sad_sep'] / r['bem_gap']):.3f}; patches exact/int "
                f"{np.median(r['bem_patches'] / np.maximum(r['int_patches'], 1)):.2f}, int contacts/patches "
                f"{np.median(r['int_n'] / np.maximum(r['int_patches'], 1)):.2f}; CPU s: SAD {float(r['cpu_sad']):.2f}, "
                f"interacting {float(r['cpu_int']):.2f}, BEM {float(r['cpu_bem']):.1f}; reach exceeded at "
                f"{int(r['reach_exceeded'])} steps",
                flush=True,
            )
    print(
        "\nD | interacting length/exact median (p5–p95) | mean gap/exact median (p5–p95) | "
        "independent length | independent gap | exact patches / interacting patches"
    )
    for d, rows in table.items():
        q = {k: np.percentile(v, [50, 5, 95]) for k, v in rows.items()}
        print(
            f"{d} | {q['len'][0]:.3f} ({q['len'][1]:.3f}–{q['len'][2]:.3f}) | {q['gap'][0]:.4f} "
            f"({q['gap'][1]:.4f}–{q['gap'][2]:.4f}) | {q['sadlen'][0]:.3f} | {q['sadgap'][0]:.3f} | "
            f"{q['n'][0]:.2f} ({q['n'][1]:.2f}–{q['n'][2]:.2f})"
        )
    if args.json is not None:
        args.json.write_text(json.dumps(table), encoding="utf-8")


if __name__ == "__main__":
    main()
