"""
Fig. 3a: profiles across the fractal dimension D
================================================

Weierstrass–Mandelbrot profiles (paper eq. 1) of the same mean roughness R_A = 5 nm for
D = 1.0 … 1.9: the higher D, the more short-wavelength content. The paper's profiles have
10⁶ points over 100 µm; these have 20 000 (dx = 5 nm), and the first 10 µm are drawn.
"""

import matplotlib.pyplot as plt
import numpy as np

import splinecontact as sc
from splinecontact import plotting

dimensions = (1.0, 1.2, 1.4, 1.6, 1.8, 1.9)
seeds = np.random.SeedSequence(2015).spawn(len(dimensions))
profiles = [
    sc.weierstrass_mandelbrot(d, n_points=20_000, length=100.0, ra=0.005, seed=s)
    for d, s in zip(dimensions, seeds, strict=True)
]
for d, p in zip(dimensions, profiles, strict=True):
    print(
        f"D = {d:.1f}: R_A = {p.ra * 1000:.3g} nm, R_q = {p.rq * 1000:.3g} nm, R_Sq = {p.rsq:.3g}"
    )

fig, ax = plt.subplots(figsize=(8, 6), layout="constrained")
plotting.plot_profiles(profiles, labels=[f"D = {d:g}" for d in dimensions], ax=ax, xlim=(0.0, 10.0))
