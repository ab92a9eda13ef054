"""Analyses of study results: the quantities of the paper's Section 3, and friction.

Every function here is pure: it takes the study :class:`xarray.Dataset` (or arrays) and returns
new xarray objects whose variables carry a ``units`` attribute.

The study Dataset
-----------------
Dimensions: one per swept parameter, named by the parameter (``dimension``, ``contact_type``,
``alpha``, ...; the *grid dimensions*), then ``realization`` and ``step``. Data variables: every
name of :data:`splinecontact.results.STEP_VARIABLES` on (grid…, realization, step), every name of
:data:`splinecontact.results.SCALAR_VARIABLES` on (grid…, realization), and ``status`` on
(grid…, realization) with 0 = not run, 1 = ok, 2 = failed. Only realizations with ``status == 1``
enter any analysis. Fixed parameters are dataset attributes under their own names
(``e_star`` [GPa], ``length`` [µm], ...); a swept parameter is a coordinate instead.

Conventions (see ``docs/analysis.md`` for the reasoning)
--------------------------------------------------------
* **Common abscissa.** Realizations end at different displacements (the final displacement is a
  multiple of each lower profile's peak-to-valley height) and different forces. Before averaging,
  each realization is interpolated linearly onto a common abscissa that runs, per grid point, from
  0 to the *smallest* end value among that grid point's realizations, so that every realization
  contributes at every sample (no extrapolation, no survivor bias near the end). The abscissa is
  therefore a coordinate on (grid…, sample).
* **Force as abscissa.** F_N(δ_N) has plateaus (no new contact in a step) and, rough-on-rough, can
  step down where an accepted contact is rejected (``docs/conventions.md``). Only the steps at
  which F_N exceeds every earlier value are used as interpolation nodes (the first time each load
  is reached), so every load has one value.
* **Ensemble statistics.** Mean, sample standard deviation (ddof = 1) and the two-sided confidence
  interval of the mean from Student's t with n − 1 degrees of freedom (95 % by default).
* **Stiffness.** k = dF_N/dδ_N by a Savitzky–Golay derivative (local least-squares quadratic over a
  sliding window of ``window`` steps on the uniform displacement grid of each realization). See
  :func:`stiffness`. The paper's Fig. 11a shows the stiffness of the *ensemble-mean* curve
  instead (:func:`mean_curve_stiffness`); the two estimators can disagree on trends with D.
* **κ (eq. 15).** κ = R_Sq · E* · s with s the least-squares slope through the origin of A_S against
  F_N over F_N ≤ ``fit_fraction`` × the realization's final load. See :func:`kappa`.

Modules
-------
* :mod:`~splinecontact.analysis.ensemble` — dataset helpers, the common abscissa, ensemble
  means, standard deviations and confidence bands.
* :mod:`~splinecontact.analysis.stiffness` — k = dF_N/dδ_N per realization and of the
  ensemble-mean curve.
* :mod:`~splinecontact.analysis.area_load` — κ (eq. 15) and the power law of A_S(F_N).
* :mod:`~splinecontact.analysis.hurst` — nominal and measured Hurst exponents.
* :mod:`~splinecontact.analysis.method` — diagnostics of the method (the split of F_N, eq. 14).
* :mod:`~splinecontact.analysis.friction` — μ_s, k_T, k_N, Mindlin's ratio, dissipation and
  dilatancy of a load-path result; :mod:`~splinecontact.analysis.friction_study` runs them over
  an ensemble against D.
* :mod:`~splinecontact.analysis.laws` — pull-off force, work of separation, residual approach
  and the energy of a load–unload cycle under an adhesive or elastic–plastic contact law;
  :mod:`~splinecontact.analysis.laws_study` runs them, and κ of an adhesive pair, over an
  ensemble against D.

The statistical tests of the report of ``splinecontact reproduce`` (trend tests, bootstrap) are
in :mod:`splinecontact.reproduce.statistics`.
"""

from __future__ import annotations

from ..errors import AnalysisError, FrictionAnalysisError
from .area_load import (
    BUSH_KAPPA,
    PERSSON_KAPPA,
    kappa,
    kappa_alternatives,
    linear_fit_through_origin,
    power_law_exponent,
)
from .ensemble import (
    confidence_halfwidth,
    ensemble_statistics,
    ensemble_vs_displacement,
    ensemble_vs_force,
    grid_dims,
    interpolate_realizations,
    ok_mask,
    parameter,
    values_at,
)
from .friction import (
    InterfaceStiffness,
    StaticFriction,
    dilatancy,
    dissipated_energy,
    driver_work,
    force_control_counts,
    interface_stiffness,
    mindlin_stiffness_ratio,
    normal_stiffness,
    segment_steps,
    spring_slider_stiffness_ratio,
    static_friction,
    tangential_stiffness,
)
from .friction_study import FRICTION_STUDY_VARIABLES, friction_study
from .hurst import measured_hurst, nominal_hurst, study_hurst
from .laws_study import LAWS_STUDY_VARIABLES, adhesive_kappa, laws_study
from .method import force_split
from .stiffness import dimensionless_stiffness, mean_curve_stiffness, stiffness

__all__ = [
    "BUSH_KAPPA",
    "FRICTION_STUDY_VARIABLES",
    "LAWS_STUDY_VARIABLES",
    "PERSSON_KAPPA",
    "AnalysisError",
    "FrictionAnalysisError",
    "InterfaceStiffness",
    "StaticFriction",
    "adhesive_kappa",
    "confidence_halfwidth",
    "dilatancy",
    "dimensionless_stiffness",
    "dissipated_energy",
    "driver_work",
    "ensemble_statistics",
    "ensemble_vs_displacement",
    "ensemble_vs_force",
    "force_control_counts",
    "force_split",
    "friction_study",
    "grid_dims",
    "interface_stiffness",
    "interpolate_realizations",
    "kappa",
    "kappa_alternatives",
    "laws_study",
    "linear_fit_through_origin",
    "mean_curve_stiffness",
    "measured_hurst",
    "mindlin_stiffness_ratio",
    "nominal_hurst",
    "normal_stiffness",
    "ok_mask",
    "parameter",
    "power_law_exponent",
    "segment_steps",
    "spring_slider_stiffness_ratio",
    "static_friction",
    "stiffness",
    "study_hurst",
    "tangential_stiffness",
    "values_at",
]
