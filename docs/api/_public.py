"""The public surface of splinecontact, and where each public name is documented.

Used by ``docs/api/_generate.py`` (writes the API pages), by ``docs/conf.py`` (resolves
``splinecontact.X`` cross-references to the page that documents ``X``) and by
``tests/test_docs_api.py`` (every public name is in the API pages). Needs no Sphinx.

A module is public when no component of its dotted name starts with an underscore; its public
names are its ``__all__``. A class or function is documented once, at its *home*: the public
module it is defined in (private submodules folded into their public parent) when that module
lists it in ``__all__``; anywhere else it is listed as a re-export with a link to its home.
Constants and type aliases are documented where they are exported.
"""

from __future__ import annotations

import importlib
import pkgutil
from types import ModuleType

PACKAGE = "splinecontact"


def public_modules() -> list[str]:
    """Dotted names of the package and of every public submodule, sorted."""
    package = importlib.import_module(PACKAGE)
    names = [PACKAGE]
    for info in pkgutil.walk_packages(package.__path__, PACKAGE + "."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


def public_names(module: str) -> list[str]:
    """The ``__all__`` of ``module`` (a module without one exports nothing)."""
    mod: ModuleType = importlib.import_module(module)
    return list(getattr(mod, "__all__", []))


def _public_parent(dotted: str) -> str:
    parts = dotted.split(".")
    keep: list[str] = []
    for part in parts:
        if part.startswith("_"):
            break
        keep.append(part)
    return ".".join(keep)


def home(module: str, name: str) -> str:
    """The module whose API page documents ``module.name`` in full."""
    obj = getattr(importlib.import_module(module), name)
    defined = getattr(obj, "__module__", None)
    if not (isinstance(obj, type) or callable(obj)) or not isinstance(defined, str):
        return module
    if not defined.startswith(PACKAGE):
        return module
    parent = _public_parent(defined)
    if parent != module and name in public_names(parent):
        return parent
    return module


def kind(module: str, name: str) -> str:
    """``"class"``, ``"exception"``, ``"function"`` or ``"data"``: the autodoc directive."""
    obj = getattr(importlib.import_module(module), name)
    if isinstance(obj, type):
        return "exception" if issubclass(obj, BaseException) else "class"
    if callable(obj) and getattr(obj, "__module__", "").startswith(PACKAGE):
        return "function"
    return "data"
