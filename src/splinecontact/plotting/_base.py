"""Axes, colours, decimation and figure writing shared by every figure of the package.

No pyplot state is used and importing this module never changes the matplotlib backend: new
figures are :class:`matplotlib.figure.Figure` objects, drawn by their own Agg (PNG) or SVG
canvas when written.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from numpy.typing import NDArray

from ..outputs import OutputFolder, atomic_path, prepare_output_folder

__all__ = [
    "DECIMATE_POINTS",
    "NM_PER_UM",
    "decimate",
    "dimension_colors",
    "figure_of",
    "new_axes",
    "render_figure",
    "save_figure",
    "window",
    "write_figures",
    "write_rendered",
]

#: Heights in nm per µm (profiles are stored in µm, drawn in nm).
NM_PER_UM = 1000.0

#: Points a long curve is reduced to before drawing (a min/max pair per bin, see
#: :func:`decimate`): twice the ~1200-pixel width of the widest figure at 150 dpi, plus margin.
DECIMATE_POINTS = 4000

#: PNG compression level (zlib 0–9). The pixels do not depend on it; level 1 encodes several
#: times faster than the default 6 for files about a third larger.
_PNG_COMPRESS_LEVEL = 1


def new_axes(ax: Axes | None = None, *, figsize: tuple[float, float] = (6.4, 4.6)) -> Axes:
    """Return ``ax``, or the axes of a new :class:`~matplotlib.figure.Figure` [inch size]."""
    if ax is not None:
        return ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def figure_of(ax: Axes) -> Figure:
    """The top-level :class:`~matplotlib.figure.Figure` that holds ``ax``."""
    fig = ax.figure
    assert isinstance(fig, Figure)
    return fig


def _render(fig: Figure, path: Path | io.BytesIO, fmt: str, dpi: int) -> None:
    """One draw of ``fig`` into ``path`` by the canvas of ``fmt`` (Agg for PNG).

    SVG files carry no date and fixed element ids, so the same figure gives the same bytes.
    """
    kwargs: dict[str, Any] = {"metadata": {"Date": None}} if fmt == "svg" else {}
    if fmt == "png":
        kwargs["pil_kwargs"] = {"compress_level": _PNG_COMPRESS_LEVEL}
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "splinecontact"}):
        fig.savefig(path, dpi=dpi, format=fmt, **kwargs)


def render_figure(
    fig: Figure, *, formats: Sequence[str] = ("png", "svg"), dpi: int = 150
) -> dict[str, bytes]:
    """The bytes of ``fig`` in each of ``formats``: what :func:`save_figure` writes, in memory.

    One draw per format, the constrained layout frozen after the first (as in
    :func:`save_figure`), so a figure can be drawn in another process (figures pickle) and its
    files written here by :func:`write_rendered`.
    """
    out: dict[str, bytes] = {}
    for i, fmt in enumerate(formats):
        buffer = io.BytesIO()
        _render(fig, buffer, fmt, dpi)
        out[fmt] = buffer.getvalue()
        if i == 0 and fig.get_layout_engine() is not None:
            fig.set_layout_engine("none")  # keep the first layout: no second constrained layout
    return out


def write_rendered(
    rendered: Mapping[str, Mapping[str, bytes]], folder: OutputFolder, *, prefix: str = ""
) -> dict[str, list[Path]]:
    """Write figures drawn by :func:`render_figure` (name → format → bytes) into ``folder``.

    Each file follows the package's output rule: announced to ``folder``, written to a
    temporary name beside it and renamed (no partial file).

    Returns
    -------
    dict of str to list of Path
        Name → written files, in the order of ``rendered``.
    """
    written: dict[str, list[Path]] = {}
    for name, files in rendered.items():
        paths = []
        for fmt, data in files.items():
            path = folder.file(f"{prefix}{name}.{fmt}")
            with atomic_path(path) as tmp:
                tmp.write_bytes(data)
            paths.append(path)
        written[name] = paths
    return written


def save_figure(
    fig: Figure, stem: str | Path, *, formats: Sequence[str] = ("png", "svg"), dpi: int = 150
) -> list[Path]:
    """Write ``fig`` as ``stem.png`` and ``stem.svg`` (or ``formats``) and return the paths.

    One draw per format: the constrained layout is computed by the first draw and then frozen,
    so the second format reuses it (same positions, no second layout pass). Each file is
    written to a temporary name beside it and renamed (no partial file). The folder of
    ``stem`` must exist. For a folder of figures use :func:`write_figures`, which follows the
    package's output rule.

    Parameters
    ----------
    fig : Figure
        The figure.
    stem : path
        File name without suffix.
    formats : sequence of str
        File formats (suffixes).
    dpi : int
        Resolution of raster formats [dots per inch].
    """
    stem = Path(stem)
    paths = []
    for i, fmt in enumerate(formats):
        path = stem.with_name(f"{stem.name}.{fmt}")
        with atomic_path(path) as tmp:
            _render(fig, tmp, fmt, dpi)
        if i == 0 and fig.get_layout_engine() is not None:
            fig.set_layout_engine("none")  # keep the first layout: no second constrained layout
        paths.append(path)
    return paths


def write_figures(
    figures: Mapping[str, Figure],
    out: str | Path | OutputFolder,
    *,
    prefix: str = "",
    overwrite: bool = False,
    command: str = "plot",
    formats: Sequence[str] = ("png", "svg"),
    dpi: int = 150,
) -> dict[str, list[Path]]:
    """Write each figure as ``NAME.png`` and ``NAME.svg``, under the package's output rule.

    Parameters
    ----------
    figures : mapping of str to Figure
        Name → figure.
    out : path or OutputFolder
        A folder path (prepared with :func:`splinecontact.outputs.prepare_output_folder`: a
        non-empty folder is refused unless splinecontact wrote it and ``overwrite`` is given),
        or an already prepared :class:`~splinecontact.outputs.OutputFolder`.
    prefix : str
        Sub-folder of ``out`` for the files (e.g. ``"figures/"``).
    overwrite : bool
        Whether a folder splinecontact wrote earlier may be reused.
    command : str
        Command recorded in the folder's marker.
    formats : sequence of str
        File formats.
    dpi : int
        Resolution of raster formats [dots per inch].

    Returns
    -------
    dict of str to list of Path
        Name → written files. Every file is written to a temporary name and renamed; each
        figure is drawn once per format (:func:`save_figure`).
    """
    folder = (
        out
        if isinstance(out, OutputFolder)
        else prepare_output_folder(out, overwrite=overwrite, command=command)
    )
    written: dict[str, list[Path]] = {}
    for name, fig in figures.items():
        for fmt in formats:
            folder.file(f"{prefix}{name}.{fmt}")
        written[name] = save_figure(fig, folder.path / f"{prefix}{name}", formats=formats, dpi=dpi)
    return written


def dimension_colors(values: Sequence[float] | NDArray[Any]) -> dict[float, Any]:
    """A viridis colour per fractal dimension (or any ordered parameter), dark = low."""
    vals = [float(v) for v in np.asarray(values, dtype=float)]
    cmap = matplotlib.colormaps["viridis"]
    lo, hi = min(vals), max(vals)
    span = hi - lo if hi > lo else 1.0
    return {v: cmap(0.9 * (v - lo) / span) for v in vals}


def decimate(
    x: NDArray[np.float64], z: NDArray[np.float64], max_points: int = DECIMATE_POINTS
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Reduce a long curve to what a figure can show: the min and max of each bin, in x order.

    A profile of 10⁶ points drawn on an axes about 1000 pixels wide puts ~1000 points on
    each pixel column; the eye sees only their vertical extent. The curve is cut into
    ``max_points // 2`` bins of equal point count and each bin is kept as its lowest and
    highest point (in their x order), so every peak and valley stays visible and the drawn
    line covers the same pixels, while the path holds at most ``max_points`` vertices.
    Curves of at most ``max_points`` points are returned unchanged.

    Parameters
    ----------
    x, z : ndarray
        Abscissae (increasing) and ordinates, same length [any unit].
    max_points : int
        Points kept at most (default :data:`DECIMATE_POINTS`, twice the pixel width).

    Returns
    -------
    (ndarray, ndarray)
        The kept abscissae and ordinates.
    """
    n = x.size
    bins = max_points // 2
    if n <= max_points:
        return x, z
    size = n // bins
    m = bins * size
    zb = z[:m].reshape(bins, size)
    xb = x[:m].reshape(bins, size)
    imin = zb.argmin(axis=1)
    imax = zb.argmax(axis=1)
    first = np.minimum(imin, imax)
    second = np.maximum(imin, imax)
    rows = np.arange(bins)
    xo = np.column_stack([xb[rows, first], xb[rows, second]]).ravel()
    zo = np.column_stack([zb[rows, first], zb[rows, second]]).ravel()
    return xo, zo


def window(x: NDArray[np.float64], xlim: tuple[float, float] | None) -> NDArray[np.bool_]:
    """Mask of the points of ``x`` inside ``xlim`` [same unit] (all points when ``None``)."""
    if xlim is None:
        return np.ones(x.shape, dtype=bool)
    return np.asarray((x >= xlim[0]) & (x <= xlim[1]))


def draw_ensemble_vs_dimension(ax: Axes, studies: dict[str, Any], name: str) -> tuple[str, float]:
    """Draw the ensemble mean of variable ``name`` against D with its confidence band, one curve
    per study (datasets with ``dimension``, ``<name>_mean`` and ``<name>_ci``).

    Returns
    -------
    (units, level)
        The variable's units and the confidence level [1] of the band (0.95 without studies).
    """
    units, level = "", 0.95
    for label, ds in studies.items():
        d = ds["dimension"].values
        mean = ds[f"{name}_mean"].values
        ci = ds[f"{name}_ci"].values
        (line,) = ax.plot(d, mean, "o-", label=label)
        ax.fill_between(d, mean - ci, mean + ci, color=line.get_color(), alpha=0.2, lw=0)
        units = ds[name].attrs.get("units", "")
        level = float(ds.attrs.get("confidence", 0.95))
    return units, level
