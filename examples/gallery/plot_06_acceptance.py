"""
Fig. 6: accepted and rejected contacts
======================================

The paper's Fig. 6 is a sketch of the configurations in which two surface spheres that overlap
form a contact (accepted) and those in which they do not (rejected: the spheres face away from
each other). Here, what those conditions do during a loading: of the points whose gap has
closed (candidates), how many are accepted as contacts at each displacement, for a
rough-on-rough pair at D = 1.5.
"""

import matplotlib.pyplot as plt

import splinecontact as sc

lower, upper = sc.weierstrass_mandelbrot_pair(1.5, n_points=20_000, length=100.0, ra=0.005, seed=6)
result = sc.simulate(lower, upper, steps=200)
candidates = result.n_candidates
accepted = result.n_contacts
print(f"last step: {int(candidates[-1])} candidates, {int(accepted[-1])} accepted")

fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
ax.plot(result.displacement * 1000, candidates, label="gap closed (candidates)")
ax.plot(result.displacement * 1000, accepted, label="accepted contacts")
ax.set_xlabel("displacement δ_N [nm]")
ax.set_ylabel("number of points [1]")
ax.legend()
