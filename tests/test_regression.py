"""Fixed-seed regression: the SAD curves of six generated pairs must not change unnoticed.

The generator's compiled sum is built with fast-math, so the last bits of a profile depend on the
CPU and the compiler (LLVM) version. The curves are therefore compared to 1e−10 of their own
scale: ``|current − stored| ≤ 1e−10 · (|stored| + max|stored|)`` at every step, so a value near
zero is held to the curve's scale, not to its own few digits. Contact counts must be identical.

If a change of results is intended, regenerate with ``python tests/regression/make_regression.py``
and say why in the commit message.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent / "regression"))
from make_regression import CASES, compute

STORED = np.load(Path(__file__).parent / "regression" / "sad_curves.npz")


@pytest.fixture(scope="module")
def current() -> dict[str, np.ndarray]:
    return compute()


@pytest.mark.parametrize(("dimension", "kind"), CASES)
def test_curves_match_stored_regression(current, dimension: float, kind: str) -> None:  # type: ignore[no-untyped-def]
    key = f"D{dimension}_{kind}"
    np.testing.assert_array_equal(current[f"{key}/n_contacts"], STORED[f"{key}/n_contacts"])
    assert STORED[f"{key}/n_contacts"].max() > 0
    for name in ("normal_force", "tangential_force", "contact_area"):
        want = STORED[f"{key}/{name}"]
        scale = float(np.max(np.abs(want)))
        np.testing.assert_allclose(current[f"{key}/{name}"], want, rtol=1e-10, atol=1e-10 * scale)
