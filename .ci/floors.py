"""Print a pip constraints file pinning every declared dependency to its lower bound.

    python .ci/floors.py [EXTRA ...] > floors.txt
    pip install -c floors.txt ".[test]"

Reads ``pyproject.toml``: ``[project] dependencies`` and the named optional extras (default:
``test``). Every requirement must carry a ``>=`` lower bound; ``name>=X`` becomes ``name==X``
(extras such as ``dask[distributed]`` are pinned by their base name). A requirement without a
lower bound is an error, so a new dependency cannot slip past the floors check.
"""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

_REQUIREMENT = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)(\[[^\]]*\])?\s*(.*)$")


def floors(pyproject: Path, extras: list[str]) -> list[str]:
    project = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]
    requirements = list(project["dependencies"])
    for extra in extras:
        requirements += project["optional-dependencies"][extra]
    pins: dict[str, str] = {}
    for requirement in requirements:
        match = _REQUIREMENT.match(requirement.split(";")[0])
        if match is None:
            raise SystemExit(f"cannot parse requirement {requirement!r}")
        name, _, spec = match.groups()
        lower = [s.strip()[2:].strip() for s in spec.split(",") if s.strip().startswith(">=")]
        if len(lower) != 1:
            raise SystemExit(f"requirement {requirement!r} has no single '>=' lower bound")
        key = name.lower().replace("_", "-")
        if pins.get(key, lower[0]) != lower[0]:
            raise SystemExit(f"{name} has two different lower bounds")
        pins[key] = lower[0]
    return [f"{name}=={version}" for name, version in sorted(pins.items())]


if __name__ == "__main__":
    root = Path(__file__).resolve().parent.parent
    print("\n".join(floors(root / "pyproject.toml", sys.argv[1:] or ["test"])))
