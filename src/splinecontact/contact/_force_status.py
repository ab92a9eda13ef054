"""How each step of a load path met its normal force: the ``force_control`` output.

A force-controlled step (``Segment(normal_force=F_N)``) solves δ_N so that F_N meets the target.
The free F_N(δ_N) jumps where eq. 9 accepts or drops a contact (or an adhesive law jumps in or
out), and the target can lie inside such a jump; both drivers (:mod:`.loadpath`, non-interacting;
:mod:`.interaction_slide`, interacting) then hold the step's contact set through the solve
(``docs/friction.md``, *Force control*). The code of every step says which outcome it is:

====  ===========================  ==============================================================
code  flag meaning                 the step
====  ===========================  ==============================================================
0     ``displacement_controlled``  δ_N prescribed; no force target
1     ``held_accepted_set``        F_N = target (to ``HOLD_RTOL``), and the contacts are the ones
                                   eq. 9 accepts at that δ_N: a state of the free model
2     ``held_fixed_set``           F_N = target (to ``HOLD_RTOL``) with a contact set held through
                                   the solve that eq. 9 would not accept as a whole at that δ_N:
                                   the target lies inside a jump of the free model
3     ``missed_inside_jump``       no δ_N (nor held set) carries the target: F_N jumps across it
                                   and the nearer side is kept, F_N ≠ target (the miss is
                                   ``normal_force − normal_force_target``)
====  ===========================  ==============================================================

A step whose relative miss |F_N − target|/target exceeds ``HOLD_RTOL`` is code 3 whatever its
solver reported, so codes 1 and 2 both promise F_N within ``HOLD_RTOL`` of the target.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import schema

__all__ = [
    "DISPLACEMENT",
    "HELD",
    "HELD_FIXED_SET",
    "HOLD_RTOL",
    "MISSED",
    "finish",
    "new_codes",
]

_MEANINGS = schema.VARIABLES["force_control"].flags  # the codes' one definition

#: Displacement-controlled step (no force target).
DISPLACEMENT = _MEANINGS.index("displacement_controlled")
#: F_N held with the contact set eq. 9 accepts at the solved δ_N (the free model's state).
HELD = _MEANINGS.index("held_accepted_set")
#: F_N held with a contact set eq. 9 would not accept as a whole at the solved δ_N.
HELD_FIXED_SET = _MEANINGS.index("held_fixed_set")
#: The target lies inside a jump of F_N(δ_N): the nearer side is kept, F_N ≠ target.
MISSED = _MEANINGS.index("missed_inside_jump")

#: Relative miss of F_N [1] above which a force-controlled step is code ``MISSED``.
HOLD_RTOL = 1e-6


def new_codes(total: int) -> NDArray[np.int8]:
    """Codes of ``total`` steps [1], all ``DISPLACEMENT`` until a driver sets them."""
    return np.zeros(total, dtype=np.int8)


def finish(
    codes: NDArray[np.int8],
    normal_force: NDArray[Any],
    target: NDArray[np.float64],
    *,
    cause: str,
    stacklevel: int,
) -> NDArray[np.int8]:
    """The ``force_control`` codes of a path, with the misses marked and warned about.

    Parameters
    ----------
    codes : ndarray of int8
        The codes the driver's solver reported (1, 2 or 3 on force-controlled steps).
    normal_force, target : ndarray
        F_N of every step and its target (NaN on displacement-controlled steps) [mN/µm].
    cause : str
        Why the driver can miss (the end of the warning's message).
    stacklevel : int
        ``stacklevel`` of the warning, counted from the caller of this function.

    Returns
    -------
    ndarray of int8
        0 where ``target`` is NaN; ``MISSED`` where the relative miss exceeds ``HOLD_RTOL``;
        otherwise the driver's code. A ``RuntimeWarning`` counts the ``MISSED`` steps.
    """
    held = np.isfinite(target)
    out = np.where(held, codes, DISPLACEMENT).astype(np.int8)
    miss = np.zeros(target.size)
    miss[held] = np.abs(normal_force[held] - target[held]) / target[held]
    out[held & ~(miss <= HOLD_RTOL)] = MISSED  # NaN or infinite F_N counts as missed too
    missed = out == MISSED
    if missed.any():
        warnings.warn(
            f"F_N could not be held at {int(missed.sum())} of {int(held.sum())} "
            f"force-controlled steps (largest relative miss {float(miss[missed].max()):.3g}; "
            f"force_control = {MISSED} marks them): {cause}; the nearer side was taken (see "
            "normal_force − normal_force_target)",
            RuntimeWarning,
            stacklevel=stacklevel + 1,
        )
    return out
