"""The ``reproduce`` run: the embedded studies (:data:`SCALES`), the output folder, the study,
the figures, the findings and the report, in that order."""

from __future__ import annotations

import json
import math
import time
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..errors import OutputExistsError, ParameterError
from ..outputs import OUTPUT_MARKER, OutputFolder, atomic_path, prepare_output_folder

if TYPE_CHECKING:
    from ._pool import IllustrativeOutcome
    from .findings import Finding

__all__ = ["CONTACT_TYPES", "SCALES", "STUDY_SEED", "ReproduceResult", "reproduce", "study_mapping"]

Scale = Literal["tiny", "quick", "paper"]

_D_QUICK = [1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8, 1.9]
_D_PAPER = [1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8, 1.9]

#: The embedded studies. ``quick`` keeps the paper's resolution (10⁶ points, 1000 steps; eq. 3
#: ties the spline to the grid spacing, so a coarser grid is a different model) with 20
#: realizations per grid point; ``paper`` is the full study; ``tiny`` is a smoke test on a coarse
#: short grid whose numbers mean nothing physically.
SCALES: dict[str, dict[str, Any]] = {
    "tiny": {
        "realizations": 3,
        "fixed": {"n_points": 4000, "length": 4.0, "steps": 60},
        "sweep": {"dimension": [1.2, 1.5, 1.8]},
    },
    "quick": {
        "realizations": 20,
        "fixed": {"n_points": 1_000_000, "length": 100.0, "steps": 1000},
        "sweep": {"dimension": _D_QUICK},
    },
    "paper": {
        "realizations": 200,
        "fixed": {"n_points": 1_000_000, "length": 100.0, "steps": 1000},
        "sweep": {"dimension": _D_PAPER},
    },
}

#: Seed of the embedded studies.
STUDY_SEED = 20150121

CONTACT_TYPES = ("rough-on-rough", "rough-on-flat")


def study_mapping(scale: Scale) -> dict[str, Any]:
    """The study (as the mapping of a TOML study file) that ``reproduce`` runs at ``scale``."""
    if scale not in SCALES:
        raise ParameterError(f"scale must be one of {sorted(SCALES)}, got {scale!r}")
    spec = SCALES[scale]
    return {
        "study": {
            "name": f"hanaor2015-{scale}",
            "seed": STUDY_SEED,
            "realizations": spec["realizations"],
            "description": "Hanaor, Gan & Einav (2015), Section 3, via splinecontact reproduce",
        },
        "fixed": {
            "e_star": 10.0,
            "alpha": 2.0,
            "ra": 0.005,
            "wavelength": 1.0,
            "final_displacement_factor": 0.2,
            **spec["fixed"],
        },
        "sweep": {**spec["sweep"], "contact_type": list(CONTACT_TYPES)},
    }


# --- the command ------------------------------------------------------------------------------


@dataclass(frozen=True)
class ReproduceResult:
    """What :func:`reproduce` wrote.

    Attributes
    ----------
    out_dir, store, study_file, report, findings_file : Path
    figures : dict of str to list of Path
    findings : list of Finding
    wall_time : float
        Total duration [s].
    study_time : float
        Duration of the study run [s].
    figure_time : float
        Duration of drawing and writing the figures [s].
    """

    out_dir: Path
    store: Path
    study_file: Path
    report: Path
    findings_file: Path
    figures: dict[str, list[Path]]
    findings: list[Finding]
    wall_time: float
    study_time: float
    figure_time: float = math.nan

    def files(self) -> list[Path]:
        """Every file promised (the store is a directory)."""
        out = [self.study_file, self.report, self.findings_file]
        for paths in self.figures.values():
            out.extend(paths)
        return out


def _earlier_reproduce(out: Path) -> bool:
    """Whether ``out`` is a folder an earlier ``reproduce`` wrote (its marker and its store)."""
    marker = out / OUTPUT_MARKER
    if not (out.is_dir() and marker.is_file() and (out / "study.zarr").is_dir()):
        return False
    try:
        return bool(json.loads(marker.read_text(encoding="utf-8")).get("command") == "reproduce")
    except (OSError, ValueError, AttributeError):
        return False


def _prepare_reproduce_folder(out: Path, study_toml: str, *, overwrite: bool) -> OutputFolder:
    """The output folder of ``reproduce`` under the package's output rule.

    A folder an earlier ``reproduce`` of the same scale wrote (its marker, ``study.zarr`` and the
    same ``study.toml``) is reused without ``--overwrite``: running the same command again
    continues an interrupted study. Nothing is removed; the files this run writes (study.toml,
    figures, findings, report) replace the earlier ones atomically; the study store is kept and
    handled by :func:`splinecontact.study.run_study`. The folder of another scale is refused unless
    ``overwrite`` (the store is then discarded by ``run_study``); any other non-empty folder is
    refused, and nothing is touched.
    """
    resume = _earlier_reproduce(out)
    if resume and not overwrite:
        try:
            same = (out / "study.toml").read_text(encoding="utf-8") == study_toml
        except OSError:
            same = False
        if not same:
            raise OutputExistsError(
                f"-o {out} holds another reproduce study (its study.toml differs); choose "
                "another folder, or pass --overwrite to discard that study and start again"
            )
        # our own folder, same study: nothing is removed; each file this run writes replaces
        # the earlier one atomically (this also works for -o . , which is never emptied)
        return OutputFolder(out, "reproduce")
    return prepare_output_folder(out, overwrite=overwrite, command="reproduce")


def _run_reproduce_study(
    config: Any,
    store: Path,
    *,
    progress: bool,
    overwrite: bool,
    workers: int | None = None,
    executor: Any = None,
) -> None:
    """Run the embedded study (on ``executor``, else ``workers`` local processes); with
    ``progress``, a progress bar and the summary on the terminal (the study runner itself
    prints nothing)."""
    from ..errors import StudyExecutionError
    from ..study import StudyProgressBar, print_summary, run_study

    where: dict[str, Any] = {"workers": workers} if executor is None else {"executor": executor}
    if not progress:
        run_study(config, store, overwrite=overwrite, **where)
        return
    with StudyProgressBar() as bar:
        try:
            summary = run_study(config, store, progress=bar, overwrite=overwrite, **where)
        except StudyExecutionError as exc:
            if exc.summary is not None:
                print_summary(exc.summary)
            raise
    print_summary(summary)


def _start_illustrative(executor: Any, config: Any, hurst_profiles: int) -> tuple[Any, Any]:
    """Submit the illustrative figures to the pool (they need the seed rule, not the results).

    Returns (job, future), or (None, None) when the study has no ``dimension`` sweep.
    """
    from ._pool import draw_illustrative, illustrative_job

    swept = dict(config.swept)
    if "dimension" not in swept:
        return None, None
    fixed = {k: v for k, v in config.fixed_parameters.items() if v is not None}
    job = illustrative_job(
        swept["dimension"], fixed, config.study.seed, hurst_profiles=hurst_profiles
    )
    return job, executor.submit(draw_illustrative, job)


def _figures(
    ds: Any,
    folder: OutputFolder,
    *,
    executor: Any,
    illustrative: tuple[Any, Any],
    kappa_options: Mapping[str, Any] | None,
    hurst_profiles: int,
) -> tuple[dict[str, list[Path]], Any, list[str], list[Finding]]:
    """Every figure and the findings, once the study is stored.

    The illustrative figures come from the worker that drew them during the study, if it drew
    them for the same D values and the same final displacement as the stored study (else they
    are made again here); the study figures are drawn here and rendered by the workers, one per
    task, while this process evaluates the findings. Returns the written files by figure, the
    Hurst exponents, the notes and the findings.
    """
    from ..plotting import build_figures, drawable_study, write_rendered
    from ._pool import render_job
    from .figures import _final_displacement, figure_inputs, hurst_dataset
    from .findings import evaluate_findings

    job, future = illustrative
    outcome: IllustrativeOutcome | None = None
    if future is not None:
        try:
            outcome = future.result()
        except Exception:  # the worker died, ...: made again here below
            outcome = None
    drawable, _ = drawable_study(ds)
    dims = [float(d) for d in drawable["dimension"].values] if "dimension" in drawable.dims else []
    if not (
        outcome is not None
        and job is not None
        and list(job.dimensions) == dims
        and (
            not outcome.rendered
            or outcome.final_displacement == _final_displacement(drawable, job.focus)
        )
    ):
        outcome = None
    rendered: dict[str, dict[str, bytes]] = {}
    if outcome is not None:
        rendered.update(outcome.rendered)
        measured = outcome.measured_hurst
        hurst = hurst_dataset(dims, measured) if measured is not None else None
        if hurst is None and hurst_profiles and dims:
            from .. import analysis

            hurst = analysis.study_hurst(ds, n_profiles=hurst_profiles)
        inputs_notes = list(outcome.notes)
        illustrative_inputs = None
    else:  # made again here, from the stored study
        inputs = figure_inputs(ds, hurst_profiles=hurst_profiles)
        hurst, inputs_notes, illustrative_inputs = inputs.hurst, inputs.notes, inputs.illustrative
    measured_hurst = (
        None
        if hurst is None
        else {
            float(d): float(h)
            for d, h in zip(
                hurst["dimension"].values, hurst["hurst_measured_mean"].values, strict=True
            )
        }
    )
    figs, notes = build_figures(
        ds,
        illustrative=illustrative_inputs,
        measured_hurst=measured_hurst,
        kappa_options=kappa_options,
    )
    formats, dpi = ("png", "svg"), 150
    # the costliest first, so that the workers finish together
    order = sorted(figs, key=lambda n: (not n.startswith("fig11"), not n.startswith("fig10")))
    futures = {name: executor.submit(render_job, (figs[name], formats, dpi)) for name in order}
    findings = evaluate_findings(ds, kappa_options=kappa_options)
    for name in figs:
        rendered[name] = futures[name].result()
    figures = write_rendered(rendered, folder, prefix="figures/")
    return figures, hurst, [*notes, *inputs_notes], findings


def reproduce(
    out_dir: str | Path,
    *,
    scale: Scale = "quick",
    workers: int | None = None,
    progress: bool = True,
    kappa_options: Mapping[str, Any] | None = None,
    hurst_profiles: int = 1,
    command: str = "",
    overwrite: bool = False,
) -> ReproduceResult:
    """Run the paper's study at ``scale``, write every figure, ``report.md`` and findings.

    Parameters
    ----------
    out_dir : path
        Output folder, under the package's output rule, with one addition: running again on a
        folder an earlier ``reproduce`` of the same scale wrote continues its study (the
        figures, findings and report it wrote are replaced; other files are left untouched).
    scale : {"tiny", "quick", "paper"}
        Size of the study (:data:`SCALES`).
    workers : int, optional
        Local worker processes of the study (default: the cores available). They also draw
        the illustrative figures while the study runs and render the study figures after it.
    progress : bool
        Progress bar and summary of the study.
    kappa_options : mapping, optional
        Options of :func:`splinecontact.analysis.kappa` for Fig. 12 and findings (d), (e).
    hurst_profiles : int
        Lower profiles per D whose Hurst exponent is measured (1: the profiles of the
        illustrative figures, no extra generation).
    command : str
        The command line, written into the report.
    overwrite : bool
        Reuse a folder splinecontact wrote for another command, and discard a study store that
        belongs to another study.

    Returns
    -------
    ReproduceResult
    """
    from ..study import LocalExecutor, open_study, parse_study
    from ..study.warmup import warm_up_workers

    t0 = time.perf_counter()
    config = parse_study(study_mapping(scale))
    out = Path(out_dir)
    study_toml = config.to_toml()
    folder = _prepare_reproduce_folder(out, study_toml, overwrite=overwrite)
    study_file = folder.file("study.toml")
    with atomic_path(study_file) as tmp:
        tmp.write_text(study_toml, encoding="utf-8")
    store = out / "study.zarr"
    executor = LocalExecutor(workers)
    try:
        # the workers start (and share out the kernels' compilation) while this process goes on
        warm_up_workers(executor, config)
        illustrative = _start_illustrative(executor, config, hurst_profiles)
        t1 = time.perf_counter()
        _run_reproduce_study(
            config, store, executor=executor, progress=progress, overwrite=overwrite
        )
        study_time = time.perf_counter() - t1
        ds = open_study(store)
        t2 = time.perf_counter()
        figures, hurst, notes, findings = _figures(
            ds,
            folder,
            executor=executor,
            illustrative=illustrative,
            kappa_options=kappa_options,
            hurst_profiles=hurst_profiles,
        )
        figure_time = time.perf_counter() - t2
    finally:
        executor.close()
    from .report import write_report

    findings_file = folder.file("findings.json")
    with atomic_path(findings_file) as tmp:
        tmp.write_text(
            json.dumps(
                {
                    "scale": scale,
                    "study_time_s": study_time,
                    "figure_time_s": figure_time,
                    "notes": notes,
                    "findings": [
                        {k: v for k, v in asdict(f).items() if k != "tables"} for f in findings
                    ],
                },
                indent=2,
                default=_json_default,
            ),
            encoding="utf-8",
        )
    wall = time.perf_counter() - t0
    report_path = folder.file("report.md")
    with atomic_path(report_path) as tmp:
        write_report(
            tmp,
            ds,
            findings,
            figures,
            command=command or f"splinecontact reproduce --scale {scale} -o {out}",
            wall_time=wall,
            kappa_options=kappa_options,
            hurst=hurst,
            root=out,
        )
    return ReproduceResult(
        out_dir=out,
        store=store,
        study_file=study_file,
        report=report_path,
        findings_file=findings_file,
        figures=figures,
        findings=findings,
        wall_time=time.perf_counter() - t0,
        study_time=study_time,
        figure_time=figure_time,
    )


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return str(value)
