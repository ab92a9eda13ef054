"""Every malformed input gives its own error naming the file, the line or index, and the fix."""

from __future__ import annotations

from pathlib import Path

import pytest

from splinecontact import (
    GridNotIncreasingError,
    NonFiniteValueError,
    ProfileError,
    ProfileReadError,
    SplineContactError,
)
from splinecontact.io import (
    EmptyFileError,
    FormatMismatchError,
    MalformedRowError,
    MissingUnitsError,
    NoDataError,
    UnitError,
    read_profile,
)
from splinecontact.preprocess import (
    DuplicatePositionError,
    GridOrderError,
    Preprocessing,
    UndefinedPointsError,
)

DATA = Path(__file__).parent / "data"

#: file -> (error class, fragments the message must contain)
MALFORMED: dict[str, tuple[type[SplineContactError], tuple[str, ...]]] = {
    "malformed-empty.csv": (EmptyFileError, ("malformed-empty.csv", "empty")),
    "malformed-header-only.csv": (
        NoDataError,
        ("malformed-header-only.csv", "line 1", "header but no data"),
    ),
    "malformed-nan-rows.csv": (
        UndefinedPointsError,
        ("2 undefined point(s)", "index 3, line 5", "index 7, line 9", "--undefined interpolate"),
    ),
    "malformed-mixed-delimiters.csv": (
        MalformedRowError,
        ("line 8", "','", "semicolon", "mixes delimiters"),
    ),
    "malformed-duplicate-x.txt": (
        DuplicatePositionError,
        ("index 5", "lines 6 and 7", "--duplicates average"),
    ),
    "malformed-descending-x.csv": (
        GridOrderError,
        ("index 6 (line 8)", "x[5]=5000 µm, x[6]=4500 µm", "--order sort"),
    ),
    "malformed-missing-units.csv": (
        MissingUnitsError,
        ("malformed-missing-units.csv", "unit=", "--unit"),
    ),
    "malformed-binary-wrong-extension.csv": (
        FormatMismatchError,
        (".csv says text", "NumPy .npy array", "format='npy'"),
    ),
    "malformed-not-x3p.x3p": (FormatMismatchError, (".x3p says an X3P archive", "holds text")),
    "malformed-bad-number.csv": (
        MalformedRowError,
        ("line 4, column 2", "'3..5' is not a number", "fix or remove"),
    ),
    "malformed-unknown-unit.csv": (UnitError, ("line 1", "'inch'", "not a length unit")),
    "tail-repeats.txt": (GridOrderError, ("index 20 (line 21)", "x[19]=1.9 µm, x[20]=1.7 µm")),
}


@pytest.mark.parametrize("name", sorted(MALFORMED))
def test_malformed_file_gives_specific_error(name: str) -> None:
    error, fragments = MALFORMED[name]
    unit = "um" if name == "tail-repeats.txt" else None
    with pytest.raises(error) as info:
        read_profile(DATA / name, unit=unit)
    message = str(info.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)
    # one base class for scripts: read errors vs irregular data
    assert isinstance(info.value, ProfileReadError | ProfileError)


def test_error_hierarchy() -> None:
    assert issubclass(UndefinedPointsError, NonFiniteValueError)
    assert issubclass(GridOrderError, GridNotIncreasingError)
    assert issubclass(DuplicatePositionError, GridNotIncreasingError)
    for error in (EmptyFileError, NoDataError, MalformedRowError, MissingUnitsError, UnitError):
        assert issubclass(error, ProfileReadError)


def test_each_irregularity_has_its_option() -> None:
    """What is refused by default reads with the option the message names."""
    p = read_profile(
        DATA / "malformed-nan-rows.csv", preprocessing=Preprocessing(undefined="interpolate")
    )
    assert p.n_points == 12
    p = read_profile(
        DATA / "malformed-duplicate-x.txt", preprocessing=Preprocessing(duplicates="average")
    )
    assert p.n_points == 10
    # sorted: 0 1 2 3 4 4.5 5 6 7 8 mm is not uniform -> resample on request
    with pytest.raises(ProfileError, match="not uniform"):
        read_profile(DATA / "malformed-descending-x.csv", preprocessing=Preprocessing(order="sort"))
    p = read_profile(
        DATA / "malformed-descending-x.csv",
        preprocessing=Preprocessing(order="sort", nonuniform="resample"),
    )
    assert [s["step"] for s in p.metadata["preprocessing"]] == ["sort", "resample"]
    p = read_profile(DATA / "malformed-missing-units.csv", unit="nm")
    assert p.dx == pytest.approx(1e-3)
    tail = read_profile(
        DATA / "tail-repeats.txt",
        unit="um",
        preprocessing=Preprocessing(order="sort", duplicates="average"),
    )
    assert tail.n_points == 20
    cropped = read_profile(
        DATA / "tail-repeats.txt", unit="um", preprocessing=Preprocessing(crop=(0.0, 1.65))
    )
    assert cropped.n_points == 17  # 0.0 … 1.6 and nothing of the repeated tail
