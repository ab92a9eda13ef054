"""
A measured profile and its spline
=================================

A row of the areal X3P measurement shipped in ``tests/data`` (650 points, dx ≈ 0.13 µm),
levelled as it is read, with its smoothing spline (α = 2) and surface spheres on a short
window.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import splinecontact as sc
from splinecontact import io, plotting, preprocess


def find_data() -> Path:
    for base in (Path.cwd(), *Path.cwd().parents):
        if (base / "tests" / "data" / "x3p-2.x3p").is_file():
            return base / "tests" / "data"
    raise FileNotFoundError("run this example from a clone of the repository")


profile = io.read_profile(
    find_data() / "x3p-2.x3p", line=300, preprocessing=preprocess.Preprocessing(detrend="tilt")
)
print(
    f"{profile.n_points} points over {profile.length:.4g} µm; R_q = {profile.rq * 1000:.3g} nm, "
    f"R_Sq = {profile.rsq:.3g}; units read as {profile.metadata['units']['x']}"
)
fit = sc.fit_spline(profile)

fig, (ax_all, ax_zoom) = plt.subplots(2, 1, figsize=(8, 7), layout="constrained")
ax_all.plot(profile.x, profile.z * 1000, ".", ms=2, color="0.5", label="measured points")
ax_all.plot(fit.x, fit.f * 1000, lw=0.8, label="spline, α = 2")
ax_all.set_xlabel("x [µm]")
ax_all.set_ylabel("height [nm]")
ax_all.legend(fontsize="small")
x0 = float(profile.x[profile.n_points // 2])
plotting.plot_spheres(fit, ax=ax_zoom, xlim=(x0, x0 + 3.0), every=2)
