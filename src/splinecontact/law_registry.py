"""Contact laws by name, as study files and the command line select them."""

from __future__ import annotations

import dataclasses
from typing import Any

from .adhesion import DMT, JKR, MaugisDugdale
from .errors import ContactLawError, UnknownContactLawError
from .plasticity import ElasticPlastic

__all__ = ["LAWS", "make_law"]

#: Law name → class (``"hertz"`` is the package's default Hertz law, handled by the caller).
LAWS: dict[str, Any] = {
    JKR.name: JKR,
    DMT.name: DMT,
    MaugisDugdale.name: MaugisDugdale,
    ElasticPlastic.name: ElasticPlastic,
}


def make_law(name: str, **parameters: Any) -> Any:
    """The validated law called ``name`` with ``parameters`` (see each law for their units).

    Raises
    ------
    UnknownContactLawError
        ``name`` is not a known law.
    ContactLawError
        A parameter the law does not have, or an invalid value (a specific subclass).
    """
    cls = LAWS.get(str(name).strip().lower()) if isinstance(name, str) else None
    if cls is None:
        known = ", ".join(["hertz", *sorted(LAWS)])
        raise UnknownContactLawError(f"contact law {name!r} does not exist; choose one of {known}")
    fields = {f.name for f in dataclasses.fields(cls)} - {"reach_bound"}
    unknown = sorted(set(parameters) - fields)
    if unknown:
        raise ContactLawError(
            f"the {name} law has no parameter {', '.join(unknown)}; its parameters are "
            f"{', '.join(sorted(fields))}"
        )
    law = cls(**parameters)
    law.validate()
    return law
