"""
Fig. 8: opposing profiles at first contact
==========================================

A rough-on-rough pair (D = 1.4) at δ_N = 0: the upper body (turned over to face the lower one)
is placed at zero minimum gap; the star marks the first contact point.
"""

import matplotlib.pyplot as plt

import splinecontact as sc
from splinecontact import plotting

lower, upper = sc.weierstrass_mandelbrot_pair(1.4, n_points=20_000, length=100.0, ra=0.005, seed=8)
fit_lower, fit_upper = sc.fit_spline(lower), sc.fit_spline(upper)
fig, ax = plt.subplots(figsize=(9, 4), layout="constrained")
plotting.plot_first_contact(fit_lower, fit_upper, ax=ax)
