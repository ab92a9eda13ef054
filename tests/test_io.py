"""Readers and writer of measured profiles: real files, every format, units, round trips."""

from __future__ import annotations

import hashlib
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact import Profile, ProfileReadError
from splinecontact.io import (
    FORMATS,
    LineSelectionError,
    MissingExtraError,
    MissingSpacingError,
    MissingUnitsError,
    ReadOptionError,
    UnitError,
    UnknownFormatError,
    X3PError,
    detect_format,
    read_profile,
    read_raw,
    write_profile,
)
from splinecontact.io._tokens import _resolution
from splinecontact.io._units import normalize_unit, unit_in_text
from splinecontact.preprocess import Preprocessing

DATA = Path(__file__).parent / "data"


# --- the real measured files (tests/data/README.md) -------------------------------------------


def test_hfm_stylus_scan() -> None:
    """hfm-1: 9600 points, x 8.6722 … 13.4717 mm every 0.5 µm, heights ~106.6 mm absolute."""
    p = read_profile(DATA / "hfm-1.hfm")
    assert p.n_points == 9600
    assert p.dx == pytest.approx(0.5, rel=1e-9)
    assert p.length == pytest.approx(4799.5, rel=1e-9)
    assert p.x[0] == pytest.approx(8672.2, rel=1e-12)
    # the stylus records absolute heights in mm: 106.606 828 … 106.610 085 mm
    assert p.z.min() == pytest.approx(106606.828, abs=1e-6)
    assert p.peak_to_valley == pytest.approx(3.257, abs=1e-6)
    assert p.metadata["units"]["x"] == "mm" and p.metadata["units"]["z"] == "mm"
    assert p.metadata["units"]["x_from"] == "header"
    assert p.metadata["n_flagged_invalid"] == 0
    assert p.metadata["format"] == "table"
    assert p.metadata["validity_column"] == "valid [1/0]"
    assert p.metadata["preprocessing"] == []
    tilt_free = read_profile(DATA / "hfm-1.hfm", preprocessing=Preprocessing(detrend="tilt"))
    # R_q 0.906 µm with the instrument tilt, 0.245 µm without
    assert p.rq == pytest.approx(0.9057, abs=1e-4)
    assert tilt_free.rq == pytest.approx(0.2453, abs=1e-4)
    assert tilt_free.metadata["preprocessing"][0]["step"] == "remove_tilt"
    assert tilt_free.metadata["preprocessing"][0]["coefficients"][1] == pytest.approx(
        6.29e-4, rel=1e-2
    )


def test_xy_line_scan_needs_units_and_regularises_printed_grid() -> None:
    """xy-4: 10 001 rows, no header; x printed with 6 decimals (steps 0.000099/0.000100)."""
    with pytest.raises(MissingUnitsError, match=r"xy-4\.txt"):
        read_profile(DATA / "xy-4.txt")
    p = read_profile(DATA / "xy-4.txt", unit="um")  # SurfaceTopography's own tests read it as µm
    assert p.n_points == 10001
    assert p.length == pytest.approx(0.995613, abs=1e-6)
    assert p.dx == pytest.approx(9.95613e-5, rel=1e-5)
    assert p.peak_to_valley == pytest.approx(0.057078, abs=1e-9)
    step = p.metadata["preprocessing"][0]
    assert step["step"] == "regularize_grid"
    assert step["print_resolution_um"] == pytest.approx(1e-6)
    assert step["max_deviation_um"] <= 1e-6
    raw = read_raw(DATA / "xy-4.txt", unit="um")
    np.testing.assert_array_equal(raw.z, p.z)  # heights untouched
    assert np.max(np.abs(raw.x - p.x)) <= 1e-6
    assert raw.rows is not None and raw.rows[0] == 1 and raw.rows[-1] == 10001


def test_x3p_areal_row() -> None:
    """x3p-2: 650 × 650 doubles in metres, dx = 0.127 656 5 µm; one row is a line profile."""
    with pytest.raises(LineSelectionError, match="0 … 649"):
        read_profile(DATA / "x3p-2.x3p")
    p = read_profile(DATA / "x3p-2.x3p", line=0)
    assert p.n_points == 650
    assert p.dx == pytest.approx(1.27656509837346e-1, rel=1e-12)
    assert p.length == pytest.approx(649 * 0.127656509837346, rel=1e-12)
    assert p.x[0] == pytest.approx(76.5614218798151, rel=1e-12)
    assert p.rq == pytest.approx(0.0807426, rel=1e-5)  # ~0.08 µm: a polished surface
    assert p.metadata["units"] == {
        "x": "m",
        "z": "m",
        "x_from": "X3P standard (metres)",
        "z_from": "X3P standard (metres)",
        "x_factor_to_um": 1e6,
        "z_factor_to_um": 1e6,
    }
    assert p.metadata["instrument"]["Manufacturer"] == "DIGITAL SURF"
    last = read_profile(DATA / "x3p-2.x3p", line=649)
    assert last.metadata["line_y_um"] == pytest.approx(
        (1.29451679506934e-5 + 649 * 3.14582113527746e-7) * 1e6
    )
    with pytest.raises(LineSelectionError, match="line=650"):
        read_profile(DATA / "x3p-2.x3p", line=650)
    # the row is the x-fastest block of the binary data
    with zipfile.ZipFile(DATA / "x3p-2.x3p") as archive:
        data = np.frombuffer(archive.read("bindata/data.bin"), "<f8").reshape(650, 650)
    np.testing.assert_array_equal(last.z, data[649] * 1e6)


# the sample scans and random parameters can legitimately trigger simulate()'s diagnostics
@pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")
@pytest.mark.parametrize(
    ("name", "kwargs"),
    [("hfm-1.hfm", {}), ("xy-4.txt", {"unit": "um"}), ("x3p-2.x3p", {"line": 0})],
)
@pytest.mark.parametrize("upper", ["flat", "self"])
def test_real_files_run_through_simulate(name: str, kwargs: dict, upper: str) -> None:
    from splinecontact import simulate

    p = read_profile(DATA / name, preprocessing=Preprocessing(detrend="tilt"), **kwargs)
    result = simulate(p, "flat" if upper == "flat" else p, steps=50)
    forces = np.asarray(result.curves["normal_force"])
    assert forces.shape == (51,)
    assert np.all(np.isfinite(forces))
    assert forces[-1] > max(forces[0], 0.0)  # pressing harder carries more load
    assert int(result.curves["n_contacts"][-1]) >= 1
    assert np.all(np.diff(np.asarray(result.curves["displacement"])) > 0)
    assert result.lower_metadata["file"].endswith(name)
    assert result.lower_metadata["source"].endswith(name)


# --- detection --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "fmt"),
    [
        ("hfm-1.hfm", "table"),
        ("xy-4.txt", "table"),
        ("x3p-2.x3p", "x3p"),
        ("dektak-synthetic.csv", "dektak"),
        ("heights-nm.txt", "table"),
    ],
)
def test_detect_format(name: str, fmt: str) -> None:
    assert detect_format(DATA / name) == fmt


def test_detect_from_content_when_extension_is_silent(tmp_path: Path) -> None:
    np.save(tmp_path / "a.npy", np.zeros(8))
    (tmp_path / "a.npy").rename(tmp_path / "scan")
    assert detect_format(tmp_path / "scan") == "npy"
    (tmp_path / "x3p").write_bytes((DATA / "x3p-2.x3p").read_bytes())
    assert detect_format(tmp_path / "x3p") == "x3p"
    (tmp_path / "text").write_text("x [um] z [um]\n0 1\n1 2\n")
    assert detect_format(tmp_path / "text") == "table"
    (tmp_path / "blob.bin").write_bytes(bytes(range(256)) * 4)
    with pytest.raises(UnknownFormatError, match="instruments"):
        detect_format(tmp_path / "blob.bin")


def test_unknown_format_option() -> None:
    with pytest.raises(ReadOptionError, match="format='gwyddion'"):
        read_profile(DATA / "xy-4.txt", format="gwyddion")
    assert set(FORMATS) == {"table", "dektak", "x3p", "npy", "npz", "surfacetopography"}


# --- text tables ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "unit"),
    [
        ("x [mm], z [mm]\n", "mm"),
        ("x (mm);z (mm)\n", "mm"),
        ("x/mm\tz/mm\n", "mm"),
        ("X;Y\n[mm];[mm]\n", "mm"),
        ("x [mm] z [mm]\n", "mm"),
        ("Lateral millimeter,Height millimeter\n", "mm"),
    ],
)
def test_header_units(tmp_path: Path, text: str, unit: str) -> None:
    delimiter = ";" if ";" in text else ("," if "," in text else " ")
    rows = "".join(f"{0.001 * i}{delimiter}{0.002 * i}\n" for i in range(8))
    path = tmp_path / "scan.txt"
    path.write_text(text + rows, encoding="utf-8")
    p = read_profile(path)
    assert p.metadata["units"]["x"] == unit
    np.testing.assert_allclose(p.x, np.arange(8) * 1.0)  # 0.001 mm = 1 µm
    np.testing.assert_allclose(p.z, np.arange(8) * 2.0)


@pytest.mark.parametrize(
    ("given", "canonical"),
    [("µm", "µm"), ("μm", "µm"), ("um", "µm"), ("micron", "µm"), ("nm", "nm"),
     ("mm", "mm"), ("m", "m"), ("Å", "Å"), ("Å", "Å"), ("A", "Å"), ("angstrom", "Å")],
)  # fmt: skip
def test_unit_names(given: str, canonical: str) -> None:
    assert normalize_unit(given) == canonical


def test_unit_errors(tmp_path: Path) -> None:
    with pytest.raises(UnitError, match="furlong"):
        normalize_unit("furlong")
    assert unit_in_text("valid [1/0]") == (None, "1/0")
    assert unit_in_text("X") == (None, None)
    path = tmp_path / "s.csv"
    path.write_text("x [mm], z [mm]\n" + "".join(f"{i}, {i}\n" for i in range(6)))
    with pytest.raises(UnitError, match="drop unit="):
        read_profile(path, unit="nm")
    assert read_profile(path, unit="mm").metadata["units"]["x"] == "mm"  # agreeing is fine


def test_legacy_encoding_and_comma_titles_over_space_data(tmp_path: Path) -> None:
    path = tmp_path / "old.txt"
    text = "Höhe, z\nx [µm] z [µm]\n" + "".join(f"{i} {i * i}\n" for i in range(6))
    path.write_bytes(text.encode("cp1252"))  # µ and ö as single bytes
    p = read_profile(path)
    assert p.metadata["units"]["x"] == "µm"
    np.testing.assert_allclose(p.z, np.arange(6.0) ** 2)
    path.write_text("x, z\n" + "".join(f"{i} {i * i}\n" for i in range(6)))
    raw = read_raw(path, unit="um")
    np.testing.assert_allclose(raw.z, np.arange(6.0) ** 2)  # titles "x," and "z" recognised
    assert raw.metadata["header_lines"] == 1


def test_height_unit_differs_from_lateral(tmp_path: Path) -> None:
    path = tmp_path / "s.txt"
    path.write_text("".join(f"{i}\t{i}\n" for i in range(6)))
    p = read_profile(path, unit="mm", height_unit="nm")
    np.testing.assert_allclose(p.x, np.arange(6) * 1000.0)
    np.testing.assert_allclose(p.z, np.arange(6) * 1e-3)


def test_one_column_heights() -> None:
    with pytest.raises(MissingSpacingError, match="spacing="):
        read_profile(DATA / "heights-nm.txt")
    p = read_profile(DATA / "heights-nm.txt", spacing=0.01)
    assert p.n_points == 40
    assert p.dx == pytest.approx(0.01)
    assert p.z[1] == pytest.approx(5 * np.sin(0.25) * 1e-3, abs=5e-7)  # printed to 0.001 nm
    with pytest.raises(ReadOptionError, match="one column"):
        read_profile(DATA / "hfm-1.hfm", spacing=0.5)


def test_decimal_comma_and_tab(tmp_path: Path) -> None:
    path = tmp_path / "de.txt"
    path.write_text("x [µm]\tz [µm]\n" + "".join(f"{i},5\t{i},25\n" for i in range(6)))
    p = read_profile(path)
    np.testing.assert_allclose(p.x, np.arange(6) + 0.5)
    np.testing.assert_allclose(p.z, np.arange(6) + 0.25)


def test_stylus_validity_flags() -> None:
    raw = read_raw(DATA / "stylus-invalid.hfm")
    assert raw.metadata["n_flagged_invalid"] == 3
    assert np.flatnonzero(np.isnan(raw.z)).tolist() == [4, 5, 17]
    p = read_profile(
        DATA / "stylus-invalid.hfm", preprocessing=Preprocessing(undefined="interpolate")
    )
    z = raw.z
    assert p.z[4] == pytest.approx(z[3] + (z[6] - z[3]) / 3)
    assert p.z[17] == pytest.approx(0.5 * (z[16] + z[18]))


# --- Dektak -----------------------------------------------------------------------------------


def test_dektak_export() -> None:
    p = read_profile(DATA / "dektak-synthetic.csv")
    assert p.metadata["format"] == "dektak"
    assert p.n_points == 64
    # lateral positions are printed with one decimal at 0.156 µm per sample
    assert p.dx == pytest.approx(0.156, abs=2e-3)
    assert p.metadata["preprocessing"][0]["step"] == "regularize_grid"
    assert p.metadata["units"]["z"] == "Å"
    expected = (120 * np.sin(np.pi / 2) + 30 * np.cos(8 * np.pi / 5)) * 1e-4
    assert p.z[4] == pytest.approx(expected, abs=5e-7)  # printed to 0.01 Å
    assert p.metadata["instrument_parameters"]["Resolution"] == "0.156 um/sample"


def test_dektak_without_units_uses_argument(tmp_path: Path) -> None:
    text = "Scan Parameters\nLength,10 um\n\nScan Data\nLateral,Total Profile,\n"
    text += "".join(f"{i}.0,{i * 2}.0,,\n" for i in range(8))
    path = tmp_path / "d.csv"
    path.write_text(text)
    with pytest.raises(MissingUnitsError):
        read_profile(path)
    p = read_profile(path, unit="um", height_unit="nm")
    np.testing.assert_allclose(p.z, np.arange(8) * 2e-3)


# --- X3P (synthetic files exercise the options of the format) ---------------------------------


def _x3p(
    path: Path,
    z: np.ndarray,
    *,
    feature: str = "PRF",
    dtype: str = "D",
    increment: float | None = None,
    valid: np.ndarray | None = None,
    checksum: str | None = None,
) -> None:
    ny, nx = z.shape
    inc = f"<Increment>{increment!r}</Increment>" if increment is not None else ""
    codes = {"I": "<u2", "L": "<u4", "F": "<f4", "D": "<f8"}
    data = z.astype(codes[dtype]).tobytes()
    md5 = checksum if checksum is not None else hashlib.md5(data).hexdigest().upper()
    valid_link = "<ValidPntsLink>bindata/valid.bin</ValidPntsLink>" if valid is not None else ""
    xml = f"""<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
<Record1><Revision>ISO5436 - 2000</Revision><FeatureType>{feature}</FeatureType><Axes>
<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>2e-6</Increment><Offset>0</Offset></CX>
<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>5e-6</Increment></CY>
<CZ><AxisType>A</AxisType><DataType>{dtype}</DataType>{inc}</CZ></Axes></Record1>
<Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
<DataLink><PointDataLink>bindata/data.bin</PointDataLink>
<MD5ChecksumPointData>{md5}</MD5ChecksumPointData></DataLink>{valid_link}</Record3>
</p:ISO5436_2>"""
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("main.xml", xml)
        archive.writestr("bindata/data.bin", data)
        if valid is not None:
            archive.writestr(
                "bindata/valid.bin", np.packbits(valid.ravel(), bitorder="little").tobytes()
            )


def test_x3p_profile_integer_data_scaled(tmp_path: Path) -> None:
    counts = np.arange(10, dtype=np.uint16)[None, :] * 3
    _x3p(tmp_path / "p.x3p", counts, dtype="I", increment=1e-9)
    p = read_profile(tmp_path / "p.x3p")
    np.testing.assert_allclose(p.z, np.arange(10) * 3e-3)  # 3 nm per point
    assert p.dx == pytest.approx(2.0)
    with pytest.raises(LineSelectionError, match="single profile"):
        read_profile(tmp_path / "p.x3p", line=3)


def test_x3p_valid_mask_and_checksum(tmp_path: Path) -> None:
    z = np.linspace(0, 1e-6, 24).reshape(3, 8)
    valid = np.ones((3, 8), dtype=bool)
    valid[1, 2] = False
    _x3p(tmp_path / "s.x3p", z, feature="SUR", valid=valid)
    raw = read_raw(tmp_path / "s.x3p", line=1)
    assert np.flatnonzero(np.isnan(raw.z)).tolist() == [2]
    assert raw.metadata["line_y_um"] == pytest.approx(5.0)
    _x3p(tmp_path / "bad.x3p", z, feature="SUR", checksum="0" * 32)
    with pytest.raises(X3PError, match="checksum"):
        read_profile(tmp_path / "bad.x3p", line=0)


def test_x3p_refuses_units_and_point_clouds(tmp_path: Path) -> None:
    with pytest.raises(ReadOptionError, match="metres"):
        read_profile(DATA / "x3p-2.x3p", line=0, unit="um")
    _x3p(tmp_path / "pcl.x3p", np.zeros((1, 8)), feature="PCL")
    with pytest.raises(X3PError, match="PCL"):
        read_profile(tmp_path / "pcl.x3p")
    with zipfile.ZipFile(tmp_path / "nomain.x3p", "w") as archive:
        archive.writestr("other.txt", "x")
    with pytest.raises(ProfileReadError, match=r"main\.xml"):
        read_profile(tmp_path / "nomain.x3p")


# --- NumPy ------------------------------------------------------------------------------------


def test_npy_forms(tmp_path: Path) -> None:
    z = np.sin(np.arange(16) / 3.0)
    np.save(tmp_path / "h.npy", z)
    with pytest.raises(MissingUnitsError):
        read_profile(tmp_path / "h.npy", spacing=0.1)
    with pytest.raises(MissingSpacingError):
        read_profile(tmp_path / "h.npy", unit="nm")
    p = read_profile(tmp_path / "h.npy", unit="nm", spacing=0.1)
    np.testing.assert_allclose(p.z, z * 1e-3)
    np.save(tmp_path / "pairs.npy", np.column_stack([np.arange(16) * 2.0, z]))
    p = read_profile(tmp_path / "pairs.npy", unit="um")
    assert p.dx == pytest.approx(2.0)
    np.save(tmp_path / "map.npy", np.vstack([z, 2 * z, 3 * z]))
    with pytest.raises(LineSelectionError, match="line="):
        read_profile(tmp_path / "map.npy", unit="um", spacing=1.0)
    p = read_profile(tmp_path / "map.npy", unit="um", spacing=1.0, line=2)
    np.testing.assert_allclose(p.z, 3 * z)


def test_npz_without_metadata(tmp_path: Path) -> None:
    np.savez(tmp_path / "a.npz", x=np.arange(6.0), z=np.ones(6))
    with pytest.raises(MissingUnitsError):
        read_profile(tmp_path / "a.npz")
    assert read_profile(tmp_path / "a.npz", unit="mm").dx == pytest.approx(1000.0)
    np.savez(tmp_path / "b.npz", heights=np.ones(6))
    with pytest.raises(ProfileReadError, match="no 'z'"):
        read_profile(tmp_path / "b.npz", unit="um")


# --- writing ----------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".txt"])
def test_write_read_round_trip(tmp_path: Path, suffix: str) -> None:
    x = 3.0 + 0.1 * np.arange(50)
    z = np.sin(x) * 0.01 + 1e-7 / 3
    meta = {"source": "weierstrass_mandelbrot", "seed": 3, "dimension": 1.5}
    p = Profile(x, z, metadata=meta)
    path = write_profile(p, tmp_path / f"out{suffix}")
    back = read_profile(path)
    np.testing.assert_array_equal(back.x, p.x)
    np.testing.assert_array_equal(back.z, p.z)
    for key, value in meta.items():  # the stored metadata come back
        assert back.metadata[key] == value
    assert back.metadata["file"] == str(path)
    assert back.metadata["format"] == ("npz" if suffix == ".npz" else "table")
    assert [f.name for f in tmp_path.iterdir()] == [f"out{suffix}"]  # no temporary left


@pytest.mark.parametrize("suffix", [".npz", ".csv"])
def test_generated_profile_round_trip_keeps_its_analysis(tmp_path: Path, suffix: str) -> None:
    from splinecontact import weierstrass_mandelbrot
    from splinecontact.spectra import hurst_exponent

    p = weierstrass_mandelbrot(1.5, n_points=4000, seed=3)
    back = read_profile(write_profile(p, tmp_path / f"g{suffix}"))
    assert back.metadata["source"] == "weierstrass_mandelbrot"
    assert back.metadata["seed_entropy"] == p.metadata["seed_entropy"]
    assert hurst_exponent(back) == hurst_exponent(p)


def test_csv_header_is_documented_form(tmp_path: Path) -> None:
    path = write_profile(Profile(np.arange(5.0), np.zeros(5)), tmp_path / "p.csv")
    lines = path.read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("# splinecontact-metadata:")
    json.loads(lines[0].split(":", 1)[1])
    assert lines[1] == "x [µm], z [µm]"


def test_write_refuses_unknown_extension(tmp_path: Path) -> None:
    with pytest.raises(ReadOptionError, match=r"\.h5"):
        write_profile(Profile(np.arange(5.0), np.zeros(5)), tmp_path / "p.h5")
    assert not list(tmp_path.iterdir())


@settings(max_examples=30, deadline=None)
@given(
    n=st.integers(5, 60),
    x0=st.floats(-1e4, 1e4, allow_nan=False),
    dx=st.floats(1e-4, 1e2),
    seed=st.integers(0, 2**32 - 1),
    suffix=st.sampled_from([".npz", ".csv"]),
)
def test_round_trip_property(n: int, x0: float, dx: float, seed: int, suffix: str) -> None:
    import tempfile

    x = x0 + dx * np.arange(n)
    if not np.all(np.diff(x) > 0):
        return
    try:
        p = Profile(x, np.random.default_rng(seed).normal(size=n))
    except ValueError:
        return  # rounding made this grid non-uniform for Profile itself
    with tempfile.TemporaryDirectory() as tmp:
        back = read_profile(write_profile(p, Path(tmp) / f"r{suffix}"))
    np.testing.assert_array_equal(back.x, p.x)
    np.testing.assert_array_equal(back.z, p.z)


# --- printed resolution -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("token", "resolution"),
    [("0.0125", 1e-4), ("12", 1.0), ("1.5e-3", 1e-4), ("-2.50E+02", 1.0), ("3.", 1.0)],
)
def test_printed_resolution(token: str, resolution: float) -> None:
    assert _resolution(token) == pytest.approx(resolution)


# --- SurfaceTopography extra ------------------------------------------------------------------


def test_instrument_format_without_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import splinecontact.io._instruments as instruments

    monkeypatch.setattr(instruments, "_import_surfacetopography", lambda: None)
    path = tmp_path / "scan.sur"
    path.write_bytes(b"DIGITAL SURF\x00\x01\x02" * 10)
    assert detect_format(path) == "surfacetopography"
    with pytest.raises(MissingExtraError, match=r'pip install "splinecontact\[instruments\]"'):
        read_profile(path)
    with pytest.raises(MissingExtraError, match=r"scan\.sur"):
        read_profile(path, format="surfacetopography")


def test_surfacetopography_really_missing() -> None:
    """The test environment does not install the extra: the real import path is exercised."""
    import importlib.util

    if importlib.util.find_spec("SurfaceTopography") is not None:
        pytest.skip("SurfaceTopography is installed")
    path = DATA / "x3p-2.x3p"
    with pytest.raises(MissingExtraError, match="not installed"):
        read_profile(path, format="surfacetopography")
