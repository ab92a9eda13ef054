"""
Fig. 11: contact stiffness and contact area
===========================================

(a) Dimensionless stiffness k/E* against dimensionless load F_N/(E* L0), log–log, and (b)
contact area A_S against F_N, for D = 1.2, 1.5, 1.8, rough-on-flat (ensemble means, 95 %
bands). A tiny study: 3 realizations per D, 20 000-point profiles, 100 steps.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from splinecontact import analysis, plotting, study

config = {
    "study": {"name": "gallery-fig11", "seed": 11, "realizations": 3},
    "fixed": {"n_points": 20_000, "length": 100.0, "ra": 0.005, "e_star": 10.0, "steps": 100},
    "sweep": {"dimension": [1.2, 1.5, 1.8], "contact_type": ["rough-on-flat"]},
}
with tempfile.TemporaryDirectory() as folder:
    store = Path(folder) / "fig11.zarr"
    study.run_study(config, store, workers=1, progress=False)
    ds = study.open_study(store).load().sel(contact_type="rough-on-flat")

fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4.4), layout="constrained")
plotting.plot_dimensionless_stiffness(analysis.dimensionless_stiffness(ds), ax=ax_a)
plotting.plot_area_force(analysis.ensemble_vs_force(ds), ax=ax_b)
ax_a.set_title("(a)", loc="left")
ax_b.set_title("(b)", loc="left")
