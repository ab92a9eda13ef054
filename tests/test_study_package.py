"""The study package's parts: silent runner, one source of variable attributes, executors, imports."""

from __future__ import annotations

import ast
import threading
import time
from pathlib import Path
from typing import Any

import pytest

import splinecontact
from splinecontact.errors import StudyConfigError, StudyExecutionError
from splinecontact.parameters import PARAMETERS
from splinecontact.study import (
    LocalExecutor,
    Lost,
    make_executor,
    open_study,
    run_study,
    variable_attrs,
)

SRC = Path(__file__).resolve().parents[1] / "src" / "splinecontact"

SMALL: dict[str, Any] = {
    "study": {"name": "parts", "seed": 3, "realizations": 2},
    "fixed": {"n_points": 64, "steps": 4},
    "sweep": {"dimension": [1.3, 1.6], "e_star": [10.0, 20.0]},
}


@pytest.fixture(scope="module")
def store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("parts") / "parts.zarr"
    run_study(SMALL, out, workers=1)
    return out


def test_run_study_prints_nothing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    events: list[Any] = []
    summary = run_study(SMALL, tmp_path / "s.zarr", workers=1, progress=events.append)
    assert summary.complete and summary.ok == 8
    assert capsys.readouterr() == ("", "")
    assert events[0].done == 0 and events[-1].summary == summary


def test_progress_must_be_a_callback(tmp_path: Path) -> None:
    out = tmp_path / "s.zarr"
    with pytest.raises(StudyConfigError, match=r"progress = True: give a callable"):
        run_study(SMALL, out, workers=1, progress=True)  # type: ignore[arg-type]
    assert not out.exists()


def test_every_stored_variable_takes_its_attributes_from_variable_attrs(store: Path) -> None:
    ds = open_study(store)
    for name, variable in ds.variables.items():
        attrs = variable_attrs(str(name))
        assert {k: variable.attrs.get(k) for k in attrs} == attrs, name
    for name in ("dimension", "e_star"):  # swept: the registry's unit and meaning
        assert ds[name].attrs == {
            "units": PARAMETERS[name].unit,
            "long_name": PARAMETERS[name].description,
        }
    with pytest.raises(KeyError):
        variable_attrs("no_such_variable")


def test_the_serial_executor_runs_in_order_and_in_this_process() -> None:
    executor = make_executor(workers=1)
    assert isinstance(executor, LocalExecutor) and executor.workers == 1
    assert list(executor.run(str.upper, ["a", "b", "c"])) == ["A", "B", "C"]
    executor.close()


@pytest.mark.slow
def test_the_pool_executor_reports_a_task_it_could_not_run_as_lost() -> None:
    executor = LocalExecutor(2)
    outcomes = list(executor.run(int, ["1", "x", "3"]))
    lost = [o for o in outcomes if isinstance(o, Lost)]
    assert sorted(o for o in outcomes if not isinstance(o, Lost)) == [1, 3]
    assert len(lost) == 1 and lost[0].task == "x" and lost[0].reason.startswith("ValueError")


def test_study_execution_error_is_public_and_carries_the_summary() -> None:
    exc = StudyExecutionError("lost", summary=None)
    assert isinstance(exc, splinecontact.SplineContactError)
    assert splinecontact.StudyExecutionError is StudyExecutionError
    assert splinecontact.study.StudyExecutionError is StudyExecutionError


#: Modules above the study stage: the study package never imports them.
ABOVE_STUDY = {"analysis", "plotting", "reproduce", "cli"}


def _imports(file: Path, level: int) -> set[str]:
    """Top names imported by ``file`` at relative ``level`` (0: absolute imports)."""
    found = set()
    for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level == level and node.module:
            found.add(node.module.split(".")[0])
        elif isinstance(node, ast.Import) and level == 0:
            found.update(alias.name.split(".")[0] for alias in node.names)
    return found


def test_the_study_package_imports_only_modules_below_it() -> None:
    for file in (SRC / "study").glob("*.py"):
        assert not _imports(file, 2) & ABOVE_STUDY, file.name
        assert "pydantic" not in _imports(file, 0) or file.name == "config.py", file.name


def test_the_parameter_registry_is_a_base_module() -> None:
    assert _imports(SRC / "parameters.py", 1) <= {"errors"}
    assert "pydantic" not in _imports(SRC / "parameters.py", 0)


def test_ctrl_c_inside_a_worker_start_is_held_not_lost() -> None:
    """SIGINT that comes while the executor starts workers (the block that keeps it from them)
    still interrupts the main process: blocked there, not ignored (ignoring discarded it, and
    a study under load could run to its end after a Ctrl-C)."""
    import signal

    from splinecontact.study.executors import _sigint_held

    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        pytest.skip("signals cannot be blocked here")
    reached_end_of_block = False
    # Python's own Ctrl-C handler, as in the command's main process (a test process may have
    # set another one, e.g. a pool worker's initializer run in-process ignores SIGINT)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            with _sigint_held():
                # (to the main thread itself: no other thread of the test process may take it)
                signal.pthread_kill(threading.main_thread().ident or 0, signal.SIGINT)
                time.sleep(0.05)
                reached_end_of_block = True  # held back in the block ...
            time.sleep(1.0)  # ... and delivered when it ends (never reached)
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, previous)
    assert reached_end_of_block
    assert signal.SIGINT not in signal.pthread_sigmask(signal.SIG_BLOCK, set())
