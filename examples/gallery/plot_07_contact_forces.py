"""
Fig. 7: forces at the contact points
====================================

At each accepted contact the normal force (π/4) E* δ_i acts along the repulsive direction e_i,
and an incremental tangential force F^t_i acts along the contact tangent (paper eqs. 10–13).
Recorded at the last step of a rough-on-rough loading (D = 1.3) and drawn as arrows on the
lower profile: normal forces in red, tangential forces in
blue (same scale). Right: each contact's tangential force against its normal force, with
the cap ``μ0 |F^n|`` of eqs. 12–13.
"""

import matplotlib.pyplot as plt
import numpy as np

import splinecontact as sc

lower, upper = sc.weierstrass_mandelbrot_pair(1.3, n_points=20_000, length=100.0, ra=0.005, seed=7)
result = sc.simulate(lower, upper, steps=200, record_contacts="last")
record = result.contacts[-1]
print(
    f"{record.point.size} contacts; Σ|F^n| = {record.normal_force.sum():.4g} mN/µm, "
    f"Σ|F^t| = {np.abs(record.tangential_force).sum():.4g} mN/µm"
)

ex, ez = record.normal_x, record.normal_z
fn, ft = record.normal_force, record.tangential_force

# Arrow length: 0.7 inch for the largest normal force, the same scale for both forces.
arrows = {"angles": "uv", "scale_units": "inches", "scale": float(fn.max()) / 0.7, "width": 0.003}
fig, (ax, ax_t) = plt.subplots(
    1, 2, figsize=(11, 4), layout="constrained", gridspec_kw={"width_ratios": [2.2, 1]}
)
ax.plot(lower.x, lower.z * 1000, lw=0.4, color="0.5", label="lower profile")
x, z = record.x, record.z * 1000
ax.quiver(x, z, ex * fn, ez * fn, color="C3", label="normal force", **arrows)
ax.quiver(x, z, ez * ft, -ex * ft, color="C0", label="tangential force", **arrows)
low, high = float(lower.z.min() * 1000), float(lower.z.max() * 1000)
ax.set_ylim(low, high + 1.2 * (high - low))  # room above the profile for the arrows
ax.set_xlabel("x [µm]")
ax.set_ylabel("height z [nm]")
ax.legend(loc="upper right", fontsize="small")
mu0 = result.parameters["mu0"]
ax_t.plot(fn, np.abs(ft), "C0o", ms=4, label="contacts")
ax_t.plot([0, fn.max()], [0, mu0 * fn.max()], "k--", lw=0.8, label=f"cap μ0 |F^n|, μ0 = {mu0:g}")
ax_t.set_xlabel("|F^n_i| [mN/µm]")
ax_t.set_ylabel("|F^t_i| [mN/µm]")
ax_t.legend(fontsize="small")
