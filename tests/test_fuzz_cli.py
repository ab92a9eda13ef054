"""Fuzz suite of the command line: whatever the file, ``splinecontact inspect`` and
``splinecontact simulate --upper flat`` exit 0, or exit 1 with exactly one ``error:`` line,
no traceback and nothing written.

The inputs are the mutations of ``tests/test_fuzz_readers.py`` (the sample files of
``tests/data`` and seeds written at test time; byte flips, truncation, garbage, BOMs, hostile
number tokens, huge lines, bracket runs, damaged or forged zip members), each run with random
reading and preprocessing options, in-process with typer's ``CliRunner``. A fixed seed makes
every run the same. The default run tries 100 inputs; the ``slow`` tier tries 1 000 and prints
the tally quoted in ``docs/reliability.md`` (``pytest -m slow -s tests/test_fuzz_cli.py``).
Each input's wall time is recorded and the slowest is printed: a time bound per input, not a
timing assert.
"""

from __future__ import annotations

import random
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from typer.testing import CliRunner

from splinecontact.cli import app
from test_fuzz_readers import _mutate_bytes, _mutate_zip, _seeds

runner = CliRunner()


@dataclass
class CliTally:
    """Outcome of a CLI fuzz run."""

    inputs: int = 0
    ok: int = 0
    refused: Counter[str] = field(default_factory=Counter)
    broken: list[str] = field(default_factory=list)
    slowest: float = 0.0
    slowest_label: str = ""
    seconds: float = 0.0
    cpu: float = 0.0

    def summary(self) -> str:
        lines = [
            f"inputs {self.inputs}, exit 0 {self.ok}, refused in one line "
            f"{sum(self.refused.values())}, broken contract {len(self.broken)}; "
            f"slowest input {self.slowest:.2f} s wall ({self.slowest_label}); "
            f"total {self.seconds:.1f} s wall, {self.cpu:.1f} s CPU",
        ]
        lines += [f"  {name}: {count}" for name, count in self.refused.most_common()]
        lines += [f"  BROKEN {text}" for text in self.broken[:20]]
        return "\n".join(lines)


def _options(rng: random.Random) -> list[str]:
    options: list[str] = []
    if rng.random() < 0.6:
        options += ["--unit", rng.choice(["um", "nm", "mm", "inch"])]
    if rng.random() < 0.15:
        options += ["--height-unit", rng.choice(["nm", "A"])]
    if rng.random() < 0.2:
        options += ["--spacing", rng.choice(["1", "0.5", "-1", "nan"])]
    if rng.random() < 0.3:
        options += ["--line", rng.choice(["0", "1", "3", "1000000000", "-1"])]
    if rng.random() < 0.15:
        options += ["--format", rng.choice(["table", "dektak", "x3p", "npy", "npz", "bogus"])]
    if rng.random() < 0.2:
        options += ["--undefined", "interpolate"]
    if rng.random() < 0.2:
        options += ["--order", "sort"]
    if rng.random() < 0.2:
        options += ["--duplicates", "average"]
    if rng.random() < 0.15:
        options += ["--nonuniform", "resample"]
    if rng.random() < 0.15:
        options += ["--crop", rng.choice(["0,10", "-1e300,1e300", "5,1"])]
    if rng.random() < 0.3:
        options += ["--detrend", rng.choice(["mean", "tilt", "poly3"])]
    return options


def _check(
    args: list[str], work: Path, expected_files: set[str], tally: CliTally, label: str
) -> None:
    start = time.perf_counter()
    result = runner.invoke(app, args)
    elapsed = time.perf_counter() - start
    if elapsed > tally.slowest:
        tally.slowest, tally.slowest_label = elapsed, label
    tally.inputs += 1
    output = result.output
    lines = [line for line in output.splitlines() if line.strip()]
    left = {p.name for p in work.iterdir()}
    problem = ""
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        problem = f"exception {type(result.exception).__name__}: {result.exception}"
    elif "Traceback" in output:
        problem = "traceback printed"
    elif result.exit_code == 0:
        tally.ok += 1
    elif result.exit_code != 1:
        problem = f"exit {result.exit_code}"
    elif len(lines) != 1 or not lines[0].startswith("error: "):
        problem = f"{len(lines)} lines instead of one error line"
    elif left != expected_files:
        problem = f"files left behind: {sorted(left - expected_files)}"
    else:
        tally.refused[lines[0].split(":")[1].strip().split(" ")[0]] += 1
    if problem:
        tally.broken.append(f"{label} {args[2:]}: {problem}; output {output[-300:]!r}")


def run_cli_fuzz(folder: Path, n_inputs: int, seed: int) -> CliTally:
    """Mutate the seeds ``n_inputs`` times (fixed ``seed``); run ``inspect`` on even inputs and
    ``simulate --upper flat`` on odd ones."""
    rng = random.Random(seed)
    (folder / "seeds").mkdir()
    seeds = _seeds(folder / "seeds")
    tally = CliTally()
    start, cpu = time.perf_counter(), time.process_time()
    for k in range(n_inputs):
        suffix, data = rng.choice(seeds)
        zipped = data.startswith(b"PK\x03\x04")
        mutated = _mutate_zip(rng, data) if zipped and rng.random() < 0.7 else data
        if not zipped or mutated is data:
            mutated = _mutate_bytes(rng, data)
        if rng.random() < 0.1:
            suffix = rng.choice([".csv", ".x3p", ".npz", ".npy", ".txt", ""])
        work = folder / f"case{k}"
        work.mkdir()
        path = work / f"input{suffix}"
        path.write_bytes(mutated)
        options = _options(rng)
        if k % 2 == 0:
            args = ["inspect", str(path), *options]
        else:
            out = work / "result.nc"
            args = ["simulate", "--lower", str(path), "--upper", "flat", "--steps", "5",
                    "-o", str(out), *options]  # fmt: skip
        before = {path.name}
        _check(args, work, before, tally, f"input {k} ({args[0]}, {suffix or 'no suffix'})")
        if tally.inputs and (work / "result.nc").exists():
            (work / "result.nc").unlink()  # a success wrote its result; keep the folder small
        path.unlink()
        work.rmdir()
    tally.seconds = time.perf_counter() - start
    tally.cpu = time.process_time() - cpu
    return tally


def test_cli_fuzz_default_budget(tmp_path: Path) -> None:
    tally = run_cli_fuzz(tmp_path, n_inputs=100, seed=20261124)
    print("\nCLI fuzz, seed 20261124:\n" + tally.summary())
    assert tally.broken == [], tally.summary()
    assert tally.inputs == 100
    assert sum(tally.refused.values()) > 50  # the mutations do reach the error paths


@pytest.mark.slow
def test_cli_fuzz_slow_budget(tmp_path: Path) -> None:
    tally = run_cli_fuzz(tmp_path, n_inputs=1_000, seed=11)
    print("\nCLI fuzz, seed 11:\n" + tally.summary())
    assert tally.broken == [], tally.summary()
    assert tally.inputs >= 1_000


@pytest.mark.parametrize("height", ["1e300", "-1e308", "1.7e308"])
def test_heights_near_the_float_limit_in_a_file_are_one_line(tmp_path: Path, height: str) -> None:
    # inspect used to print R_q = inf with seven RuntimeWarnings; simulate returned zero force
    path = tmp_path / "big.csv"
    path.write_text(f"x [um], z [um]\n0,{height}\n1,0\n2,1\n3,0\n4,1\n5,0\n", encoding="utf-8")
    for args in (
        ["inspect", str(path)],
        ["simulate", "--lower", str(path), "--upper", "flat", "-o", str(tmp_path / "r.nc")],
    ):
        result = runner.invoke(app, args)
        lines = [line for line in result.output.splitlines() if line.strip()]
        assert result.exit_code == 1, result.output
        assert len(lines) == 1 and lines[0].startswith("error: ProfileRangeError"), result.output
        assert "beyond ±1e+50 µm" in lines[0]
        assert sorted(p.name for p in tmp_path.iterdir()) == ["big.csv"]
