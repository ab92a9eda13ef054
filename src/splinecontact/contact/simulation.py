"""``simulate``: the public entry point of the contact stage and its argument checks."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from .._checks import check_integer
from ..errors import ParameterError
from ..profile import Profile, surface_statistics
from ..results import ContactRecord, SimulationResult
from ..spline import SplineFit, fit_spline_pair
from ._arguments import MAX_STEPS, check_model_arguments, check_reserved, run_parameters
from .geometry import check_bodies, contact_geometry
from .interaction import InteractionSettings
from .kernel import run_loading
from .laws import ContactLaw, Hertz, bind_law, convex_samples, law_record
from .streamed import STREAM_MIN_POINTS

if TYPE_CHECKING:
    from .segments import Segment

__all__ = ["MAX_RECORDED_CONTACTS", "MAX_STEPS", "SIMULATION_PARAMETERS", "simulate"]

#: Keyword parameters of :func:`simulate` that describe the model (not ``record_contacts``).
SIMULATION_PARAMETERS = (
    "steps",
    "final_displacement",
    "final_displacement_factor",
    "e_star",
    "g_star",
    "mu0",
    "alpha",
    "x0",
)

#: Most contact slots ``record_contacts`` may reserve (points whose gap has closed, summed over
#: the recorded steps) [1]: 2·10⁷ slots are 1.6 GB.
MAX_RECORDED_CONTACTS = 20_000_000


def _record_steps(record_contacts: Iterable[int] | str | None, steps: int) -> NDArray[np.int64]:
    if record_contacts is None:
        return np.zeros(0, dtype=np.int64)
    if isinstance(record_contacts, str):
        if record_contacts == "all":
            return np.arange(steps + 1, dtype=np.int64)
        if record_contacts == "last":
            return np.array([steps], dtype=np.int64)
        raise ParameterError(
            f"record_contacts = {record_contacts!r}; give step indices, 'all' or 'last'"
        )
    if isinstance(record_contacts, np.ndarray):
        record_contacts = record_contacts.ravel().tolist()
    if not isinstance(record_contacts, Iterable):
        raise ParameterError(
            f"record_contacts = {record_contacts!r}; give a list of step indices (for example "
            "[0, 10]), 'all' or 'last'"
        )
    chosen_steps: list[int] = []
    for value in record_contacts:
        try:
            chosen_steps.append(check_integer("record_contacts step", value, minimum=0))
        except ParameterError:
            raise ParameterError(
                f"record_contacts step {value!r} is not a step index; give integers in "
                f"0…{steps} (the steps of this run)"
            ) from None
    chosen = np.unique(np.asarray(chosen_steps, dtype=np.int64))
    bad = chosen[(chosen < 0) | (chosen > steps)]
    if bad.size:
        raise ParameterError(
            f"record_contacts step {int(bad[0])} is outside 0…{steps} (the steps of this run)"
        )
    return chosen


def simulate(
    lower: Profile,
    upper: Profile | Literal["flat"],
    *,
    steps: int = 1000,
    final_displacement: float | None = None,
    final_displacement_factor: float = 0.2,
    e_star: float = 10.0,
    g_star: float | None = None,
    mu0: float = 0.3,
    alpha: float = 2.0,
    x0: float = 1.0,
    record_contacts: Iterable[int] | str | None = None,
    path: Sequence[Segment] | None = None,
    max_steps: int = MAX_STEPS,
    diagnostics: bool = True,
    law: ContactLaw | None = None,
    interaction: bool | InteractionSettings = False,
) -> SimulationResult:
    """Press two rough bodies (or a rough body and a rigid flat) together by SAD.

    The upper body is lowered in ``steps`` equal increments from zero minimum gap (step 0) to
    ``final_displacement``; at every step the accepted contacts of Table 1 and eq. 9 carry a
    Hertzian line-contact force (π/4)E*δ along their repulsive direction and an incremental
    tangential force (eqs. 11–13); eq. 14 sums them.

    Parameters
    ----------
    lower : Profile
        Lower body; heights [µm] point out of the body (as a profilometer records them).
    upper : Profile or "flat"
        Upper body, also with heights [µm] out of its own body (it is turned over here to face
        the lower one), or ``"flat"`` for a rigid flat. Must share the lower profile's grid.
    steps : int, optional
        Number of displacement increments N [1] (paper: 1000); results have N + 1 records.
    final_displacement : float, optional
        Displacement δ_N at the last step [µm]. Default: ``final_displacement_factor`` × the
        lower profile's peak-to-valley height.
    final_displacement_factor : float, optional
        Fraction [1] of the lower peak-to-valley height used by default (paper: 0.2).
    e_star : float, optional
        Effective modulus E* [GPa] (paper: 10 GPa).
    g_star : float, optional
        Effective shear modulus G* [GPa]; default E*/2.6 (ν = 0.3).
    mu0 : float, optional
        Molecular friction coefficient μ0 [1] capping |F^t| ≤ μ0|F^n| (eqs. 12–13).
    alpha : float, optional
        Spline tightness exponent α [1] (eq. 3; paper: 2).
    x0 : float, optional
        Spline unit length x0 [µm] (eqs. 2–3; paper: 1 µm).
    record_contacts : iterable of int, "all", "last" or None, optional
        Steps at which to keep every accepted contact (for plots such as Fig. 9). The points
        whose gap has closed, summed over these steps, may not exceed
        ``MAX_RECORDED_CONTACTS`` (2·10⁷).
    path : sequence of Segment, optional
        A load path of normal [µm] or force-controlled [mN/µm] and tangential [µm] segments
        (:class:`splinecontact.Segment`, see ``docs/friction.md``). Replaces ``steps`` and
        ``final_displacement``; without it the run is the single normal loading above.
    max_steps : int, optional
        Ceiling [1] on ``steps`` (default ``MAX_STEPS`` = 10⁶), checked before anything is
        allocated.
    diagnostics : bool, optional
        Run the checks of :mod:`splinecontact.diagnostics` (form, coarse grid, near-full
        contact) and issue their warnings (default). ``False`` skips them (about 35 ms at 10⁶
        points), e.g. for the realizations of an ensemble.
    law : ContactLaw, optional
        Local normal contact law (:mod:`splinecontact.contact.laws`); default
        :class:`~splinecontact.contact.laws.Hertz`, F = (π/4)E*δ (eq. 10). Also
        :class:`~splinecontact.contact.JKR`, :class:`~splinecontact.contact.DMT`,
        :class:`~splinecontact.contact.MaugisDugdale` (adhesion; work of adhesion [J/m²],
        Dugdale stress [GPa]) and :class:`~splinecontact.contact.ElasticPlastic` (yield strength
        or hardness [GPa]), or :func:`~splinecontact.contact.make_law` by name
        (``docs/contact-laws.md``; the Sec. 4 proposal). Their history (jump-in/out, the plastic
        residual interference) shows on a ``path`` that unloads.
    interaction : bool or InteractionSettings, optional
        ``False`` (default): the paper's independent contacts. ``True`` (or an
        :class:`~splinecontact.contact.interaction.InteractionSettings`): the accepted contacts
        interact through the elastic half-plane (:mod:`splinecontact.contact.interaction`,
        ``docs/accuracy.md``); the curves gain ``coalesced_contact_length``,
        ``n_contact_patches``, ``interaction_iterations`` and ``reach_exceeded``. Any
        ``path`` with the Hertz law (sliding and force control: :mod:`.interaction_slide`);
        every other law on normal, displacement-controlled paths (:mod:`.interaction_laws`).

    Returns
    -------
    SimulationResult
        Curves of F_N, F_T [mN/µm], A_S [µm], contact counts and mean separation [µm] per step.

    Raises
    ------
    ParameterError
        A body is not a Profile (or ``"flat"``); a parameter is not a finite number of the right
        kind (``None``, a string, ``True``, NaN, inf); steps < 1 or above ``max_steps``,
        E* ≤ 0, G* < 0, μ0 < 0, α ≤ 0, x0 ≤ 0, final displacement ≤ 0 or beyond 10⁵⁰ µm,
        a non-integer or out-of-range ``record_contacts`` step, too many contacts to record.
    GridMismatchError
        The two profiles do not share a grid.

    Warns
    -----
    splinecontact.diagnostics.SimulationWarning
        A body dominated by tilt or form, a grid too coarse for the spline, or a final contact
        area near full contact (see :mod:`splinecontact.diagnostics`).

    Examples
    --------
    >>> import numpy as np
    >>> from splinecontact import simulate, weierstrass_mandelbrot_pair
    >>> lower, upper = weierstrass_mandelbrot_pair(1.5, seed=1, n_points=4096, length=10.0)
    >>> result = simulate(lower, upper, steps=20)
    >>> result.normal_force.shape, bool((np.diff(result.normal_force) >= 0).all())
    ((21,), True)
    >>> result.to_xarray()["normal_force"].attrs["units"]
    'mN/µm'
    """
    check_bodies(lower, upper)
    max_steps = check_integer("max_steps", max_steps, minimum=1)
    steps, e_star, g_star, mu0, law = check_model_arguments(
        steps=steps, final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, law=law, max_steps=max_steps, raise_with="max_steps",
    )  # fmt: skip
    if interaction is not False:
        settings = _interaction_settings(interaction, path, law)
    fits = None
    if getattr(law, "needs_radius", False):
        check_bodies(lower, upper)
        fits = spline_fits(lower, upper, alpha=alpha, x0=x0)
        law = bind_law(law, e_star, _reach_radius(lower, fits))
    elif law.code != Hertz.code:
        law = bind_law(law, e_star, 0.0)
    if path is not None and interaction is not False:
        from .interaction_path import simulate_interacting_path

        return simulate_interacting_path(
            lower, upper, path, settings, record_contacts, steps=steps,
            final_displacement=final_displacement, e_star=e_star, g_star=g_star, mu0=mu0,
            alpha=alpha, x0=x0, law=law,
        )  # fmt: skip
    if path is not None:
        from .loadpath import simulate_path

        return simulate_path(
            lower, upper, path, steps=steps, final_displacement=final_displacement, e_star=e_star,
            g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, record_contacts=record_contacts, law=law,
            fits=fits,
        )  # fmt: skip
    record_steps = _record_steps(record_contacts, steps)

    check_bodies(lower, upper)
    if interaction is False and fits is None and lower.n_points >= STREAM_MIN_POINTS:
        return _simulate_streamed(
            lower, upper, record_steps, steps=steps, final_displacement=final_displacement,
            final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
            mu0=mu0, alpha=alpha, x0=x0, law=law, diagnostics=diagnostics,
        )  # fmt: skip
    fit_l, fit_u = spline_fits(lower, upper, alpha=alpha, x0=x0) if fits is None else fits
    if interaction is not False:
        return _simulate_interacting(
            lower, upper, (fit_l, fit_u), settings, record_steps, steps=steps,
            final_displacement=final_displacement,
            final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
            mu0=mu0, alpha=alpha, x0=x0, diagnostics=diagnostics, law=law,
        )  # fmt: skip
    geometry = contact_geometry(
        lower, upper, steps=steps, final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor, alpha=alpha, x0=x0,
        fits=(fit_l, fit_u), reach=law.reach,
    )  # fmt: skip
    check_reserved(geometry.first_step_index, record_steps, MAX_RECORDED_CONTACTS)
    run = run_loading(
        geometry, e_star=e_star, g_star=g_star, mu0=mu0, record_steps=record_steps, law=law
    )
    if diagnostics:
        from ..diagnostics import warn_simulation  # form, coarse grid, near-full contact

        warn_simulation(lower, upper, run.curves, alpha=alpha, x0=x0)
    return build_result(
        lower, upper, (fit_l, fit_u), run.curves, run.contacts, steps=steps,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, extra=law_record(law),
    )  # fmt: skip


def _simulate_streamed(
    lower: Profile,
    upper: Profile | Literal["flat"],
    record_steps: NDArray[np.int64],
    *,
    diagnostics: bool,
    **arguments: Any,
) -> SimulationResult:
    """``simulate`` from ``STREAM_MIN_POINTS`` points: fits and placement in chunks, no array of
    n values (:mod:`.streamed`; the same results to ≤ 1e−9 relative)."""
    from .geometry import check_same_grid
    from .streamed import simulate_streamed

    check_same_grid(lower, upper)
    result = simulate_streamed(
        lower, upper if isinstance(upper, Profile) else None, record_steps=record_steps,
        max_recorded=MAX_RECORDED_CONTACTS, **arguments,
    )  # fmt: skip
    if diagnostics:
        from ..diagnostics import warn_simulation

        warn_simulation(lower, upper, result.curves, alpha=arguments["alpha"], x0=arguments["x0"])
    return result


def _reach_radius(lower: Profile, fits: tuple[SplineFit, SplineFit | None]) -> float:
    """R_eff [µm] for which an adhesive law's reach is resolved: 2 × the 90th percentile of the
    radii of the convex points of either body (from every 8th point). A contact of larger R_eff
    (near an inflection) lets go at δ = −reach instead of at its own jump-out."""
    radii = []
    for fit in fits:
        if fit is None:
            continue
        slope, second = convex_samples(fit.slope, fit.second_derivative, 8)
        kappa = -second / (1.0 + slope * slope) ** 1.5
        convex = kappa[kappa > 0.0]
        if convex.size:
            radii.append(1.0 / float(np.percentile(convex, 10.0)))
    return 2.0 * max(radii) if radii else 2.0 * float(lower.x[-1] - lower.x[0])


def _interaction_settings(
    interaction: object, path: object, law: ContactLaw
) -> InteractionSettings:
    """The settings of ``simulate(..., interaction=...)``, refused where not supported."""
    if interaction is True:
        settings = InteractionSettings()
    elif isinstance(interaction, InteractionSettings):
        settings = interaction
    else:
        raise ParameterError(
            f"interaction = {interaction!r}; give True, False or an InteractionSettings"
        )
    return settings


def _simulate_interacting(
    lower: Profile,
    upper: Profile | Literal["flat"],
    fits: tuple[SplineFit, SplineFit | None],
    settings: InteractionSettings,
    record_steps: NDArray[np.int64],
    *,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    diagnostics: bool,
    law: ContactLaw,
) -> SimulationResult:
    """``simulate`` with contacts coupled through the half-plane (units as there)."""
    from .interaction import extended_geometry, interacting_loading

    geometry = extended_geometry(
        lower, upper, steps=steps, final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor, alpha=alpha, x0=x0, fits=fits,
        reach_fraction=settings.reach_fraction,
    )  # fmt: skip
    curves, contacts = interacting_loading(
        geometry, e_star=e_star, g_star=g_star, mu0=mu0, n_points=lower.n_points,
        settings=settings, record_steps=record_steps, law=law,
    )  # fmt: skip
    if diagnostics:
        from ..diagnostics import warn_simulation

        warn_simulation(lower, upper, curves, alpha=alpha, x0=x0)
    extra = {
        "interaction": "elastic half-plane",
        "interaction_boundary": "periodic" if settings.periodic else "symmetry walls",
        "interaction_tol": settings.tol,
        "interaction_width": settings.width,
        **({} if isinstance(law, Hertz) else law_record(law)),
    }
    return build_result(
        lower, upper, fits, curves, contacts, steps=int(curves["displacement"].size) - 1,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, extra=extra,
    )  # fmt: skip


def spline_fits(
    lower: Profile, upper: Profile | Literal["flat"], *, alpha: float, x0: float
) -> tuple[SplineFit, SplineFit | None]:
    """Spline fits (eqs. 2–3) of the lower body and of the upper one (``None`` for a flat)."""
    return fit_spline_pair(lower, upper if isinstance(upper, Profile) else None, alpha=alpha, x0=x0)


def build_result(
    lower: Profile,
    upper: Profile | Literal["flat"],
    fits: tuple[SplineFit, SplineFit | None],
    curves: dict[str, NDArray[Any]],
    contacts: tuple[ContactRecord, ...],
    *,
    steps: int,
    final_displacement_factor: float,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    extra: dict[str, Any] | None = None,
) -> SimulationResult:
    """A :class:`SimulationResult`: the curves, the model parameters (and ``extra`` ones), the
    grid, and the roughness scalars of :func:`splinecontact.profile.surface_statistics`.

    Units as in :func:`simulate` (E*, G* [GPa], α, μ0 [1], x0 [µm]).
    """
    parameters = run_parameters(
        curves, flat=not isinstance(upper, Profile), steps=steps,
        final_displacement_factor=final_displacement_factor, e_star=e_star, g_star=g_star,
        mu0=mu0, alpha=alpha, x0=x0, dx=lower.dx, n_points=lower.n_points, length=lower.length,
        extra=extra,
    )  # fmt: skip
    fit_l, fit_u = fits
    stats = surface_statistics(
        lower,
        upper if isinstance(upper, Profile) else None,
        fit_l.slope,
        None if fit_u is None else fit_u.slope,
    )
    return SimulationResult(
        curves=curves,
        scalars={**stats, "final_displacement": parameters["final_displacement"]},
        parameters=parameters,
        contacts=contacts,
        lower_metadata=dict(lower.metadata),
        upper_metadata=dict(upper.metadata) if isinstance(upper, Profile) else {"source": "flat"},
    )
