"""``splinecontact plot`` and ``splinecontact reproduce``: the paper's figures and findings."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated, Literal

import typer

from ._common import fail, handle_errors

__all__ = ["register"]


@handle_errors
def plot(
    store: Annotated[
        Path,
        typer.Argument(help="Study store (the -o of `study run`), or a `simulate` result (.nc)."),
    ],
    out_dir: Annotated[
        Path, typer.Option("-o", "--out", help="Directory for the figures (PNG and SVG).")
    ] = Path("figures"),
    rsq_method: Annotated[
        str,
        typer.Option(
            "--rsq-method", help="R_Sq of κ: 'grid' (eq. 15 grid differences) or 'spline' (f′)."
        ),
    ] = "grid",
    fit_fraction: Annotated[
        float,
        typer.Option(
            "--fit-fraction",
            help="κ fit range: F_N ≤ this × the final load (0 < value ≤ 1).",
        ),
    ] = 0.3,
    illustrative: Annotated[
        bool,
        typer.Option(
            "--illustrative/--no-illustrative",
            help="Also draw Figs. 3a, 4, 5, 8, 9 from the study's first profiles (regenerated).",
        ),
    ] = True,
    overwrite: Annotated[
        bool,
        typer.Option(
            "--overwrite",
            help="Reuse a folder splinecontact wrote before: only the files it recorded there "
            "are replaced.",
        ),
    ] = False,
) -> None:
    """Draw every figure of the paper (Figs. 3a, 4, 5, 8–12) from a study store.

    The figures are drawn in memory first: a store with nothing to draw is refused before the
    output folder is created. A non-empty folder is refused unless splinecontact wrote it and
    --overwrite is given; other files in it are never touched.

    Given one `simulate` or `friction` result (.nc), draw its F_N–δ_N, F_T–δ_N, A_S–F_N and
    mean separation–F_N curves instead.
    """
    if store.suffix.lower() == ".nc" and store.is_file():
        from ._measured import plot_result

        files = plot_result(store, out_dir, overwrite=overwrite)
        typer.echo(f"wrote {len(files)} figures to {out_dir}")
        return
    from ..plotting import write_figures
    from ..reproduce.figures import draw_figures
    from ..study import open_study

    if rsq_method not in ("grid", "spline"):
        raise fail(f"--rsq-method must be 'grid' or 'spline', got {rsq_method!r}")
    if not 0.0 < fit_fraction <= 1.0:
        raise fail(f"--fit-fraction must lie in (0, 1], got {fit_fraction!r}")
    ds = open_study(store)
    figures, _, notes = draw_figures(
        ds,
        illustrative=illustrative,
        kappa_options={"rsq_method": rsq_method, "fit_fraction": fit_fraction},
    )
    written = write_figures(figures, out_dir, overwrite=overwrite, command="plot")
    for note in notes:
        typer.echo(f"note: {note}")
    n = sum(len(v) for v in written.values())
    typer.echo(f"wrote {len(written)} figures ({n} files) to {out_dir}")


@handle_errors
def reproduce(
    scale: Annotated[
        str,
        typer.Option(
            "--scale",
            help="quick: D 1.1–1.9, both contact types, 10⁶ points, 1000 steps, 20 realizations "
            "(minutes); paper: D 1.0–1.9, 200 realizations (hours); tiny: a smoke test.",
        ),
    ] = "quick",
    out_dir: Annotated[
        Path | None,
        typer.Option("-o", "--out", help="Output directory [default: reproduce-SCALE]."),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option("--workers", min=1, help="Worker processes [default: cores available]."),
    ] = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No progress bar; only the final lines.")
    ] = False,
    overwrite: Annotated[
        bool,
        typer.Option(
            "--overwrite",
            help="Reuse a folder splinecontact wrote for another command, and discard a study "
            "store of another study in it.",
        ),
    ] = False,
) -> None:
    """Run the paper's study, draw every figure and write report.md checking its findings.

    Writes OUT/study.toml, OUT/study.zarr, OUT/figures/*.png|svg, OUT/findings.json and
    OUT/report.md. Running the same command again on the same OUT continues an interrupted
    study; any other non-empty folder is refused and left untouched.
    """
    from ..reproduce import SCALES
    from ..reproduce import reproduce as run

    if scale not in SCALES:
        raise fail(f"--scale must be one of {', '.join(SCALES)}, got {scale!r}")
    scale_lit: Literal["tiny", "quick", "paper"] = scale  # type: ignore[assignment]
    out = out_dir if out_dir is not None else Path(f"reproduce-{scale}")
    result = run(
        out,
        scale=scale_lit,
        workers=workers,
        progress=not quiet,
        command="splinecontact " + " ".join(sys.argv[1:]) if sys.argv[1:] else "",
        overwrite=overwrite,
    )
    for f in result.findings:
        typer.echo(f"({f.key}) {f.verdict}: {f.summary}")
    typer.echo(
        f"report: {result.report}  (study {result.study_time:.1f} s, figures "
        f"{result.figure_time:.1f} s, total {result.wall_time:.1f} s)"
    )


def register(app: typer.Typer) -> None:
    """Add the ``plot`` and ``reproduce`` commands to ``app``."""
    app.command("plot")(plot)
    app.command("reproduce")(reproduce)
