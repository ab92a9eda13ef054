"""The shared reading options: declared once, the same on every command that reads bodies."""

from __future__ import annotations

import inspect
from typing import Any

import pytest
import typer

from splinecontact.cli import app
from splinecontact.cli._common import profile_reading, with_reading_options

READING = list(inspect.signature(profile_reading).parameters)
UPPER = [name for name in READING if name.startswith("upper_")]


def _params(command: str) -> list[Any]:
    root: Any = typer.main.get_command(app)
    return list(root.commands[command].params)


@pytest.mark.parametrize("command", ["simulate", "friction", "compare"])
def test_two_body_commands_end_with_every_reading_option(command: str) -> None:
    params = _params(command)[-len(READING) :]
    assert [p.name for p in params] == READING
    defaults = inspect.signature(profile_reading).parameters
    assert [p.default for p in params] == [defaults[name].default for name in READING]


def test_inspect_has_the_reading_options_without_the_upper_ones() -> None:
    own = [name for name in READING if name not in UPPER]
    assert [p.name for p in _params("inspect")[-len(own) :]] == own
    assert not {p.name for p in _params("inspect")} & set(UPPER)


def test_the_options_reach_profile_reading() -> None:
    @with_reading_options(upper=False)
    def command(*, reading_options: Any) -> Any:
        return reading_options()

    reading = command(crop="1,2", line=3)
    assert reading.preprocessing.crop == (1.0, 2.0)
    assert reading.read["line"] == 3
    assert "upper_crop" not in inspect.signature(command).parameters


def test_a_command_without_reading_options_is_refused() -> None:
    with pytest.raises(TypeError, match="reading_options"):

        @with_reading_options(upper=True)
        def command(x: int) -> None:
            pass
