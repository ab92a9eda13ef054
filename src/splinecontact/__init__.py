"""splinecontact: contact mechanics of rough surfaces by spline assisted discretization.

Implements Hanaor, Gan & Einav, *Contact mechanics of fractal surfaces by spline assisted
discretisation*, Int. J. Solids Struct. 59 (2015) 121–131, with the corrections documented in
``docs/conventions.md``.

Units throughout: lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness
(1 GPa · 1 µm² = 1 mN).

The names of ``__all__`` are the core API. The documented modules ``analysis``, ``bem``,
``compare``, ``contact``, ``diagnostics``, ``generate``, ``io``, ``outputs``,
``parameters``, ``plotting``, ``preprocess``, ``reference``, ``reproduce``, ``results``, ``schema``,
``spectra`` and ``study`` are imported on first use, so
``splinecontact.study.run_study`` works after a plain ``import splinecontact``.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from ._version import __version__
from .errors import *  # noqa: F403
from .errors import __all__ as _errors_all

if TYPE_CHECKING:
    from .compare import compare_profiles as compare_profiles
    from .contact import Segment as Segment
    from .contact import simulate as simulate
    from .generate import weierstrass_mandelbrot as weierstrass_mandelbrot
    from .generate import weierstrass_mandelbrot_pair as weierstrass_mandelbrot_pair
    from .io import read_profile as read_profile
    from .profile import Profile as Profile
    from .results import ContactRecord as ContactRecord
    from .results import SimulationResult as SimulationResult
    from .spheres import SurfaceSpheres as SurfaceSpheres
    from .spheres import surface_spheres as surface_spheres
    from .spline import SplineFit as SplineFit
    from .spline import fit_spline as fit_spline

# The core API, imported on first use (numba, numpy, scipy load only when needed, so that
# importing the package and the command line's --help are quick): name -> defining module.
_LAZY: dict[str, str] = {
    "ContactRecord": "results",
    "Profile": "profile",
    "Segment": "contact",
    "SimulationResult": "results",
    "SplineFit": "spline",
    "SurfaceSpheres": "spheres",
    "compare_profiles": "compare",
    "fit_spline": "spline",
    "read_profile": "io",
    "simulate": "contact",
    "surface_spheres": "spheres",
    "weierstrass_mandelbrot": "generate",
    "weierstrass_mandelbrot_pair": "generate",
}

__all__ = [*sorted(_LAZY), "__version__", *_errors_all]

# The documented public modules (besides the names of ``__all__``), imported on first use.
_SUBMODULES = (
    "analysis",
    "bem",
    "compare",
    "contact",
    "diagnostics",
    "generate",
    "io",
    "outputs",
    "parameters",
    "plotting",
    "preprocess",
    "reference",
    "reproduce",
    "results",
    "schema",
    "spectra",
    "study",
)


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is not None:
        value = getattr(import_module(f".{module}", __name__), name)
        globals()[name] = value
        return value
    if name in _SUBMODULES:
        return import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*__all__, *_SUBMODULES})
