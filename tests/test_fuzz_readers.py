"""Fuzz suite of the readers: whatever the bytes, ``read_profile`` returns a profile or raises a
:class:`~splinecontact.SplineContactError` subclass — never another exception.

Two parts, both with fixed seeds:

* a mutation loop over the committed sample files in ``tests/data`` plus seeds written at test
  time (a small X3P, ``.npz``/``.npy``/``.csv`` files written by ``write_profile``): byte flips,
  truncation, garbage, non-UTF-8 bytes, BOMs, NaN/inf/1e308/1e400 tokens, huge lines, bracket
  runs in headers, wrong dtypes, object/pickle arrays, damaged or renamed (path-traversal) zip
  members, forged X3P sizes, each read with random options;
* hypothesis strategies for text tables and binary blobs.

The default run tries a few hundred inputs (a few seconds); the ``slow`` tier tries 10 000 and
prints the tally quoted in ``docs/measured-profiles.md``
(``pytest -m slow -s tests/test_fuzz_readers.py``).
"""

from __future__ import annotations

import io
import random
import time
import zipfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from _hostile import good_x3p, npy_bytes, x3p_xml
from splinecontact import SplineContactError
from splinecontact.errors import NoDataError
from splinecontact.generate import weierstrass_mandelbrot
from splinecontact.io import read_profile, write_profile
from splinecontact.preprocess import Preprocessing

#: A warning while reading is an extra line besides the one error line: it counts as an escape.
pytestmark = pytest.mark.filterwarnings("error")

DATA = Path(__file__).parent / "data"
_TEXT_SUFFIXES = {".csv", ".txt", ".hfm", ".dat"}
_MAX_TEXT_LINES = 300  # large text seeds are cut (their headers kept) to keep each read fast


@dataclass
class Tally:
    """Outcome of a fuzz run."""

    inputs: int = 0
    accepted: int = 0
    refused: Counter[str] = field(default_factory=Counter)
    escaped: list[str] = field(default_factory=list)
    slowest: float = 0.0
    seconds: float = 0.0

    def summary(self) -> str:
        lines = [
            f"inputs {self.inputs}, read {self.accepted}, refused {sum(self.refused.values())}, "
            f"other exceptions {len(self.escaped)}; slowest input {self.slowest:.2f} s; "
            f"total {self.seconds:.1f} s",
        ]
        lines += [f"  {name}: {count}" for name, count in self.refused.most_common()]
        lines += [f"  ESCAPED {text}" for text in self.escaped[:20]]
        return "\n".join(lines)


# --- seeds -----------------------------------------------------------------------------------


def _seeds(folder: Path) -> list[tuple[str, bytes]]:
    """(suffix, content) of every seed file."""
    seeds: list[tuple[str, bytes]] = []
    for path in sorted(DATA.iterdir()):
        if path.suffix.lower() not in {*_TEXT_SUFFIXES, ".x3p"}:
            continue
        data = path.read_bytes()
        if path.suffix.lower() in _TEXT_SUFFIXES:
            data = b"\n".join(data.splitlines()[:_MAX_TEXT_LINES]) + b"\n"
        seeds.append((path.suffix.lower(), data))
    good_x3p(folder / "seed.x3p", n=64)
    seeds.append((".x3p", (folder / "seed.x3p").read_bytes()))
    profile = weierstrass_mandelbrot(1.5, n_points=64, seed=3)
    for suffix in (".npz", ".csv"):
        write_profile(profile, folder / f"seed{suffix}")
        seeds.append((suffix, (folder / f"seed{suffix}").read_bytes()))
    seeds.append((".npy", npy_bytes(np.column_stack([profile.x, profile.z]))))
    seeds.append((".npy", npy_bytes(np.arange(24.0).reshape(4, 6))))
    return seeds


# --- mutations -------------------------------------------------------------------------------

_TOKENS = [b"nan", b"inf", b"-inf", b"1e308", b"1e400", b"-1e999", b"0", b"1e-320", b"NaN", b""]
_GARBAGE = [
    b"\xff\xfe\x80\x81",
    b"\x00" * 7,
    b"[" * 5000,
    b"x [" + b" " * 3000 + b"a",
    b"(" * 3000,
    b";;;;,,,,\t\t",
    "µm Å μm".encode(),
    b"\r\r\n\n",
    b'# splinecontact-metadata: {"profile_metadata": {"preprocessing": 5}}\n',
    b"# splinecontact-metadata: " + b"[" * 3000 + b"\n",
]
_BOMS = [b"\xef\xbb\xbf", b"\xff\xfe", b"\xfe\xff"]
_DTYPES = ["<f2", "<f4", ">f8", "<i2", "<u8", "|b1", "<c16", "<U3", "|S4", "<M8[s]", "<m8[s]"]


def _mutate_bytes(rng: random.Random, data: bytes) -> bytes:
    kind = rng.randrange(9)
    buf = bytearray(data)
    if kind == 0 and buf:  # byte flips
        for _ in range(rng.randint(1, 12)):
            buf[rng.randrange(len(buf))] ^= 1 << rng.randrange(8)
    elif kind == 1:  # truncation
        del buf[rng.randrange(len(buf) + 1) :]
    elif kind == 2:  # garbage spliced in
        at = rng.randrange(len(buf) + 1)
        buf[at:at] = rng.choice(_GARBAGE)
    elif kind == 3:  # random bytes overwrite a span
        at = rng.randrange(len(buf) + 1)
        buf[at : at + rng.randint(1, 64)] = rng.randbytes(rng.randint(1, 64))
    elif kind == 4:  # BOM
        buf[0:0] = rng.choice(_BOMS)
    elif kind == 5:  # a number token replaced by a hostile one
        text = bytes(buf)
        digits = [i for i, b in enumerate(text) if 48 <= b <= 57]
        if digits:
            at = rng.choice(digits)
            end = at
            while end < len(text) and text[end] in b"0123456789.eE+-":
                end += 1
            buf[at:end] = rng.choice(_TOKENS)
    elif kind == 6:  # a huge line
        at = rng.randrange(len(buf) + 1)
        buf[at:at] = b"\n" + b"1," * rng.choice([1000, 100_000]) + b"\n"
    elif kind == 7:  # lines duplicated or dropped
        lines = bytes(buf).split(b"\n")
        if lines:
            k = rng.randrange(len(lines))
            if rng.random() < 0.5:
                lines.insert(k, lines[k])
            else:
                del lines[k]
        buf = bytearray(b"\n".join(lines))
    else:  # entirely random
        buf = bytearray(rng.randbytes(rng.randint(0, 2048)))
    return bytes(buf)


def _mutate_zip(rng: random.Random, data: bytes) -> bytes:
    """Rebuild a zip archive with one member mutated, renamed, added or removed."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            members = [(info.filename, archive.read(info)) for info in archive.infolist()]
    except (zipfile.BadZipFile, OSError, ValueError, EOFError):
        return _mutate_bytes(rng, data)
    kind = rng.randrange(6)
    k = rng.randrange(len(members)) if members else 0
    if kind == 0 and members:  # content mutated
        name, content = members[k]
        members[k] = (name, _mutate_bytes(rng, content))
    elif kind == 1 and members:  # path traversal / absolute member names
        name, content = members[k]
        members[k] = (rng.choice(["../../" + name, "/" + name, "..\\" + name]), content)
        if rng.random() < 0.5:
            members.append((name, content))
    elif kind == 2 and members:
        del members[k]
    elif kind == 3:  # an array with a wrong dtype, an object array or a pickle
        name = rng.choice(["z.npy", "x.npy", "metadata.npy", "bindata/data.bin"])
        if rng.random() < 0.3:
            buffer = io.BytesIO()
            np.save(buffer, np.array([{"a": 1}, None], dtype=object), allow_pickle=True)
            content = buffer.getvalue()
        else:
            content = npy_bytes(np.zeros(rng.choice([0, 1, 5, 64]), dtype=rng.choice(_DTYPES)))
        members = [(n, c) for n, c in members if n != name] + [(name, content)]
    elif kind == 4:  # a forged X3P description
        size = rng.choice(["nan", "inf", "0", "-3", "1e12", "64", "2.5", "99999999999"])
        dtype = rng.choice(["D", "F", "I", "L", "Q", ""])
        xml = x3p_xml(size_x=size, size_y=rng.choice(["1", "2", size]), dtype=dtype)
        members = [(n, c) for n, c in members if n != "main.xml"] + [("main.xml", xml.encode())]
    else:
        return _mutate_bytes(rng, data)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, content in members:
            archive.writestr(name, content)
    return out.getvalue()


def _options(rng: random.Random) -> dict[str, object]:
    options: dict[str, object] = {}
    if rng.random() < 0.6:
        options["unit"] = rng.choice(["um", "nm", "mm", "inch"])
    if rng.random() < 0.2:
        options["height_unit"] = rng.choice(["nm", "A"])
    if rng.random() < 0.25:
        options["spacing"] = rng.choice([1.0, 0.5, -1.0, float("nan")])
    if rng.random() < 0.3:
        options["line"] = rng.choice([0, 1, 3, 10**9, -1])
    if rng.random() < 0.2:
        options["format"] = rng.choice(["table", "dektak", "x3p", "npy", "npz", "bogus"])
    if rng.random() < 0.1:
        options["max_points"] = rng.choice([5, 100, 10**8])
    if rng.random() < 0.5:
        options["preprocessing"] = Preprocessing(
            undefined=rng.choice(["refuse", "interpolate"]),
            order=rng.choice(["refuse", "sort"]),
            duplicates=rng.choice(["refuse", "average"]),
            nonuniform=rng.choice(["refuse", "resample"]),
            crop=rng.choice([None, (0.0, 10.0), (-1e300, 1e300)]),
            detrend=rng.choice(["none", "mean", "tilt", "poly3"]),
        )
    return options


def _attempt(path: Path, options: dict[str, object], tally: Tally, label: str) -> None:
    start = time.perf_counter()
    try:
        read_profile(path, **options)  # type: ignore[arg-type]
        tally.accepted += 1
    except SplineContactError as exc:
        tally.refused[type(exc).__name__] += 1
    except Exception as exc:  # the failure this suite exists to find
        tally.escaped.append(f"{label} {options}: {type(exc).__name__}: {str(exc)[:200]}")
    tally.slowest = max(tally.slowest, time.perf_counter() - start)
    tally.inputs += 1


def run_mutation_fuzz(folder: Path, n_inputs: int, seed: int) -> Tally:
    """Mutate the seeds ``n_inputs`` times (fixed ``seed``) and read each result."""
    rng = random.Random(seed)
    seeds = _seeds(folder)
    tally = Tally()
    start = time.perf_counter()
    for k in range(n_inputs):
        suffix, data = rng.choice(seeds)
        zipped = data.startswith(b"PK\x03\x04")
        mutated = _mutate_zip(rng, data) if zipped and rng.random() < 0.7 else data
        if not zipped or mutated is data:
            mutated = _mutate_bytes(rng, data)
        if rng.random() < 0.1:
            suffix = rng.choice([".csv", ".x3p", ".npz", ".npy", ".txt", ""])
        path = folder / f"input{suffix}"
        path.write_bytes(mutated)
        _attempt(path, _options(rng), tally, f"input {k} ({suffix})")
    tally.seconds = time.perf_counter() - start
    return tally


def test_mutation_fuzz_default_budget(tmp_path: Path) -> None:
    tally = run_mutation_fuzz(tmp_path, n_inputs=150, seed=20261123)
    assert tally.escaped == [], tally.summary()
    assert tally.inputs == 150


@pytest.mark.slow
def test_mutation_fuzz_slow_budget(tmp_path: Path) -> None:
    tally = run_mutation_fuzz(tmp_path, n_inputs=10_000, seed=1)
    print("\nmutation fuzz, seed 1:\n" + tally.summary())
    assert tally.escaped == [], tally.summary()
    assert tally.inputs >= 10_000


# --- hypothesis: arbitrary tables and blobs ---------------------------------------------------

_cells = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(10**30), 10**30).map(str),
    st.sampled_from(["nan", "bad", "", "-", "1e400", "1,5", "x [um]", "z (nm)", "[", "(", "µm"]),
    st.text(max_size=8),
)
_tables = st.tuples(
    st.lists(st.text(max_size=30), max_size=3),
    st.sampled_from([",", ";", "\t", " ", "  "]),
    st.lists(st.lists(_cells, min_size=1, max_size=4), max_size=30),
    st.sampled_from(["\n", "\r\n", "\r"]),
    st.sampled_from(["utf-8", "utf-8-sig", "utf-16", "cp1252", "latin-1"]),
)


def _hypothesis_check(tmp_path: Path, suffix: str, data: bytes, options: dict[str, object]) -> None:
    path = tmp_path / f"h{suffix}"
    path.write_bytes(data)
    tally = Tally()
    _attempt(path, options, tally, "hypothesis")
    assert tally.escaped == [], tally.escaped


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(table=_tables, unit=st.sampled_from([None, "um"]), spacing=st.sampled_from([None, 1.0]))
@example(table=([], ",", [["bad"], ["0.0"]], "\n", "utf-8"), unit=None, spacing=None)
def test_any_text_table_gives_profile_or_specific_error(
    tmp_path: Path,
    table: tuple[list[str], str, list[list[str]], str, str],
    unit: str | None,
    spacing: float | None,
) -> None:
    header, delimiter, rows, newline, encoding = table
    lines = [*header, *(delimiter.join(row) for row in rows)]
    data = newline.join(lines).encode(encoding, errors="replace")
    _hypothesis_check(tmp_path, ".csv", data, {"unit": unit, "spacing": spacing})


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    blob=st.binary(max_size=4096),
    prefix=st.sampled_from([b"", b"PK\x03\x04", b"\x93NUMPY\x01\x00", b"\xff\xfe"]),
    suffix=st.sampled_from([".csv", ".x3p", ".npy", ".npz", ""]),
)
def test_any_bytes_give_profile_or_specific_error(
    tmp_path: Path, blob: bytes, prefix: bytes, suffix: str
) -> None:
    _hypothesis_check(tmp_path, suffix, prefix + blob, {"unit": "um"})


@pytest.mark.parametrize("title", ["bad", "valid"])
def test_a_lone_flag_column_is_no_data(tmp_path: Path, title: str) -> None:
    """A table whose only column is a validity flag has no heights (was an IndexError)."""
    path = tmp_path / "flag.csv"
    path.write_text(f"{title}\n0.0\n1.0\n")
    with pytest.raises(NoDataError, match="validity flag"):
        read_profile(path, spacing=1.0)
