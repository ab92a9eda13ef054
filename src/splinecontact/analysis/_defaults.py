"""Defaults of the analysis stage, in one place.

``_MODEL_DEFAULTS`` holds the package-wide defaults of the model parameters this stage needs:
those :func:`splinecontact.analysis.parameter` fills in when a study Dataset neither sweeps them
nor stores them as attributes (``_PARAMETER_DEFAULTS``), and those of
:func:`splinecontact.analysis.friction_study`.
The κ options are the defaults of :func:`splinecontact.analysis.kappa`, also used by the report
of ``splinecontact reproduce``.
"""

from __future__ import annotations

from typing import Any, Literal

from ..parameters import default

#: Whose rms slope R_Sq enters κ (eq. 15): see :func:`splinecontact.analysis.kappa`.
RsqSource = Literal["auto", "gap", "lower", "upper"]
#: How R_Sq is computed: grid differences of the heights, or the spline slope f′.
RsqMethod = Literal["grid", "spline"]

#: Package-wide defaults of the model parameters this stage uses: E* [GPa], the profile length
#: L [µm] and μ0 [1], read from :mod:`splinecontact.parameters`.
_MODEL_DEFAULTS: dict[str, Any] = {k: default(k) for k in ("e_star", "length", "mu0")}

#: Parameters :func:`splinecontact.analysis.parameter` fills in when a study Dataset neither
#: sweeps them nor stores them as attributes.
_PARAMETER_DEFAULTS: dict[str, Any] = {k: _MODEL_DEFAULTS[k] for k in ("e_star", "length")}

#: Default upper end of the κ fit range, as a fraction of the final load [1].
DEFAULT_FIT_FRACTION: float = 0.3
#: Default source of R_Sq for κ.
DEFAULT_RSQ_SOURCE: RsqSource = "auto"
#: Default method of R_Sq for κ.
DEFAULT_RSQ_METHOD: RsqMethod = "grid"
