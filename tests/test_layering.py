"""The package's import order: no module imports a module above it in the pipeline.

The order (bottom first) is the one ``docs/architecture.md`` documents; a module may import
modules of its own layer or below. Each file is parsed, not imported, so a violation is found
even in an import inside a function.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import splinecontact

ROOT = Path(splinecontact.__file__).parent

#: Layers, bottom first: the top-level module or package names of ``splinecontact``.
LAYERS: list[set[str]] = [
    {
        "_version",
        "errors",
        "_checks",
        "_memory",
        "_fft",
        "_roughness",
        "parameters",
        "schema",
        "outputs",
        "results",
    },
    {"profile"},
    {"preprocess", "spectra", "diagnostics"},
    {"generate", "io"},
    {"spline"},
    {"spheres"},
    {"contact"},
    {"bem", "reference", "compare"},
    {"study"},
    {"analysis"},
    {"plotting"},
    {"reproduce"},
    {"cli"},
    {"__init__", "__main__"},
]
LAYER = {name: i for i, names in enumerate(LAYERS) for name in names}


def _top(path: Path) -> str:
    return path.relative_to(ROOT).with_suffix("").parts[0]


def _imported_tops(path: Path) -> set[str]:
    """Top-level splinecontact modules imported anywhere in ``path``."""
    package = list(path.relative_to(ROOT).with_suffix("").parts)[:-1]
    return _imports_in(path.read_text(encoding="utf-8"), package)


def _imports_in(text: str, package: list[str]) -> set[str]:
    """Top-level splinecontact modules imported in source ``text`` of a module in ``package``."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom) and node.level > 0:
            base = package[: len(package) - (node.level - 1)]
            target = base + (node.module.split(".") if node.module else [])
            found |= {target[0]} if target else {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("splinecontact."):
            found.add(node.module.split(".")[1])  # type: ignore[union-attr]
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("splinecontact."):
                    found.add(alias.name.split(".")[1])
    return found


FILES = sorted(ROOT.rglob("*.py"))


def test_every_module_has_a_layer() -> None:
    missing = sorted({_top(f) for f in FILES} - set(LAYER))
    assert not missing, f"modules without a layer in docs/architecture.md: {missing}"


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_module_imports_a_module_above_it(path: Path) -> None:
    own = _top(path)
    above = sorted(t for t in _imported_tops(path) if t in LAYER and LAYER[t] > LAYER[own])
    assert not above, f"{path.relative_to(ROOT)} (layer of {own!r}) imports {above} above it"


def test_the_checker_sees_an_upward_import() -> None:
    """Planted violations are found (the test above can fail)."""
    inside = "def f():\n    from ..study import run_study\n"
    assert _imports_in(inside, ["contact"]) == {"study"}
    assert _imports_in("from . import analysis\n", []) == {"analysis"}
    assert _imports_in("import splinecontact.plotting\n", ["io"]) == {"plotting"}


def test_no_file_is_too_long_unless_it_is_one_algorithm() -> None:
    """Files over ~600 lines are the cohesive algorithms ``docs/architecture.md`` names."""
    allowed = LONG_FILES
    long = {
        str(f.relative_to(ROOT)): n
        for f in FILES
        if (n := len(f.read_text(encoding="utf-8").splitlines())) > 650
    }
    assert set(long) <= allowed, f"files over 650 lines not named as one algorithm: {long}"


#: Files over 650 lines, each one cohesive algorithm (see docs/architecture.md).
LONG_FILES: set[str] = set()
