"""Figures of the paper (Figs. 3a, 4, 5, 8, 9, 10, 11, 12), of single results and of friction.

Two kinds of figures, in separate modules:

- **study figures drawn from datasets** — Figs. 10, 11, 12 and the force-split diagnostics
  from a study Dataset (:func:`study_figures`), the four curves of one ``simulate`` result
  (:func:`result_figures`), and the friction figures (:func:`plot_friction_loop`,
  :func:`plot_path_history`, :func:`plot_study_vs_dimension`), and the contact-law study
  figure (:func:`plot_laws_study`);
- **illustrative figures drawn from profiles passed in** — Figs. 3a, 4, 5, 8 and 9
  (:func:`plot_profiles`, :func:`plot_spline_fits`, :func:`plot_spheres`,
  :func:`plot_first_contact`, :func:`plot_contact_zoom`; all five at once from an
  :class:`IllustrativeInputs` by :func:`illustrative_figures`). Nothing in this package
  generates a profile: ``splinecontact reproduce`` and ``splinecontact plot`` regenerate the
  study's own realization-0 profiles once and hand them down.

Every plotting function takes ``ax=`` (a matplotlib ``Axes``; a new figure is made when it is
``None``) and returns the axes, so figures can be composed freely. No pyplot state is used and
importing this package never changes the matplotlib backend: new figures are
:class:`matplotlib.figure.Figure` objects, written by their own canvas, once per format
(:func:`write_figures`, under the package's output rule). Curves longer than the pixel
resolution are decimated before drawing (:func:`decimate`). Axes carry their units: lengths
µm (heights in nm where they are nanometre-sized), forces mN per µm of thickness.
"""

from __future__ import annotations

from ._base import (
    decimate,
    dimension_colors,
    new_axes,
    render_figure,
    save_figure,
    write_figures,
    write_rendered,
)
from ._figures import FIGURE_FILES, build_figures, make_figures
from ._friction import plot_friction_loop, plot_path_history, plot_study_vs_dimension
from ._illustrative import IllustrativeInputs, illustrative_figures, make_illustrative_figures
from ._laws import LAWS_STUDY_LABELS, plot_laws_study
from ._profiles import (
    plot_contact_zoom,
    plot_first_contact,
    plot_profiles,
    plot_spheres,
    plot_spline_fits,
)
from ._result import RESULT_FIGURES, result_figures
from ._study import (
    drawable_study,
    make_study_figures,
    plot_area_force,
    plot_dimensionless_stiffness,
    plot_force_displacement,
    plot_force_split,
    plot_kappa_hurst,
    plot_separation_force,
    study_figures,
)

__all__ = [
    "FIGURE_FILES",
    "LAWS_STUDY_LABELS",
    "RESULT_FIGURES",
    "IllustrativeInputs",
    "build_figures",
    "decimate",
    "dimension_colors",
    "drawable_study",
    "illustrative_figures",
    "make_figures",
    "make_illustrative_figures",
    "make_study_figures",
    "new_axes",
    "plot_area_force",
    "plot_contact_zoom",
    "plot_dimensionless_stiffness",
    "plot_first_contact",
    "plot_force_displacement",
    "plot_force_split",
    "plot_friction_loop",
    "plot_kappa_hurst",
    "plot_laws_study",
    "plot_path_history",
    "plot_profiles",
    "plot_separation_force",
    "plot_spheres",
    "plot_spline_fits",
    "plot_study_vs_dimension",
    "render_figure",
    "result_figures",
    "save_figure",
    "study_figures",
    "write_figures",
    "write_rendered",
]
