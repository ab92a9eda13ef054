"""Laws-study files: the ensemble of :func:`~splinecontact.analysis.laws_study` in TOML.

A laws-study file runs the same load–unload cycle over an ensemble of rough pairs under one or
more local contact laws (``docs/contact-laws.md``), e.g.::

    [laws_study]
    dimensions = [1.2, 1.5, 1.8]    # fractal dimensions D [1] (eq. 1), required
    seeds = [1, 2, 3, 4, 5]         # one realization per seed, required
    contact_type = "rough-on-flat"  # or "rough-on-rough"
    n_points = 20_000               # grid points [1]
    length = 2.0                    # profile length [µm]
    load_fraction = 0.1             # δ_max / peak-to-valley height [1]
    steps = 150                     # steps of the loading and of the unloading [1]
    e_star = 10.0                   # E* [GPa]
    fit_fraction = 0.3              # load range of the κ fit [1]
    confidence = 0.95               # level of the confidence band of the mean [1]

    [[law]]                         # one table per law (default: one Hertz law)
    name = "hertz"
    [[law]]
    name = "jkr"
    work_of_adhesion = 0.1          # [J/m²]; also cohesive_stress, yield_strength, hardness
    label = "JKR, w = 0.1 J/m²"     # optional legend label (default: the law's name)

Everything but ``dimensions`` and ``seeds`` has the default shown. :func:`load_laws_study`
checks the whole file before anything runs; every mistake is one
:class:`~splinecontact.errors.StudyConfigError` naming the key, the value and what to give.
:func:`run_laws_study` runs it (silent; a progress callback) and returns one dataset with a
``law`` dimension.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import xarray as xr

from ..errors import ContactLawError, StudyConfigError
from ._defaults import _MODEL_DEFAULTS

__all__ = ["LawsStudySpec", "load_laws_study", "parse_laws_study", "run_laws_study"]

_CONTACT_TYPES = ("rough-on-flat", "rough-on-rough")
_KEYS = {
    "dimensions", "seeds", "contact_type", "n_points", "length", "load_fraction", "steps",
    "e_star", "fit_fraction", "confidence",
}  # fmt: skip


@dataclass(frozen=True)
class LawsStudySpec:
    """A checked laws-study file (see the module documentation for the keys and units).

    Attributes
    ----------
    dimensions : tuple of float
        Fractal dimensions D [1].
    seeds : tuple of int
        One realization per seed [1].
    flat : bool
        Rough-on-flat (else rough-on-rough).
    n_points : int
        Grid points [1].
    length : float
        Profile length [µm].
    load_fraction : float
        δ_max as a fraction of the lower peak-to-valley height [1].
    steps : int
        Steps of the loading and of the unloading [1].
    e_star : float
        E* [GPa].
    fit_fraction, confidence : float
        κ fit range and confidence level [1].
    laws : tuple of (str, str, dict)
        (label, law name, parameters as :func:`splinecontact.contact.make_law` takes them).
    """

    dimensions: tuple[float, ...]
    seeds: tuple[int, ...]
    flat: bool = True
    n_points: int = 20_000
    length: float = 2.0
    load_fraction: float = 0.1
    steps: int = 150
    e_star: float = _MODEL_DEFAULTS["e_star"]
    fit_fraction: float = 0.3
    confidence: float = 0.95
    laws: tuple[tuple[str, str, dict[str, Any]], ...] = (("hertz", "hertz", {}),)

    @property
    def realizations(self) -> int:
        """Runs per law: dimensions × seeds [1]."""
        return len(self.dimensions) * len(self.seeds)


#: The default of every key a file may omit: the :class:`LawsStudySpec` field defaults.
_DEFAULTS: dict[str, Any] = {f.name: f.default for f in fields(LawsStudySpec)}


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _is_dimension(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and 1.0 <= value <= 2.0


def _number(
    table: Mapping[str, Any],
    key: str,
    *,
    integer: bool = False,
    low: float = -math.inf,
    high: float = math.inf,
    low_open: bool = False,
    high_open: bool = False,
) -> Any:
    where = f"laws_study.{key}"
    value = table.get(key, _DEFAULTS[key])
    if integer and (not isinstance(value, int) or isinstance(value, bool)):
        raise StudyConfigError(f"{where} = {value!r}: must be a whole number")
    if not _is_number(value) or not math.isfinite(value):
        raise StudyConfigError(f"{where} = {value!r}: must be a finite number")
    below = value <= low if low_open else value < low
    above = value >= high if high_open else value > high
    if below or above:
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        raise StudyConfigError(f"{where} = {value!r}: must lie in {left}{low:g}, {high:g}{right}")
    return int(value) if integer else float(value)


def _list(table: Mapping[str, Any], key: str, check: Callable[[object], bool], what: str) -> list:
    where = f"laws_study.{key}"
    if key not in table:
        raise StudyConfigError(f"{where} is missing: give a list of {what}")
    values = table[key]
    if not isinstance(values, list) or not values:
        raise StudyConfigError(f"{where} = {values!r}: must be a non-empty list of {what}")
    for i, value in enumerate(values):
        if not check(value):
            raise StudyConfigError(f"{where}[{i}] = {value!r}: must be {what}")
    return values


def _law(index: int, table: object) -> tuple[str, str, dict[str, Any]]:
    from ..contact import make_law

    where = f"law[{index}]"
    if not isinstance(table, dict):
        raise StudyConfigError(f"{where} = {table!r}: must be a table with name = ...")
    entries = dict(table)
    name = entries.pop("name", None)
    if not isinstance(name, str):
        raise StudyConfigError(f'{where}.name = {name!r}: give the law\'s name, e.g. "jkr"')
    label = entries.pop("label", None)
    if label is not None and (not isinstance(label, str) or not label.strip()):
        raise StudyConfigError(f"{where}.label = {label!r}: must be a non-empty string")
    try:
        law = make_law(name, **entries)
    except ContactLawError as error:
        raise StudyConfigError(f"{where}: {error}") from None
    return (label or law.name), law.name, entries


def parse_laws_study(data: Mapping[str, Any]) -> LawsStudySpec:
    """Check a laws-study mapping (a parsed TOML file) and return its :class:`LawsStudySpec`.

    Raises
    ------
    StudyConfigError
        An unknown key, a missing or wrong value, or a bad law (the message names the key).
    """
    unknown = sorted(set(data) - {"laws_study", "law"})
    if unknown:
        raise StudyConfigError(
            f"unknown section {unknown[0]!r}: a laws-study file has [laws_study] and [[law]]"
        )
    table = data.get("laws_study")
    if not isinstance(table, dict):
        raise StudyConfigError("[laws_study] is missing: give dimensions = [...], seeds = [...]")
    extra = sorted(set(table) - _KEYS)
    if extra:
        raise StudyConfigError(
            f"laws_study.{extra[0]} is not a key of [laws_study]; known: {', '.join(sorted(_KEYS))}"
        )
    dims = _list(table, "dimensions", _is_dimension, "numbers in [1, 2]")
    seeds = _list(
        table, "seeds", lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 0,
        "whole numbers ≥ 0",
    )  # fmt: skip
    contact_type = table.get("contact_type", "rough-on-flat")
    if contact_type not in _CONTACT_TYPES:
        raise StudyConfigError(
            f"laws_study.contact_type = {contact_type!r}: must be "
            f"{' or '.join(map(repr, _CONTACT_TYPES))}"
        )
    laws_table = data.get("law", [{"name": "hertz"}])
    if not isinstance(laws_table, list) or not laws_table:
        raise StudyConfigError("law must be one or more [[law]] tables, each with name = ...")
    laws = [_law(i, t) for i, t in enumerate(laws_table)]
    labels = [label for label, _, _ in laws]
    for label in labels:
        if labels.count(label) > 1:
            raise StudyConfigError(
                f"two [[law]] tables are labelled {label!r}: give each a distinct label = ..."
            )
    return LawsStudySpec(
        dimensions=tuple(float(d) for d in dims),
        seeds=tuple(int(s) for s in seeds),
        flat=contact_type == "rough-on-flat",
        n_points=_number(table, "n_points", integer=True, low=8, high=10**8),
        length=_number(table, "length", low=0.0, low_open=True, high=1e50),
        load_fraction=_number(table, "load_fraction", low=0.0, low_open=True, high=1.0),
        steps=_number(table, "steps", integer=True, low=3, high=10**7),
        e_star=_number(table, "e_star", low=0.0, low_open=True, high=1e50),
        fit_fraction=_number(table, "fit_fraction", low=0.0, low_open=True, high=1.0),
        confidence=_number(table, "confidence", low=0.0, high=1.0, low_open=True, high_open=True),
        laws=tuple(laws),
    )


def load_laws_study(path: str | Path) -> LawsStudySpec:
    """Read and check the laws-study file ``path`` (TOML).

    Raises
    ------
    StudyConfigError
        The file cannot be read, is not TOML, or is invalid (one line naming the key).
    """
    file = Path(path)
    try:
        text = file.read_bytes().decode("utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise StudyConfigError(f"cannot read the laws-study file {file}: {error}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise StudyConfigError(f"{file} is not valid TOML: {error}") from None
    except RecursionError:
        raise StudyConfigError(
            f"{file} is not a laws-study file (arrays or tables nested too deeply)"
        ) from None
    return parse_laws_study(data)


def run_laws_study(
    spec: LawsStudySpec, progress: Callable[[str, int, int], None] | None = None
) -> xr.Dataset:
    """Run ``spec``: :func:`~splinecontact.analysis.laws_study` once per law.

    Parameters
    ----------
    spec : LawsStudySpec
        From :func:`load_laws_study` or :func:`parse_laws_study`.
    progress : callable, optional
        ``progress(label, done, total)`` after each realization of the law ``label`` [1].

    Returns
    -------
    xarray.Dataset
        The variables of ``laws_study`` (units in their attributes) on (law, dimension,
        realization) and their ``_mean``/``_ci`` on (law, dimension); the attributes record
        each law's name and parameters (``law_<i>`` and ``law_<i>_<parameter>``, by position).
    """
    from ..contact import make_law
    from .laws_study import laws_study

    parts = []
    attrs: dict[str, Any] = {}
    for i, (label, name, parameters) in enumerate(spec.laws):

        def step(done: int, total: int, label: str = label) -> None:
            if progress is not None:
                progress(label, done, total)

        ds = laws_study(
            spec.dimensions, spec.seeds, law=make_law(name, **parameters), flat=spec.flat,
            n_points=spec.n_points, length=spec.length, load_fraction=spec.load_fraction,
            steps=spec.steps, e_star=spec.e_star, fit_fraction=spec.fit_fraction,
            confidence=spec.confidence, progress=step,
        )  # fmt: skip
        attrs = {**ds.attrs, **attrs}
        attrs[f"law_{i}"] = name
        attrs.update({f"law_{i}_{k}": v for k, v in parameters.items()})
        parts.append(ds)
    attrs.pop("law", None)
    attrs["work_of_adhesion_unit"] = "J/m²"
    # "override": the variables keep their units (the same for every law)
    combined = xr.concat(parts, dim="law", combine_attrs="override")
    combined = combined.assign_coords(law=[label for label, _, _ in spec.laws])
    combined.attrs = attrs
    return combined
