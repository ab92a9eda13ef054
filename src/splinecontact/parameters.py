"""The model parameters of splinecontact: one registry of names, defaults, units and ranges.

Every parameter that describes a simulation — the profile generator of eq. 1, the spline of
eqs. 2–3, the contact laws of eqs. 10–13, the loading — is declared here once, with

* its default (the value the functions, the command line and the study files use when it is not
  given; :data:`REQUIRED` for the fractal dimension, which has none, and ``None`` where the
  engine derives the value, e.g. G* = E*/2.6),
* its unit (``"1"`` dimensionless, ``""`` for words),
* its range (bounds, or the allowed words),
* its meaning, with the paper's equation.

The function signatures (:func:`splinecontact.simulate`,
:func:`splinecontact.weierstrass_mandelbrot`), the command-line options and the study files are
held to this registry by a contract test, and the study files build their validation from it.
This module imports only :mod:`splinecontact.errors`.

Examples
--------
>>> from splinecontact.parameters import PARAMETERS, default
>>> default("e_star")
10.0
>>> PARAMETERS["e_star"].unit
'GPa'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Final

from .errors import ParameterError

__all__ = [
    "CONTACT",
    "GENERATOR",
    "PARAMETERS",
    "REQUIRED",
    "STUDY",
    "Parameter",
    "default",
]


class _Required:
    """Marker of a parameter without a default (it must be given)."""

    _instance: _Required | None = None

    def __new__(cls) -> _Required:
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "REQUIRED"

    def __reduce__(self) -> str:
        return "REQUIRED"


#: The default of a parameter that has none (it must be given).
REQUIRED: Final = _Required()

#: Group of the keywords of :func:`splinecontact.weierstrass_mandelbrot` (eq. 1).
GENERATOR: Final = "generator"
#: Group of the keywords of :func:`splinecontact.simulate` (eqs. 2–14).
CONTACT: Final = "contact"
#: Group of the choices of a study (which bodies are pressed together).
STUDY: Final = "study"


@dataclass(frozen=True)
class Parameter:
    """One model parameter.

    Attributes
    ----------
    name : str
        Keyword name (the same in the functions, the study files and, with ``-`` for ``_``,
        on the command line).
    kind : type
        ``float``, ``int`` or ``str`` (one value).
    default : object
        The default value; :data:`REQUIRED` if there is none; ``None`` if the engine derives it
        (the description says how).
    unit : str
        Unit of the value [µm, GPa, mN/µm]; ``"1"`` dimensionless, ``""`` for words.
    description : str
        Meaning, with the paper's equation.
    group : str
        :data:`GENERATOR`, :data:`CONTACT` or :data:`STUDY`: who consumes it.
    gt, ge, lt, le : float or int, optional
        Bounds of the value (strict: ``gt``, ``lt``; inclusive: ``ge``, ``le``).
    choices : tuple of str, optional
        The allowed words of a ``str`` parameter.
    optional : bool
        ``None`` is a valid value (the engine derives it).
    """

    name: str
    kind: type
    default: Any
    unit: str
    description: str
    group: str
    gt: float | int | None = None
    ge: float | int | None = None
    lt: float | int | None = None
    le: float | int | None = None
    choices: tuple[str, ...] | None = None
    optional: bool = False

    @property
    def required(self) -> bool:
        """The parameter has no default and must be given."""
        return self.default is REQUIRED

    @property
    def bounds(self) -> dict[str, Any]:
        """The bounds that are set, by keyword (``gt``, ``ge``, ``lt``, ``le``)."""
        return {
            key: value
            for key in ("gt", "ge", "lt", "le")
            if (value := getattr(self, key)) is not None
        }


#: Largest length the engine accepts [µm] (lengths are refused above it, before a run).
MAX_LENGTH: Final = 1e50


def _length(name: str, default: Any, description: str, group: str, **kw: Any) -> Parameter:
    return Parameter(name, float, default, "µm", description, group, gt=0.0, le=MAX_LENGTH, **kw)


_ALL = (
    Parameter(
        "dimension",
        float,
        REQUIRED,
        "1",
        "fractal dimension D (eq. 1); required",
        GENERATOR,
        ge=1.0,
        le=2.0,
    ),
    Parameter(
        "contact_type",
        str,
        "rough-on-rough",
        "",
        "two rough profiles, or one rough profile against a rigid flat",
        STUDY,
        choices=("rough-on-rough", "rough-on-flat"),
    ),
    Parameter("alpha", float, 2.0, "1", "spline tightness exponent α (eq. 3)", CONTACT, gt=0.0),
    _length("x0", 1.0, "spline unit length x0 (eqs. 2–3)", CONTACT),
    Parameter("e_star", float, 10.0, "GPa", "effective modulus E* (eq. 10)", CONTACT, gt=0.0),
    Parameter(
        "g_star",
        float,
        None,
        "GPa",
        "effective shear modulus G* (eq. 11); default E*/2.6",
        CONTACT,
        gt=0.0,
        optional=True,
    ),
    Parameter("mu0", float, 0.3, "1", "friction coefficient μ0 (eq. 13)", CONTACT, ge=0.0),
    Parameter("steps", int, 1000, "1", "displacement increments", CONTACT, ge=1),
    _length(
        "final_displacement",
        None,
        "final displacement δ_N; default final_displacement_factor × amplitude",
        CONTACT,
        optional=True,
    ),
    Parameter(
        "final_displacement_factor",
        float,
        0.2,
        "1",
        "final displacement as a fraction of the lower profile's amplitude",
        CONTACT,
        gt=0.0,
    ),
    Parameter("n_points", int, 1_000_000, "1", "grid points", GENERATOR, ge=8),
    _length("length", 100.0, "profile length L (eq. 1)", GENERATOR),
    _length("wavelength", 1.0, "longest wavelength parameter (eq. 1)", GENERATOR),
    Parameter("gamma", float, 1.5, "1", "frequency density γ (eq. 1)", GENERATOR, gt=1.0),
    Parameter("directions", int, 20, "1", "number of ridge directions M (eq. 1)", GENERATOR, ge=1),
    Parameter("n_max", int, 20, "1", "highest frequency index (eq. 1)", GENERATOR, ge=0),
    _length("ra", 0.005, "mean roughness R_A the heights are scaled to", GENERATOR),
    Parameter(
        "amplitude_law",
        str,
        "hurst",
        "",
        "amplitude law of eq. 1: γ^{n(D−2)} (hurst) or γ^{2n(D−2)} (as printed)",
        GENERATOR,
        choices=("hurst", "as_printed"),
    ),
)

#: Every model parameter, by name (the order is the study schema's).
PARAMETERS: Final[dict[str, Parameter]] = {p.name: p for p in _ALL}


def default(name: str) -> Any:
    """The default value of parameter ``name`` (``None``: derived by the engine).

    Raises
    ------
    ParameterError
        ``name`` is not a model parameter, or it has no default (:data:`REQUIRED`).
    """
    parameter = PARAMETERS.get(name)
    if parameter is None:
        raise ParameterError(f"{name!r} is not a model parameter; known: {', '.join(PARAMETERS)}")
    if parameter.required:
        raise ParameterError(f"parameter {name!r} has no default; it must be given")
    return parameter.default
