"""The API reference lists every public name, and the docs' sources are consistent.

Fast (no Sphinx build): imports every public module, collects its ``__all__`` and checks the
API pages in ``docs/api`` document each name (at its home module) or link to it.
"""

from __future__ import annotations

import importlib
import inspect
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
API = ROOT / "docs" / "api"
sys.path.insert(0, str(API))

from _public import home, kind, public_modules, public_names  # noqa: E402

DIRECTIVES = {
    "function": "autofunction",
    "class": "autoclass",
    "exception": "autoexception",
    "data": "autodata",
}


def _api_text() -> str:
    return "\n".join(p.read_text(encoding="utf-8") for p in sorted(API.glob("*.rst")))


def _page_of(module: str) -> Path:
    stem = "package" if module == "splinecontact" else module.removeprefix("splinecontact.")
    return API / f"{stem}.rst"


MODULES = public_modules()


def test_the_public_modules_include_the_ones_users_import() -> None:
    for name in (
        "splinecontact",
        "splinecontact.io",
        "splinecontact.bem",
        "splinecontact.reference",
        "splinecontact.compare",
        "splinecontact.study",
        "splinecontact.analysis",
        "splinecontact.plotting",
        "splinecontact.outputs",
        "splinecontact.errors",
    ):
        assert name in MODULES


@pytest.mark.parametrize("module", MODULES)
def test_every_public_module_has_an_api_page_in_the_index(module: str) -> None:
    page = _page_of(module)
    assert page.is_file(), f"no API page for {module}: run `python docs/api/_generate.py`"
    assert f".. automodule:: {module}\n" in page.read_text(encoding="utf-8")
    assert f"   {page.stem}\n" in (API / "index.rst").read_text(encoding="utf-8")


@pytest.mark.parametrize("module", MODULES)
def test_every_public_name_is_in_the_api_reference(module: str) -> None:
    text = _api_text()
    page = _page_of(module).read_text(encoding="utf-8")
    missing = []
    for name in public_names(module):
        where = home(module, name)
        documented = f".. {DIRECTIVES[kind(where, name)]}:: {where}.{name}\n"
        if documented not in text:
            missing.append(f"{module}.{name} (expected `{documented.strip()}`)")
        elif where != module and f"<{where}.{name}>`" not in page:
            missing.append(f"{module}.{name} (no link from the {module} page)")
    assert not missing, "not in docs/api (run `python docs/api/_generate.py`): " + ", ".join(
        missing
    )


def test_every_documented_name_exists() -> None:
    """The pages document nothing that the package no longer has."""
    for match in re.finditer(
        r"^\.\. auto(?:function|class|exception|data):: (\S+)$", _api_text(), re.M
    ):
        module, _, name = match.group(1).rpartition(".")
        assert hasattr(importlib.import_module(module), name), match.group(1)
        assert name in public_names(module), f"{match.group(1)} is not in {module}.__all__"


def test_public_names_are_documented_once() -> None:
    targets = re.findall(r"^\.\. auto(?:function|class|exception):: (\S+)$", _api_text(), re.M)
    objects = [
        getattr(importlib.import_module(t.rpartition(".")[0]), t.rpartition(".")[2])
        for t in targets
    ]
    ids = [id(o) for o in objects]
    duplicates = {t for t, i in zip(targets, ids, strict=True) if ids.count(i) > 1}
    assert not duplicates, f"documented more than once (ambiguous references): {duplicates}"


def test_the_guides_are_all_in_the_site() -> None:
    """The guides' toctree names the known pages and globs the others (changelog.md, so that
    the glob is never empty, and new pages such as architecture.md)."""
    index = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    guides = index[index.index(":caption: Guides") :]
    assert ":glob:" in guides.split("```")[0]
    assert "\n*\n" in guides.split("```")[0]
    for page in sorted((ROOT / "docs").glob("*.md")):
        if page.stem in ("index", "architecture", "changelog"):  # globbed
            continue
        assert f"\n{page.stem}\n" in index, f"docs/{page.name} is not in the toctree of index.md"


def test_every_gallery_example_is_executed_by_the_build() -> None:
    """sphinx-gallery runs the files matching ``filename_pattern`` (``/plot_``) only."""
    for folder in (ROOT / "examples" / "gallery", ROOT / "docs" / "tutorial_src"):
        scripts = sorted(folder.glob("*.py"))
        assert scripts, folder
        assert all(p.name.startswith("plot_") for p in scripts), scripts
        assert (folder / "README.txt").is_file()


def test_the_gallery_has_each_of_the_papers_figures_3_to_12() -> None:
    names = [p.name for p in (ROOT / "examples" / "gallery").glob("plot_*.py")]
    for figure in range(3, 13):
        assert any(n.startswith(f"plot_{figure:02d}_") for n in names), f"no Fig. {figure}"


_FLOAT_TYPES = re.compile(
    r"(float|float or None|float \| None|array_like of float|ndarray of float|sequence of float)"
)


def _parameter_entries(doc: str) -> list[tuple[str, str, str]]:
    """(name, type, description) of the Parameters and Attributes sections of a numpydoc text."""
    lines = inspect.cleandoc(doc).splitlines()
    entries: list[tuple[str, str, str]] = []
    section = None
    for i, line in enumerate(lines):
        if i + 1 < len(lines) and set(lines[i + 1].strip()) == {"-"} and line.strip():
            section = line.strip()
            continue
        if section not in ("Parameters", "Attributes") or not line or line[0] == " ":
            continue
        if set(line.strip()) == {"-"}:
            continue
        name, _, type_ = line.partition(" : ")
        desc = []
        for follow in lines[i + 1 :]:
            if follow and not follow.startswith(" "):
                break
            desc.append(follow.strip())
        entries.append((name.strip(), type_.strip(), " ".join(desc)))
    return entries


def test_every_real_valued_parameter_names_its_unit() -> None:
    """Every float parameter or attribute of the public API states its unit in brackets
    ([µm], [GPa], [mN/µm], or [1] when dimensionless), as the API reference promises."""
    missing = []
    for module in MODULES:
        for name in public_names(module):
            if home(module, name) != module:
                continue
            obj = getattr(importlib.import_module(module), name)
            if not (inspect.isclass(obj) or inspect.isfunction(obj)) or not obj.__doc__:
                continue
            for param, type_, desc in _parameter_entries(obj.__doc__):
                if _FLOAT_TYPES.fullmatch(type_.split(",")[0].strip()) and "[" not in desc + type_:
                    missing.append(f"{module}.{name}({param})")
    assert not missing, "float parameters without a [unit]: " + ", ".join(missing)


def test_docs_name_only_what_the_repository_holds() -> None:
    """No reference to design notes or trackers a reader of the repository cannot open."""
    pattern = re.compile(r"PHYSICS\.md|STYLE\.md|\b[Ii]ssue [0-9]+|\bissue #|shared/")
    texts = [ROOT / "README.md", ROOT / "CHANGELOG.md"]
    texts += sorted((ROOT / "docs").glob("*.md"))
    texts += sorted((ROOT / "src").rglob("*.py"))
    texts += sorted((ROOT / "examples").rglob("*.py")) + sorted((ROOT / "benchmarks").rglob("*.py"))
    found = [
        f"{path.relative_to(ROOT)}:{number}"
        for path in texts
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if pattern.search(line)
    ]
    assert not found, "references outside the repository: " + ", ".join(found)
