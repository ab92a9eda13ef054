"""
Fig. 4: spline fits of varied tightness α
=========================================

The smoothing spline of paper eqs. 2–3 on a D = 1.4 profile for α = 1, 2, 3: the higher the
tightness exponent α, the closer the spline follows the points (α = 2 is the paper's choice).
"""

import matplotlib.pyplot as plt
import numpy as np

import splinecontact as sc
from splinecontact import plotting

profile = sc.weierstrass_mandelbrot(1.4, n_points=20_000, length=100.0, ra=0.005, seed=4)
fits = [sc.fit_spline(profile, alpha=a) for a in (1.0, 2.0, 3.0)]
for fit in fits:
    rms = np.sqrt(np.mean((fit.f - profile.z) ** 2)) * 1000
    print(f"α = {fit.alpha:g}: rms distance from the points {rms:.3g} nm")

centre = float(profile.x[np.argmax(profile.z)])
window = 60 * profile.dx
fig, ax = plt.subplots(figsize=(7, 4.5), layout="constrained")
plotting.plot_spline_fits(profile, fits, ax=ax, xlim=(centre - window, centre + window))
