"""SAD against the exact elastic reference (BEM) on one geometry (``splinecontact compare``).

Both methods see the same smoothed geometry: the SAD spline f(x_i) of each body (paper eqs. 2–3,
:func:`splinecontact.spline.fit_spline`). SAD (:func:`splinecontact.simulate`) runs its
displacement steps; at a selection of its forces the boundary element reference
(:mod:`splinecontact.bem`) solves the exact plane-strain contact of the composite profile
f_lower + f_upper against a flat at the same force. The profile is made periodic by appending
its mirror image (:func:`splinecontact.bem.mirror_extend`), which is the segment between two
frictionless symmetry walls; all BEM quantities are those of the original segment.

Compared quantities (at equal force F per unit thickness [mN/µm]):

* contact length: SAD's Hertz contact width Σ 2aᵢ = √2·A_S (with aᵢ = √(δᵢ R_eff,i/2), the
  2D Hertz half-width of a line contact loaded by (π/4)E*δᵢ), SAD's A_S = Σ √(δᵢ R_eff,i) as the
  paper defines it, and the exact contact length (sub-grid estimate and node count);
* mean gap: SAD's mean separation (rigid bodies) and the exact mean gap (deformed surfaces),
  both the distance between the mean lines;
* approach: SAD's displacement δ_N from first contact and the exact mean-gap reduction;
* counts: SAD's accepted contacts and the exact number of contact patches.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from . import bem, schema
from .errors import NoConvergenceError, ParameterError
from .profile import Profile

if TYPE_CHECKING:  # xarray is imported when a Dataset is made, not with the package
    import xarray as xr

__all__ = [
    "COLUMNS",
    "COMPARE_MAX_ITERATIONS",
    "INTERACTING_TRAVEL",
    "MAX_BISECTIONS",
    "MAX_CONTACT_FRACTION",
    "Comparison",
    "compare_profiles",
    "write_figure",
    "write_table",
]

#: Share of the profile in exact contact [1] at which a comparison stops (near full contact the
#: mean gap tends to zero and ratios to it are meaningless).
MAX_CONTACT_FRACTION = 0.9

#: BEM iteration limit per solve [1] in a comparison (converged solves take tens to hundreds;
#: a solve that has not converged by then is approached again in smaller load steps).
COMPARE_MAX_ITERATIONS = 5000

#: Interacting SAD runs this many times SAD's displacement (and steps), so that its forces,
#: smaller at equal displacement, cover SAD's [1].
INTERACTING_TRAVEL = 2

#: Halvings of a load step tried when a BEM solve does not converge.
MAX_BISECTIONS = 2

#: Columns of the comparison table: name -> (units, description) (defined in
#: :mod:`splinecontact.schema`, table ``comparison``).
COLUMNS: dict[str, tuple[str, str]] = schema.legacy_table("comparison")


@dataclass(frozen=True, eq=False)
class Comparison:
    """SAD and the exact reference at matched forces.

    Attributes
    ----------
    columns : dict of str to ndarray
        One array per key of ``COLUMNS`` (units there), one entry per compared force.
    parameters : dict
        Grid, modulus, spline and solver settings, and the sources of the two profiles.
    notes : tuple of str
        Anything the reader must know (forces skipped beyond full contact, ...).
    """

    columns: dict[str, NDArray[np.float64]]
    parameters: dict[str, Any]
    notes: tuple[str, ...] = ()

    def median(self, name: str) -> float:
        """Median of one column over the compared forces (NaN entries ignored)."""
        values = self.columns[name]
        finite = values[np.isfinite(values)]
        return float(np.median(finite)) if finite.size else float("nan")

    def to_xarray(self) -> xr.Dataset:
        """Return the comparison as an :class:`xarray.Dataset` (dimension ``load``).

        One variable per key of ``COLUMNS`` with ``units`` and ``long_name``
        (:mod:`splinecontact.schema`); the attributes hold the parameters and the notes.
        """
        import xarray as xr

        data_vars = {
            name: schema.xr_variable(name, np.asarray(self.columns[name], dtype=np.float64))
            for name in COLUMNS
        }
        attrs: dict[str, Any] = {
            key: value if isinstance(value, int | float | str) else str(value)
            for key, value in self.parameters.items()
        }
        attrs["notes"] = "\n".join(self.notes)
        attrs["units_convention"] = (
            "lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness"
        )
        n = int(np.size(self.columns["force"]))
        coords = {"load": schema.coordinate("load", n)}
        return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _select_steps(force: NDArray[np.float64], n_forces: int) -> NDArray[np.int64]:
    """SAD steps whose forces are closest above n_forces evenly spaced targets up to max F."""
    positive = np.flatnonzero(force > 0.0)
    if positive.size == 0:
        return np.zeros(0, dtype=np.int64)
    top = float(force.max())
    targets = top * np.arange(1, n_forces + 1) / n_forces
    chosen: list[int] = []
    for target in targets:
        above = np.flatnonzero(force >= target * (1.0 - 1e-12))
        if above.size:
            chosen.append(int(above[0]))
    return np.unique(np.asarray(chosen, dtype=np.int64))


def _solve_in_substeps(
    problem: bem.ContactProblem,
    load: float,
    initial: NDArray[np.float64] | None,
    initial_load: float,
    tol: float,
    max_iterations: int,
    depth: int = 0,
) -> bem.BEMStep:
    """Solve at mean pressure ``load`` [GPa], warm-started; on failure approach it in halves.

    A new contact spot far from the loaded ones can make the constrained conjugate gradients
    cycle from a warm start; approaching the load from the last converged state in smaller
    steps lets the contact set grow gradually (at most :data:`MAX_BISECTIONS` halvings).
    """
    try:
        return bem.solve_pressure(
            problem,
            load,
            initial_pressure=initial,
            tol=tol,
            max_iterations=max_iterations,
            fields=True,
        )
    except NoConvergenceError:
        if depth >= MAX_BISECTIONS:
            raise
    middle = 0.5 * (initial_load + load)
    half = _solve_in_substeps(
        problem, middle, initial, initial_load, tol, max_iterations, depth + 1
    )
    return _solve_in_substeps(problem, load, half.pressure, middle, tol, max_iterations, depth + 1)


def compare_profiles(
    lower: Profile,
    upper: Profile | Literal["flat"] = "flat",
    *,
    e_star: float = 10.0,
    steps: int = 1000,
    final_displacement: float | None = None,
    final_displacement_factor: float = 0.2,
    alpha: float = 2.0,
    x0: float = 1.0,
    n_forces: int = 20,
    tol: float = bem.DEFAULT_TOLERANCE,
    max_iterations: int = COMPARE_MAX_ITERATIONS,
    max_contact_fraction: float = MAX_CONTACT_FRACTION,
    progress: Callable[[str], None] | None = None,
    interaction: bool = False,
) -> Comparison:
    """Run SAD and the exact BEM reference on the same smoothed geometry at matched forces.

    Parameters
    ----------
    lower : Profile
        Lower body, heights [µm] out of the body.
    upper : Profile or "flat"
        Upper body (heights [µm] out of its own body, same grid) or a rigid flat.
    e_star : float
        Effective modulus E* [GPa].
    steps : int
        SAD displacement steps [1].
    final_displacement : float, optional
        SAD's last displacement [µm] (default: ``final_displacement_factor`` × peak-to-valley).
    final_displacement_factor : float
        Fraction of the lower peak-to-valley height [1] used by default.
    alpha, x0 : float
        Spline tightness exponent α [1] and unit length x0 [µm] (eqs. 2–3).
    n_forces : int
        Number of forces at which to compare [1] (evenly spaced up to SAD's largest force).
    tol : float
        BEM convergence tolerance [1] (see :mod:`splinecontact.bem`).
    max_iterations : int
        BEM iteration limit per solve [1]. A force that does not converge within it is
        approached again from the last converged force in up to :data:`MAX_BISECTIONS`
        halvings before the comparison stops.
    max_contact_fraction : float
        Share of the profile in exact contact [1] at which the comparison stops: states at or
        near full contact (mean gap → 0) are not reported; a note says so.
    progress : callable, optional
        Called with one line of text before SAD and after each BEM force.
    interaction : bool
        Also run interacting SAD (``simulate(..., interaction=True)``) over
        ``INTERACTING_TRAVEL`` × the displacement, ended at the first step whose force reaches
        the largest compared force, and report it at the same forces (the ``int_*`` columns;
        NaN beyond its largest force). ``False`` leaves them NaN.

    Returns
    -------
    Comparison

    Raises
    ------
    ParameterError
        No SAD force below the exact full-contact force, or bad ``n_forces`` /
        ``max_contact_fraction``.
    NoConvergenceError
        The BEM did not converge at one force; the message names the force and what to change.

    Examples
    --------
    >>> from splinecontact import compare_profiles, weierstrass_mandelbrot
    >>> profile = weierstrass_mandelbrot(1.5, n_points=1024, length=10.0, seed=3)
    >>> comparison = compare_profiles(profile, "flat", steps=20, n_forces=3)
    >>> comparison.columns["force"].size
    3
    >>> comparison.to_xarray()["bem_contact_length_subgrid"].attrs["units"]
    'µm'
    """
    import time

    from .contact import simulate
    from .spline import fit_spline

    say = progress if progress is not None else (lambda _text: None)
    if isinstance(n_forces, bool) or int(n_forces) != n_forces or n_forces < 1:
        raise ParameterError(f"n_forces must be an integer ≥ 1, got {n_forces!r}")
    if not 0.0 < max_contact_fraction <= 1.0:
        raise ParameterError(
            f"max_contact_fraction must be in (0, 1], got {max_contact_fraction!r}"
        )
    n = lower.n_points
    say(f"SAD: {steps} steps on {n} points")
    t0 = time.perf_counter()
    result = simulate(
        lower,
        upper,
        steps=steps,
        final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor,
        e_star=e_star,
        alpha=alpha,
        x0=x0,
    )
    composite = fit_spline(lower, alpha=alpha, x0=x0).f
    if not isinstance(upper, str):
        composite = composite + fit_spline(upper, alpha=alpha, x0=x0).f
    smoothed = Profile(lower.x, composite, metadata={"source": "SAD spline, composite"})
    problem = bem.contact_problem(bem.mirror_extend(smoothed), e_star=e_star)
    segment = n * lower.dx

    curves = result.curves
    force_curve = np.asarray(curves["normal_force"], dtype=np.float64)
    chosen = _select_steps(force_curve, n_forces)
    notes: list[str] = []
    p_full = problem.full_contact_pressure
    keep = [i for i in chosen if force_curve[i] / segment < p_full]
    if len(keep) < len(chosen):
        notes.append(
            f"{len(chosen) - len(keep)} SAD force(s) at or beyond the exact full-contact force "
            f"{p_full * segment:.4g} mN/µm were skipped"
        )
    if not keep:
        raise ParameterError(
            "no SAD step has a positive force below the exact full-contact force "
            f"({p_full * segment:.4g} mN/µm; largest SAD force {force_curve.max():.4g} mN/µm); "
            "change the final displacement or the number of steps"
        )
    say(
        f"SAD done in {time.perf_counter() - t0:.1f} s; exact BEM at {len(keep)} forces on "
        f"{problem.n_points} nodes (mirrored), tol {tol:g}, ≤ {max_iterations} iterations each"
    )
    solved: list[bem.BEMStep] = []
    previous: NDArray[np.float64] | None = None
    previous_load = 0.0
    for k, step_index in enumerate(keep):
        force = float(force_curve[step_index])
        t1 = time.perf_counter()
        try:
            state = _solve_in_substeps(
                problem, force / segment, previous, previous_load, tol, max_iterations
            )
        except NoConvergenceError as exc:
            raise NoConvergenceError(
                f"the exact BEM did not converge at force {k + 1} of {len(keep)} "
                f"(F = {force:.4g} mN/µm, SAD step {step_index}): {exc}; to go on, raise "
                "max_iterations (--max-iterations) or tol (--tol), lower the final "
                "displacement (--final-displacement-factor), remove form (--detrend) or use "
                "fewer points (--crop / --resample-spacing)"
            ) from None
        fraction = state.contact_nodes / problem.n_points
        say(
            f"BEM force {k + 1}/{len(keep)}: F = {force:.4g} mN/µm, exact contact "
            f"{state.contact_nodes} of {problem.n_points} nodes ({100 * fraction:.3g} %), "
            f"{state.iterations} iterations, "
            f"{time.perf_counter() - t1:.1f} s"
        )
        if fraction >= max_contact_fraction:
            notes.append(
                f"stopped at force {k + 1} of {len(keep)} (F = {force:.4g} mN/µm): the exact "
                f"contact covers {100 * fraction:.0f} % of the profile (limit "
                f"{100 * max_contact_fraction:.0f} %, near full contact), so it and the "
                f"{len(keep) - k - 1} larger force(s) are not reported"
            )
            say(notes[-1])
            break
        solved.append(state)
        previous, previous_load = state.pressure, force / segment
    if not solved:
        raise ParameterError(
            f"the exact contact is near full contact (≥ {100 * max_contact_fraction:.0f} % of "
            f"the profile) already at the smallest compared force {force_curve[keep[0]]:.4g} "
            "mN/µm; lower the final displacement (--final-displacement-factor) or remove form "
            "(--detrend)"
        )
    keep = keep[: len(solved)]
    path = bem.BEMPath(tuple(solved), problem.e_star, problem.dx, problem.n_points, float(tol))
    idx = np.asarray(keep, dtype=np.int64)
    forces = force_curve[idx]
    coupled = None
    if interaction:
        # up to INTERACTING_TRAVEL × SAD's displacement at SAD's increment, ended at the first
        # step whose force reaches the largest compared force (beyond it the coupled contacts
        # head for full contact, where every step costs a dense solve)
        from .contact import InteractionSettings

        say(f"interacting SAD: ≤ {INTERACTING_TRAVEL * steps} steps on {n} points")
        t1 = time.perf_counter()
        travel = float(result.displacement[-1]) * INTERACTING_TRAVEL
        coupled = simulate(
            lower, upper, steps=INTERACTING_TRAVEL * steps, final_displacement=travel,
            e_star=e_star, alpha=alpha, x0=x0, diagnostics=False,
            interaction=InteractionSettings(stop_force=float(forces.max())),
        )  # fmt: skip
        say(
            f"interacting SAD done in {time.perf_counter() - t1:.1f} s "
            f"({coupled.displacement.size - 1} steps)"
        )

    bem_len = np.empty(idx.size)
    bem_sub = np.empty(idx.size)
    bem_patches = np.empty(idx.size)
    for k, step in enumerate(path.steps):
        assert step.pressure is not None
        stats = bem.contact_statistics(step.pressure[:n], lower.dx, periodic=False)
        bem_len[k] = stats.contact_length
        bem_sub[k] = stats.contact_length_subgrid
        bem_patches[k] = stats.n_patches
    bem_gap = path.column("mean_gap")
    bem_approach = path.column("approach")

    area = np.asarray(curves["contact_area"], dtype=np.float64)[idx]
    width = np.sqrt(2.0) * area
    n_contacts = np.asarray(curves["n_contacts"], dtype=np.float64)[idx]
    separation = np.asarray(curves["mean_separation"], dtype=np.float64)[idx]
    displacement = np.asarray(curves["displacement"], dtype=np.float64)[idx]
    with np.errstate(divide="ignore", invalid="ignore"):
        columns = {
            "force": forces,
            "sad_step": idx.astype(np.float64),
            "sad_displacement": displacement,
            "sad_contact_width": width,
            "sad_contact_area": area,
            "sad_n_contacts": n_contacts,
            "sad_mean_separation": separation,
            "bem_contact_length": bem_len,
            "bem_contact_length_subgrid": bem_sub,
            "bem_n_patches": bem_patches,
            "bem_mean_gap": bem_gap,
            "bem_approach": bem_approach,
            "ratio_width": width / bem_sub,
            "ratio_area": area / bem_sub,
            "mean_gap_error": separation / bem_gap - 1.0,
            "ratio_approach": bem_approach / displacement,
            "ratio_contacts": bem_patches / n_contacts,
        }
    columns.update(_interacting_columns(coupled, forces, bem_sub, bem_gap, bem_approach,
                                        bem_patches))  # fmt: skip
    parameters: dict[str, Any] = {
        "e_star_GPa": float(e_star),
        "n_points": n,
        "dx_um": lower.dx,
        "sad_steps": int(steps),
        "alpha": float(alpha),
        "x0_um": float(x0),
        "bem_tolerance": float(tol),
        "bem_max_iterations": int(max_iterations),
        "max_contact_fraction": float(max_contact_fraction),
        "bem_periodic_extension": "mirror",
        "lower_source": str(lower.metadata.get("source", "?")),
        "upper_source": "flat" if isinstance(upper, str) else str(upper.metadata.get("source")),
    }
    return Comparison(columns, parameters, tuple(notes))


def _interacting_columns(
    coupled: Any,
    forces: NDArray[np.float64],
    bem_sub: NDArray[np.float64],
    bem_gap: NDArray[np.float64],
    bem_approach: NDArray[np.float64],
    bem_patches: NDArray[np.float64],
) -> dict[str, NDArray[np.float64]]:
    """The ``int_*`` columns: interacting SAD interpolated at the compared forces."""
    names = ("int_displacement", "int_contact_length", "int_contact_area", "int_n_contacts",
             "int_n_patches", "int_mean_separation")  # fmt: skip
    if coupled is None:
        values = {name: np.full(forces.size, np.nan) for name in names}
    else:
        curve = np.maximum.accumulate(np.asarray(coupled.normal_force, dtype=np.float64))
        rising = np.concatenate([[True], np.diff(curve) > 0.0])
        sources = (
            coupled.displacement,
            coupled.coalesced_contact_length,
            coupled.contact_area,
            coupled.n_contacts,
            coupled.n_contact_patches,
            coupled.mean_separation,
        )
        values = {
            name: np.interp(
                forces,
                curve[rising],
                np.asarray(source, dtype=np.float64)[rising],
                right=np.nan,
            )
            for name, source in zip(names, sources, strict=True)
        }
    with np.errstate(divide="ignore", invalid="ignore"):
        return {
            **values,
            "ratio_length_int": values["int_contact_length"] / bem_sub,
            "mean_gap_error_int": values["int_mean_separation"] / bem_gap - 1.0,
            "ratio_approach_int": bem_approach / values["int_displacement"],
            "ratio_patches_int": bem_patches / values["int_n_patches"],
        }


def write_table(comparison: Comparison, path: Path) -> Path:
    """Write the comparison as CSV; the header names each column with its units."""
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(COLUMNS)
    with path.open("w", newline="", encoding="utf-8") as handle:
        for key, value in comparison.parameters.items():
            handle.write(f"# {key} = {value}\n")
        for note in comparison.notes:
            handle.write(f"# note: {note}\n")
        writer = csv.writer(handle)
        writer.writerow([f"{name} [{COLUMNS[name][0]}]" for name in names])
        rows = np.column_stack([comparison.columns[name] for name in names])
        for row in rows:
            writer.writerow([f"{v:.10g}" for v in row])
    return path


def write_figure(comparison: Comparison, path: Path) -> Path:
    """Plot contact length, mean gap and counts against force, with their ratios (PNG)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    c = comparison.columns
    force = c["force"]
    fig = Figure(figsize=(13.0, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, 3, sharex=True)
    top, bottom = axes[0], axes[1]

    top[0].plot(force, c["bem_contact_length_subgrid"], "k-o", ms=3, label="exact (BEM)")
    top[0].plot(force, c["sad_contact_width"], "C0-s", ms=3, label="SAD Hertz width √2·A_S")
    top[0].plot(force, c["sad_contact_area"], "C1-^", ms=3, label="SAD A_S")
    top[0].set_ylabel("contact length [µm]")
    bottom[0].plot(force, c["ratio_width"], "C0-s", ms=3, label="SAD width / exact")
    bottom[0].plot(force, c["ratio_area"], "C1-^", ms=3, label="A_S / exact")
    bottom[0].set_ylabel("ratio to exact [1]")

    top[1].plot(force, c["bem_mean_gap"] * 1e3, "k-o", ms=3, label="exact (BEM)")
    top[1].plot(force, c["sad_mean_separation"] * 1e3, "C0-s", ms=3, label="SAD")
    top[1].set_ylabel("mean gap [nm]")
    bottom[1].plot(force, c["mean_gap_error"], "C0-s", ms=3, label="SAD / exact − 1")
    bottom[1].plot(force, c["ratio_approach"], "C2-d", ms=3, label="approach exact / SAD")
    bottom[1].set_ylabel("[1]")

    top[2].plot(force, c["bem_n_patches"], "k-o", ms=3, label="exact patches")
    top[2].plot(force, c["sad_n_contacts"], "C0-s", ms=3, label="SAD contacts")
    top[2].set_ylabel("count [1]")
    bottom[2].plot(force, c["ratio_contacts"], "C0-s", ms=3, label="patches / SAD contacts")
    bottom[2].set_ylabel("ratio [1]")

    for ax in (*top, *bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    for ax in bottom:
        ax.axhline(1.0, color="0.5", lw=0.8)
        ax.set_xlabel("force F [mN/µm]")
    p = comparison.parameters
    fig.suptitle(
        f"SAD vs exact elastic contact: {p['lower_source']} on {p['upper_source']}, "
        f"{p['n_points']} points, E* = {p['e_star_GPa']:g} GPa"
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    return path
