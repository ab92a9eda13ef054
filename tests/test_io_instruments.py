"""The ``[instruments]`` extra: formats read through SurfaceTopography (skipped without it).

Files are written at test time with SurfaceTopography's own writers (Gwyddion ``.gwy``,
NetCDF ``.nc``, X3P), or are small hand-made damaged files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from splinecontact import SplineContactError
from splinecontact.io import (
    FileTooLargeError,
    InstrumentFileError,
    LineSelectionError,
    ProfileReadError,
    detect_format,
    read_profile,
    read_raw,
)

st = pytest.importorskip("SurfaceTopography")

HEIGHTS = np.arange(48.0).reshape(8, 6) * 0.01  # [x, y] as SurfaceTopography stores them


@pytest.fixture
def topography() -> object:
    return st.Topography(HEIGHTS, (4.0, 3.0), unit="um")  # dx = 0.5 µm, dy = 0.5 µm


@pytest.mark.parametrize("suffix", [".gwy", ".nc"])
def test_areal_instrument_file_row(tmp_path: Path, topography: object, suffix: str) -> None:
    path = tmp_path / f"t{suffix}"
    getattr(topography, "to_gwy" if suffix == ".gwy" else "to_netcdf")(str(path))
    assert detect_format(path) == "surfacetopography"
    with pytest.raises(LineSelectionError, match="choose a line"):
        read_profile(path)
    with pytest.raises(LineSelectionError, match="line=6 does not exist"):
        read_profile(path, line=6)
    raw = read_raw(path, line=2)
    np.testing.assert_allclose(raw.z, HEIGHTS[:, 2], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(raw.x, np.arange(8) * 0.5, rtol=1e-12)
    assert raw.x[0] == 0.0  # the one origin rule: only a spacing is known -> x starts at 0
    assert raw.metadata["x_origin"].startswith("0")
    assert read_profile(path, line=2).n_points == 8


def test_limit_checked_from_the_declared_grid(tmp_path: Path, topography: object) -> None:
    path = tmp_path / "t.gwy"
    topography.to_gwy(str(path))  # type: ignore[attr-defined]
    with pytest.raises(FileTooLargeError, match="48 points"):
        read_profile(path, line=0, max_points=47)


def test_x3p_through_both_paths_agrees(tmp_path: Path, topography: object) -> None:
    path = tmp_path / "t.x3p"
    topography.to_x3p(str(path))  # type: ignore[attr-defined]
    ours = read_raw(path, line=3)
    theirs = read_raw(path, line=3, format="surfacetopography")
    np.testing.assert_allclose(theirs.z, ours.z, rtol=1e-12)
    np.testing.assert_allclose(theirs.x, ours.x, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    ("name", "content"),
    [
        ("damaged.tiff", b"II*\x00" + bytes(100)),
        ("metropro.dat", b"\x88\x1b\x03\x6f" + bytes(200)),
        ("damaged.gwy", b"GWYP" + bytes(64)),
        ("random.sur", bytes(range(256)) * 4),
        ("empty.xlsx", b"PK\x05\x06" + bytes(18)),
        ("scan.stp", b"WSxM file copyright Nanotec Electronica\n" + bytes(50)),
        ("scan.bcrf", b"fileformat = bcrstm\nxpixels = 99999\n"),
    ],
)
def test_damaged_instrument_files_give_one_read_error(
    tmp_path: Path, name: str, content: bytes, capfd: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / name
    path.write_bytes(content)
    assert detect_format(path) == "surfacetopography"
    with pytest.raises(ProfileReadError) as info:
        read_profile(path, unit="um", line=0)
    assert "\n" not in str(info.value)
    assert capfd.readouterr().err == ""  # no warnings or log lines besides the error


def test_refusal_is_instrument_error(tmp_path: Path) -> None:
    path = tmp_path / "damaged.gwy"
    path.write_bytes(b"GWYP" + bytes(64))
    with pytest.raises(InstrumentFileError, match="SurfaceTopography cannot read"):
        read_profile(path, line=0)


def test_instrument_fuzz(tmp_path: Path, topography: object) -> None:
    """Mutated instrument files: a profile or a SplineContactError, nothing else."""
    import random

    seeds = []
    for suffix, writer in ((".gwy", "to_gwy"), (".nc", "to_netcdf")):
        path = tmp_path / f"seed{suffix}"
        getattr(topography, writer)(str(path))
        seeds.append((suffix, path.read_bytes()))
    rng = random.Random(7)
    escaped = []
    for k in range(60):
        suffix, data = rng.choice(seeds)
        buf = bytearray(data)
        if rng.random() < 0.5:
            for _ in range(rng.randint(1, 8)):
                buf[rng.randrange(len(buf))] ^= 1 << rng.randrange(8)
        else:
            del buf[rng.randrange(len(buf)) :]
        path = tmp_path / f"m{k}{suffix}"
        path.write_bytes(bytes(buf))
        try:
            read_profile(path, line=rng.choice([None, 0, 2]), unit=rng.choice([None, "um"]))
        except SplineContactError:
            pass
        except Exception as exc:
            escaped.append(f"{k}: {type(exc).__name__}: {exc}")
    assert escaped == []
