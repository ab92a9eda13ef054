"""``reproduce``'s figure work in the worker processes: the same bytes as drawn in one process."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from splinecontact.outputs import OUTPUT_MARKER, prepare_output_folder
from splinecontact.plotting import render_figure, save_figure, write_rendered
from splinecontact.reproduce import reproduce


def _figure() -> Figure:
    fig = Figure(figsize=(4, 3), layout="constrained")
    ax = fig.subplots()
    x = np.linspace(1e-3, 1.0, 200)
    ax.loglog(x, x**1.5, label="F ∝ δ^1.5")
    ax.set_xlabel("δ [µm]")
    ax.legend()
    return fig


def test_rendered_bytes_are_the_saved_files(tmp_path: Path) -> None:
    saved = save_figure(_figure(), tmp_path / "a")
    rendered = render_figure(_figure())
    assert [p.read_bytes() for p in saved] == [rendered["png"], rendered["svg"]]
    # a figure sent to another process (pickled) draws the same bytes
    assert render_figure(pickle.loads(pickle.dumps(_figure()))) == rendered


def test_rendered_figures_are_written_under_the_output_rule(tmp_path: Path) -> None:
    folder = prepare_output_folder(tmp_path / "out", overwrite=False, command="plot")
    written = write_rendered({"f": {"png": b"p", "svg": b"s"}}, folder, prefix="figures/")
    assert written == {"f": [folder.path / "figures/f.png", folder.path / "figures/f.svg"]}
    assert (folder.path / "figures/f.svg").read_bytes() == b"s"
    marker = json.loads((folder.path / OUTPUT_MARKER).read_text(encoding="utf-8"))
    assert marker["files"] == ["figures/f.png", "figures/f.svg"]


@pytest.mark.slow  # two worker processes, two tiny reproduce runs
def test_two_workers_write_the_same_files_as_one(tmp_path: Path) -> None:
    one = reproduce(tmp_path / "one", scale="tiny", workers=1, progress=False)
    two = reproduce(tmp_path / "two", scale="tiny", workers=2, progress=False)
    assert list(one.figures) == list(two.figures)
    for name, paths in one.figures.items():
        for a, b in zip(paths, two.figures[name], strict=True):
            assert a.read_bytes() == b.read_bytes(), a.name
    data = [json.loads(r.findings_file.read_text(encoding="utf-8")) for r in (one, two)]
    for d in data:
        d.pop("study_time_s")
        d.pop("figure_time_s")
    assert data[0] == data[1]
