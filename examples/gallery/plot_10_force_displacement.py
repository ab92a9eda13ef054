"""
Fig. 10: normal force and mean separation
=========================================

(a) Ensemble-mean normal force F_N against displacement δ_N and (b) mean separation against
F_N, for D = 1.2, 1.5, 1.8, rough-on-rough, with 95 % confidence bands. A tiny study: 3
realizations per D of 20 000-point profiles and 100 steps (the paper: 200 realizations of 10⁶
points and 1000 steps; ``examples/paper-study.toml``).
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from splinecontact import analysis, plotting, study

config = {
    "study": {"name": "gallery-fig10", "seed": 10, "realizations": 3},
    "fixed": {"n_points": 20_000, "length": 100.0, "ra": 0.005, "e_star": 10.0, "steps": 100},
    "sweep": {"dimension": [1.2, 1.5, 1.8], "contact_type": ["rough-on-rough"]},
}
with tempfile.TemporaryDirectory() as folder:
    store = Path(folder) / "fig10.zarr"
    summary = study.run_study(config, store, workers=1, progress=False)
    ds = study.open_study(store).load().sel(contact_type="rough-on-rough")
print(f"{summary.ok} of {summary.total} realizations ok")

fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4.4), layout="constrained")
plotting.plot_force_displacement(analysis.ensemble_vs_displacement(ds, ["normal_force"]), ax=ax_a)
plotting.plot_separation_force(analysis.ensemble_vs_force(ds), ax=ax_b)
ax_a.set_title("(a)", loc="left")
ax_b.set_title("(b)", loc="left")
