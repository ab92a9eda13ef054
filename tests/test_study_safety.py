"""Studies keep the user's data safe: --overwrite, damaged stores, atomic export, refusals.

Every refusal leaves every pre-existing file byte-identical (the tree is hashed before and after).
"""

from __future__ import annotations

import errno
import fcntl
import hashlib
import io
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Mapping
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import splinecontact.study as study
import splinecontact.study.export as study_export
import splinecontact.study.store as study_store
from splinecontact.errors import (
    OutputError,
    OutputExistsError,
    SplineContactError,
    StudyConfigError,
    StudyStoreError,
    UnsafeOutputError,
)
from splinecontact.results import SCALAR_VARIABLES, STEP_VARIABLES
from splinecontact.study import (
    StudyLimits,
    StudyProgress,
    StudyProgressBar,
    check_limits,
    export_netcdf,
    open_study,
    parse_study,
    run_study,
)

CLI = str(Path(sys.executable).parent / "splinecontact")

SMALL: dict[str, Any] = {
    "study": {"name": "small", "seed": 11, "realizations": 3},
    "fixed": {"n_points": 64, "steps": 4},
    "sweep": {"dimension": [1.3, 1.6]},
}
OTHER: dict[str, Any] = {**SMALL, "study": {**SMALL["study"], "seed": 12}}


def fake_realization(parameters: Mapping[str, Any], seed: np.random.SeedSequence) -> Any:
    """A fast stand-in engine: deterministic numbers from the seed and the parameters."""
    rng = np.random.default_rng(seed)
    n = int(parameters["steps"]) + 1
    shift = float(parameters["dimension"])
    curves = {name: rng.random(n) + shift for name in STEP_VARIABLES}
    scalars = {name: float(rng.random()) for name in SCALAR_VARIABLES}
    return SimpleNamespace(curves=curves, scalars=scalars)


def run(config: Any, out: Path | str, **kwargs: Any) -> study.StudySummary:
    return run_study(config, out, workers=1, realization_function=fake_realization, **kwargs)


def tree_hash(root: Path) -> dict[str, str]:
    """Every file, folder and link under ``root`` with a digest of its content."""
    items: dict[str, str] = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in [*dirnames, *filenames]:
            item = Path(dirpath) / name
            rel = item.relative_to(root).as_posix()
            if item.is_symlink():
                items[rel] = "link:" + os.readlink(item)
            elif item.is_dir():
                items[rel] = "dir"
            else:
                items[rel] = hashlib.sha256(item.read_bytes()).hexdigest()
    return items


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished small study store (fake engine), made once."""
    out = tmp_path_factory.mktemp("pristine") / "small.zarr"
    summary = run(SMALL, out)
    assert summary.complete and summary.ok == 6
    return out


@pytest.fixture
def store(pristine: Path, tmp_path: Path) -> Path:
    """A copy of the finished small study store, for this test alone."""
    out = tmp_path / "small.zarr"
    shutil.copytree(pristine, out)
    return out


@pytest.fixture
def sandbox(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A folder of user files, made the current directory."""
    box = tmp_path / "box"
    box.mkdir()
    (box / "small.csv").write_text("x,z\n0,1\n1,2\n", encoding="utf-8")
    (box / "study.toml").write_text('[study]\nname = "s"\n', encoding="utf-8")
    (box / "mydata").mkdir()
    (box / "mydata" / "precious.txt").write_text("mine", encoding="utf-8")
    monkeypatch.chdir(box)
    return box


# --- D1: --overwrite never discards anything but a study store ----------------------------------


@pytest.mark.parametrize("target", [".", "", "mydata", "small.csv", "study.toml"])
def test_overwrite_refuses_what_is_not_a_store(sandbox: Path, target: str) -> None:
    before = tree_hash(sandbox.parent)
    with pytest.raises(SplineContactError, match="not a splinecontact study store"):
        run(SMALL, target, overwrite=True)
    assert tree_hash(sandbox.parent) == before


def test_overwrite_refuses_a_parent_of_the_current_directory(
    sandbox: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(sandbox / "mydata")
    before = tree_hash(sandbox.parent)
    with pytest.raises(SplineContactError):
        run(SMALL, "..", overwrite=True)
    with pytest.raises(SplineContactError):
        run(SMALL, sandbox.parent, overwrite=True)
    assert tree_hash(sandbox.parent) == before


def test_overwrite_refuses_the_home_directory(
    sandbox: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("HOME", str(sandbox / "mydata"))
    before = tree_hash(sandbox.parent)
    with pytest.raises(SplineContactError):
        run(SMALL, Path.home(), overwrite=True)
    assert tree_hash(sandbox.parent) == before


def test_overwrite_refuses_the_home_directory_even_if_it_is_a_store(
    store: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("HOME", str(store))
    before = tree_hash(store.parent)
    with pytest.raises(UnsafeOutputError, match="home directory"):
        run(OTHER, store, overwrite=True)
    assert tree_hash(store.parent) == before


def test_overwrite_refuses_the_current_directory_even_if_it_is_a_store(
    store: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(store)
    before = tree_hash(store.parent)
    with pytest.raises(UnsafeOutputError, match="current directory"):
        run(OTHER, ".", overwrite=True)
    assert tree_hash(store.parent) == before
    assert run(SMALL, ".").ran_now == 0  # the same study is resumed (nothing to do) in place


def test_overwrite_refuses_a_store_holding_user_files(store: Path) -> None:
    (store / "notes.txt").write_text("my notes", encoding="utf-8")
    before = tree_hash(store.parent)
    with pytest.raises(UnsafeOutputError, match=r"notes\.txt, which is not part of a study store"):
        run(OTHER, store, overwrite=True)
    assert tree_hash(store.parent) == before


def test_overwrite_refuses_a_link_to_a_store(store: Path) -> None:
    link = store.parent / "link.zarr"
    link.symlink_to(store)
    before = tree_hash(store.parent)
    with pytest.raises(UnsafeOutputError, match="symbolic link"):
        run(OTHER, link, overwrite=True)
    assert tree_hash(store.parent) == before


def test_overwrite_refuses_a_store_whose_root_metadata_is_unreadable(store: Path) -> None:
    (store / "zarr.json").write_text("{not json", encoding="utf-8")
    before = tree_hash(store.parent)
    with pytest.raises(StudyStoreError, match=r"zarr\.json cannot be read"):
        run(OTHER, store, overwrite=True)
    assert tree_hash(store.parent) == before


def test_overwrite_replaces_a_store_of_another_study(store: Path) -> None:
    summary = run(OTHER, store, overwrite=True)
    assert summary.ran_now == 6
    assert open_study(store).attrs["study_seed"] == 12


def test_a_store_is_not_created_inside_a_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(StudyStoreError, match="does not exist"):
        run(SMALL, tmp_path / "no" / "such" / "s.zarr")
    assert list(tmp_path.iterdir()) == []


# --- D21: concurrent first runs ------------------------------------------------------------------


def test_temporary_store_of_a_live_run_is_kept_and_stale_ones_removed(tmp_path: Path) -> None:
    live = tmp_path / ".s.zarr.creating-live"
    stale = tmp_path / ".s.zarr.creating-stale"
    for folder in (live, stale):
        folder.mkdir()
        (folder / "zarr.json").write_text("{}", encoding="utf-8")
    fd = os.open(live, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # what a live creating run holds
        run(SMALL, tmp_path / "s.zarr")
        assert live.is_dir() and (live / "zarr.json").read_text(encoding="utf-8") == "{}"
        assert not stale.exists()
    finally:
        os.close(fd)


def test_losing_the_race_to_create_a_store_resumes_the_winners_store(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "race.zarr"
    template = study_store._template
    config = parse_study(SMALL)

    def winner_first(cfg: Any) -> Any:
        if not out.exists():
            monkeypatch.setattr(study_store, "_template", template)
            assert study_store._create_store(out, config)  # the other run renames its store first
        return template(cfg)

    monkeypatch.setattr(study_store, "_template", winner_first)
    summary = run(SMALL, out)
    assert summary.complete and summary.ran_now == 6
    assert sorted(p.name for p in tmp_path.iterdir()) == ["race.zarr"]


# --- D16: damaged stores, no-op runs -------------------------------------------------------------


def _chunk(store: Path, name: str) -> Path:
    return next(p for p in sorted((store / name / "c").rglob("*")) if p.is_file())


def damage_truncated_status(store: Path) -> str:
    chunk = _chunk(store, "status")
    chunk.write_bytes(chunk.read_bytes()[:5])
    return "'status'"


def damage_garbage_data(store: Path) -> str:
    chunk = _chunk(store, "normal_force")
    chunk.write_bytes(b"\x28\xb5\x2f\xfd" + b"garbage" * 20)
    return "'normal_force'"


def damage_missing_status_metadata(store: Path) -> str:
    (store / "status" / "zarr.json").unlink()
    return "'status' is missing"


def damage_deleted_variable(store: Path) -> str:
    shutil.rmtree(store / "rq_lower")
    return "'rq_lower' is missing"


def damage_root_metadata(store: Path) -> str:
    (store / "zarr.json").write_bytes(b"\x00\x01 not json")
    return "root metadata zarr.json cannot be read"


def damage_study_toml(store: Path) -> str:
    meta = json.loads((store / "zarr.json").read_text(encoding="utf-8"))
    meta["attributes"]["study_toml"] = "[study\nname = "
    (store / "zarr.json").write_text(json.dumps(meta), encoding="utf-8")
    return "study_toml is not a valid study"


def damage_status_code(store: Path) -> str:
    import zarr

    group = zarr.open_group(store, mode="r+")
    status = group["status"][...]
    status[1, 2] = 7
    group["status"][...] = status
    return "unknown code 7"


DAMAGES = {
    f.__name__.removeprefix("damage_"): f
    for f in (
        damage_truncated_status,
        damage_garbage_data,
        damage_missing_status_metadata,
        damage_deleted_variable,
        damage_root_metadata,
        damage_study_toml,
        damage_status_code,
    )
}


@pytest.mark.parametrize("damage", DAMAGES)
@pytest.mark.parametrize("action", ["run", "export", "open"])
def test_damaged_store_is_named_and_left_untouched(
    store: Path, tmp_path: Path, damage: str, action: str
) -> None:
    expected = DAMAGES[damage](store)
    before = tree_hash(tmp_path)
    with pytest.raises(StudyStoreError) as info:
        if action == "run":
            run(SMALL, store)
        elif action == "export":
            pytest.importorskip("h5py")
            export_netcdf(store, tmp_path / "x.nc")
        else:
            open_study(store)
    message = str(info.value)
    assert "\n" not in message
    assert "damaged" in message and str(store) in message
    assert expected in message
    assert tree_hash(tmp_path) == before


def test_status_reset_by_hand_is_resumed_not_refused(store: Path) -> None:
    import zarr

    group = zarr.open_group(store, mode="r+")
    status = group["status"][...]
    status[0, :2] = 0
    group["status"][...] = status
    assert run(SMALL, store).ran_now == 2


def test_no_op_rerun_of_a_finished_study_does_not_modify_the_store(store: Path) -> None:
    before = tree_hash(store)
    summary = run(SMALL, store)
    assert summary.complete and summary.ran_now == 0
    assert tree_hash(store) == before


def test_a_study_completed_without_the_finished_mark_gets_it(store: Path) -> None:
    import zarr

    zarr.open_group(store, mode="r+").attrs.update({"finished": ""})
    assert run(SMALL, store).ran_now == 0
    assert open_study(store).attrs["finished"]


# --- D4: export under the output rule, atomic --------------------------------------------------


@pytest.fixture
def h5py() -> Any:
    return pytest.importorskip("h5py")


def test_export_refuses_an_existing_file_without_overwrite(
    store: Path, tmp_path: Path, h5py: Any
) -> None:
    target = tmp_path / "out.nc"
    target.write_text("earlier", encoding="utf-8")
    with pytest.raises(OutputExistsError, match="--overwrite"):
        export_netcdf(store, target)
    assert target.read_text(encoding="utf-8") == "earlier"
    export_netcdf(store, target, overwrite=True)
    assert open_study(store)["status"].values.tobytes() == _exported(target, "status")


def _exported(target: Path, name: str) -> bytes:
    import xarray as xr

    with xr.open_dataset(target, engine="h5netcdf") as ds:
        return bytes(ds[name].values.tobytes())


@pytest.mark.parametrize("inside", ["zarr.json", "status/zarr.json", "new.nc", "."])
def test_export_never_writes_into_the_store(
    store: Path, tmp_path: Path, h5py: Any, inside: str
) -> None:
    before = tree_hash(tmp_path)
    with pytest.raises(UnsafeOutputError):
        export_netcdf(store, store / inside, overwrite=True)
    assert tree_hash(tmp_path) == before


def test_export_on_a_full_disk_leaves_no_file_and_keeps_the_earlier_one(
    store: Path, tmp_path: Path, h5py: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out.nc"
    export_netcdf(store, target)
    good = target.read_bytes()

    def full_disk(path: Path, data: memoryview) -> None:
        with open(path, "xb") as file:
            file.write(bytes(data)[: len(data) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(study_export, "_write_bytes", full_disk)
    before = tree_hash(tmp_path)
    with pytest.raises(OutputError) as info:
        export_netcdf(store, target, overwrite=True)
    assert "No space left on device" in str(info.value)
    assert "\n" not in str(info.value)
    assert tree_hash(tmp_path) == before  # no partial, no temporary file
    assert target.read_bytes() == good
    new = tmp_path / "new.nc"
    with pytest.raises(OutputError):
        export_netcdf(store, new)
    assert not new.exists()


# --- D8, D11, D12, D17: refused before anything is written ------------------------------------


BIG = {
    "steps": {"fixed": {"dimension": 1.5, "steps": 100_000_000}},
    "realizations": {
        "study": {"name": "r", "seed": 1, "realizations": 10_000_000},
        "fixed": {"dimension": 1.5},
    },
    "grid_points": {
        "fixed": {"n_points": 64},
        "sweep": {
            "dimension": [1.0 + i / 100 for i in range(100)],
            "e_star": [float(i + 1) for i in range(100)],
            "mu0": [i / 100 for i in range(100)],
        },
    },
    "points_terms": {"fixed": {"dimension": 1.5, "n_points": 10**8, "directions": 1000}},
    "realization_points": {
        "study": {"name": "r", "seed": 1, "realizations": 200_000},
        "fixed": {"dimension": 1.5, "n_points": 10**6},
    },
    "stored_values": {
        "study": {"name": "r", "seed": 1, "realizations": 200_000},
        "fixed": {"dimension": 1.5, "n_points": 64, "steps": 1000},
    },
}


@pytest.mark.parametrize("ceiling", BIG)
def test_a_study_above_a_ceiling_is_refused_before_anything_is_written(
    tmp_path: Path, ceiling: str
) -> None:
    data = {"study": {"name": "big", "seed": 1, "realizations": 1}, **BIG[ceiling]}
    with pytest.raises(StudyConfigError, match=f"above the ceiling {ceiling} = ") as info:
        run(data, tmp_path / "big.zarr")
    assert f"--limit {ceiling}=" in str(info.value)
    assert list(tmp_path.iterdir()) == []
    config = parse_study(data)
    raised = StudyLimits.parse([f"{ceiling}=1e15"])
    try:
        check_limits(config, raised)  # the option raises this ceiling ...
    except StudyConfigError as exc:
        assert f"ceiling {ceiling} =" not in str(exc)  # ... another one may still hold
    check_limits(config, StudyLimits.parse([f"{name}=1e15" for name in BIG]))


def test_limit_option_values_are_checked() -> None:
    assert StudyLimits.parse(["steps=2_000_000"]).steps == 2_000_000
    for bad in ("steps", "nope=3", "steps=0", "steps=1.5", "steps=inf", "steps=abc"):
        with pytest.raises(StudyConfigError, match="--limit"):
            StudyLimits.parse([bad])


@pytest.mark.parametrize("address", ["foo://bar", "", "   ", 42])
def test_a_bad_scheduler_address_is_refused_before_anything_is_written(
    tmp_path: Path, address: Any
) -> None:
    pytest.importorskip("distributed")
    with pytest.raises(StudyConfigError, match="not a Dask scheduler address"):
        run_study(SMALL, tmp_path / "s.zarr", scheduler=address)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("option", "value"), [("workers", 0), ("workers", 1.5), ("batch_size", True)]
)
def test_bad_worker_and_batch_options_are_refused(tmp_path: Path, option: str, value: Any) -> None:
    with pytest.raises(StudyConfigError, match=option):
        run_study(SMALL, tmp_path / "s.zarr", **{option: value})
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "fixed",
    [
        {"e_star": float("inf")},
        {"length": float("inf")},
        {"ra": float("nan")},
        {"n_max": 2000},
        {"ra": 1e308},
        {"length": 1e300},
        {"wavelength": 1e200},
        {"final_displacement": 1e308},
        {"x0": 1e-300},  # the spline weight λ of eqs. 2–3 overflows
    ],
)
def test_engine_impossible_values_are_refused_before_anything_is_written(
    tmp_path: Path, fixed: dict[str, Any]
) -> None:
    data = {**SMALL, "fixed": {**SMALL["fixed"], **fixed}}
    with pytest.raises(StudyConfigError):
        run(data, tmp_path / "s.zarr")
    assert list(tmp_path.iterdir()) == []


# --- silence and progress ------------------------------------------------------------------------


def test_run_study_is_silent_by_default(tmp_path: Path, capfd: pytest.CaptureFixture[str]) -> None:
    run(SMALL, tmp_path / "s.zarr")
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""


def test_progress_callback_sees_every_batch_and_the_summary(tmp_path: Path) -> None:
    events: list[StudyProgress] = []
    summary = run(SMALL, tmp_path / "s.zarr", batch_size=1, progress=events.append)
    assert [e.done for e in events] == [0, 1, 2, 3, 4, 5, 6, 6]
    assert [e.ran_now for e in events][-1] == 6
    assert all(e.total == 6 and e.store == tmp_path / "s.zarr" for e in events)
    assert [e.summary for e in events[:-1]] == [None] * 7
    assert events[-1].summary == summary


def test_progress_bar_draws_on_a_terminal(tmp_path: Path) -> None:
    from rich.console import Console

    text = io.StringIO()
    with StudyProgressBar(Console(file=text, force_terminal=True, width=120)) as bar:
        run(SMALL, tmp_path / "s.zarr", batch_size=2, progress=bar)
    assert "6/6" in text.getvalue()


# --- the command line ----------------------------------------------------------------------------


def _cli(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([CLI, *args], capture_output=True, text=True, check=False, cwd=cwd)


def _one_error_line(proc: subprocess.CompletedProcess[str]) -> str:
    assert proc.returncode == 1, proc.stdout + proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error: ")
    assert "Traceback" not in proc.stdout + proc.stderr
    return lines[0]


TOML = """
[study]
name = "tiny"
seed = 3
realizations = 2

[fixed]
n_points = 2000
steps = 5
dimension = 1.5
"""


@pytest.mark.slow
@pytest.mark.parametrize("target", [".", "", "mydata", "small.csv", "study.toml", ".."])
def test_cli_overwrite_refuses_and_touches_nothing(sandbox: Path, target: str) -> None:
    (sandbox / "study.toml").write_text(TOML, encoding="utf-8")
    before = tree_hash(sandbox.parent)
    line = _one_error_line(
        _cli(["study", "run", "study.toml", "-o", target, "-q", "--overwrite"], sandbox)
    )
    assert "refus" in line or "not a splinecontact study store" in line
    assert tree_hash(sandbox.parent) == before


@pytest.mark.slow
def test_cli_refusals_are_one_line_and_write_nothing(sandbox: Path) -> None:
    (sandbox / "study.toml").write_text(TOML, encoding="utf-8")
    big = TOML.replace("steps = 5", "steps = 100_000_000")
    (sandbox / "big.toml").write_text(big, encoding="utf-8")
    inf = TOML.replace("dimension = 1.5", "dimension = 1.5\ne_star = inf")
    (sandbox / "inf.toml").write_text(inf, encoding="utf-8")
    before = tree_hash(sandbox)
    cases = [
        (["study", "run", "big.toml", "-o", "b.zarr"], "above the ceiling steps"),
        (["study", "run", "inf.toml", "-o", "i.zarr"], "fixed.e_star = inf: must be a finite"),
        (["study", "run", "study.toml", "-o", "s.zarr", "--scheduler", "foo://bar"], "scheduler"),
        (["study", "run", "study.toml", "-o", "s.zarr", "--scheduler", ""], "scheduler"),
        (["study", "run", "study.toml", "-o", "s.zarr", "--limit", "steps=x"], "--limit"),
        (
            [
                "study",
                "run",
                "study.toml",
                "-o",
                "s.zarr",
                "--scheduler",
                "tcp://h:1",
                "--workers",
                "2",
            ],
            "give one of them",
        ),
    ]
    for args, expected in cases:
        assert expected in _one_error_line(_cli(args, sandbox)), args
    assert tree_hash(sandbox) == before


@pytest.mark.slow
def test_cli_export_follows_the_output_rule(sandbox: Path) -> None:
    pytest.importorskip("h5py")
    (sandbox / "study.toml").write_text(TOML, encoding="utf-8")
    assert _cli(["study", "run", "study.toml", "-o", "s.zarr", "-q"], sandbox).returncode == 0
    before = tree_hash(sandbox)
    for args in (
        ["study", "export", "s.zarr", "--netcdf", "small.csv"],
        ["study", "export", "s.zarr", "--netcdf", "s.zarr/zarr.json", "--overwrite"],
        ["study", "export", "s.zarr", "--netcdf", "mydata"],
    ):
        _one_error_line(_cli(args, sandbox))
    assert tree_hash(sandbox) == before
    ok = _cli(["study", "export", "s.zarr", "--netcdf", "small.csv", "--overwrite"], sandbox)
    assert ok.returncode == 0, ok.stderr
    assert (sandbox / "small.csv").read_bytes()[:4] == b"\x89HDF"
    assert sorted(p.name for p in sandbox.iterdir()) == sorted(
        ["small.csv", "study.toml", "mydata", "s.zarr"]
    )


@pytest.mark.slow  # a process-level test (spawns Python)
def test_export_removes_the_temporary_file_of_a_killed_export(
    store: Path, tmp_path: Path, h5py: Any
) -> None:
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    left = tmp_path / f".out.tmp-{dead.pid}-0123abcd.nc"  # what kill -9 during a write leaves
    left.write_bytes(b"partial")
    live = tmp_path / f".out.tmp-{os.getppid()}-0123abcd.nc"  # a live process's: kept
    live.write_bytes(b"busy")
    export_netcdf(store, tmp_path / "out.nc")
    assert not left.exists()
    assert live.read_bytes() == b"busy"


@pytest.mark.slow
@pytest.mark.parametrize("delay", [0.0, 0.5, 1.0, 1.5, 2.0, 3.0])
def test_killed_export_leaves_the_earlier_file_or_none(
    store: Path, tmp_path: Path, h5py: Any, delay: float
) -> None:
    import signal
    import time

    target = tmp_path / "out.nc"
    export_netcdf(store, target)
    good = target.read_bytes()
    proc = subprocess.Popen(
        [CLI, "study", "export", str(store), "--netcdf", str(target), "--overwrite"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    time.sleep(delay)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    exported = target.read_bytes()
    assert exported == good or _exported(target, "status") == _exported_bytes(good)


def _exported_bytes(data: bytes) -> bytes:
    import xarray as xr

    with xr.open_dataset(io.BytesIO(data), engine="h5netcdf") as ds:
        return bytes(ds["status"].values.tobytes())


def die_at_realization_one(parameters: Mapping[str, Any], seed: np.random.SeedSequence) -> Any:
    """Kill the worker process (SIGKILL) at realization 1, the first time only."""
    import signal

    marker = Path(os.environ["SPLINECONTACT_TEST_DIE_ONCE"])
    if seed.spawn_key == (1,) and not marker.exists():
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return fake_realization(parameters, seed)


@pytest.mark.slow
def test_lost_batches_carry_the_summary_and_reach_the_callback(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("SPLINECONTACT_TEST_DIE_ONCE", str(tmp_path / "died"))
    events: list[StudyProgress] = []
    with pytest.raises(study.StudyExecutionError) as info:
        run_study(
            SMALL,
            tmp_path / "s.zarr",
            workers=2,
            batch_size=1,
            progress=events.append,
            realization_function=die_at_realization_one,
        )
    summary = info.value.summary
    assert summary is not None and summary.not_run > 0 and summary.lost
    assert events[-1].summary == summary


@pytest.mark.slow
def test_two_first_runs_started_together_do_not_fail_on_each_other(tmp_path: Path) -> None:
    (tmp_path / "study.toml").write_text(TOML, encoding="utf-8")
    args = [CLI, "study", "run", "study.toml", "-o", "s.zarr", "-q", "--workers", "1"]
    for attempt in range(3):
        out = tmp_path / "s.zarr"
        shutil.rmtree(out, ignore_errors=True)
        procs = [
            subprocess.Popen(args, cwd=tmp_path, stderr=subprocess.PIPE, text=True)
            for _ in range(2)
        ]
        results = []
        for p in procs:  # communicate() reads and closes the pipe (no unclosed-file warning)
            _, err = p.communicate(timeout=300)
            results.append((p.returncode, err or ""))
        for code, err in results:
            assert "Errno" not in err and "Traceback" not in err, (attempt, err)
            if code != 0:
                assert code == 1 and len(err.strip().splitlines()) == 1, err
                assert "another running study" in err, err
        assert any(code == 0 for code, _ in results)
        assert [p.name for p in tmp_path.iterdir() if ".creating-" in p.name] == []
        assert (open_study(out)["status"].values != 0).all()


def test_dask_rescheduling_log_lines_are_held_back_on_the_command_line() -> None:
    """D18: a worker lost in a run that completes made distributed log "Couldn't gather N keys,
    rescheduling" beside the command's own output; the study CLI holds Dask's logs below ERROR."""
    import logging

    import distributed  # noqa: F401  (sets its loggers' levels on import)

    from splinecontact.cli._study import _dask_logs_quiet

    logger = logging.getLogger("distributed.client")
    assert logger.isEnabledFor(logging.WARNING)  # what a run would print without the guard
    with _dask_logs_quiet(True):
        assert not logger.isEnabledFor(logging.WARNING)
        assert logger.isEnabledFor(logging.ERROR)  # errors still show
    assert logger.isEnabledFor(logging.WARNING)  # restored afterwards
