"""Friction quantities of rough pairs at the paper's spacing (the table in docs/friction.md).

    python benchmarks/friction_table.py

``friction_study`` with one realisation (seed 7) per row: 10⁵ points over 10 µm, D = 1.3, 1.5,
1.7, rough-on-rough and rough-on-flat, pressed to 0.1 × the lower peak-to-valley height, then
F_N held while sliding +50 nm, −50 nm, +50 nm.
"""

from __future__ import annotations

import time

from splinecontact.analysis import friction_study

HEADER = (
    "| D | contact | F_N [mN/µm] | μ_s | k_T/k_N | dissipation per cycle [mN·µm/µm] "
    "| dilatancy [nm] | steps with F_N held to 1e−6 |"
)


def main() -> None:
    print(HEADER)
    print("|---|---|---|---|---|---|---|---|")
    cpu0, wall0 = time.process_time(), time.perf_counter()
    dims = [1.3, 1.5, 1.7]
    studies = {
        flat: friction_study(dims, [7], flat=flat, n_points=100_000, length=10.0)
        for flat in (False, True)
    }
    for a, dimension in enumerate(dims):
        for flat, ds in studies.items():
            v = {name: float(ds[name].values[a, 0]) for name in ds.data_vars if ds[name].ndim == 2}
            print(
                f"| {dimension} | {'rough-on-flat' if flat else 'rough-on-rough'} "
                f"| {v['normal_force']:.3g} | {v['mu_s']:.3f} | {v['stiffness_ratio']:.3f} "
                f"| {v['dissipation']:.3e} | {1e3 * v['dilatancy']:.3f} "
                f"| {100 * v['force_held']:.0f} % |"
            )
    print(f"CPU {time.process_time() - cpu0:.1f} s, wall {time.perf_counter() - wall0:.1f} s")


if __name__ == "__main__":
    main()
