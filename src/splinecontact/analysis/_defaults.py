"""Defaults of the analysis stage, in one place.

``_PARAMETER_DEFAULTS`` holds the model parameters an analysis may need when a study Dataset
neither sweeps them nor stores them as attributes (read by
:func:`splinecontact.analysis.parameter`); they are the package-wide defaults of those parameters.
The κ options are the defaults of :func:`splinecontact.analysis.kappa`, also used by the report
of ``splinecontact reproduce``.
"""

from __future__ import annotations

from typing import Any, Literal

#: Whose rms slope R_Sq enters κ (eq. 15): see :func:`splinecontact.analysis.kappa`.
RsqSource = Literal["auto", "gap", "lower", "upper"]
#: How R_Sq is computed: grid differences of the heights, or the spline slope f′.
RsqMethod = Literal["grid", "spline"]

#: Defaults of model parameters that may be neither swept nor stored as attributes: E* [GPa]
#: and the profile length L [µm]; also E* and μ0 [1] of
#: :func:`~splinecontact.analysis.friction_study`.
_PARAMETER_DEFAULTS: dict[str, Any] = {"e_star": 10.0, "length": 100.0, "mu0": 0.3}

#: Default upper end of the κ fit range, as a fraction of the final load [1].
DEFAULT_FIT_FRACTION: float = 0.3
#: Default source of R_Sq for κ.
DEFAULT_RSQ_SOURCE: RsqSource = "auto"
#: Default method of R_Sq for κ.
DEFAULT_RSQ_METHOD: RsqMethod = "grid"
