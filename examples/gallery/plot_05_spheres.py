"""
Fig. 5: surface spheres and normals
===================================

Each point of the smoothed profile carries a "surface sphere": its centre lies along the
local normal at the radius of curvature (paper eqs. 4–6). Drawn on a short segment of a
D = 1.4 profile, every 6th point, with equal axes.
"""

import matplotlib.pyplot as plt
import numpy as np

import splinecontact as sc
from splinecontact import plotting

profile = sc.weierstrass_mandelbrot(1.4, n_points=20_000, length=100.0, ra=0.005, seed=5)
fit = sc.fit_spline(profile)
spheres = sc.surface_spheres(fit)
radius = 1.0 / np.maximum(np.abs(spheres.curvature), 1e-300)
print(
    f"{profile.n_points} spheres; median radius {np.median(radius):.3g} µm "
    f"(r_min = {spheres.r_min:.3g} µm)"
)

centre = float(profile.x[np.argmax(profile.z)])
window = 60 * profile.dx
fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
plotting.plot_spheres(fit, ax=ax, xlim=(centre - window, centre + window), every=6)
