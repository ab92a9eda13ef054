"""Every public exception is defined in ``splinecontact.errors`` and exported by the package."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import splinecontact
from splinecontact import errors
from splinecontact.errors import SplineContactError


def _all_subclasses(cls: type) -> set[type]:
    found: set[type] = set()
    for sub in cls.__subclasses__():
        found |= {sub, *_all_subclasses(sub)}
    return found


def _import_every_module() -> None:
    for info in pkgutil.walk_packages(splinecontact.__path__, "splinecontact."):
        if info.name.endswith("__main__"):
            continue
        try:
            importlib.import_module(info.name)
        except ImportError as error:  # an optional extra that is not installed
            if "splinecontact" in str(getattr(error, "name", "") or ""):
                raise


def test_every_error_class_is_defined_in_errors_and_exported() -> None:
    _import_every_module()
    classes = {c for c in _all_subclasses(SplineContactError) if not c.__name__.startswith("_")}
    classes.add(SplineContactError)
    assert len(classes) > 40
    for cls in sorted(classes, key=lambda c: c.__name__):
        name = cls.__name__
        assert cls.__module__ == "splinecontact.errors", f"{name} is defined in {cls.__module__}"
        assert name in errors.__all__, name
        assert getattr(errors, name) is cls, name
        assert name in splinecontact.__all__, name
        assert getattr(splinecontact, name) is cls, name


def test_errors_all_lists_only_error_classes() -> None:
    for name in errors.__all__:
        value = getattr(errors, name)
        assert isinstance(value, type) and issubclass(value, SplineContactError), name


@pytest.mark.parametrize(
    ("module", "name"),
    [
        ("splinecontact.io", "X3PError"),
        ("splinecontact.io", "DamagedX3PError"),
        ("splinecontact.io", "NumpyFileError"),
        ("splinecontact.preprocess", "CropError"),
        ("splinecontact.bem", "FullContactError"),
    ],
)
def test_stage_modules_re_export_their_errors(module: str, name: str) -> None:
    assert getattr(importlib.import_module(module), name) is getattr(errors, name)
