"""Text files read one line at a time: encoding (UTF-16 with BOM, UTF-8, Windows-1252) and
line endings, with a ceiling on the length of a line."""

from __future__ import annotations

import codecs
import io
from collections.abc import Generator
from pathlib import Path

from ..errors import FileTooLargeError
from ._limits import MAX_LINE_CHARS

__all__ = ["decode_text", "has_utf16_bom", "iter_lines"]


def has_utf16_bom(head: bytes) -> bool:
    """Whether bytes start with a UTF-16 byte-order mark (little or big endian)."""
    return head.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE))


def decode_text(data: bytes) -> str:
    """Decode text: UTF-16 with a BOM, UTF-8 (with or without BOM), else Windows-1252."""
    if has_utf16_bom(data):
        return data.decode("utf-16", errors="replace")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1252", errors="replace")


def _decode_line(line: str) -> str:
    """A line read as UTF-8 with surrogate escapes; a line that is not UTF-8 is Windows-1252."""
    try:
        line.encode("utf-8")
    except UnicodeEncodeError:
        return line.encode("utf-8", "surrogateescape").decode("cp1252", errors="replace")
    return line


def iter_lines(
    path: Path, *, max_line_chars: int = MAX_LINE_CHARS
) -> Generator[tuple[int, str], None, None]:
    """``(line number, text)`` of each line of a text file, read one line at a time.

    UTF-16 (with BOM), UTF-8 (with or without BOM) or, line by line, Windows-1252; ``\\n``,
    ``\\r\\n`` and ``\\r`` end lines.

    Raises
    ------
    FileTooLargeError
        A line is longer than ``max_line_chars`` characters (checked before it is kept).
    """
    with open(path, "rb") as raw:
        utf16 = has_utf16_bom(raw.read(2))
        raw.seek(0)
        text = io.TextIOWrapper(
            raw,
            encoding="utf-16" if utf16 else "utf-8-sig",
            errors="replace" if utf16 else "surrogateescape",
            newline=None,
        )
        number = 0
        while True:
            line = text.readline(max_line_chars + 1)
            if not line:
                return
            number += 1
            if len(line) > max_line_chars and not line.endswith("\n"):
                raise FileTooLargeError(
                    f"{path}, line {number}: longer than {max_line_chars:,} characters; not a "
                    "text table (binary data, or rows without line breaks?)"
                )
            yield number, _decode_line(line.rstrip("\r\n"))
