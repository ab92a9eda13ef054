"""splinecontact: contact mechanics of rough surfaces by spline assisted discretization.

Implements Hanaor, Gan & Einav, *Contact mechanics of fractal surfaces by spline assisted
discretisation*, Int. J. Solids Struct. 59 (2015) 121–131, with the corrections documented in
``docs/conventions.md``.

Units throughout: lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness
(1 GPa · 1 µm² = 1 mN).
"""

from __future__ import annotations

from ._version import __version__
from .contact import simulate
from .errors import *  # noqa: F403
from .errors import __all__ as _errors_all
from .generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from .loadpath import Segment
from .profile import Profile
from .results import ContactRecord, SimulationResult
from .spheres import SurfaceSpheres, surface_spheres
from .spline import SplineFit, fit_spline

__all__ = [
    "ContactRecord",
    "Profile",
    "Segment",
    "SimulationResult",
    "SplineFit",
    "SurfaceSpheres",
    "fit_spline",
    "simulate",
    "surface_spheres",
    "weierstrass_mandelbrot",
    "weierstrass_mandelbrot_pair",
    "__version__",
    *_errors_all,
]
