"""A throw-away plain-numba SAD pipeline: the floor the package is measured against.

No validation, no metadata, no results object: two Weierstrass–Mandelbrot profiles by the phasor
recurrence (one point at a time, all terms), Reinsch's smoothing spline (full LDLᵀ factor
arrays), one geometry pass (gap, closing points, curvatures and normals of those points), and the
closed-gap loop (each step visits the points closed so far and sums their (π/4) E* δ forces).
It does the same work per point as the package, written the plain way, so the ratio of their
CPU times says how far the package is from a straightforward implementation.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray


@numba.njit(cache=True, fastmath=True, nogil=True)
def wm_profile(
    n_points: int, dx: float, omega: NDArray[np.float64], amp: NDArray[np.complex128], ra: float
) -> NDArray[np.float64]:
    """Σ_k Re(A_k e^{iω_k x}) by phasor rotation (re-anchored every 2048 points), R_A-scaled."""
    n_terms = omega.size
    z = np.empty(n_points)
    p_re = np.empty(n_terms)
    p_im = np.empty(n_terms)
    r_re = np.cos(omega * dx)
    r_im = np.sin(omega * dx)
    for j in range(n_points):
        if j % 2048 == 0:
            for k in range(n_terms):
                c = math.cos(omega[k] * j * dx)
                s = math.sin(omega[k] * j * dx)
                p_re[k] = amp[k].real * c - amp[k].imag * s
                p_im[k] = amp[k].real * s + amp[k].imag * c
        acc = 0.0
        for k in range(n_terms):
            acc += p_re[k]
            new_re = p_re[k] * r_re[k] - p_im[k] * r_im[k]
            p_im[k] = p_re[k] * r_im[k] + p_im[k] * r_re[k]
            p_re[k] = new_re
        z[j] = acc
    z -= z.mean()
    z *= ra / np.mean(np.abs(z))
    return z


@numba.njit(cache=True, nogil=True)
def reinsch(
    z: NDArray[np.float64], lam: float, dx: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Smoothing spline on a uniform grid: f, f′, f″ (full pentadiagonal LDLᵀ)."""
    n = z.size
    m = n - 2
    lg = lam / dx**3
    a = 2.0 / 3.0 + 6.0 * lg
    b = 1.0 / 6.0 - 4.0 * lg
    c = lg
    d = np.empty(m)
    l1 = np.zeros(m)
    l2 = np.zeros(m)
    d[0] = a
    l1[1] = b / d[0]
    d[1] = a - l1[1] ** 2 * d[0]
    for i in range(2, m):
        l2[i] = c / d[i - 2]
        l1[i] = (b - l2[i] * l1[i - 1] * d[i - 2]) / d[i - 1]
        d[i] = a - l1[i] ** 2 * d[i - 1] - l2[i] ** 2 * d[i - 2]
    y = np.zeros(n)
    for i in range(m):
        rhs = z[i] - 2.0 * z[i + 1] + z[i + 2]
        y[i + 1] = rhs - l1[i] * y[i] - (l2[i] * y[i - 1] if i >= 2 else 0.0)
    gamma = np.zeros(n)
    for i in range(m - 1, -1, -1):
        v = y[i + 1] / d[i]
        if i + 1 < m:
            v -= l1[i + 1] * gamma[i + 2]
        if i + 2 < m:
            v -= l2[i + 2] * gamma[i + 3]
        gamma[i + 1] = v
    f = np.empty(n)
    f[0] = z[0] - lg * gamma[1]
    f[n - 1] = z[n - 1] - lg * gamma[n - 2]
    for i in range(1, n - 1):
        f[i] = z[i] - lg * (gamma[i - 1] - 2.0 * gamma[i] + gamma[i + 1])
    slope = np.empty(n)
    for i in range(n - 1):
        slope[i] = ((f[i + 1] - f[i]) - (2.0 * gamma[i] + gamma[i + 1]) / 6.0) / dx
    slope[n - 1] = ((f[n - 1] - f[n - 2]) + gamma[n - 2] / 6.0) / dx
    return f, slope, gamma / dx**2


@numba.njit(cache=True, nogil=True)
def geometry(
    f_low: NDArray[np.float64],
    f_up: NDArray[np.float64],
    s_low: NDArray[np.float64],
    s_up: NDArray[np.float64],
    c_low: NDArray[np.float64],
    c_up: NDArray[np.float64],
    final: float,
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """One pass: gap to first touch, the points that close by ``final``, their R_eff."""
    n = f_low.size
    top = -np.inf
    for i in range(n):
        top = max(top, f_low[i] + f_up[i])
    count = 0
    for i in range(n):
        if top - (f_low[i] + f_up[i]) <= final:
            count += 1
    index = np.empty(count, np.int64)
    gap0 = np.empty(count)
    r_eff = np.empty(count)
    k = 0
    for i in range(n):
        g = top - (f_low[i] + f_up[i])
        if g <= final:
            kl = -c_low[i] / (1.0 + s_low[i] ** 2) ** 1.5
            ku = -c_up[i] / (1.0 + s_up[i] ** 2) ** 1.5
            index[k] = i
            gap0[k] = g
            r_eff[k] = 2.0 / (kl + ku) if kl + ku > 0.0 else 0.0
            k += 1
    return index, gap0, r_eff


@numba.njit(cache=True, nogil=True)
def loading(gap0: NDArray[np.float64], r_eff: NDArray[np.float64], final: float, steps: int,
            e_star: float) -> NDArray[np.float64]:  # fmt: skip
    """Closed-gap loop: step k visits the points closed so far; force Σ (π/4) E* δ."""
    order = np.argsort(gap0)
    g = gap0[order]
    r = r_eff[order]
    force = np.zeros(steps)
    closed = 0
    for k in range(steps):
        delta = final * (k + 1) / steps
        while closed < g.size and g[closed] <= delta:
            closed += 1
        total = 0.0
        for j in range(closed):
            overlap = delta - g[j]
            if overlap > 0.0 and r[j] > 0.0:
                total += 0.25 * math.pi * e_star * overlap
        force[k] = total
    return force


def wm_terms(dimension: float, seed: np.random.SeedSequence, dx: float) -> tuple:  # type: ignore[type-arg]
    """Frequencies and complex amplitudes of eq. 1 (m and M − m merged), below Nyquist."""
    gamma, directions, n_max, wavelength = 1.5, 20, 20, 1.0
    phases = np.random.default_rng(seed).uniform(0, 2 * np.pi, size=(directions, n_max + 1))
    omega, amp = [], []
    for m in range(1, directions + 1):
        cosine = math.cos(math.pi * m / directions)
        if abs(cosine) < 1e-12:
            continue
        for n in range(n_max + 1):
            frequency = gamma**n * abs(cosine) / wavelength
            if frequency > 0.5 / dx:
                continue
            a = gamma ** ((dimension - 2.0) * n)
            phi = phases[m - 1, n] * (1.0 if cosine > 0 else -1.0)
            omega.append(2 * math.pi * frequency)
            amp.append(-a * complex(math.cos(phi), math.sin(phi)))
    return np.array(omega), np.array(amp)


def realization(n_points: int, seed: int, steps: int = 1000) -> NDArray[np.float64]:
    """One rough-on-rough realization at D = 1.5 (10⁶ points over 100 µm at the default)."""
    length = 100.0 * n_points / 1_000_000
    dx = length / (n_points - 1)
    parent = np.random.SeedSequence(seed)
    low_seed, up_seed = parent.spawn(2)
    z_low = wm_profile(n_points, dx, *wm_terms(1.5, low_seed, dx), 0.005)
    z_up = wm_profile(n_points, dx, *wm_terms(1.5, up_seed, dx), 0.005)
    lam = dx**2 / 10.0
    f_low, s_low, c_low = reinsch(z_low, lam, dx)
    f_up, s_up, c_up = reinsch(z_up, lam, dx)
    final = 0.2 * float(z_low.max() - z_low.min())
    _, gap0, r_eff = geometry(f_low, f_up, s_low, s_up, c_low, c_up, final)
    return loading(gap0, r_eff, final, steps, 10.0)
