"""Shared fixtures and analytic profile builders for the tests."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

ANGSTROM = 1e-4  # [µm]


def circle_cap(x: NDArray[np.float64], radius: float, centre: float = 0.0) -> NDArray[np.float64]:
    """Heights [µm] of a circular peak of the given radius [µm], apex 0 at ``centre``.

    Written as −s²/(R + √(R² − s²)) so that it stays exact for radii up to 1e12 µm.
    """
    s = x - centre
    return -(s * s) / (radius + np.sqrt(radius * radius - s * s))


def circle_cup(x: NDArray[np.float64], radius: float, centre: float = 0.0) -> NDArray[np.float64]:
    """Heights [µm] of a circular valley (cup) of the given radius [µm], bottom 0 at ``centre``."""
    return -circle_cap(x, radius, centre)


def pressed_interacting_driver() -> tuple[Any, float]:
    """The interacting path driver of a 1024-point rough pair (D = 1.5 on 1.3, 4 µm, seeds 3/8,
    μ0 = 0.3) pressed to half of δ_top = 0.2 × the summed peak-to-valley heights; (driver, δ_top
    [µm]). Shared by the force-control and the per-shift reuse tests."""
    from splinecontact import Segment, simulate
    from splinecontact.contact import InteractionSettings
    from splinecontact.contact.interaction_slide import _Driver
    from splinecontact.contact.simulation import spline_fits
    from splinecontact.generate import weierstrass_mandelbrot

    lower = weierstrass_mandelbrot(1.5, n_points=1024, length=4.0, seed=3)
    upper = weierstrass_mandelbrot(1.3, n_points=1024, length=4.0, seed=8)
    first = simulate(
        lower, upper, interaction=True, diagnostics=False, path=[Segment(normal=1e-3, steps=1)]
    )
    p = first.parameters
    fits = spline_fits(lower, upper, alpha=p["alpha"], x0=p["x0"])
    top = 0.2 * (lower.peak_to_valley + upper.peak_to_valley)
    driver = _Driver(
        lower, fits, InteractionSettings(), top, e_star=p["e_star"], g_star=p["g_star"], mu0=0.3
    )
    driver.evaluate(0.0, 0.0, True)
    driver.evaluate(0.0, 0.5 * top, True)
    return driver, top


def held_force_slide(
    lower: Any, upper: Any, top: float, **kwargs: Any
) -> tuple[Any, float, list[str]]:
    """A force-held slide of a rough pair: pressed to ``top`` [µm] in 3 steps, then F_N held at
    0.7 × that force for 2 steps and for 4 steps of 0.02 µm sliding (``kwargs`` to ``simulate``);
    (result, target [mN/µm], the messages of the "could not be held" RuntimeWarnings)."""
    import warnings

    from splinecontact import Segment, simulate

    loaded = simulate(lower, upper, path=[Segment(normal=top, steps=3)], **kwargs)
    target = 0.7 * float(loaded.normal_force[-1])
    path = [
        Segment(normal=top, steps=3),
        Segment(normal_force=target, steps=2),
        Segment(normal_force=target, tangential=0.02, steps=4),
    ]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        result = simulate(lower, upper, path=path, **kwargs)
    messages = [str(w.message) for w in caught if "could not be held" in str(w.message)]
    return result, target, messages


def pytest_configure(config: pytest.Config) -> None:
    """Before a parallel run of the whole default tier, compile the kernels once.

    Only in the pytest-xdist controller (not in its workers), only with more than one worker
    and only when no test selection was given (the README's test command): two processes
    (``tests/_warm_kernels.py``, one part each) fill numba's on-disk cache side by side, so the
    workers load the kernels instead of each compiling them. A part that fails changes nothing
    but the time: the kernels then compile on first use, as always.
    """
    if hasattr(config, "workerinput") or not config.pluginmanager.hasplugin("xdist"):
        return
    if config.getoption("numprocesses", default=None) in (None, 0, "0"):
        return
    if config.args_source != pytest.Config.ArgsSource.TESTPATHS:
        return
    script = Path(__file__).with_name("_warm_kernels.py")
    parts = [
        subprocess.Popen([sys.executable, str(script), part], stdout=subprocess.DEVNULL)
        for part in ("contact", "paths")
    ]
    for part in parts:
        part.wait()
