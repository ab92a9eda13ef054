"""`splinecontact study` on the command line: errors, progress bar, summary, export."""

from __future__ import annotations

import fcntl
import os
import pty
import re
import struct
import subprocess
import sys
import termios
from pathlib import Path

import pytest

from splinecontact.study import open_study, run_study

# Every test here spawns the command line (a process-level test): run with `pytest -m slow`.
pytestmark = pytest.mark.slow

CLI = str(Path(sys.executable).parent / "splinecontact")

TINY = """
[study]
name = "tiny"
seed = 2015
realizations = 3

[fixed]
n_points = 2000
steps = 20

[sweep]
dimension = [1.3, 1.7]
contact_type = ["rough-on-rough", "rough-on-flat"]
"""


def _env() -> dict[str, str]:
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("NO_COLOR", "FORCE_COLOR", "TTY_COMPATIBLE", "TTY_INTERACTIVE", "COLUMNS")
    }
    env["TERM"] = "xterm-256color"
    return env


def run_on_terminal(args: list[str]) -> tuple[int, str]:
    """Run the command with a pseudo-terminal as stdin, stdout and stderr."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, 160, 0, 0))
    proc = subprocess.Popen(
        args, stdin=slave, stdout=slave, stderr=slave, close_fds=True, env=_env()
    )
    os.close(slave)
    chunks = []
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(master)
    text = b"".join(chunks).decode("utf-8", errors="replace")
    return proc.wait(timeout=120), re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", text)


@pytest.fixture
def study_file(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.toml"
    path.write_text(TINY, encoding="utf-8")
    return path


def test_progress_bar_and_summary_on_a_terminal(study_file: Path, tmp_path: Path) -> None:
    code, output = run_on_terminal(
        [CLI, "study", "run", str(study_file), "-o", str(tmp_path / "o.zarr"), "--workers", "1"]
    )
    assert code == 0, output
    assert "12/12" in output  # done/total
    assert "real./s" in output  # rate
    assert "ETA" in output
    assert "study complete: 12 ok, 0 failed, 0 not run, of 12 realizations" in output
    assert "wall time" in output


def test_quiet_prints_nothing_on_a_terminal(study_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "q.zarr"
    code, output = run_on_terminal(
        [CLI, "study", "run", str(study_file), "-o", str(out), "-q", "--workers", "1"]
    )
    assert code == 0
    assert output.strip() == ""
    assert (open_study(out)["status"].values == 1).all()


def test_without_a_terminal_summary_only(study_file: Path, tmp_path: Path) -> None:
    proc = subprocess.run(
        [CLI, "study", "run", str(study_file), "-o", str(tmp_path / "p.zarr"), "--workers", "1"],
        capture_output=True,
        text=True,
        check=False,
        env=_env(),
    )
    assert proc.returncode == 0, proc.stderr
    assert "study complete: 12 ok" in proc.stdout
    assert "real./s" not in proc.stdout + proc.stderr  # no progress bar in a pipe


INVALID = {
    "unknown key": ("[fixed]\ndimension = 1.5\nfrobnicate = 2\n", "fixed.frobnicate = 2: unknown"),
    "D = 2.5": ("[sweep]\ndimension = [1.5, 2.5]\n", "sweep.dimension[1] = 2.5: must be ≤ 2"),
    "typo in section": ("[sweeep]\ndimension = [1.5]\n", "sweeep: unknown section"),
}


@pytest.mark.parametrize("case", [*INVALID, "negative realizations"])
def test_invalid_study_file_one_line_error_no_traceback(case: str, tmp_path: Path) -> None:
    if case == "negative realizations":
        text = '[study]\nname = "x"\nseed = 1\nrealizations = -5\n[fixed]\ndimension = 1.5\n'
        expected = "study.realizations = -5: must be ≥ 1"
    else:
        body, expected = INVALID[case]
        text = '[study]\nname = "x"\nseed = 1\nrealizations = 2\n' + body
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    proc = subprocess.run(
        [CLI, "study", "run", str(path), "-o", str(tmp_path / "o.zarr")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode != 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"error: StudyConfigError: study file {path}: ")
    assert expected in lines[0]
    assert "Traceback" not in proc.stderr + proc.stdout
    assert not (tmp_path / "o.zarr").exists()


def test_changed_study_refused_on_command_line(study_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "o.zarr"
    args = [CLI, "study", "run", str(study_file), "-o", str(out), "--workers", "1", "-q"]
    run_study(study_file, out, workers=1, progress=False)
    study_file.write_text(TINY.replace("steps = 20", "steps = 21"), encoding="utf-8")
    proc = subprocess.run(args, capture_output=True, text=True, check=False)
    assert proc.returncode == 1
    assert "belongs to a different study (fixed.steps: 20 in the store, 21" in proc.stderr
    assert "--overwrite" in proc.stderr
    assert subprocess.run([*args, "--overwrite"], check=False).returncode == 0
    assert open_study(out).sizes["step"] == 22


def test_export_netcdf(study_file: Path, tmp_path: Path) -> None:
    pytest.importorskip("h5py")
    import xarray as xr

    out = tmp_path / "o.zarr"
    run_study(study_file, out, workers=1, progress=False)
    target = tmp_path / "o.nc"
    subprocess.run([CLI, "study", "export", str(out), "--netcdf", str(target)], check=True)
    stored = open_study(out)
    with xr.open_dataset(target, engine="h5netcdf") as exported:
        exported = exported.load()
    for name in ("normal_force", "status", "rq_lower"):
        assert stored[name].values.tobytes() == exported[name].values.tobytes()
        assert exported[name].attrs["units"] == stored[name].attrs["units"]
    assert exported.attrs["study_toml"] == stored.attrs["study_toml"]


def test_export_of_a_missing_store_is_one_line(tmp_path: Path) -> None:
    proc = subprocess.run(
        [CLI, "study", "export", str(tmp_path / "nope.zarr"), "--netcdf", str(tmp_path / "x.nc")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    assert proc.stderr.strip().startswith("error: StudyStoreError: study store")
    assert "Traceback" not in proc.stderr


CTRL_C_STUDY = """
[study]
name = "ctrl-c"
seed = 4
realizations = 12

[fixed]
n_points = 50_000
steps = 100

[sweep]
dimension = [1.2, 1.5]
"""


def _done(store: Path) -> int:
    import zarr

    try:
        return int((zarr.open_group(store, mode="r")["status"][...] != 0).sum())
    except Exception:
        return 0


def test_ctrl_c_stops_with_status_130_and_the_study_resumes(tmp_path: Path) -> None:
    import signal
    import time

    path = tmp_path / "c.toml"
    path.write_text(CTRL_C_STUDY, encoding="utf-8")
    out = tmp_path / "c.zarr"
    args = [CLI, "study", "run", str(path), "-o", str(out), "--workers", "2", "--batch-size", "1"]
    master, slave = pty.openpty()
    # The command starts as a terminal's foreground job does: Ctrl-C not ignored nor blocked.
    # (A process started with SIGINT ignored keeps it ignored, and this test process may have
    # inherited or been left with that: the command then ran to its end, exit 0.)
    handler = signal.signal(signal.SIGINT, signal.default_int_handler)  # SIG_DFL after exec
    mask = signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    try:
        proc = subprocess.Popen(
            args, stdin=slave, stdout=slave, stderr=slave, env=_env(), start_new_session=True
        )
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        signal.signal(signal.SIGINT, handler)
    os.close(slave)
    deadline = time.monotonic() + 120
    while _done(out) < 2 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C goes to the terminal's foreground group
    chunks = []
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(master)
    assert proc.wait(timeout=60) == 130
    output = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", b"".join(chunks).decode(errors="replace"))
    assert "error: interrupted; everything finished is stored in" in output
    assert "Traceback" not in output
    assert 2 <= _done(out) < 24
    resumed = subprocess.run([*args, "-q"], capture_output=True, text=True, check=False)
    assert resumed.returncode == 0, resumed.stderr
    whole = tmp_path / "whole.zarr"
    run_study(path, whole, workers=1, progress=False)
    a, b = open_study(out), open_study(whole)
    for name in a.data_vars:
        assert a[name].values.tobytes() == b[name].values.tobytes() or name == "error", name
    assert (a["error"].values == b["error"].values).all()
