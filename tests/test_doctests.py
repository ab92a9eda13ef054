"""The ``Examples`` sections of the public functions' docstrings run and hold.

Each example is tiny (≤ 2¹² points, ≤ 50 steps); the numba kernels they use are compiled once
per process (and cached), as for the other tests.
"""

from __future__ import annotations

import doctest
import importlib

import pytest

# Dotted names of the documented entry points whose docstrings carry an ``Examples`` section.
WITH_EXAMPLES = [
    "splinecontact.Profile",
    "splinecontact.weierstrass_mandelbrot",
    "splinecontact.weierstrass_mandelbrot_pair",
    "splinecontact.fit_spline",
    "splinecontact.surface_spheres",
    "splinecontact.read_profile",
    "splinecontact.compare_profiles",
    "splinecontact.preprocess.to_profile",
    "splinecontact.bem.load_path",
    "splinecontact.schema",
]

# Entry points whose examples are placed when their modules are moved into packages.
PENDING = [
    "splinecontact.simulate",
    "splinecontact.study.run_study",
    "splinecontact.study.open_study",
    "splinecontact.analysis.ensemble_vs_displacement",
    "splinecontact.analysis.kappa",
]


def _resolve(dotted: str) -> object:
    try:
        return importlib.import_module(dotted)
    except ImportError:
        module, _, name = dotted.rpartition(".")
        return getattr(importlib.import_module(module), name)


def _run(dotted: str) -> tuple[int, int, str]:
    """Run the doctests in one object's docstring: (failed, attempted, report)."""
    import io

    obj = _resolve(dotted)
    finder = doctest.DocTestFinder(recurse=False)
    runner = doctest.DocTestRunner(
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False
    )
    out = io.StringIO()
    for test in finder.find(obj, dotted, globs={}):
        runner.run(test, out=out.write)
    failed, attempted = runner.summarize(verbose=False)
    return failed, attempted, out.getvalue()


@pytest.mark.parametrize("dotted", WITH_EXAMPLES)
def test_docstring_examples_run(dotted: str) -> None:
    failed, attempted, report = _run(dotted)
    assert attempted > 0, f"{dotted} has no Examples section"
    assert failed == 0, report


@pytest.mark.parametrize("dotted", PENDING)
def test_entry_points_have_examples(dotted: str) -> None:
    doc = getattr(_resolve(dotted), "__doc__", None) or ""
    assert "Examples\n" in doc, f"{dotted}: no Examples section in its docstring"
    failed, attempted, report = _run(dotted)
    assert attempted > 0 and failed == 0, report
