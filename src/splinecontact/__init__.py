"""splinecontact: contact mechanics of rough surfaces by spline assisted discretization.

Implements Hanaor, Gan & Einav, *Contact mechanics of fractal surfaces by spline assisted
discretisation*, Int. J. Solids Struct. 59 (2015) 121–131, with the corrections documented in
``docs/conventions.md``.

Units throughout: lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness
(1 GPa · 1 µm² = 1 mN).

The names of ``__all__`` are the core API. The documented modules ``analysis``, ``bem``,
``compare``, ``config``, ``generate``, ``io``, ``plotting``, ``preprocess``, ``reference``,
``reproduce``, ``results``, ``spectra`` and ``study`` are imported on first use, so
``splinecontact.study.run_study`` works after a plain ``import splinecontact``.
"""

from importlib import import_module
from types import ModuleType

from ._version import __version__
from .compare import compare_profiles
from .contact import simulate
from .errors import *  # noqa: F403
from .errors import __all__ as _errors_all
from .generate import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from .io import read_profile
from .profile import Profile
from .results import ContactRecord, SimulationResult
from .spheres import SurfaceSpheres, surface_spheres
from .spline import SplineFit, fit_spline

__all__ = [
    "ContactRecord",
    "Profile",
    "SimulationResult",
    "SplineFit",
    "SurfaceSpheres",
    "__version__",
    "compare_profiles",
    "fit_spline",
    "read_profile",
    "simulate",
    "surface_spheres",
    "weierstrass_mandelbrot",
    "weierstrass_mandelbrot_pair",
    *_errors_all,
]

# The documented public modules (besides the names of ``__all__``), imported on first use.
_SUBMODULES = (
    "analysis",
    "bem",
    "compare",
    "config",
    "generate",
    "io",
    "plotting",
    "preprocess",
    "reference",
    "reproduce",
    "results",
    "spectra",
    "study",
)


def __getattr__(name: str) -> ModuleType:
    if name in _SUBMODULES:
        return import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*__all__, *_SUBMODULES})
