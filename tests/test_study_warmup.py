"""The pool executor kept across calls, its warm-up, and the kernels' compilation shared out."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any

import numba
import numpy as np
import pytest

from splinecontact.study import LocalExecutor, parse_study, realization_seed, simulate_realization
from splinecontact.study.runner import _group_batches, _make_batches, run_batch, run_batch_group
from splinecontact.study.warmup import KERNEL_PARTS, compile_kernels

STUDY: dict[str, Any] = {
    "study": {"name": "w", "seed": 3, "realizations": 5},
    "fixed": {"n_points": 3000, "length": 3.0, "steps": 12},
    "sweep": {"dimension": [1.3, 1.6], "contact_type": ["rough-on-rough", "rough-on-flat"]},
}


def _signatures() -> dict[str, set[str]]:
    """Every compiled specialisation of every numba kernel of the package loaded so far."""
    out: dict[str, set[str]] = {}
    for name, module in list(sys.modules.items()):
        if not name.startswith("splinecontact"):
            continue
        for attr, value in vars(module).items():
            if isinstance(value, numba.core.registry.CPUDispatcher):
                out[f"{name}.{attr}"] = {str(s) for s in value.signatures}
    return out


def test_the_warm_up_compiles_every_specialisation_a_realization_uses() -> None:
    """After the two parts, a realization of either contact type compiles nothing new (else
    the workers would compile it again, each on its own)."""
    config = parse_study(STUDY)
    params = config.parameters_at((0, 0))
    for part in KERNEL_PARTS:
        compile_kernels((part, params))
    before = _signatures()
    for index in config.grid_indices():
        simulate_realization(config.parameters_at(index), realization_seed(3, 0))
    after = _signatures()
    new = {k: v - before.get(k, set()) for k, v in after.items() if v - before.get(k, set())}
    assert new == {}


def test_a_failing_warm_up_part_is_ignored() -> None:
    with pytest.raises(KeyError):
        compile_kernels(("surfaces", {}))  # the part itself raises ...
    executor = LocalExecutor(2)
    try:  # ... but in the pool the warm-up swallows it and the work goes on
        assert executor.warm_up(compile_kernels, [("surfaces", {}), ("loading", {})])
        assert sorted(executor.run(abs, [-1, -2, 3])) == [1, 2, 3]
    finally:
        executor.close()


def _record_pid(folder: str) -> None:
    Path(folder, f"{os.getpid()}").touch()


def test_each_warm_up_part_runs_in_its_own_worker_and_the_pool_is_kept(tmp_path: Path) -> None:
    executor = LocalExecutor(2)
    try:
        assert executor.warm_up(_record_pid, [str(tmp_path), str(tmp_path)])
        assert not executor.warm_up(_record_pid, [str(tmp_path)])  # the pool runs already
        first = list(executor.run(_pid, [0, 1, 2, 3]))
        second = list(executor.run(_pid, [0, 1]))
        third = executor.submit(_pid, 0).result()
    finally:
        executor.close()
    workers = {int(p.name) for p in tmp_path.iterdir()}
    assert len(workers) == 2 and os.getpid() not in workers
    assert {*first, *second, third} <= workers  # later calls run in the same processes


def _pid(_: int) -> int:
    return os.getpid()


def test_one_worker_runs_everything_here_and_warms_nothing() -> None:
    executor = LocalExecutor(1)
    assert not executor.warm_up(_record_pid, ["."])
    assert executor.submit(_pid, 0).result() == os.getpid()
    assert executor.submit(int, "x").exception() is not None
    executor.close()


def test_grouped_batches_equal_the_batches_run_alone() -> None:
    """Rough-on-flat reuses the pair's lower profile: same arrays, same stored values."""
    config = parse_study(STUDY)
    status = np.zeros((*config.grid_shape, 5), dtype=np.int8)
    tasks = _make_batches(config, status, 4)
    assert [t.stop - t.start for t in tasks[:3]] == [3, 2, 3]  # equal sizes: 3 + 2, not 4 + 1
    groups = _group_batches(tasks, share_profiles=True)
    assert len(groups) == len(tasks) // 2
    assert all(
        [t.parameters["contact_type"] for t in g] == ["rough-on-rough", "rough-on-flat"]
        for g in groups
    )
    for group in groups[:2]:
        for alone, together in zip(
            [run_batch(t) for t in group], run_batch_group(group), strict=True
        ):
            assert alone.task == together.task
            assert (alone.status == together.status).all()
            for name, values in alone.curves.items():
                assert values.tobytes() == together.curves[name].tobytes(), name
            for name, values in alone.scalars.items():
                assert values.tobytes() == together.scalars[name].tobytes(), name
    assert _group_batches(tasks, share_profiles=False) == [(t,) for t in tasks]
