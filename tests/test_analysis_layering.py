"""The analysis and reproduce stages import only stages below them, and raise errors.py classes."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import pytest

import splinecontact
from splinecontact import analysis, errors, reproduce

SRC = Path(splinecontact.__file__).resolve().parent

#: Package stages each of these may not import (the ones above it in the pipeline).
FORBIDDEN = {
    "analysis": ("plotting", "reproduce", "cli"),
    "reproduce": ("cli",),
}


def _imported_modules(path: Path) -> set[str]:
    """Dotted names (without ``splinecontact.``) of every module a file imports."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    # the package holding the file: the anchor of its relative imports
    here = ["splinecontact", *path.relative_to(SRC).parts[:-1]]
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - (node.level - 1)]
                mod = ".".join([*base, node.module] if node.module else base)
            else:
                mod = node.module or ""
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)
    return {m.removeprefix("splinecontact.") for m in out if m.startswith("splinecontact.")}


@pytest.mark.parametrize("stage", sorted(FORBIDDEN))
def test_no_stage_imports_a_stage_above_it(stage: str) -> None:
    files = sorted((SRC / stage).rglob("*.py"))
    assert files, stage
    bad = []
    for path in files:
        for mod in _imported_modules(path):
            if mod.split(".")[0] in FORBIDDEN[stage]:
                bad.append(f"{path.relative_to(SRC)} imports splinecontact.{mod}")
    assert not bad, bad


def test_the_import_scanner_sees_relative_imports() -> None:
    mods = _imported_modules(SRC / "reproduce" / "report.py")
    assert "analysis" in mods and "reproduce.findings" in mods


@pytest.mark.parametrize("stage", sorted(FORBIDDEN))
def test_no_file_of_the_stage_is_over_600_lines(stage: str) -> None:
    for path in (SRC / stage).rglob("*.py"):
        n = len(path.read_text(encoding="utf-8").splitlines())
        assert n <= 600, f"{path.relative_to(SRC)}: {n} lines"


def test_the_stage_errors_are_defined_in_errors_and_exported_at_the_top() -> None:
    for name in ("AnalysisError", "FrictionAnalysisError"):
        cls = getattr(errors, name)
        assert cls.__module__ == "splinecontact.errors"
        assert name in errors.__all__ and name in splinecontact.__all__
        assert getattr(splinecontact, name) is cls is getattr(analysis, name)
        assert issubclass(cls, errors.SplineContactError)
    assert issubclass(errors.AnalysisError, ValueError)
    assert issubclass(errors.FrictionAnalysisError, errors.ParameterError)


def test_no_exception_class_is_defined_in_the_stages() -> None:
    for module in (analysis, reproduce):
        for path in Path(module.__file__).parent.rglob("*.py"):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in ast.walk(tree):
                if isinstance(node, ast.ClassDef):
                    assert not node.name.endswith(("Error", "Warning")), (path, node.name)


def test_report_kappa_defaults_are_kappa_s_own() -> None:
    """The report describes the κ defaults that :func:`analysis.kappa` uses."""
    from splinecontact.analysis import _defaults

    sig = inspect.signature(analysis.kappa).parameters
    assert sig["fit_fraction"].default == _defaults.DEFAULT_FIT_FRACTION
    assert sig["rsq_source"].default == _defaults.DEFAULT_RSQ_SOURCE
    assert sig["rsq_method"].default == _defaults.DEFAULT_RSQ_METHOD
