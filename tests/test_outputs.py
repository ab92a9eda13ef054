"""The one output rule (splinecontact.outputs): nothing the user owns is deleted or overwritten."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from splinecontact.errors import OutputExistsError, UnsafeOutputError
from splinecontact.outputs import (
    OUTPUT_MARKER,
    atomic_path,
    check_output_file,
    prepare_output_folder,
)


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def test_new_folder_is_created_and_marked(tmp_path: Path) -> None:
    out = prepare_output_folder(tmp_path / "figs", overwrite=False, command="plot")
    out.file("a.png").write_bytes(b"x")
    assert (tmp_path / "figs" / OUTPUT_MARKER).is_file()
    assert out.written() == ["a.png"]


def test_existing_folder_refused_without_overwrite(tmp_path: Path) -> None:
    folder = tmp_path / "figs"
    out = prepare_output_folder(folder, overwrite=False, command="plot")
    out.file("a.png").write_bytes(b"x")
    with pytest.raises(OutputExistsError, match="--overwrite"):
        prepare_output_folder(folder, overwrite=False, command="plot")


def test_overwrite_removes_only_what_splinecontact_wrote(tmp_path: Path) -> None:
    folder = tmp_path / "figs"
    out = prepare_output_folder(folder, overwrite=False, command="plot")
    out.file("a.png").write_bytes(b"old")
    (folder / "notes.txt").write_text("mine")
    again = prepare_output_folder(folder, overwrite=True, command="plot")
    assert not (folder / "a.png").exists()
    assert (folder / "notes.txt").read_text() == "mine"
    assert again.written() == []


def test_user_folder_never_touched(tmp_path: Path) -> None:
    folder = tmp_path / "precious"
    folder.mkdir()
    (folder / "thesis.tex").write_text("years of work")
    (folder / "sub").mkdir()
    (folder / "sub" / "data.csv").write_text("1,2")
    before = _snapshot(folder)
    for overwrite in (False, True):
        with pytest.raises((OutputExistsError, UnsafeOutputError)):
            prepare_output_folder(folder, overwrite=overwrite, command="plot")
    assert _snapshot(folder) == before


def test_cwd_and_parents_refused_even_if_marked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    work = tmp_path / "work"
    work.mkdir()
    (work / OUTPUT_MARKER).write_text('{"files": ["keep.txt"]}')
    (work / "keep.txt").write_text("mine")
    monkeypatch.chdir(work)
    for target in (Path("."), Path(".."), Path(os.getcwd())):
        with pytest.raises(UnsafeOutputError):
            prepare_output_folder(target, overwrite=True, command="plot")
    assert (work / "keep.txt").read_text() == "mine"


def test_output_file_rules(tmp_path: Path) -> None:
    data = tmp_path / "scan.csv"
    data.write_text("0,0\n")
    with pytest.raises(UnsafeOutputError, match="input"):
        check_output_file(data, overwrite=True, inputs=[data])
    with pytest.raises(OutputExistsError):
        check_output_file(data, overwrite=False)
    with pytest.raises(UnsafeOutputError, match="folder"):
        check_output_file(tmp_path, overwrite=True)
    with pytest.raises(UnsafeOutputError, match="does not exist"):
        check_output_file(tmp_path / "nope" / "a.nc", overwrite=False)
    assert check_output_file(data, overwrite=True) == data
    assert data.read_text() == "0,0\n"


def test_atomic_path_leaves_nothing_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("disk full")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]
    with atomic_path(target) as tmp:
        assert tmp.suffix == ".csv"
        tmp.write_text("new")
    assert target.read_text() == "new"
