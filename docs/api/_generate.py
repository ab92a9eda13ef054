"""Write the API reference pages ``docs/api/*.rst`` from the package's ``__all__`` lists.

Run after adding or removing a public module or name::

    PYTHONPATH=src python docs/api/_generate.py

``tests/test_docs_api.py`` fails while a public name is missing from these pages.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from _public import PACKAGE, home, kind, public_modules, public_names  # noqa: E402

SECTIONS = (
    ("function", "Functions"),
    ("class", "Classes"),
    ("exception", "Exceptions"),
    ("data", "Constants and types"),
)
DIRECTIVE = {
    "function": "autofunction",
    "class": "autoclass",
    "exception": "autoexception",
    "data": "autodata",
}
ROLE = {"function": "func", "class": "class", "exception": "exc", "data": "data"}


def page_name(module: str) -> str:
    """File stem of a module's page (``splinecontact.io`` → ``io``)."""
    return "package" if module == PACKAGE else module.removeprefix(PACKAGE + ".")


def _summary(module: str) -> str:
    doc = importlib.import_module(module).__doc__ or ""
    return doc.strip().splitlines()[0].rstrip(".") if doc.strip() else ""


def module_page(module: str) -> str:
    """The reStructuredText of one module's API page."""
    title = f"``{module}``"
    lines = [
        ".. Written by docs/api/_generate.py; edit the docstrings, not this file.",
        "",
        title,
        "=" * len(title),
        "",
        f".. automodule:: {module}",
        "",
    ]
    own: dict[str, list[str]] = {key: [] for key, _ in SECTIONS}
    elsewhere: list[tuple[str, str, str]] = []
    for name in public_names(module):
        where = home(module, name)
        what = kind(module, name)
        if where == module:
            own[what].append(name)
        else:
            elsewhere.append((name, where, what))
    for key, heading in SECTIONS:
        names = sorted(own[key], key=str.lower)
        if not names:
            continue
        lines += [heading, "-" * len(heading), ""]
        for name in names:
            lines.append(f".. {DIRECTIVE[key]}:: {module}.{name}")
            if key == "class":
                lines.append("   :members:")
            if key in ("class", "exception"):
                lines.append("   :show-inheritance:")
            lines.append("")
    if elsewhere:
        heading = "Also available here"
        lines += [
            heading,
            "-" * len(heading),
            "",
            f"Importable from ``{module}``, documented where they are defined:",
            "",
        ]
        for name, where, what in sorted(elsewhere, key=lambda t: t[0].lower()):
            lines.append(f"* :{ROLE[what]}:`{name} <{where}.{name}>` (:mod:`{where}`)")
        lines.append("")
    return "\n".join(lines)


def index_page(modules: list[str]) -> str:
    """The API reference's index page with one toctree entry per module."""
    lines = [
        ".. Written by docs/api/_generate.py.",
        "",
        "API reference",
        "=============",
        "",
        "Every public name of the package, generated from its docstrings. Units are given in",
        "brackets after each parameter: lengths [µm], moduli [GPa], forces [mN/µm] (per µm of",
        "out-of-plane thickness), dimensionless quantities [1].",
        "",
        ".. list-table::",
        "   :header-rows: 1",
        "",
        "   * - Module",
        "     - Contents",
    ]
    for module in modules:
        lines += [f"   * - :mod:`{module}`", f"     - {_summary(module)}"]
    lines += ["", ".. toctree::", "   :hidden:", ""]
    lines += [f"   {page_name(m)}" for m in modules]
    lines.append("")
    return "\n".join(lines)


def main() -> None:
    modules = public_modules()
    for old in HERE.glob("*.rst"):
        old.unlink()
    for module in modules:
        (HERE / f"{page_name(module)}.rst").write_text(module_page(module), encoding="utf-8")
    (HERE / "index.rst").write_text(index_page(modules), encoding="utf-8")
    print(f"wrote {len(modules) + 1} pages to {HERE}")


if __name__ == "__main__":
    main()
