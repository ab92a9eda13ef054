"""splinecontact: contact mechanics of rough surfaces by spline assisted discretization.

Implements Hanaor, Gan & Einav, *Contact mechanics of fractal surfaces by spline assisted
discretisation*, Int. J. Solids Struct. 59 (2015) 121–131, with the corrections documented in
``docs/conventions.md``.

Units throughout: lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness
(1 GPa · 1 µm² = 1 mN).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ._version import __version__
from .errors import *  # noqa: F403
from .errors import __all__ as _errors_all

if TYPE_CHECKING:
    from .contact import simulate as simulate
    from .generate import weierstrass_mandelbrot as weierstrass_mandelbrot
    from .generate import weierstrass_mandelbrot_pair as weierstrass_mandelbrot_pair
    from .loadpath import Segment as Segment
    from .profile import Profile as Profile
    from .results import ContactRecord as ContactRecord
    from .results import SimulationResult as SimulationResult
    from .spheres import SurfaceSpheres as SurfaceSpheres
    from .spheres import surface_spheres as surface_spheres
    from .spline import SplineFit as SplineFit
    from .spline import fit_spline as fit_spline

# The numerical modules (numba, numpy) are imported on first use, so that importing the package
# (and the command line's --help) is quick.
_LAZY: dict[str, str] = {
    "ContactRecord": "results",
    "Profile": "profile",
    "Segment": "loadpath",
    "SimulationResult": "results",
    "SplineFit": "spline",
    "SurfaceSpheres": "spheres",
    "fit_spline": "spline",
    "simulate": "contact",
    "surface_spheres": "spheres",
    "weierstrass_mandelbrot": "generate",
    "weierstrass_mandelbrot_pair": "generate",
}

__all__ = [*sorted(_LAZY), "__version__", *_errors_all]


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'splinecontact' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
