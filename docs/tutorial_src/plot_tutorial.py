"""
From a measured scan to a study over D
======================================

This tutorial runs top to bottom on the sample scans shipped in the repository's ``tests/data``
folder, and it is executed at every build of these pages: every number and figure below is the
one this run of the code produced.

We read a measured line scan, inspect it, remove its form, press it against a rigid flat and
against a second scan, check SAD against the exact boundary-element (BEM) solution, and finish
with a small study over the fractal dimension D.

Units everywhere: lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness.
"""

# %%
# Read a measured scan
# --------------------
# :func:`splinecontact.io.read_profile` reads text tables, Dektak CSV, X3P and NumPy files.
# ``hfm-1.hfm`` is a stylus line scan whose second header line gives the units (mm); the
# reader converts to µm and records where each unit came from.

from pathlib import Path

import matplotlib.pyplot as plt

import splinecontact as sc
from splinecontact import analysis, compare, io, plotting, preprocess, spectra, study


def find_data() -> Path:
    """The repository's ``tests/data`` folder (the build may run from ``docs/``)."""
    for base in (Path.cwd(), *Path.cwd().parents):
        if (base / "tests" / "data" / "hfm-1.hfm").is_file():
            return base / "tests" / "data"
    raise FileNotFoundError("run this tutorial from a clone of the repository")


DATA = find_data()
scan = io.read_profile(DATA / "hfm-1.hfm")
print(f"splinecontact {sc.__version__}")
print(f"{scan.n_points} points, dx = {scan.dx:g} µm, length = {scan.length:g} µm")
print("units:", scan.metadata["units"])

# %%
# A file that does not say its units is refused, with a message that says what to do.
# ``xy-4.txt`` is such a file (two columns, no header):

try:
    io.read_profile(DATA / "xy-4.txt")
except sc.ProfileReadError as error:
    print(f"{type(error).__name__}: {error}")

other = io.read_profile(DATA / "xy-4.txt", unit="µm")
print(f"with unit='µm': {other.n_points} points over {other.length:.4g} µm")

# %%
# Inspect it
# ----------
# A :class:`~splinecontact.Profile` knows its roughness parameters: R_A and R_q [µm], the rms
# slope R_Sq [1] and the peak-to-valley height [µm]. The stylus records absolute positions, so
# the raw scan carries the tilt of the stage.


def describe(profile: sc.Profile) -> str:
    return (
        f"R_A = {profile.ra:.4g} µm, R_q = {profile.rq:.4g} µm, "
        f"R_Sq = {profile.rsq:.4g}, peak-to-valley = {profile.peak_to_valley:.4g} µm"
    )


print("raw:      ", describe(scan))

# %%
# Preprocess it: remove the form
# -------------------------------
# :func:`splinecontact.preprocess.detrend` removes a least-squares line (``"tilt"``), the mean
# or a polynomial; the step is recorded in the profile's metadata. The same options can be
# given to the reader as a :class:`~splinecontact.preprocess.Preprocessing`.

levelled = preprocess.detrend(scan, "tilt")
print("levelled: ", describe(levelled))
print("steps:", levelled.metadata["preprocessing"])

fig, (ax_raw, ax_lev) = plt.subplots(2, 1, figsize=(7, 5), sharex=True, layout="constrained")
ax_raw.plot(scan.x, scan.z, lw=0.6)
ax_raw.set_ylabel("raw height [µm]")
ax_lev.plot(levelled.x, levelled.z, lw=0.6)
ax_lev.set_ylabel("levelled height [µm]")
ax_lev.set_xlabel("x [µm]")

# %%
# The power spectrum and the Hurst exponent H from its slope
# (:func:`splinecontact.spectra.hurst_exponent`, default band 20/L … 1/(8 dx)). An H outside
# 0…1 means that a self-affine power law does not describe the scan over that band.

frequency, power = spectra.power_spectrum(levelled)
hurst = spectra.hurst_exponent(levelled)
print(f"H = {hurst:.3f} over the default band")
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
ax.loglog(frequency[1:], power[1:], lw=0.6)
ax.set_xlabel("spatial frequency [1/µm]")
ax.set_ylabel("power spectral density [µm³]")

# %%
# Press it against a rigid flat
# -----------------------------
# :func:`splinecontact.simulate` lowers the upper body in equal steps from first contact to
# 0.2 × the lower peak-to-valley height (the paper's choice) and records the normal force
# F_N [mN/µm], the contact area A_S [µm] and more at every step. E* = 10 GPa by default.
# The tutorial uses 200 steps instead of the paper's 1000 to stay fast.

on_flat = sc.simulate(levelled, "flat", steps=200)
print(
    f"final δ_N = {on_flat.displacement[-1]:.4g} µm: F_N = {on_flat.normal_force[-1]:.4g} mN/µm, "
    f"A_S = {on_flat.contact_area[-1]:.4g} µm, {int(on_flat.n_contacts[-1])} contacts"
)

fig, (ax_f, ax_a) = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained")
ax_f.plot(on_flat.displacement, on_flat.normal_force)
ax_f.set_xlabel("displacement δ_N [µm]")
ax_f.set_ylabel("normal force F_N [mN/µm]")
ax_a.plot(on_flat.normal_force, on_flat.contact_area)
ax_a.set_xlabel("normal force F_N [mN/µm]")
ax_a.set_ylabel("contact area A_S [µm]")

# %%
# Against a second scan
# ---------------------
# Rough-on-rough contact needs two profiles on the same grid. The X3P file is an areal
# measurement; two of its rows (``line=``) are two line scans on one grid. The reader removes
# their tilt as it reads them.

levelling = preprocess.Preprocessing(detrend="tilt")
lower = io.read_profile(DATA / "x3p-2.x3p", line=100, preprocessing=levelling)
upper = io.read_profile(DATA / "x3p-2.x3p", line=500, preprocessing=levelling)
print(f"lower: {lower.n_points} points, dx = {lower.dx:.4g} µm;", describe(lower))
print("upper:", describe(upper))

rough_rough = sc.simulate(lower, upper, steps=200)
rough_flat = sc.simulate(lower, "flat", steps=200)
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
for label, result in (("on the second scan", rough_rough), ("on a rigid flat", rough_flat)):
    ax.plot(result.displacement * 1000, result.normal_force, label=label)
ax.set_xlabel("displacement δ_N [nm]")
ax.set_ylabel("normal force F_N [mN/µm]")
ax.legend()

# %%
# Every result converts to an :class:`xarray.Dataset` whose variables carry their units:

dataset = rough_rough.to_xarray()
print({name: dataset[name].attrs["units"] for name in ("displacement", "normal_force")})

# %%
# Compare with the exact solution (BEM)
# --------------------------------------
# SAD treats each contact as an independent Hertzian line contact.
# :func:`splinecontact.compare.compare_profiles` solves the same smoothed geometry exactly
# (plane-strain boundary elements) at SAD's forces. The 650-point X3P row keeps it to a
# fraction of a second.

comparison = compare.compare_profiles(lower, "flat", steps=200, n_forces=8)
cols = comparison.columns
print("F_N [mN/µm]  SAD width [µm]  exact length [µm]  ratio")
for f, w, b, r in zip(
    cols["force"],
    cols["sad_contact_width"],
    cols["bem_contact_length_subgrid"],
    cols["ratio_width"],
    strict=True,
):
    print(f"{f:10.4f}  {w:14.4f}  {b:17.4f}  {r:5.2f}")
print(f"median width ratio SAD/exact: {comparison.median('ratio_width'):.3f}")
for note in comparison.notes:
    print("note:", note)

fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
ax.plot(cols["force"], cols["sad_contact_width"], "o-", label="SAD, Σ 2a_i")
ax.plot(cols["force"], cols["bem_contact_length_subgrid"], "s-", label="exact (BEM)")
ax.set_xlabel("normal force F_N [mN/µm]")
ax.set_ylabel("contact length [µm]")
ax.legend()

# %%
# A small study over D
# --------------------
# A study is an ensemble of simulations over a parameter grid × realizations, stored in a
# Zarr store that can be resumed (:func:`splinecontact.study.run_study`; on the command line,
# ``splinecontact study run``). This one is tiny — 3 dimensions × 4 realizations of
# 20 000-point Weierstrass–Mandelbrot profiles, 100 steps, on a flat — so it runs in seconds;
# the paper's study is ``examples/paper-study.toml``.

import tempfile  # noqa: E402

config = {
    "study": {"name": "tutorial", "seed": 2015, "realizations": 4},
    "fixed": {"n_points": 20_000, "length": 100.0, "ra": 0.005, "e_star": 10.0, "steps": 100},
    "sweep": {"dimension": [1.2, 1.5, 1.8], "contact_type": ["rough-on-flat"]},
}
with tempfile.TemporaryDirectory() as folder:
    summary = study.run_study(config, Path(folder) / "tutorial.zarr", workers=1, progress=False)
    results = study.open_study(Path(folder) / "tutorial.zarr").load()
print(f"{summary.ok} of {summary.total} realizations ok, {summary.failed} failed")
results = results.sel(contact_type="rough-on-flat")

# %%
# Ensemble means with 95 % confidence bands: F_N against δ_N (the paper's Fig. 10a) and A_S
# against F_N (Fig. 11b), one curve per D.

fig, (ax_f, ax_a) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
plotting.plot_force_displacement(
    analysis.ensemble_vs_displacement(results, ["normal_force"]), ax=ax_f
)
plotting.plot_area_force(analysis.ensemble_vs_force(results), ax=ax_a)

# %%
# The coefficient κ of A_S = κ F_N / (E* R_Sq) (paper eq. 15) per D, with the values of
# Persson and Bush et al. (Fig. 12):

kappa = analysis.kappa(results)
for d in kappa["dimension"].values:
    k = kappa.sel(dimension=d)
    print(
        f"D = {d:.1f}: κ = {float(k['kappa_mean']):.3g} "
        f"(95 % CI {float(k['kappa_ci_low']):.3g} … {float(k['kappa_ci_high']):.3g}, "
        f"{int(k['kappa_count'])} realizations)"
    )
fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
plotting.plot_kappa_hurst({"rough-on-flat": kappa}, ax=ax)

# %%
# Where to go next: the gallery shows each of the paper's figures on its own; the guides
# explain every convention (:doc:`/conventions`), how to read your own scans
# (:doc:`/measured-profiles`), how to run large studies on a cluster (:doc:`/studies`) and
# how SAD compares with exact elasticity (:doc:`/accuracy`).
