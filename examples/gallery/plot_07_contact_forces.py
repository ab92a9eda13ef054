"""
Fig. 7: forces at the contact points
====================================

At each accepted contact the normal force (π/4) E* δ_i acts along the repulsive direction e_i,
and an incremental tangential force F^t_i acts along the contact tangent (paper eqs. 10–13).
Recorded at the last step of a rough-on-rough loading (D = 1.3) and drawn as arrows on the
lower profile: normal forces in red, tangential forces in blue (same scale).
"""

import matplotlib.pyplot as plt
import numpy as np

import splinecontact as sc

lower, upper = sc.weierstrass_mandelbrot_pair(
    1.3, n_points=20_000, length=100.0, ra=0.005, seed=7
)
result = sc.simulate(lower, upper, steps=200, record_contacts="last")
record = result.contacts[-1]
print(
    f"{record.point.size} contacts; Σ|F^n| = {record.normal_force.sum():.4g} mN/µm, "
    f"Σ|F^t| = {np.abs(record.tangential_force).sum():.4g} mN/µm"
)

ex, ez = record.normal_x, record.normal_z
fn, ft = record.normal_force, record.tangential_force
scale = 1.0 / fn.max()
fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
ax.plot(lower.x, lower.z * 1000, lw=0.5, color="0.4", label="lower profile")
ax.quiver(record.x, record.z * 1000, ex * fn * scale, ez * fn * scale, color="C3",
          angles="uv", label="normal force", width=0.004)
ax.quiver(record.x, record.z * 1000, ez * ft * scale, -ex * ft * scale, color="C0",
          angles="uv", label="tangential force", width=0.004)
ax.set_xlabel("x [µm]")
ax.set_ylabel("height z [nm]")
ax.legend(loc="lower right", fontsize="small")
