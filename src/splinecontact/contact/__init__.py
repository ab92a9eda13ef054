"""The contact stage: geometry, local contact laws, loading kernels, load paths, ``simulate``.

* :mod:`.geometry` — body placement, candidate ordering, the two-sphere contact (eqs. 7–10);
* :mod:`.laws` — the local contact laws behind one interface (Hertz, eq. 10; eqs. 11–13);
* :mod:`.kernel` — the monotone normal loading loop;
* :mod:`.segments`, :mod:`.path_kernel`, :mod:`.loadpath` — load paths (their description, the
  compiled step and the driver: normal and tangential, force control);
* :mod:`.interaction` — accepted contacts coupled through the elastic half-plane
  (``simulate(..., interaction=True)``);
* :mod:`.simulation` — :func:`simulate` and its argument checks.
"""

from __future__ import annotations

from ..errors import ForceControlError, LoadPathError
from .adhesion import DMT, JKR
from .geometry import ContactGeometry, contact_geometry
from .interaction import InteractionSettings
from .kernel import LoadingRun, run_loading
from .laws import LAWS, ContactLaw, Hertz, make_law
from .loadpath import run_path, simulate_path
from .maugis_dugdale import MaugisDugdale
from .plasticity import ElasticPlastic
from .segments import Segment, parse_path, validate_path
from .simulation import MAX_RECORDED_CONTACTS, MAX_STEPS, SIMULATION_PARAMETERS, simulate

__all__ = [
    "DMT",
    "JKR",
    "LAWS",
    "MAX_RECORDED_CONTACTS",
    "MAX_STEPS",
    "SIMULATION_PARAMETERS",
    "ContactGeometry",
    "ContactLaw",
    "ElasticPlastic",
    "ForceControlError",
    "Hertz",
    "InteractionSettings",
    "LoadPathError",
    "LoadingRun",
    "MaugisDugdale",
    "Segment",
    "contact_geometry",
    "make_law",
    "parse_path",
    "run_loading",
    "run_path",
    "simulate",
    "simulate_path",
    "validate_path",
]
