"""Untrusted files: each attack and each reproduction of the reliability report is refused
with its specific error (or read correctly), in bounded time and memory.

The bombs are generated at test time (never committed). The default tier uses bombs of a few
hundred MiB (built in well under a second, refused from the zip directory or the headers); the
``slow`` tier builds the report's 2 GiB bombs and measures the peak memory of a reading
subprocess.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from _hostile import (
    good_x3p,
    member,
    npy_bytes,
    npy_header,
    npz_bomb,
    raw_zip,
    write_x3p,
    x3p_data_bomb,
    x3p_forged_size_bomb,
    x3p_xml,
    x3p_xml_bomb,
)
from splinecontact import GridNotUniformError, ProfileError, SplineContactError
from splinecontact.io import (
    CorruptFileError,
    FileTooLargeError,
    LineSelectionError,
    MalformedRowError,
    MissingUnitsError,
    NumpyFileError,
    ProfileReadError,
    ReadOptionError,
    UnitError,
    X3PError,
    read_profile,
)
from splinecontact.io._tokens import _split_titles, _title_words
from splinecontact.io._units import bracketed, strip_bracketed, unit_in_text
from splinecontact.preprocess import (
    Preprocessing,
    PreprocessingOptionError,
    RawProfile,
    UndefinedPointsError,
    to_profile,
)

MiB = 1 << 20


def test_new_errors_are_read_errors() -> None:
    assert issubclass(FileTooLargeError, ProfileReadError)
    assert issubclass(CorruptFileError, ProfileReadError)
    assert issubclass(ProfileReadError, SplineContactError)


# --- zip bombs (D3) --------------------------------------------------------------------------


def test_x3p_data_bomb_refused_from_the_zip_directory(tmp_path: Path) -> None:
    path = tmp_path / "bomb.x3p"
    x3p_data_bomb(path, 256 * MiB, (10, 1))
    with pytest.raises(CorruptFileError, match=r"268,435,456 bytes but 10×1×1 points"):
        read_profile(path)


def test_x3p_bomb_with_forged_directory_stops_while_streaming(tmp_path: Path) -> None:
    path = tmp_path / "forged.x3p"
    x3p_forged_size_bomb(path, 256 * MiB)
    with pytest.raises(CorruptFileError, match=r"data.bin"):
        read_profile(path)


def test_x3p_matching_bomb_refused_by_the_point_limit(tmp_path: Path) -> None:
    path = tmp_path / "match.x3p"
    x3p_data_bomb(path, 256 * MiB, (8192, 4096))  # declares exactly the inflated size
    with pytest.raises(FileTooLargeError, match="max_points="):
        read_profile(path, line=0, max_points=10**7)


def test_x3p_xml_bomb_refused(tmp_path: Path) -> None:
    path = tmp_path / "xml.x3p"
    x3p_xml_bomb(path, 256 * MiB)
    with pytest.raises(FileTooLargeError, match=r"main.xml declares 268,435,456 bytes"):
        read_profile(path)


def test_npz_bomb_refused_from_the_header(tmp_path: Path) -> None:
    path = tmp_path / "bomb.npz"
    npz_bomb(path, 1 << 25)  # 256 MiB per array
    with pytest.raises(FileTooLargeError, match=r"33,554,432 points"):
        read_profile(path, unit="um", max_points=10**7)


def test_max_points_is_validated_and_raises_the_limit(tmp_path: Path) -> None:
    good_x3p(tmp_path / "g.x3p", n=10)
    with pytest.raises(FileTooLargeError, match="10 points, more than the limit of 9"):
        read_profile(tmp_path / "g.x3p", max_points=9)
    assert read_profile(tmp_path / "g.x3p", max_points=10).n_points == 10
    for bad in (0, -1, 1.5, "10", True):
        with pytest.raises(ReadOptionError, match="max_points"):
            read_profile(tmp_path / "g.x3p", max_points=bad)  # type: ignore[arg-type]


# --- XML: no entity expansion, no external entity --------------------------------------------

_LAUGHS = """<!DOCTYPE lolz [
<!ENTITY lol "lol">
<!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
<!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
<!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
<!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
<!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
<!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
<!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
<!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
"""


def test_billion_laughs_refused(tmp_path: Path) -> None:
    path = tmp_path / "laughs.x3p"
    write_x3p(path, x3p_xml(prolog=_LAUGHS, manufacturer="&lol9;"), bytes(80))
    with pytest.raises(X3PError, match="document type or entities"):
        read_profile(path)


@pytest.mark.parametrize("where", ["manufacturer", "data_link", "parameter"])
def test_external_entity_never_read(tmp_path: Path, where: str) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET-42")
    uri = secret.as_uri()
    if where == "parameter":
        prolog = f'<!DOCTYPE x [<!ENTITY % ext SYSTEM "{uri}"> %ext;]>\n'
        xml = x3p_xml(prolog=prolog)
    else:
        prolog = f'<!DOCTYPE x [<!ENTITY xxe SYSTEM "{uri}">]>\n'
        xml = x3p_xml(prolog=prolog, **{where: "&xxe;"})  # type: ignore[arg-type]
    path = tmp_path / "xxe.x3p"
    write_x3p(path, xml, bytes(80))
    with pytest.raises(X3PError, match="document type or entities") as info:
        read_profile(path)
    assert "TOP-SECRET" not in str(info.value)


def test_undeclared_entity_and_deep_nesting(tmp_path: Path) -> None:
    write_x3p(tmp_path / "u.x3p", x3p_xml(manufacturer="&xxe;"), bytes(80))
    with pytest.raises(X3PError, match="not valid XML"):
        read_profile(tmp_path / "u.x3p")
    deep = "<a>" * 100_000 + "</a>" * 100_000
    raw_zip(tmp_path / "d.x3p", [member("main.xml", deep.encode()), member("x", b"")])
    with pytest.raises(X3PError, match="feature type"):
        read_profile(tmp_path / "d.x3p")


def test_path_traversal_member_names_are_only_looked_up(tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    data = np.arange(10.0).tobytes()
    xml = x3p_xml(data_link="../../outside/evil.bin")
    raw_zip(
        tmp_path / "t.x3p",
        [member("main.xml", xml.encode()), member("../../outside/evil.bin", data)],
    )
    p = read_profile(tmp_path / "t.x3p")  # read from the archive, nothing extracted
    np.testing.assert_allclose(p.z, np.arange(10.0) * 1e6)
    assert list(outside.iterdir()) == []


# --- ReDoS (D2): linear-time header and unit parsing ------------------------------------------


def test_pathological_header_lines_parse_in_linear_time(tmp_path: Path) -> None:
    n = 100_000
    rows = "\n".join(f"{i};{i % 3}" for i in range(12))
    cases = {
        "open_spaces.csv": "x [" + " " * n + "a;z [um]",  # was cubic: hours at 10 kB
        "open_brackets.csv": "[" * n + ";z [um]",  # was quadratic
    }
    for name, header in cases.items():
        path = tmp_path / name
        path.write_text(header + "\n" + rows + "\n")
        with pytest.raises(MissingUnitsError):  # the x column states no unit: refused
            read_profile(path)
        p = read_profile(path, unit="um")
        assert p.n_points == 12
    parens = tmp_path / "parens.csv"
    parens.write_text("(a) " * (n // 4) + ";z [um]\n" + rows + "\n")
    with pytest.raises(UnitError, match="'a' is not a length unit"):
        read_profile(parens, unit="um")
    ws = tmp_path / "ws.txt"
    ws.write_text("x " + "[" * n + " z\n" + "\n".join(f"{i} {i % 3}" for i in range(12)) + "\n")
    assert read_profile(ws, unit="um").n_points == 12


def test_linear_helpers_agree_with_the_documented_forms() -> None:
    assert bracketed("x [ mm ]") == "mm"
    assert bracketed("z (nm) [um]") == "nm"
    assert bracketed("] x [") is None
    assert bracketed("[" * 100_000) is None
    assert strip_bracketed("x [mm] y (a) [open") == "x  y  [open"
    assert strip_bracketed("(" * 100_000) == "(" * 100_000
    assert _title_words("x [mm]  z(nm)\tvalid") == ["x [mm]", "z(nm)", "valid"]
    assert len(_title_words("x [" + " " * 100_000 + "a")) == 2
    assert _split_titles("Lateral µm  Height microns", None, 2) == ["Lateral µm", "Height microns"]
    assert _split_titles("Lateral µm Height microns", None, 2) == ["Lateral µm", "Height microns"]
    assert unit_in_text("Height microns") == ("µm", "microns")


# --- D5: numbers beyond the float range -------------------------------------------------------


@pytest.mark.parametrize("token", ["1e400", "-1e999", "1e99999999999999999999"])
def test_numbers_beyond_float_range_refused(tmp_path: Path, token: str) -> None:
    path = tmp_path / "v.csv"
    path.write_text(f"x [um], z [um]\n0, 0\n1, {token}\n2, 0\n3, 0\n4, 0\n")
    with pytest.raises(MalformedRowError, match=r"line 3, column 2: .* beyond the range"):
        read_profile(path)
    with pytest.raises(MalformedRowError, match="beyond the range"):
        read_profile(path, preprocessing=Preprocessing(undefined="interpolate"))


def test_number_beyond_range_in_dektak(tmp_path: Path) -> None:
    path = tmp_path / "d.csv"
    rows = "".join(f"{i}.0,{'1e400' if i == 3 else i},,\n" for i in range(8))
    path.write_text("Scan Parameters\n\nScan Data\nLateral um,Total Profile nm,\n" + rows)
    with pytest.raises(MalformedRowError, match="line 8, column 2"):
        read_profile(path)


def test_inf_itself_is_an_undefined_point(tmp_path: Path) -> None:
    path = tmp_path / "inf.csv"
    path.write_text("x [um], z [um]\n0, 0\n1, inf\n2, 0\n3, 0\n4, 0\n5, 1\n")
    with pytest.raises(UndefinedPointsError, match="line 3"):
        read_profile(path)


# --- D6: damaged or hostile X3P ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("size_x", "size_y", "data", "error", "fragment"),
    [
        ("nan", 1, bytes(80), X3PError, "not a finite number"),
        ("inf", 1, bytes(80), X3PError, "not a finite number"),
        (0, 0, b"", X3PError, "not a positive whole number"),
        (-2, -5, bytes(80), X3PError, "not a positive whole number"),
        ("2.5", 4, bytes(80), X3PError, "not a positive whole number"),
        ("1e400", 1, bytes(80), X3PError, "not a finite number"),
    ],
)
def test_x3p_bad_sizes(
    tmp_path: Path,
    size_x: object,
    size_y: object,
    data: bytes,
    error: type[Exception],
    fragment: str,
) -> None:
    path = tmp_path / "s.x3p"
    write_x3p(path, x3p_xml(size_x=size_x, size_y=size_y), data)
    with pytest.raises(error, match=fragment):
        read_profile(path)


@pytest.mark.parametrize("increment", ["0", "-1e-6", "nan", "inf", "1e-320"])
def test_x3p_bad_increment(tmp_path: Path, increment: str) -> None:
    path = tmp_path / "i.x3p"
    write_x3p(path, x3p_xml(increment_x=increment), bytes(80))
    with pytest.raises(X3PError, match=r"increment|finite"):
        read_profile(path)


def test_x3p_short_or_missing_valid_mask(tmp_path: Path) -> None:
    data = np.zeros(30).tobytes()
    xml = x3p_xml(size_x=10, size_y=3, feature="SUR", valid_link="bindata/valid.bin")
    write_x3p(tmp_path / "short.x3p", xml, data, extra={"bindata/valid.bin": b"\xff"})
    with pytest.raises(CorruptFileError, match="validity bits"):
        read_profile(tmp_path / "short.x3p", line=0)
    write_x3p(tmp_path / "missing.x3p", xml, data)
    with pytest.raises(X3PError, match="lacks"):
        read_profile(tmp_path / "missing.x3p", line=0)


def _damage(path: Path, offset_from: str, find: bytes, delta: int = 0) -> None:
    data = bytearray(path.read_bytes())
    central = data.find(b"PK\x01\x02", data.find(b"PK\x01\x02") + 4)  # data.bin's entry
    if offset_from == "crc":  # the CRC of data.bin in the zip directory
        data[central + 16] ^= 0xFF
    elif offset_from == "method":  # compression method of data.bin: unknown
        data[central + 10] = 99
    elif offset_from == "stream":  # garbage in the compressed stream of the second member
        at = data.find(b"PK\x03\x04", 4)
        name_len = int.from_bytes(data[at + 26 : at + 28], "little")
        start = at + 30 + name_len
        data[start : start + 8] = b"\xff" * 8
    elif offset_from == "name":
        at = data.find(find)
        data[at] ^= 0x20
    path.write_bytes(bytes(data))


@pytest.mark.parametrize("damage", ["crc", "method", "stream", "name"])
def test_x3p_damaged_members(tmp_path: Path, damage: str) -> None:
    path = tmp_path / "d.x3p"
    good_x3p(path, n=200)
    _damage(path, damage, b"bindata/data.bin")
    with pytest.raises(X3PError) as info:
        read_profile(path)
    assert "\n" not in str(info.value)


def test_x3p_truncated_and_garbage_archives(tmp_path: Path) -> None:
    path = tmp_path / "g.x3p"
    good_x3p(path, n=200)
    whole = path.read_bytes()
    for cut in (10, 100, len(whole) // 2, len(whole) - 5):
        path.write_bytes(whole[:cut])
        with pytest.raises(ProfileReadError):
            read_profile(path, format="x3p")


# --- D6: damaged or hostile .npy / .npz -------------------------------------------------------


def _npz(path: Path, **arrays: bytes) -> None:
    with zipfile.ZipFile(path, "w") as archive:
        for name, content in arrays.items():
            archive.writestr(f"{name}.npy", content)


def test_npz_bad_crc(tmp_path: Path) -> None:
    buffer = io.BytesIO()
    np.savez(buffer, x=np.arange(10.0), z=np.arange(10.0))
    data = bytearray(buffer.getvalue())
    data[data.rfind(np.arange(10.0).tobytes()[16:24])] ^= 1
    (tmp_path / "crc.npz").write_bytes(bytes(data))
    with pytest.raises(CorruptFileError, match=r"'z'.*Bad CRC-32"):
        read_profile(tmp_path / "crc.npz", unit="um")


def test_npz_object_and_pickled_members(tmp_path: Path) -> None:
    pickled = io.BytesIO()
    np.save(pickled, np.array([{"a": 1}, 2], dtype=object), allow_pickle=True)
    _npz(tmp_path / "o.npz", x=npy_bytes(np.arange(3.0)), z=pickled.getvalue())
    with pytest.raises(NumpyFileError, match="objects, pickles"):
        read_profile(tmp_path / "o.npz", unit="um")
    (tmp_path / "o.npy").write_bytes(pickled.getvalue())
    with pytest.raises(NumpyFileError, match="objects, pickles"):
        read_profile(tmp_path / "o.npy", unit="um")


@pytest.mark.parametrize(
    ("array", "fragment"),
    [
        (np.arange(5) + 1j, "real numbers"),
        (np.ones(5, dtype=bool), "real numbers"),
        (np.zeros((2, 2, 2)), "shape"),
        (np.float64(3.0), "shape"),
        (np.array(["a", "b"]), "real numbers"),
        (np.zeros(3, dtype=[("a", "<f8")]), "records"),
    ],
)
def test_npy_wrong_dtypes_and_shapes(tmp_path: Path, array: np.ndarray, fragment: str) -> None:
    (tmp_path / "a.npy").write_bytes(npy_bytes(np.asarray(array)))
    with pytest.raises(NumpyFileError, match=fragment):
        read_profile(tmp_path / "a.npy", unit="um", spacing=1.0)


@pytest.mark.parametrize(
    ("shape", "error"),
    [
        ((10**10,), FileTooLargeError),
        ((1_500_000_000,), FileTooLargeError),
        ((50,), CorruptFileError),
    ],
)
def test_npy_header_shapes_checked_before_reading(
    tmp_path: Path, shape: tuple[int, ...], error: type[Exception]
) -> None:
    (tmp_path / "h.npy").write_bytes(npy_header(shape) + bytes(80))
    with pytest.raises(error):
        read_profile(tmp_path / "h.npy", unit="um", spacing=1.0)


def test_npy_damaged_header_dict_and_empty_files(tmp_path: Path) -> None:
    data = npy_bytes(np.arange(10.0))
    broken = data.replace(b"'shape': (10,)", b"'shape': (10, ")
    (tmp_path / "b.npy").write_bytes(broken)
    with pytest.raises(CorruptFileError, match=r"no readable .npy header"):
        read_profile(tmp_path / "b.npy", unit="um", spacing=1.0)
    (tmp_path / "e.bin").write_bytes(b"")
    for fmt in ("npy", "npz", "x3p"):
        with pytest.raises(ProfileReadError):
            read_profile(tmp_path / "e.bin", format=fmt, unit="um")
    (tmp_path / "a.npy").write_bytes(data)
    with pytest.raises(NumpyFileError, match="not a zip"):
        read_profile(tmp_path / "a.npy", format="npz", unit="um")


# --- D7: stored metadata -----------------------------------------------------------------------


@pytest.mark.parametrize(
    "stored",
    [
        '{"profile_metadata": {"preprocessing": 5}}',
        '{"profile_metadata": {"preprocessing": "ab"}}',
        '{"profile_metadata": {"preprocessing": [{"no": "step"}]}}',
        '{"profile_metadata": [1, 2]}',
        '{"units": 3}',
        "[" * 100_000 + "]" * 100_000,
        "{not json",
        "1" * 5000,
    ],
)
def test_bad_stored_metadata_refused(tmp_path: Path, stored: str) -> None:
    csv = tmp_path / "m.csv"
    csv.write_text(f"# splinecontact-metadata: {stored}\nx [um], z [um]\n0,0\n1,1\n2,0\n3,1\n4,0\n")
    with pytest.raises(CorruptFileError, match="metadata"):
        read_profile(csv)
    _npz(
        tmp_path / "m.npz",
        x=npy_bytes(np.arange(5.0)),
        z=npy_bytes(np.zeros(5)),
        metadata=npy_bytes(np.array(stored)),
    )
    with pytest.raises(CorruptFileError, match="metadata"):
        read_profile(tmp_path / "m.npz", unit="um")


def test_damaged_preprocessing_record_refused_by_to_profile() -> None:
    raw = RawProfile(np.arange(6.0), np.zeros(6), metadata={"preprocessing": 5})
    with pytest.raises(ProfileError, match="not a list of step records"):
        to_profile(raw)


# --- D9/D10: no silent wrong results -----------------------------------------------------------


@pytest.mark.parametrize(
    "positions",
    [
        [i for i in range(50) if i != 20],  # the report's gap.csv (x in nm)
        [0, 1, 2, 3, 5, 6, 7, 8],
        [10, 20, 30, 40, 60, 70, 80, 90],
    ],
)
def test_missing_sample_is_never_regularised(tmp_path: Path, positions: list[int]) -> None:
    path = tmp_path / "gap.csv"
    tokens = [f"{v}" if v < 10 or positions[1] == 1 else f"{v // 10}e1" for v in positions]
    path.write_text(
        "x [nm], z [nm]\n"
        + "".join(f"{t}, {np.sin(v):.4f}\n" for t, v in zip(tokens, positions, strict=True))
    )
    with pytest.raises(GridNotUniformError, match=r"cannot be told from rounding|missing"):
        read_profile(path)


def test_coarse_print_with_distinguishable_gap_refused(tmp_path: Path) -> None:
    exact = 0.156 * np.arange(64)
    printed = np.round(np.delete(exact, 30), 1)
    path = tmp_path / "dg.csv"
    path.write_text(
        "x [um], z [um]\n" + "".join(f"{v:.1f}, {i % 5}\n" for i, v in enumerate(printed))
    )
    with pytest.raises(GridNotUniformError, match="missing or extra"):
        read_profile(path)
    full = tmp_path / "ok.csv"
    full.write_text(
        "x [um], z [um]\n"
        + "".join(f"{v:.1f}, {i % 5}\n" for i, v in enumerate(np.round(exact, 1)))
    )
    p = read_profile(full)
    assert p.metadata["preprocessing"][0]["step"] == "regularize_grid"
    assert p.dx == pytest.approx(0.156, abs=2e-3)


def test_areal_npz_never_flattened(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    np.savez(tmp_path / "a.npz", x=np.arange(50.0), z=rng.random((5, 10)))
    with pytest.raises(LineSelectionError, match="line="):
        read_profile(tmp_path / "a.npz", unit="um")
    with pytest.raises(NumpyFileError, match="one height per position"):
        read_profile(tmp_path / "a.npz", unit="um", line=1)
    np.savez(tmp_path / "b.npz", x=np.arange(10.0), z=rng.random((5, 10)))
    p = read_profile(tmp_path / "b.npz", unit="um", line=2)
    assert p.n_points == 10


def test_raw_profile_refuses_areal_and_complex_arrays() -> None:
    with pytest.raises(ProfileError, match="flattened"):
        RawProfile(np.arange(50.0), np.zeros((5, 10)))
    with pytest.raises(ProfileError, match="real numbers"):
        RawProfile(np.arange(5.0), np.arange(5.0) + 1j)


# --- D13: degenerate preprocessing -------------------------------------------------------------


def test_all_nan_positions_with_crop(tmp_path: Path) -> None:
    path = tmp_path / "n.csv"
    path.write_text("x [um], z [um]\n" + "".join(f"nan,{i}\n" for i in range(1, 7)))
    with pytest.raises(UndefinedPointsError, match="defined position"):
        read_profile(path, preprocessing=Preprocessing(undefined="interpolate", crop=(0, 10)))


def test_subnormal_grid_refused_not_lapack_error() -> None:
    x = np.arange(10) * 1e-314
    raw = RawProfile(np.repeat(x, 2), np.arange(20.0))
    options = Preprocessing(order="sort", duplicates="average", detrend="tilt")
    with pytest.raises(GridNotUniformError, match="floating point"):
        to_profile(raw, options)


def test_unfittable_form_is_a_profile_error() -> None:
    from splinecontact.preprocess import _fit_form

    with pytest.raises(ProfileError, match="cannot be fitted"):
        _fit_form(np.arange(5.0), np.array([1e308, -1e308, 1e308, -1e308, 1e308]), 1)
    with pytest.raises(ProfileError, match="cannot be fitted"):
        _fit_form(np.arange(5.0) * 1e-320, np.arange(5.0), 1)


# --- D11: allocations ------------------------------------------------------------------------


def test_resample_size_has_a_ceiling() -> None:
    raw = RawProfile([0.0, 1.0, 2.5, 3.0, 4.0, 5.0], np.zeros(6))
    with pytest.raises(PreprocessingOptionError, match="max_points"):
        to_profile(raw, Preprocessing(nonuniform="resample", resample_spacing=1e-9))
    p = to_profile(raw, Preprocessing(nonuniform="resample", resample_spacing=0.5, max_points=11))
    assert p.n_points == 11
    with pytest.raises(PreprocessingOptionError):
        Preprocessing(resample_spacing=float("inf"))


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
def test_dev_zero_refused_line_by_line() -> None:
    with pytest.raises((FileTooLargeError, ProfileReadError)):
        read_profile("/dev/zero", format="table", unit="um")


def test_text_rows_counted_against_the_limit(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("x [um], z [um]\n" + "".join(f"{i}, 0\n" for i in range(100)))
    with pytest.raises(FileTooLargeError, match="100 points"):
        read_profile(path, max_points=99)
    assert read_profile(path, max_points=100).n_points == 100


def test_huge_line_refused(tmp_path: Path) -> None:
    path = tmp_path / "h.csv"
    path.write_text("x [um], z [um]\n" + "1" * 5_000_000 + "\n0, 1\n")
    with pytest.raises(FileTooLargeError, match="line 2: longer than"):
        read_profile(path)


# --- D22: valid tables that were refused --------------------------------------------------------


def test_decimal_comma_whitespace_table(tmp_path: Path) -> None:
    path = tmp_path / "dc.txt"
    text = "x [mm]  z [um]\n" + "".join(
        f"{i * 0.0025:.4f}  {-183.9 + i:.2f}\n".replace(".", ",") for i in range(10)
    )
    path.write_text(text)
    p = read_profile(path)
    np.testing.assert_allclose(p.x, np.arange(10) * 2.5)
    np.testing.assert_allclose(p.z, -183.9 + np.arange(10))


@pytest.mark.parametrize("sep", ["  ", " ", "\t"])
def test_multi_word_whitespace_titles_with_units(tmp_path: Path, sep: str) -> None:
    path = tmp_path / "mw.txt"
    path.write_text(
        f"Lateral µm{sep}Height microns\n" + "".join(f"{i}  {i % 3}\n" for i in range(8))
    )
    p = read_profile(path)
    assert p.metadata["units"]["x"] == "µm"
    assert p.metadata["units"]["z"] == "µm"
    assert p.n_points == 8


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be"])
def test_utf16_files(tmp_path: Path, encoding: str) -> None:
    text = "x [µm], z [nm]\n" + "".join(f"{i}, {i % 4}\n" for i in range(8))
    bom = {"utf-16": b"", "utf-16-le": b"\xff\xfe", "utf-16-be": b"\xfe\xff"}[encoding]
    path = tmp_path / "u16.csv"
    path.write_bytes(bom + text.encode(encoding))
    p = read_profile(path)
    np.testing.assert_allclose(p.z, (np.arange(8) % 4) * 1e-3)


# --- matrices (Gwyddion ASCII and the like) -----------------------------------------------------


def test_height_matrix_refused_unless_a_row_is_chosen(tmp_path: Path) -> None:
    matrix = np.arange(24.0).reshape(4, 6)
    path = tmp_path / "gwy.txt"
    path.write_text(
        "# Channel: Height\n# Width: 5.000 µm\n"
        + "".join("\t".join(f"{v:.3e}" for v in row) + "\n" for row in matrix)
    )
    with pytest.raises(LineSelectionError, match="matrix"):
        read_profile(path, unit="m")
    p = read_profile(path, unit="um", line=2, spacing=0.5)
    np.testing.assert_allclose(p.z, matrix[2])
    np.testing.assert_allclose(p.x, np.arange(6) * 0.5)
    with pytest.raises(LineSelectionError, match="line=4"):
        read_profile(path, unit="um", line=4, spacing=0.5)
    two = tmp_path / "two.csv"
    two.write_text("x [um], z [um]\n" + "".join(f"{i}, 0\n" for i in range(6)))
    with pytest.raises(ReadOptionError, match="line="):
        read_profile(two, line=0)


# --- the CLI: one line, no traceback ------------------------------------------------------------


def _inspect(args: list[str]) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).parents[1] / "src"))
    return subprocess.run(
        [sys.executable, "-m", "splinecontact", "inspect", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        check=False,
    )


@pytest.mark.slow
def test_cli_refuses_hostile_files_in_one_line(tmp_path: Path) -> None:
    x3p_data_bomb(tmp_path / "bomb.x3p", 256 * MiB, (10, 1))
    write_x3p(tmp_path / "laughs.x3p", x3p_xml(prolog=_LAUGHS, manufacturer="&lol9;"), bytes(80))
    (tmp_path / "v.csv").write_text("x [um], z [um]\n0, 0\n1, 1e400\n2, 0\n3, 0\n4, 0\n")
    for args in (["bomb.x3p", "--line", "0"], ["laughs.x3p"], ["v.csv"]):
        result = _inspect([str(tmp_path / args[0]), *args[1:]])
        assert result.returncode != 0
        assert "Traceback" not in result.stderr
        assert len(result.stderr.strip().splitlines()) == 1, result.stderr


# --- the report's bombs at full size, with memory measured ----------------------------------------

_MEASURE = textwrap.dedent(
    """
    import resource, subprocess, sys, time
    start = time.perf_counter()
    child = subprocess.run(sys.argv[1:], capture_output=True, text=True)
    wall = time.perf_counter() - start
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = usage.ru_utime + usage.ru_stime
    print(child.returncode, usage.ru_maxrss, f"{wall:.3f}", f"{cpu:.3f}", *child.stdout.split())
    sys.stderr.write(child.stderr)
    """
)


def _measured_read(path: Path, **options: object) -> tuple[str, int, float, float, float]:
    """Read in a grandchild; return (error class, peak RSS [kB], wall, CPU, read time [s]).

    The child runs the reader in its own child and reports ``RUSAGE_CHILDREN``: the peak
    resident memory of the reading process alone (interpreter and imports included).
    """
    code = textwrap.dedent(
        f"""
        import time
        from splinecontact.io import read_profile
        from splinecontact import SplineContactError
        start = time.perf_counter()
        try:
            read_profile({str(path)!r}, **{options!r})
            outcome = "accepted"
        except SplineContactError as exc:
            outcome = type(exc).__name__
        print(outcome, f"{{time.perf_counter() - start:.4f}}")
        """
    )
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).parents[1] / "src"))
    result = subprocess.run(
        [sys.executable, "-c", _MEASURE, sys.executable, "-c", code],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=True,
    )
    rc, rss, wall, cpu, outcome, read_time = result.stdout.split()
    assert rc == "0", result.stderr
    return outcome, int(rss), float(wall), float(cpu), float(read_time)


@pytest.mark.slow
def test_report_bombs_refused_in_bounded_memory(tmp_path: Path) -> None:
    gib2 = 2048 * MiB
    x3p_data_bomb(tmp_path / "bomb-data-mismatch.x3p", gib2, (10, 1))
    x3p_data_bomb(tmp_path / "bomb-data-match.x3p", gib2, (16384, 16384))
    x3p_forged_size_bomb(tmp_path / "bomb-forged.x3p", gib2)
    x3p_xml_bomb(tmp_path / "bomb-xml.x3p", 1024 * MiB)
    npz_bomb(tmp_path / "bomb.npz", 1 << 28)
    cases = {
        "bomb-data-mismatch.x3p": ({"line": 0}, "DamagedX3PError"),
        "bomb-data-match.x3p": ({"line": 0}, "FileTooLargeError"),
        "bomb-forged.x3p": ({}, "DamagedX3PError"),
        "bomb-xml.x3p": ({}, "FileTooLargeError"),
        "bomb.npz": ({"unit": "um"}, "FileTooLargeError"),
    }
    report = []
    for name, (options, expected) in cases.items():
        path = tmp_path / name
        outcome, rss_kb, wall, cpu, read_time = _measured_read(path, **options)
        report.append(
            f"{name}: {path.stat().st_size / MiB:.1f} MiB file, {outcome}, peak RSS "
            f"{rss_kb / 1024:.0f} MB; read_profile {read_time * 1000:.1f} ms; whole process "
            f"(interpreter, imports) wall {wall:.2f} s, CPU {cpu:.2f} s"
        )
        assert outcome == expected, report[-1]
        assert rss_kb <= 200 * 1024, report[-1]
    print("\n".join(report))  # the figures quoted in docs/measured-profiles.md (run with -s)


# --- D22 oracle: well-formed tables read back exactly --------------------------------------------

_TITLES = [
    (("x [um]", "z [nm]"), (1.0, 1e-3)),
    (("Lateral µm", "Height nm"), (1.0, 1e-3)),
    (("Lateral um", "Total Profile nm"), (1.0, 1e-3)),
    (("x (mm)", "z (um)"), (1e3, 1.0)),
    (("Position microns", "Height microns"), (1.0, 1.0)),
]


@settings(
    max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    n=st.integers(5, 40),
    step=st.sampled_from([0.5, 0.25, 1.0, 2.5]),
    seed=st.integers(0, 2**16),
    sep=st.sampled_from(["  ", "\t", " ", ";", ","]),
    decimal_comma=st.booleans(),
    titles=st.sampled_from(_TITLES),
    encoding=st.sampled_from(["utf-8", "utf-8-sig", "utf-16", "cp1252"]),
    newline=st.sampled_from(["\n", "\r\n", "\r"]),
)
def test_well_formed_tables_read_back_exactly(
    tmp_path: Path,
    n: int,
    step: float,
    seed: int,
    sep: str,
    decimal_comma: bool,
    titles: tuple[tuple[str, str], tuple[float, float]],
    encoding: str,
    newline: str,
) -> None:
    if decimal_comma and sep == ",":
        sep = ";"
    (x_title, z_title), (x_factor, z_factor) = titles
    x = np.arange(n) * step
    z = np.round(np.random.default_rng(seed).normal(scale=50.0, size=n), 4)

    def num(v: float, digits: int) -> str:
        text = f"{v:.{digits}f}"
        return text.replace(".", ",") if decimal_comma else text

    lines = [f"{x_title}{sep}{z_title}"]
    lines += [f"{num(a, 2)}{sep}{num(b, 4)}" for a, b in zip(x, z, strict=True)]
    path = tmp_path / "oracle.txt"
    path.write_bytes((newline.join(lines) + newline).encode(encoding))
    p = read_profile(path)
    np.testing.assert_allclose(p.x, x * x_factor, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(p.z, z * z_factor, rtol=1e-12, atol=1e-12)


def test_wrong_option_types_are_specific_errors(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("x [um], z [um]\n" + "".join(f"{i}, 0\n" for i in range(6)))
    with pytest.raises(ReadOptionError, match="format=5"):
        read_profile(path, format=5)  # type: ignore[arg-type]
    with pytest.raises(PreprocessingOptionError, match="not a Preprocessing"):
        read_profile(path, preprocessing="tilt")  # type: ignore[arg-type]
    with pytest.raises(ReadOptionError, match="line="):
        read_profile(path, line=1.5)  # type: ignore[arg-type]
    with pytest.raises(ReadOptionError, match="spacing="):
        read_profile(path, spacing="wide")  # type: ignore[arg-type]
    with pytest.raises(PreprocessingOptionError, match="crop="):
        Preprocessing(crop=(0, "a"))  # type: ignore[arg-type]
