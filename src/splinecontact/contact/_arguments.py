"""The model arguments of a loading run: their checks and the parameter record of its result.

One home for what :func:`splinecontact.simulate` and the streamed runs
(:mod:`splinecontact.contact.streamed`) both check before anything is allocated, and for the
``parameters`` mapping both write into a :class:`~splinecontact.results.SimulationResult`.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._checks import check_integer
from ..errors import ParameterError
from .geometry import check_positive
from .laws import ContactLaw, Hertz, check_law

__all__ = [
    "MAX_STEPS",
    "ModelArguments",
    "check_model_arguments",
    "check_reserved",
    "run_parameters",
]

#: Default ceiling on ``steps`` [1] (10⁶; the paper uses 1000). Raise it with ``max_steps=``.
MAX_STEPS = 1_000_000


class ModelArguments(NamedTuple):
    """The checked arguments that a run uses in a normalised form (units as in ``simulate``)."""

    steps: int
    e_star: float
    g_star: float
    mu0: float
    law: ContactLaw


def check_model_arguments(
    *,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    e_star: float,
    g_star: float | None,
    mu0: float,
    alpha: float,
    x0: float,
    law: ContactLaw | None,
    max_steps: int = MAX_STEPS,
    raise_with: str = "",
) -> ModelArguments:
    """Check the model arguments of :func:`splinecontact.simulate` (units and ranges as there).

    ``steps`` [1] may be at most ``max_steps`` (``raise_with`` names the keyword that raises
    it, if the caller has one); G* defaults to E*/2.6 [GPa] and the law to
    :class:`~splinecontact.contact.laws.Hertz` (eq. 10), not yet bound.

    Raises
    ------
    ParameterError
        A value that is not a finite number of the right kind or out of its range.
    """
    steps = check_integer(
        "steps", steps, minimum=1, maximum=max_steps, note="paper: 1000", raise_with=raise_with
    )
    if final_displacement is not None:
        check_positive("final_displacement", final_displacement, " µm")
    check_positive("final_displacement_factor", final_displacement_factor, "")
    e_star = check_positive("e_star", e_star, " GPa")
    g_star = (
        e_star / 2.6
        if g_star is None
        else check_positive("g_star", g_star, " GPa", allow_zero=True)
    )
    mu0 = check_positive("mu0", mu0, "", allow_zero=True)
    check_positive("alpha", alpha, "")
    check_positive("x0", x0, " µm")
    return ModelArguments(steps, e_star, g_star, mu0, Hertz() if law is None else check_law(law))


def check_reserved(
    first_step_index: NDArray[np.int64], record_steps: NDArray[np.int64], maximum: int
) -> None:
    """Refuse ``record_steps`` that would reserve more than ``maximum`` contact slots [1].

    A step reserves a slot for every candidate whose gap has closed by then
    (``first_step_index`` counts them per step, :class:`~.geometry.ContactGeometry`).

    Raises
    ------
    ParameterError
        More than ``maximum`` slots.
    """
    if record_steps.size:
        reserved = int(first_step_index[record_steps].sum())
        if reserved > maximum:
            raise ParameterError(
                f"record_contacts would reserve {reserved} contact slots (points whose gap has "
                f"closed, summed over {record_steps.size} recorded steps), above "
                f"{maximum}; record fewer steps"
            )


def run_parameters(
    curves: dict[str, Any],
    *,
    flat: bool,
    steps: int,
    final_displacement_factor: float,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    dx: float,
    n_points: int,
    length: float,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """The ``parameters`` of a :class:`~splinecontact.results.SimulationResult`: the model
    parameters (and ``extra`` ones), the contact type and the grid (dx, length [µm]); r_min =
    dx/2 [µm] (eq. 6) and the final displacement [µm] from the curves."""
    return {
        "contact_type": "rough-on-flat" if flat else "rough-on-rough",
        "steps": steps,
        "final_displacement": float(curves["displacement"][-1]),
        "final_displacement_factor": float(final_displacement_factor),
        "e_star": e_star,
        "g_star": g_star,
        "mu0": mu0,
        "alpha": float(alpha),
        "x0": float(x0),
        "r_min": 0.5 * dx,
        "dx": dx,
        "n_points": n_points,
        "length": length,
        **(extra or {}),
    }
