"""
Fig. 9: the accepted contact spheres
====================================

A zoom on a rough-on-rough pair (D = 1.4) a quarter of the way through the loading, with the
accepted contact spheres in red.
"""

import matplotlib.pyplot as plt

import splinecontact as sc
from splinecontact import plotting

lower, upper = sc.weierstrass_mandelbrot_pair(1.4, n_points=20_000, length=100.0, ra=0.005, seed=9)
step = 50
result = sc.simulate(lower, upper, steps=200, record_contacts=[step])
record = result.contacts[0]
print(f"step {step}: δ_N = {result.displacement[step] * 1000:.3g} nm, {record.point.size} contacts")

fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
plotting.plot_contact_zoom(
    sc.fit_spline(lower), sc.fit_spline(upper), record, float(result.displacement[step]), ax=ax
)
