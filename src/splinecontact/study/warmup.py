"""Compiling the numba kernels of a realization once, shared out between the pool's workers.

On a study's first run (an empty numba cache) every worker process would compile every kernel a
realization uses, all at the same time. Instead the first two workers each compile one half —
the loading loop (:mod:`splinecontact.contact.kernel`, about half of the compile time) and
everything before it (generation, spline fits, placement, roughness statistics) — into numba's
on-disk cache, wait for each other, and load the other half from the cache. With a warm cache
each part only loads its kernels. Results never depend on it: a kernel compiles on first use
anyway, and a part that fails is ignored.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .config import StudyConfig

__all__ = ["KERNEL_PARTS", "compile_kernels", "warm_up_workers"]


#: The parts of :func:`compile_kernels`: the loading loop alone, and everything before it.
KERNEL_PARTS = ("loading", "surfaces")


def _warm_up_parameters(parameters: Mapping[str, Any]) -> dict[str, Any]:
    """``parameters`` on a tiny grid (same types, so the same compiled specialisations)."""
    return {**parameters, "n_points": 4000, "length": 4.0, "steps": 4}


def compile_kernels(job: tuple[str, Mapping[str, Any]]) -> None:
    """Compile (or load from numba's on-disk cache) one part of the kernels a realization runs.

    ``job`` is (part, parameters of the study). Part ``"loading"`` runs only the loading loop
    (eqs. 7–14) on a one-candidate geometry; part ``"surfaces"`` generates a tiny pair and
    flat, fits the splines, places the bodies and takes the roughness statistics, without the
    loading loop. Run in two workers at once (:meth:`LocalExecutor.warm_up`), the first run of
    a study compiles the two halves side by side (the loop is about half of the compile time)
    instead of every worker compiling everything; each worker then loads the other half from
    the cache. Results do not depend on it (a kernel compiles on first use anyway).
    """
    part, parameters = job
    params = _warm_up_parameters(parameters)
    if part == "loading":
        from ..contact import ContactGeometry, run_loading

        one = np.ones(1)
        geometry = ContactGeometry(
            point=np.zeros(1, dtype=np.int64),
            x=np.zeros(1),
            gap0=np.zeros(1),
            height_lower=np.zeros(1),
            curvature_lower=one.copy(),
            curvature_upper=one.copy(),
            m_x=np.zeros(1),
            m_z=one.copy(),
            n_x=np.zeros(1),
            n_z=one.copy(),
            first_step_index=np.ones(2, dtype=np.int64),
            displacement=np.array([0.0, 1e-3]),
            dx=1e-3,
            mean_gap0=0.0,
        )
        e_star = float(params.get("e_star") or 10.0)
        g_star = params.get("g_star")
        run_loading(
            geometry,
            e_star=e_star,
            g_star=e_star / 2.6 if g_star is None else float(g_star),
            mu0=float(params.get("mu0") or 0.0),
        )
    elif part == "surfaces":
        from ..contact import contact_geometry
        from ..contact.simulation import spline_fits
        from ..generate import GENERATOR_PARAMETERS, weierstrass_mandelbrot_pair
        from ..profile import surface_statistics

        gen = {k: params[k] for k in GENERATOR_PARAMETERS if k in params}
        lower, upper = weierstrass_mandelbrot_pair(
            float(params["dimension"]), seed=np.random.SeedSequence(0, spawn_key=(0,)), **gen
        )
        alpha, x0 = float(params.get("alpha") or 2.0), float(params.get("x0") or 1.0)
        for body in (upper, "flat"):
            fits = spline_fits(lower, body, alpha=alpha, x0=x0)
            contact_geometry(
                lower, body, steps=4, final_displacement=None, final_displacement_factor=0.2,
                alpha=alpha, x0=x0, fits=fits,
            )  # fmt: skip
            surface_statistics(
                lower,
                upper if body is upper else None,
                fits[0].slope,
                None if fits[1] is None else fits[1].slope,
            )


def warm_up_workers(executor: Any, config: StudyConfig) -> bool:
    """Share out the kernels' compilation between the pool's first two workers (see
    :func:`compile_kernels`), if ``executor`` is a local pool that has not started yet and the
    study runs the plain normal loading (no load path, no contact law, no interaction).

    Returns whether the warm-up was started (it runs in the background).
    """
    warm_up = getattr(executor, "warm_up", None)
    if warm_up is None:
        return False
    params = config.parameters_at(next(iter(config.grid_indices())))
    if any(params.get(name) not in (None, False) for name in ("path", "law", "interaction")):
        return False
    return bool(warm_up(compile_kernels, [(part, params) for part in KERNEL_PARTS]))
