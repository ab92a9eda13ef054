"""The preprocess, cli and io packages stay split by job: small files, imports one way, names kept."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import splinecontact
from splinecontact import preprocess

SRC = Path(splinecontact.__file__).resolve().parent

#: Modules of the package that preprocess may import (all below it in the pipeline).
PREPROCESS_MAY_IMPORT = {
    "errors",
    "_checks",
    "profile",
    "parameters",
    "schema",
    "outputs",
    "results",
    "_version",
}


def _package_imports(path: Path) -> set[str]:
    """First component (below ``splinecontact``) of every package module a file imports."""
    here = ["splinecontact", *path.relative_to(SRC).parts[:-1]]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = here[: len(here) - (node.level - 1)]
            dotted = [*base, *(node.module.split(".") if node.module else [])]
            names = [dotted] if node.module else [[*dotted, a.name] for a in node.names]
            out.update(parts[1] for parts in names if len(parts) > 1)
        elif isinstance(node, ast.ImportFrom):
            absolute = [node.module or ""]
            out.update(m.split(".")[1] for m in absolute if m.startswith("splinecontact."))
        elif isinstance(node, ast.Import):
            absolute = [a.name for a in node.names]
            out.update(m.split(".")[1] for m in absolute if m.startswith("splinecontact."))
    return out


@pytest.mark.parametrize("package", ["preprocess", "cli", "io"])
def test_no_file_of_the_package_is_over_600_lines(package: str) -> None:
    for path in (SRC / package).rglob("*.py"):
        n = len(path.read_text(encoding="utf-8").splitlines())
        assert n <= 600, f"{path.relative_to(SRC)}: {n} lines"


def test_preprocess_imports_only_modules_below_it() -> None:
    files = sorted((SRC / "preprocess").glob("*.py"))
    assert len(files) > 1
    for path in files:
        outside = _package_imports(path) - PREPROCESS_MAY_IMPORT - {"preprocess"}
        assert not outside, f"preprocess/{path.name} imports {sorted(outside)}"


def test_the_import_scanner_sees_relative_imports() -> None:
    found = _package_imports(SRC / "preprocess" / "_pipeline.py")
    assert {"errors", "profile", "preprocess"} <= found


def test_preprocess_keeps_its_public_names_and_the_top_level_ones() -> None:
    for name in preprocess.__all__:
        obj = getattr(preprocess, name)
        if name in splinecontact.__all__:
            assert getattr(splinecontact, name) is obj
    assert preprocess.to_profile.__module__.startswith("splinecontact.preprocess")
