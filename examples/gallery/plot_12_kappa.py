"""
Fig. 12: κ against the Hurst exponent
=====================================

The coefficient κ = R_Sq A_S E* / F_N (paper eq. 15), fitted at low load, against the Hurst
exponent H = 2 − D, for rough-on-rough and rough-on-flat contact, with the values of Persson
and of Bush et al. A tiny study (5 dimensions × 2 contact types × 3 realizations, 20 000-point
profiles, 100 steps): its confidence intervals are wide, and the paper's finding is checked at
full size by ``splinecontact reproduce``.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from splinecontact import analysis, plotting, study

config = {
    "study": {"name": "gallery-fig12", "seed": 12, "realizations": 3},
    "fixed": {"n_points": 20_000, "length": 100.0, "ra": 0.005, "e_star": 10.0, "steps": 100},
    "sweep": {
        "dimension": [1.1, 1.3, 1.5, 1.7, 1.9],
        "contact_type": ["rough-on-rough", "rough-on-flat"],
    },
}
with tempfile.TemporaryDirectory() as folder:
    store = Path(folder) / "fig12.zarr"
    study.run_study(config, store, workers=1, progress=False)
    ds = study.open_study(store).load()

kappa = analysis.kappa(ds)
print(kappa[["kappa_mean", "kappa_ci_low", "kappa_ci_high"]].to_dataframe().round(3))
kappas = {str(c): kappa.sel(contact_type=c) for c in kappa["contact_type"].values}
fig, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
plotting.plot_kappa_hurst(kappas, ax=ax)
