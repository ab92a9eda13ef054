"""A contact as wide as the period leaves the interacting model: a specific error, never inf."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import splinecontact as sc
from splinecontact.errors import ParameterError, SplineContactError


def _circle() -> sc.Profile:
    """Circle of radius 0.5 µm on 401 points at 1 Å spacing (segment 0.04 µm long)."""
    x = np.arange(401) * 1e-4
    x = x - x.mean()
    return sc.Profile(x=x, z=np.sqrt(0.25 - x * x) - 0.5)


def _run(final: float, steps: int) -> sc.SimulationResult:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # form warning: the circle is all form
        warnings.simplefilter("error", RuntimeWarning)
        return sc.simulate(
            _circle(), "flat", steps=steps, final_displacement=final, interaction=True
        )


def test_contact_wider_than_period_raises_specific_error() -> None:
    with pytest.raises(ParameterError, match=r"left its validity at step 10 .*longer profile"):
        _run(5e-4, 40)
    assert issubclass(ParameterError, SplineContactError)


def test_just_inside_validity_is_unchanged() -> None:
    result = _run(1e-4, 4)
    # pinned from the code before the validity check: bit-identical with the current
    # dependencies; at the declared lower bounds (CI floors) the last two bits differ: 1e-13
    assert result.normal_force == pytest.approx(
        [
            2.8771401547853563e-34,
            2.049103599056095e-05,
            0.0003059768739939101,
            0.0009561419721648057,
            0.002144080167564835,
        ],
        rel=1e-13,
        abs=1e-40,
    )
    assert result.contact_area == pytest.approx(
        [
            6.052510766459392e-18,
            0.0016152398459434738,
            0.006241649298683477,
            0.011033575040007619,
            0.0165224928022173,
        ],
        rel=1e-13,
        abs=1e-30,
    )
    assert np.all(np.isfinite(result.normal_force))


@pytest.mark.parametrize(
    ("segment", "message"),
    [
        ("normal=0.0005,steps=40", "left its validity"),
        # the sliding driver (three width updates per step) leaves it one step earlier
        ("normal=0.0005,tangential=0.0001,steps=40", "left its validity at step 9"),
    ],
)
def test_cli_gives_one_line_and_writes_nothing(tmp_path: Path, segment: str, message: str) -> None:
    from typer.testing import CliRunner

    from splinecontact.cli import app

    profile = _circle()
    source = tmp_path / "circle.csv"
    np.savetxt(
        source, np.c_[profile.x, profile.z], delimiter=",", header="x [um],z [um]", comments=""
    )
    target = tmp_path / "out.nc"
    args = ["friction", "--lower", str(source), "--upper", "flat", "-o", str(target)]
    args += ["--path", segment, "--interaction"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code != 0
    errors = [line for line in result.output.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and message in errors[0]
    assert "Traceback" not in result.output
    assert not target.exists()
