"""Builders of hostile and damaged input files for the reader tests (written at test time).

Zip bombs are built without ever holding their inflated content: a raw deflate block of
16 MiB of zeros, flushed so that it stands alone, is repeated; the zip structure is written by
hand, so the sizes in the zip directory can also be forged.
"""

from __future__ import annotations

import hashlib
import struct
import zlib
from pathlib import Path

import numpy as np

_BLOCK = 1 << 24  # 16 MiB of zeros per repeated deflate block


def _zeros_deflate(n_bytes: int) -> tuple[bytes, int]:
    """Raw deflate stream of ``n_bytes`` zeros (a multiple of 16 MiB, or less) and its CRC-32."""
    compressor = zlib.compressobj(9, zlib.DEFLATED, -15)
    if n_bytes >= _BLOCK:
        assert n_bytes % _BLOCK == 0
        block = compressor.compress(bytes(_BLOCK)) + compressor.flush(zlib.Z_FULL_FLUSH)
        count = n_bytes // _BLOCK
        stream = block * count + zlib.compressobj(9, zlib.DEFLATED, -15).flush()
        crc = 0
        zeros = bytes(_BLOCK)
        for _ in range(count):
            crc = zlib.crc32(zeros, crc)
        return stream, crc
    data = bytes(n_bytes)
    return compressor.compress(data) + compressor.flush(), zlib.crc32(data)


def raw_zip(path: Path, members: list[tuple[str, bytes, int, int, int]]) -> None:
    """Write a zip of deflated members ``(name, deflate stream, crc, true size, declared size)``.

    The declared (uncompressed) size goes into both the local header and the directory.
    """
    local = bytearray()
    central = bytearray()
    for name, stream, crc, _size, declared in members:
        encoded = name.encode("utf-8")
        offset = len(local)
        local += struct.pack(
            "<IHHHHHIIIHH", 0x04034B50, 20, 0x800, 8, 0, 0x21, crc, len(stream), declared,
            len(encoded), 0,
        )  # fmt: skip
        local += encoded + stream
        central += struct.pack(
            "<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, 0x800, 8, 0, 0x21, crc, len(stream),
            declared, len(encoded), 0, 0, 0, 0, 0, offset,
        )  # fmt: skip
        central += encoded
    end = struct.pack(
        "<IHHHHIIH", 0x06054B50, 0, 0, len(members), len(members), len(central), len(local), 0
    )
    path.write_bytes(bytes(local) + bytes(central) + end)


def member(name: str, data: bytes, declared: int | None = None) -> tuple[str, bytes, int, int, int]:
    """A deflated member of real content (optionally with a forged declared size)."""
    compressor = zlib.compressobj(6, zlib.DEFLATED, -15)
    stream = compressor.compress(data) + compressor.flush()
    size = len(data)
    return name, stream, zlib.crc32(data), size, size if declared is None else declared


def zeros_member(
    name: str, n_bytes: int, declared: int | None = None
) -> tuple[str, bytes, int, int, int]:
    """A member inflating to ``n_bytes`` zeros (a bomb when large)."""
    stream, crc = _zeros_deflate(n_bytes)
    return name, stream, crc, n_bytes, n_bytes if declared is None else declared


def x3p_xml(
    *,
    size_x: object = 10,
    size_y: object = 1,
    size_z: object = 1,
    feature: str = "PRF",
    dtype: str = "D",
    increment_x: object = "2e-6",
    data_link: str = "bindata/data.bin",
    md5: str | None = None,
    valid_link: str | None = None,
    prolog: str = "",
    manufacturer: str = "fuzz",
) -> str:
    """``main.xml`` of an X3P file (every field can be given as text, forged or not)."""
    checksum = f"<MD5ChecksumPointData>{md5}</MD5ChecksumPointData>" if md5 else ""
    valid = f"<ValidPntsLink>{valid_link}</ValidPntsLink>" if valid_link else ""
    return f"""<?xml version="1.0" encoding="UTF-8"?>
{prolog}<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
<Record1><Revision>ISO5436 - 2000</Revision><FeatureType>{feature}</FeatureType><Axes>
<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>{increment_x}</Increment><Offset>0</Offset></CX>
<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>5e-6</Increment></CY>
<CZ><AxisType>A</AxisType><DataType>{dtype}</DataType></CZ></Axes></Record1>
<Record2><Instrument><Manufacturer>{manufacturer}</Manufacturer></Instrument></Record2>
<Record3><MatrixDimension><SizeX>{size_x}</SizeX><SizeY>{size_y}</SizeY><SizeZ>{size_z}</SizeZ></MatrixDimension>
<DataLink><PointDataLink>{data_link}</PointDataLink>{checksum}</DataLink>{valid}</Record3>
</p:ISO5436_2>"""


def write_x3p(path: Path, xml: str, data: bytes, extra: dict[str, bytes] | None = None) -> None:
    """An X3P of ``main.xml`` and ``bindata/data.bin`` (plus ``extra`` members by name)."""
    members = [member("main.xml", xml.encode()), member("bindata/data.bin", data)]
    members += [member(name, content) for name, content in (extra or {}).items()]
    raw_zip(path, members)


def good_x3p(path: Path, n: int = 10) -> bytes:
    """A valid profile X3P with its MD5; returns the point data."""
    data = np.sin(np.arange(n) / 3.0).astype("<f8").tobytes() if n else b""
    write_x3p(path, x3p_xml(size_x=n, md5=hashlib.md5(data).hexdigest()), data)
    return data


def npy_bytes(array: np.ndarray) -> bytes:
    import io

    buffer = io.BytesIO()
    np.save(buffer, array, allow_pickle=False)
    return buffer.getvalue()


def npy_header(shape: tuple[int, ...], descr: str = "<f8") -> bytes:
    """Only the header of an .npy file declaring ``shape`` (no data)."""
    import io

    buffer = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        buffer, {"descr": descr, "fortran_order": False, "shape": shape}
    )
    return buffer.getvalue()


# --- the bombs of the reliability report -------------------------------------------------------


def x3p_data_bomb(path: Path, n_bytes: int, size: tuple[int, int]) -> None:
    """``bindata/data.bin`` inflates to ``n_bytes`` zeros; main.xml declares ``size`` points."""
    xml = x3p_xml(size_x=size[0], size_y=size[1], feature="SUR" if size[1] > 1 else "PRF")
    raw_zip(path, [member("main.xml", xml.encode()), zeros_member("bindata/data.bin", n_bytes)])


def x3p_forged_size_bomb(path: Path, n_bytes: int) -> None:
    """data.bin inflates to ``n_bytes`` but the zip directory declares the 80 bytes expected."""
    xml = x3p_xml(size_x=10, size_y=1)
    raw_zip(
        path,
        [member("main.xml", xml.encode()), zeros_member("bindata/data.bin", n_bytes, declared=80)],
    )


def x3p_xml_bomb(path: Path, n_bytes: int) -> None:
    """``main.xml`` inflates to ``n_bytes`` zeros."""
    raw_zip(path, [zeros_member("main.xml", n_bytes), member("bindata/data.bin", bytes(80))])


def npz_bomb(path: Path, n_points: int) -> None:
    """Arrays ``x`` and ``z`` declaring ``n_points`` float64 each, inflating to zeros."""
    members = []
    for name in ("x", "z"):
        header = npy_header((n_points,))
        stream, _ = _zeros_deflate(n_points * 8)
        # the header must be deflated too: prepend it as a stored-then-flushed block
        compressor = zlib.compressobj(9, zlib.DEFLATED, -15)
        head = compressor.compress(header) + compressor.flush(zlib.Z_FULL_FLUSH)
        crc_full = zlib.crc32(header)
        zeros = bytes(_BLOCK)
        for _ in range(n_points * 8 // _BLOCK):
            crc_full = zlib.crc32(zeros, crc_full)
        size = len(header) + n_points * 8
        members.append((f"{name}.npy", head + stream, crc_full, size, size))
    raw_zip(path, members)
