"""Sphinx configuration of the splinecontact documentation.

Build (warnings are errors, examples executed)::

    bash .ci/docs            # or: python -m sphinx -W --keep-going -b html docs docs/_build/html
"""

from __future__ import annotations

import importlib
import os
import re
import sys
from pathlib import Path

from sphinx.util import logging

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "src"))  # document this tree's code, installed or not
sys.path.insert(0, str(DOCS / "api"))

import splinecontact  # noqa: E402

project = "splinecontact"
author = "splinecontact developers"
copyright = "splinecontact developers (MIT licence)"
version = release = splinecontact.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "tutorial_src",
    "gallery/*.md5",
    "tutorial/*.md5",
    "**/*.ipynb",
]
templates_path: list[str] = []

# --- Markdown pages (the hand-written guides) ---------------------------------------------------
myst_enable_extensions = ["dollarmath", "colon_fence", "substitution"]
myst_substitutions = {"version": release}
myst_heading_anchors = 3

# --- API reference ------------------------------------------------------------------------------
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # the numpydoc sections carry types and units
autodoc_preserve_defaults = True
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# --- Executed examples: the tutorial and the gallery ---------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": [str(ROOT / "examples" / "gallery"), str(DOCS / "tutorial_src")],
    "gallery_dirs": ["gallery", "tutorial"],
    "filename_pattern": r"/plot_",  # every example is executed
    "within_subsection_order": "sphinx_gallery.sorting.FileNameSortKey",
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "plot_gallery": os.environ.get("SPLINECONTACT_DOCS_EXAMPLES", "1") != "0",
    "show_memory": False,
    "min_reported_time": 1,
    # Each example page states its own running time; no separate top-level page (the guides
    # toctree globs top-level pages).
    "write_computation_times": False,
}

# --- HTML ---------------------------------------------------------------------------------------
html_theme = "alabaster"
html_title = f"splinecontact {release}"
html_static_path: list[str] = []
html_theme_options = {
    "description": "Contact mechanics of rough surfaces by spline assisted discretization",
    "fixed_sidebar": True,
}

# --- Cross-references to re-exported names --------------------------------------------------------
_log = logging.getLogger("splinecontact.docs")


def _candidates(target: str, module: str | None) -> list[str]:
    """Fully qualified names a reference may mean: as written, in the current module, or a
    top-level name of the package."""
    if target.startswith("splinecontact"):
        return [target]
    names = []
    if module and module.startswith("splinecontact"):
        names.append(f"{module}.{target}")
    names.append(f"splinecontact.{target}")
    return names


def _resolve_reexport(app, env, node, contnode):  # type: ignore[no-untyped-def]
    """Send a reference to a re-exported name to the page that documents it.

    ``splinecontact.Profile`` is documented as ``splinecontact.profile.Profile``; the
    references in the docstrings use either. References into the package that nothing
    documents are warnings (errors under ``-W``); references to other projects (numpy,
    xarray, ...) are left as plain text.
    """
    if node.get("refdomain") != "py":
        return None
    from _public import home

    target = str(node.get("reftarget", ""))
    domain = env.get_domain("py")
    for candidate in _candidates(target, node.get("py:module")):
        module_name, _, name = candidate.rpartition(".")
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        if not hasattr(module, name):
            continue
        try:
            where = home(module_name, name)
        except (AttributeError, ValueError):
            continue
        found = domain.resolve_xref(
            env, node["refdoc"], app.builder, node["reftype"], f"{where}.{name}", node, contnode
        )
        if found is not None:
            return found
    if target.startswith("splinecontact."):
        _log.warning("unresolved reference to %s", target, location=node)
    return None


_LITERAL = re.compile(r"(``.*?``|:math:`[^`]*`|`[^`]*`_?)")


def _escape_bars(app, what, name, obj, options, lines):  # type: ignore[no-untyped-def]
    """Docstrings write |x| for a magnitude; reStructuredText would read a substitution."""
    for i, line in enumerate(lines):
        if "|" not in line or line.lstrip().startswith(("|", "+-", "+=")):
            continue
        parts = _LITERAL.split(line)
        lines[i] = "".join(
            part if k % 2 else re.sub(r"(?<!\\)\|", r"\\|", part) for k, part in enumerate(parts)
        )


def setup(app):  # type: ignore[no-untyped-def]
    app.connect("missing-reference", _resolve_reexport)
    app.connect("autodoc-process-docstring", _escape_bars)
