"""
SAD against the exact BEM
=========================

SAD treats every accepted contact as an independent Hertzian line contact. The built-in
boundary-element solver gives the exact plane-strain solution on the same smoothed geometry;
:func:`splinecontact.compare.compare_profiles` runs both at the same forces. Here on a
D = 1.5 Weierstrass–Mandelbrot profile of 4096 points against a rigid flat (see the
``accuracy`` guide for ensembles).
"""

import matplotlib.pyplot as plt

import splinecontact as sc
from splinecontact import compare

lower = sc.weierstrass_mandelbrot(1.5, n_points=4096, length=100.0, ra=0.005, seed=14)
comparison = compare.compare_profiles(lower, "flat", steps=200, n_forces=10)
c = comparison.columns
print(f"median SAD width / exact contact length: {comparison.median('ratio_width'):.3f}")
print(f"median SAD mean separation / exact − 1:  {comparison.median('mean_gap_error'):.3f}")

fig, (ax_len, ax_ratio) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
ax_len.plot(c["force"], c["bem_contact_length_subgrid"], "k-o", ms=3, label="exact (BEM)")
ax_len.plot(c["force"], c["sad_contact_width"], "C0-s", ms=3, label="SAD, Hertz width √2·A_S")
ax_len.set_xlabel("normal force F_N [mN/µm]")
ax_len.set_ylabel("contact length [µm]")
ax_len.legend(fontsize="small")
ax_ratio.plot(c["force"], c["ratio_width"], "C0-s", ms=3, label="contact length")
ax_ratio.plot(c["force"], c["ratio_approach"], "C2-^", ms=3, label="approach (exact / SAD)")
ax_ratio.axhline(1.0, color="0.5", lw=0.8)
ax_ratio.set_xlabel("normal force F_N [mN/µm]")
ax_ratio.set_ylabel("ratio [1]")
ax_ratio.legend(fontsize="small")
