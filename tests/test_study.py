"""Study runner: schema, determinism across executors, resume after kill -9, failures."""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import time
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rich.console import Console

from splinecontact.errors import StudyStoreError
from splinecontact.generate import child_seed, weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from splinecontact.results import SCALAR_VARIABLES, STEP_VARIABLES
from splinecontact.study import (
    STATUS_FAILED,
    STATUS_OK,
    StudyExecutionError,
    open_study,
    parameter_value,
    print_summary,
    realization_seed,
    run_study,
    simulate_realization,
)
from splinecontact.study.config import PARAMETERS, parse_study
from splinecontact.study.store import _locked

CLI = [str(Path(sys.executable).parent / "splinecontact")]

TINY: dict[str, Any] = {
    "study": {"name": "tiny", "seed": 2015, "realizations": 3},
    "fixed": {"n_points": 2000, "steps": 20},
    "sweep": {"dimension": [1.3, 1.7], "contact_type": ["rough-on-rough", "rough-on-flat"]},
}


def store_bytes(path: Path) -> dict[str, bytes]:
    """Every file of a store, except the root metadata (it holds start/finish times)."""
    files = {}
    for file in sorted(path.rglob("*")):
        rel = file.relative_to(path).as_posix()
        if file.is_file() and rel != "zarr.json":
            files[rel] = file.read_bytes()
    return files


def root_metadata(path: Path) -> dict[str, Any]:
    meta = json.loads((path / "zarr.json").read_text(encoding="utf-8"))
    for key in ("started", "finished"):
        meta["attributes"].pop(key)
    return meta


def assert_identical_stores(a: Path, b: Path) -> None:
    files_a, files_b = store_bytes(a), store_bytes(b)
    assert sorted(files_a) == sorted(files_b)
    for name, content in files_a.items():
        assert content == files_b[name], f"{name} differs between {a} and {b}"
    assert root_metadata(a) == root_metadata(b)
    ds_a, ds_b = open_study(a), open_study(b)
    for name in ds_a.variables:
        va, vb = ds_a[name].values, ds_b[name].values
        assert va.dtype == vb.dtype
        if va.dtype.kind == "f":
            assert va.tobytes() == vb.tobytes(), name
        else:
            assert (va == vb).all(), name


# --- failure injection: a picklable, module-level realization function ------------------------


def fail_one_realization(parameters: Mapping[str, Any], seed: np.random.SeedSequence) -> Any:
    """The real realization, except D = 1.7 rough-on-flat realization 1, which raises."""
    if (
        parameters["dimension"] == 1.7
        and parameters["contact_type"] == "rough-on-flat"
        and seed.spawn_key == (1,)
    ):
        raise RuntimeError("injected [/] failure\nwith a second line")
    return simulate_realization(parameters, seed)


# --- tests ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The tiny study run serially in this process."""
    out = tmp_path_factory.mktemp("ref") / "tiny.zarr"
    summary = run_study(TINY, out, workers=1, progress=False)
    assert summary.complete and summary.ok == 12 and summary.failed == 0
    assert summary.ran_now == 12
    return out


def test_seed_of_realization_is_the_spawned_child() -> None:
    children = np.random.SeedSequence(2015).spawn(5)
    for r, child in enumerate(children):
        mine = realization_seed(2015, r)
        assert mine.spawn_key == (r,)
        assert mine.entropy == 2015
        assert np.array_equal(mine.generate_state(8), child.generate_state(8))


def test_rough_on_flat_lower_profile_is_the_rough_on_rough_lower_profile() -> None:
    seed = realization_seed(2015, 2)
    kwargs = {"n_points": 2000, "length": 100.0}
    lower_pair, _ = weierstrass_mandelbrot_pair(1.5, seed=seed, **kwargs)
    lower_alone = weierstrass_mandelbrot(1.5, seed=child_seed(seed, 0), **kwargs)
    assert np.array_equal(lower_pair.z, lower_alone.z)


def test_schema(reference: Path) -> None:
    ds = open_study(reference)
    assert tuple(ds.sizes) == ("dimension", "contact_type", "realization", "step")
    assert ds.sizes["step"] == 21
    assert list(ds["dimension"].values) == [1.3, 1.7]
    assert list(ds["contact_type"].values) == ["rough-on-rough", "rough-on-flat"]
    assert list(ds["realization"].values) == [0, 1, 2]
    for name, (units, _) in STEP_VARIABLES.items():
        assert ds[name].dims == ("dimension", "contact_type", "realization", "step")
        assert ds[name].attrs["units"] == units
    for name, (units, _) in SCALAR_VARIABLES.items():
        assert ds[name].dims == ("dimension", "contact_type", "realization")
        assert ds[name].attrs["units"] == units
    assert ds["status"].dtype == np.int8
    assert (ds["status"].values == STATUS_OK).all()
    assert (ds["error"].values == "").all()
    assert ds["seed_spawn_key"].dims == ("realization",)
    assert list(ds["seed_spawn_key"].values) == [0, 1, 2]
    for name in ds.variables:
        assert "units" in ds[name].attrs, name
    # Provenance.
    assert ds.attrs["e_star"] == 10.0
    assert ds.attrs["n_points"] == 2000
    assert ds.attrs["steps"] == 20
    assert "g_star" not in ds.attrs  # engine default E*/2.6
    assert ds.attrs["study_seed"] == 2015
    assert ds.attrs["started"] <= ds.attrs["finished"]
    assert ds.attrs["splinecontact_version"]
    resolved = parse_study(tomllib.loads(ds.attrs["study_toml"]))
    assert resolved.identity() == parse_study(TINY).identity()
    # parameter_value looks in coords, then attrs.
    assert parameter_value(ds, "dimension", dimension=1) == 1.7
    assert parameter_value(ds.sel(contact_type="rough-on-flat"), "contact_type") == "rough-on-flat"
    assert parameter_value(ds, "e_star", dimension=1) == 10.0
    assert parameter_value(ds, "g_star") is None
    with pytest.raises(StudyStoreError):
        parameter_value(ds, "not_a_parameter")


def test_stored_values_are_the_realizations_own_results(reference: Path) -> None:
    ds = open_study(reference)
    cfg = parse_study(TINY)
    for grid_index, r in [((1, 1), 2), ((0, 0), 0)]:
        params = cfg.parameters_at(grid_index)
        result = simulate_realization(params, realization_seed(2015, r))
        for name in STEP_VARIABLES:
            stored = ds[name].values[(*grid_index, r)]
            assert np.asarray(result.curves[name], dtype=float).tobytes() == stored.tobytes()
        for name in SCALAR_VARIABLES:
            assert ds[name].values[(*grid_index, r)] == result.scalars[name]


def test_paired_design_same_lower_profile_across_contact_types(reference: Path) -> None:
    ds = open_study(reference)
    for name in ("ra_lower", "rq_lower", "peak_to_valley_lower", "rsq_lower"):
        rr = ds[name].sel(contact_type="rough-on-rough").values
        rf = ds[name].sel(contact_type="rough-on-flat").values
        assert np.array_equal(rr, rf), name
    # ... and different realizations are different profiles.
    assert len(set(ds["rq_lower"].values[0, 0])) == 3


@pytest.mark.slow
def test_two_workers_and_batch_sizes_give_identical_store(reference: Path, tmp_path: Path) -> None:
    out = tmp_path / "two.zarr"
    run_study(TINY, out, workers=2, batch_size=2, progress=False)
    assert_identical_stores(reference, out)


@pytest.mark.slow
def test_dask_local_cluster_gives_identical_store(reference: Path, tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",
    ) as cluster:
        out = tmp_path / "dask.zarr"
        summary = run_study(
            TINY, out, scheduler=cluster.scheduler_address, batch_size=1, progress=False
        )
    assert summary.ok == 12
    assert_identical_stores(reference, out)


@pytest.mark.slow
def test_failing_realization_is_recorded_and_study_completes(tmp_path: Path) -> None:
    out = tmp_path / "fail.zarr"
    summary = run_study(
        TINY,
        out,
        workers=2,
        batch_size=2,
        progress=False,
        realization_function=fail_one_realization,
    )
    assert summary.complete
    assert (summary.ok, summary.failed, summary.not_run) == (11, 1, 0)
    (failure,) = summary.failures
    assert failure.grid == {"dimension": 1.7, "contact_type": "rough-on-flat"}
    assert failure.realization == 1
    assert failure.message == "RuntimeError: injected [/] failure with a second line"
    text = io.StringIO()
    print_summary(summary, Console(file=text, width=200))
    assert "1 failed" in text.getvalue()
    assert f"realization=1: {failure.message}" in text.getvalue()
    ds = open_study(out)
    status = ds["status"].values
    assert status[1, 1, 1] == STATUS_FAILED
    assert (np.delete(status.ravel(), np.ravel_multi_index((1, 1, 1), status.shape)) == 1).all()
    assert ds["error"].values[1, 1, 1] == failure.message
    assert np.isnan(ds["normal_force"].values[1, 1, 1]).all()
    assert np.isnan(ds["rq_lower"].values[1, 1, 1])
    assert np.isfinite(ds["normal_force"].values[1, 1, 2]).all()
    # A re-run does not retry recorded failures: nothing left to do.
    again = run_study(TINY, out, workers=1, progress=False)
    assert again.ran_now == 0 and again.failed == 1


def test_changed_study_is_refused_unless_overwrite(reference: Path, tmp_path: Path) -> None:
    import shutil

    out = tmp_path / "copy.zarr"
    shutil.copytree(reference, out)
    changed = {**TINY, "fixed": {**TINY["fixed"], "e_star": 20.0}}
    with pytest.raises(StudyStoreError, match=r"fixed\.e_star: 10\.0 in the store, 20\.0"):
        run_study(changed, out, workers=1, progress=False)
    # Output options are not part of the study's identity.
    same = {**TINY, "output": {"batch_size": 5}}
    assert run_study(same, out, workers=1, progress=False).ran_now == 0
    summary = run_study(changed, out, workers=1, progress=False, overwrite=True)
    assert summary.ran_now == 12
    assert open_study(out).attrs["e_star"] == 20.0


def test_refuses_a_directory_that_is_not_a_store(tmp_path: Path) -> None:
    out = tmp_path / "something"
    out.mkdir()
    (out / "data.txt").write_text("mine", encoding="utf-8")
    with pytest.raises(StudyStoreError, match="not a splinecontact study store"):
        run_study(TINY, out, workers=1, progress=False)
    assert (out / "data.txt").exists()


def test_a_store_being_written_is_locked(reference: Path, tmp_path: Path) -> None:
    import shutil

    out = tmp_path / "locked.zarr"
    shutil.copytree(reference, out)
    with _locked(out), pytest.raises(StudyStoreError, match="another running study"):
        run_study(TINY, out, workers=1, progress=False)


@pytest.mark.slow
def test_partial_store_resumes_to_identical_result(reference: Path, tmp_path: Path) -> None:
    """Simulate an interruption: forget some batches (status 0) and leave stale temp files."""
    import shutil

    import zarr

    out = tmp_path / "partial.zarr"
    shutil.copytree(reference, out)
    group = zarr.open_group(out, mode="r+")
    status = group["status"][...]
    status[0, 1, 1:] = 0
    status[1, 0, :2] = 0
    group["status"][...] = status
    group["normal_force"][1, 0, 0, 5:] = -1.0  # half-written data of a batch not marked done
    stale = next((out / "normal_force").rglob("c/*/*/0")).with_suffix(".0123.partial")
    stale.write_bytes(b"garbage")
    summary = run_study(TINY, out, workers=2, batch_size=1, progress=False)
    assert summary.ran_now == 4
    assert not stale.exists()
    assert_identical_stores(reference, out)


KILL_STUDY = """
[study]
name = "kill"
seed = 99
realizations = 12

[fixed]
n_points = 50_000
steps = 100
contact_type = "rough-on-rough"

[sweep]
dimension = [1.2, 1.5]
"""


def _done(store: Path) -> int:
    import zarr

    try:
        return int((zarr.open_group(store, mode="r")["status"][...] != 0).sum())
    except Exception:
        return 0


@pytest.mark.slow
@pytest.mark.parametrize("workers", [1, 2])
def test_sigkill_midway_then_resume_equals_uninterrupted_run(tmp_path: Path, workers: int) -> None:
    """kill -9 of the main process (alone, or with its pool), then resume with another count."""
    import psutil

    study_file = tmp_path / "kill.toml"
    study_file.write_text(KILL_STUDY, encoding="utf-8")
    killed = tmp_path / "killed.zarr"
    args = [*CLI, "study", "run", str(study_file), "-o", str(killed), "--quiet"]
    proc = subprocess.Popen(
        [*args, "--workers", str(workers), "--batch-size", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 120
    while _done(killed) < 2 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    children = psutil.Process(proc.pid).children(recursive=True)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    done_at_kill = _done(killed)
    assert proc.returncode == -signal.SIGKILL
    assert 2 <= done_at_kill < 24, "the run must be killed midway"
    # The pool's workers do not outlive the killed main process.
    _, alive = psutil.wait_procs(children, timeout=60)
    assert not alive
    # Resume with another worker count and batch size.
    resumed = subprocess.run(
        [*args, "--workers", str(3 - workers)], capture_output=True, text=True, check=False
    )
    assert resumed.returncode == 0, resumed.stderr
    assert _done(killed) == 24
    uninterrupted = tmp_path / "whole.zarr"
    summary = run_study(study_file, uninterrupted, workers=1, progress=False)
    assert summary.ok == 24
    assert_identical_stores(uninterrupted, killed)


def die_once(parameters: Mapping[str, Any], seed: np.random.SeedSequence) -> Any:
    """Kill the worker process (SIGKILL) at realization 2, the first time only."""
    marker = Path(os.environ["SPLINECONTACT_TEST_DIE_ONCE"])
    if seed.spawn_key == (2,) and not marker.exists():
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return simulate_realization(parameters, seed)


@pytest.mark.slow
def test_killed_worker_loses_nothing_and_rerun_completes(
    reference: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SPLINECONTACT_TEST_DIE_ONCE", str(tmp_path / "died"))
    out = tmp_path / "worker.zarr"
    with pytest.raises(StudyExecutionError, match="run the same command again"):
        run_study(TINY, out, workers=2, batch_size=1, progress=False, realization_function=die_once)
    assert (tmp_path / "died").exists()
    assert _done(out) < 12
    summary = run_study(TINY, out, workers=2, progress=False, realization_function=die_once)
    assert summary.complete and summary.ok == 12
    assert_identical_stores(reference, out)


def test_parameters_are_passed_to_the_engine(tmp_path: Path) -> None:
    """A swept engine parameter changes the results, a fixed one lands in the attributes."""
    data = {
        "study": {"name": "p", "seed": 5, "realizations": 1},
        "fixed": {"n_points": 2000, "steps": 10, "dimension": 1.5, "mu0": 0.0},
        "sweep": {"e_star": [10.0, 20.0]},
    }
    out = tmp_path / "p.zarr"
    run_study(data, out, workers=1, progress=False)
    ds = open_study(out)
    force = ds["normal_force"].values[:, 0, -1]
    assert force[1] == pytest.approx(2 * force[0], rel=1e-12)  # F ∝ E* (eq. 10)
    assert ds.attrs["mu0"] == 0.0
    assert set(PARAMETERS) - {"g_star", "final_displacement", "e_star"} <= set(ds.attrs)


def test_swept_steps_pad_with_nan_and_unswept_study_has_no_grid_dims(tmp_path: Path) -> None:
    base = {"study": {"name": "s", "seed": 1, "realizations": 2}}
    fixed = {"n_points": 2000, "dimension": 1.4}
    out = tmp_path / "steps.zarr"
    run_study({**base, "fixed": fixed, "sweep": {"steps": [10, 5]}}, out, workers=1, progress=False)
    ds = open_study(out)
    assert ds["normal_force"].dims == ("steps", "realization", "step")
    assert ds.sizes["step"] == 11
    short = ds["displacement"].sel(steps=5).values
    assert np.isfinite(short[:, :6]).all() and np.isnan(short[:, 6:]).all()
    assert np.isfinite(ds["displacement"].sel(steps=10).values).all()
    assert ds.attrs["dimension"] == 1.4
    assert "steps" not in ds.attrs
    assert parameter_value(ds, "steps", steps=1) == 5

    plain = tmp_path / "plain.zarr"
    summary = run_study({**base, "fixed": {**fixed, "steps": 5}}, plain, workers=1, progress=False)
    assert summary.ok == 2 and summary.failures == ()
    flat = open_study(plain)
    assert flat["normal_force"].dims == ("realization", "step")
    assert flat["status"].dims == ("realization",)
    # Same seed, same realization, same parameters: the same numbers as inside the sweep.
    assert flat["displacement"].values.tobytes() == short[:, :6].tobytes()


def test_store_of_another_engine_code_is_refused(reference: Path, tmp_path: Path) -> None:
    import shutil

    import zarr

    from splinecontact.study import engine_fingerprint

    assert open_study(reference).attrs["engine_fingerprint"] == engine_fingerprint()
    out = tmp_path / "old.zarr"
    shutil.copytree(reference, out)
    zarr.open_group(out, mode="r+").attrs.update({"engine_fingerprint": "0123456789abcdef"})
    with pytest.raises(StudyStoreError, match=r"simulation code changed.*0123456789abcdef"):
        run_study(TINY, out, workers=1, progress=False)


@pytest.mark.slow
def test_batches_straddling_chunks_store_the_same_values(
    reference: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Chunks of 2 realizations, batches of 2 starting at odd offsets after a resume."""
    import zarr

    import splinecontact.study.store as store

    monkeypatch.setattr(store, "_CHUNK_BYTES", 8 * 21 * 2)
    out = tmp_path / "chunks.zarr"
    run_study(TINY, out, workers=1, batch_size=1, progress=False)
    assert zarr.open_group(out, mode="r")["normal_force"].chunks == (1, 1, 2, 21)
    group = zarr.open_group(out, mode="r+")
    status = group["status"][...]
    status[:, :, 1:] = 0  # forget realizations 1, 2 (batch 1–2 spans two chunks)
    group["status"][...] = status
    run_study(TINY, out, workers=2, batch_size=2, progress=False)
    a, b = open_study(reference), open_study(out)
    for name in a.data_vars:
        if a[name].dtype.kind == "f":
            assert a[name].values.tobytes() == b[name].values.tobytes(), name
        else:
            assert (a[name].values == b[name].values).all(), name


def test_overwrite_refuses_a_store_being_written(reference: Path, tmp_path: Path) -> None:
    import shutil

    out = tmp_path / "busy.zarr"
    shutil.copytree(reference, out)
    changed = {**TINY, "study": {**TINY["study"], "seed": 1}}
    with _locked(out), pytest.raises(StudyStoreError, match="another running study"):
        run_study(changed, out, workers=1, progress=False, overwrite=True)
    assert open_study(out).attrs["study_seed"] == 2015
