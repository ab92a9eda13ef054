"""Provenance of a study store: the fingerprint of the engine code a realization runs."""

from __future__ import annotations

import ast
import functools
import hashlib
from collections.abc import Iterator
from pathlib import Path

__all__ = ["engine_fingerprint"]

#: The package of the runner itself: not part of the engine fingerprint.
_RUNNER_PACKAGE = "study"
#: The module a realization starts from (its imports are followed).
_ENGINE_ROOT = "study.runner"


def _module_file(root: Path, name: str) -> Path | None:
    """The source file of package module ``name`` (dotted, relative to the package root)."""
    file = root.joinpath(*name.split(".")).with_suffix(".py")
    if file.is_file():
        return file
    file = root.joinpath(*name.split("."), "__init__.py")
    return file if file.is_file() else None


def _relative_imports(name: str, file: Path) -> Iterator[str]:
    """The package modules that module ``name`` imports relatively (inside functions too)."""
    parts = name.split(".")
    package = parts if file.name == "__init__.py" else parts[:-1]
    for node in ast.walk(ast.parse(file.read_bytes())):
        if not (isinstance(node, ast.ImportFrom) and node.level >= 1):
            continue
        base = package[: len(package) - (node.level - 1)] if node.level > 1 else package
        if node.module:
            yield ".".join([*base, node.module])
            for alias in node.names:  # ``from .io import _text`` imports a submodule
                yield ".".join([*base, node.module, alias.name])
        else:
            for alias in node.names:
                yield ".".join([*base, alias.name])


@functools.cache
def engine_fingerprint() -> str:
    """SHA-256 (16 hex digits) of the source of every package module a realization runs.

    The modules are found by following the package-relative imports of the runner
    (:mod:`splinecontact.study.runner`, those inside functions too) and of the engine modules
    they reach, so a new engine module is covered without a list to maintain. The study package
    itself (config, store, executors, runner) is excluded. A store records it;
    resuming with another fingerprint is refused, because the store would mix results of two
    codes.
    """
    root = Path(__file__).resolve().parents[1]
    todo, seen = [_ENGINE_ROOT], set()
    digest = hashlib.sha256()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        file = _module_file(root, name)
        if file is None:
            continue
        seen.add(name)
        # the rest of the study package (files, store, executors) is not run by a realization
        if name == _ENGINE_ROOT or name.split(".")[0] != _RUNNER_PACKAGE:
            todo.extend(_relative_imports(name, file))
    for name in sorted(seen):
        if name.split(".")[0] == _RUNNER_PACKAGE:
            continue
        file = _module_file(root, name)
        assert file is not None
        digest.update(name.encode() + b"\0" + file.read_bytes() + b"\0")
    return digest.hexdigest()[:16]
