"""The tokens of a text table: delimiters, column titles (with their units), numbers.

Every parser here is a single left-to-right scan (no backtracking regular expression), so
the time is linear in the length of the line."""

from __future__ import annotations

import math
from collections.abc import Sequence

from ._units import is_unit_word

_MISSING = {
    "",
    "nan",
    "-nan",
    "+nan",
    "bad",
    "invalid",
    "na",
    "n/a",
    "-",
    "--",
    "*",
    "none",
    "null",
}
_COMMENT_PREFIXES = ("#", "%", "//", "!")
_INF_WORDS = frozenset({"inf", "infinity"})


def _is_comment(stripped: str) -> bool:
    return stripped.startswith(_COMMENT_PREFIXES)


def _is_ascii_digits(text: str) -> bool:
    return text.isascii() and text.isdigit()


def _is_decimal_comma_number(token: str) -> bool:
    """``-183,90`` or ``1,5e-3``: digits, one decimal comma, digits, optional exponent."""
    head, sep, tail = token.lstrip("+-").partition(",")
    if not sep:
        return False
    mantissa, e, exponent = tail.lower().partition("e")
    return (
        (_is_ascii_digits(head) or head == "")
        and _is_ascii_digits(mantissa)
        and (not e or _is_ascii_digits(exponent.lstrip("+-")))
    )


def _delimiter_of(line: str) -> str | None:
    """Semicolon, else white space if the line has a tab, else comma, else white space.

    A line of white-space separated numbers with decimal commas (``0,0025  -183,90``) is
    white space separated.
    """
    if ";" in line:
        return ";"
    if "\t" in line:
        return None
    if "," in line:
        words = line.split()
        if len(words) >= 2 and all(
            _is_decimal_comma_number(w) or _plain_float(w, ",") for w in words
        ):
            return None
        return ","
    return None


def _split(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    parts = [p.strip() for p in line.split(delimiter)]
    while parts and parts[-1] == "":  # trailing delimiters (Dektak exports end rows with ",,")
        parts.pop()
    return parts


def _closer(line: str, start: int) -> int:
    """Index of the first ``]`` or ``)`` at or after ``start``, or -1 (a plain scan)."""
    for j in range(start, len(line)):
        if line[j] in "])":
            return j
    return -1


def _title_words(line: str) -> list[str]:
    """Words of a white-space title line; ``x [mm]`` and ``z(nm)`` stay one word.

    One left-to-right scan: a bracketed part joins the word right before it; an opening
    bracket without a closing one after it is dropped. Linear in the length of the line.
    """
    last_closer = max(line.rfind("]"), line.rfind(")"))
    spans: list[list[int]] = []
    attachable = False
    i, n = 0, len(line)
    while i < n:
        c = line[i]
        if c.isspace():
            i += 1
            continue
        if c in "[(":
            j = _closer(line, i + 1) if i < last_closer else -1
            if j < 0:
                i += 1
                attachable = False
                continue
            if attachable:
                spans[-1][1] = j + 1
            else:
                spans.append([i, j + 1])
            attachable = False
            i = j + 1
            continue
        j = i
        while j < n and not line[j].isspace() and line[j] not in "[(":
            j += 1
        spans.append([i, j])
        attachable = True
        i = j
    return [line[a:b] for a, b in spans]


def _wide_split(line: str) -> list[str]:
    """Split on tabs and on runs of two or more spaces (titles that hold single spaces)."""
    parts: list[str] = []
    current: list[str] = []
    spaces = 0
    for c in line:
        if c == " ":
            spaces += 1
            continue
        if c == "\t" or spaces >= 2:
            parts.append("".join(current))
            current = []
        elif spaces:
            current.append(" ")
        spaces = 0
        if c != "\t":
            current.append(c)
    parts.append("".join(current))
    return [p.strip() for p in parts if p.strip()]


def _ends_with_unit(word: str) -> bool:
    return word.endswith(("]", ")")) or is_unit_word(word)


def _split_titles(line: str, delimiter: str | None, n_columns: int | None = None) -> list[str]:
    """Split a title line; with white space, keep ``x [mm]``, ``z (nm)`` or ``Height µm`` whole.

    With white space, titles may be separated by tabs or runs of spaces (``Lateral µm  Height
    microns``), or be words followed by their unit (``Lateral µm Height microns``): the split
    that gives ``n_columns`` titles is used.
    """
    if delimiter is not None:
        return _split(line, delimiter)
    words = _title_words(line)
    if n_columns is None or len(words) == n_columns:
        return words
    wide = _wide_split(line)
    if len(wide) == n_columns:
        return wide
    groups: list[str] = []
    current: list[str] = []
    for word in words:
        current.append(word)
        if _ends_with_unit(word):
            groups.append(" ".join(current))
            current = []
    if current:
        groups.append(" ".join(current))
    return groups if len(groups) == n_columns else words


def _number(token: str, delimiter: str | None) -> float | None:
    """Value of a data token; NaN for an undefined marker; None if it is not a number."""
    if delimiter != "," and "," in token and "." not in token:
        token = token.replace(",", ".")  # decimal comma
    try:
        return float(token)
    except ValueError:
        if token.strip().lower() in _MISSING:
            return float("nan")
        return None


def _overflows(token: str, value: float) -> bool:
    """A finite number written beyond the float range (``1e400``), as opposed to ``inf``."""
    return math.isinf(value) and token.strip().lstrip("+-").lower() not in _INF_WORDS


def _resolution(token: str) -> float:
    """One unit of the last printed decimal of a number token (``0.0125`` -> 1e-4)."""
    text = token.strip().lower().lstrip("+-").replace(",", ".")
    mantissa, _, exponent = text.partition("e")
    if len(exponent) > 6:
        return 0.0
    try:
        power = int(exponent) if exponent else 0
    except ValueError:
        return 0.0
    decimals = len(mantissa.split(".", 1)[1]) if "." in mantissa else 0
    try:
        return float(10.0 ** (power - decimals))
    except OverflowError:
        return 0.0


def _is_data_line(tokens: Sequence[str], delimiter: str | None) -> bool:
    if not tokens:
        return False
    values = [_number(t, delimiter) for t in tokens]
    if any(v is None for v in values):
        return False
    return any(_plain_float(t, delimiter) for t in tokens)


def _plain_float(token: str, delimiter: str | None) -> bool:
    if delimiter != "," and "," in token and "." not in token:
        token = token.replace(",", ".")
    try:
        float(token)
    except ValueError:
        return False
    return True
