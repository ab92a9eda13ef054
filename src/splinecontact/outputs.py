"""Where commands may write: one rule for every output file and folder.

The rule (documented in ``docs/outputs.md``):

1. An output that does not exist is created.
2. An output that exists is refused unless ``overwrite=True`` (``--overwrite`` on the CLI).
3. With ``overwrite=True``:

   * a **file** is replaced, atomically (written beside it, then renamed), unless it is one of the
     command's own inputs, which is always refused;
   * a **folder** is reused only if it carries the splinecontact marker file
     (:data:`OUTPUT_MARKER`), which lists the files splinecontact wrote there. Only those files are
     removed; anything else in the folder is left untouched. A folder without the marker, the
     current directory, one of its parents, the home directory and the filesystem root are
     refused and nothing is touched.

4. Nothing half-written is left behind: files are written to a temporary name in the same folder
   and renamed into place when complete.
"""

from __future__ import annotations

import contextlib
import json
import os
import uuid
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from .errors import OutputExistsError, UnsafeOutputError

__all__ = [
    "OUTPUT_MARKER",
    "OutputFolder",
    "atomic_path",
    "check_output_file",
    "is_protected_directory",
    "prepare_output_folder",
]

OUTPUT_MARKER = ".splinecontact-output.json"
"""Name of the marker file that identifies a folder written by splinecontact."""


def is_protected_directory(path: Path) -> bool:
    """Whether ``path`` must never be removed or emptied: cwd, its parents, home or root.

    Parameters
    ----------
    path : Path
        A directory path (need not exist).

    Returns
    -------
    bool
        True for the current working directory, any of its ancestors, the home directory, and
        the filesystem root.
    """
    resolved = path.expanduser().resolve()
    cwd = Path.cwd().resolve()
    if resolved == cwd or resolved in cwd.parents:
        return True
    if resolved == Path.home().resolve():
        return True
    return resolved == Path(resolved.anchor)


def check_output_file(
    path: Path | str, *, overwrite: bool, inputs: Iterable[Path | str] = (), option: str = "-o"
) -> Path:
    """Check that a command may write the file ``path``; touch nothing.

    Parameters
    ----------
    path : Path or str
        The output file.
    overwrite : bool
        Whether an existing file may be replaced.
    inputs : iterable of Path or str
        The command's input files: never replaced, even with ``overwrite``.
    option : str
        The CLI option that named ``path``, for the error message.

    Returns
    -------
    Path
        ``path`` as a :class:`~pathlib.Path`.

    Raises
    ------
    UnsafeOutputError
        ``path`` is a directory, one of the inputs, or its folder does not exist.
    OutputExistsError
        ``path`` exists and ``overwrite`` is false.
    """
    out = Path(path)
    if out.is_dir():
        raise UnsafeOutputError(f"{option} {out} is a folder; give a file name")
    resolved = out.expanduser().resolve()
    for item in inputs:
        if Path(item).expanduser().resolve() == resolved:
            raise UnsafeOutputError(
                f"{option} {out} is also an input of this command; refusing to overwrite it"
            )
    if not resolved.parent.is_dir():
        raise UnsafeOutputError(f"{option} {out}: the folder {out.parent} does not exist")
    if out.exists() and not overwrite:
        raise OutputExistsError(
            f"{option} {out} exists; choose another name or pass --overwrite to replace it"
        )
    return out


@contextlib.contextmanager
def atomic_path(path: Path | str) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` if the block succeeds.

    The temporary file keeps ``path``'s suffix (writers that pick a format from it still work)
    and is removed if the block raises, so a failure leaves neither a partial nor a stray file.

    Parameters
    ----------
    path : Path or str
        The final file name.

    Yields
    ------
    Path
        The temporary name to write to.
    """
    final = Path(path)
    tmp = final.with_name(f".{final.stem}.tmp-{os.getpid()}-{uuid.uuid4().hex[:8]}{final.suffix}")
    try:
        yield tmp
        os.replace(tmp, final)
    finally:
        if tmp.exists():
            tmp.unlink()


@dataclass(frozen=True)
class OutputFolder:
    """A folder a command writes into, with the marker that lists what it wrote.

    Obtain one from :func:`prepare_output_folder`; call :meth:`file` for every file written
    there, so that a later ``--overwrite`` removes exactly those files and nothing else.
    """

    path: Path
    command: str

    @property
    def marker(self) -> Path:
        """The marker file."""
        return self.path / OUTPUT_MARKER

    def written(self) -> list[str]:
        """Names (relative to the folder) of the files splinecontact recorded as written."""
        return _read_marker(self.path) or []

    def file(self, name: str) -> Path:
        """Record ``name`` as written by splinecontact and return its path in the folder.

        Parameters
        ----------
        name : str
            A file name relative to the folder (sub-folders allowed, no ``..``).
        """
        relative = Path(name)
        if relative.is_absolute() or ".." in relative.parts:
            raise UnsafeOutputError(f"output name {name!r} must stay inside {self.path}")
        names = self.written()
        if name not in names:
            names.append(name)
            _write_marker(self.path, self.command, names)
        target = self.path / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        return target


def _read_marker(folder: Path) -> list[str] | None:
    marker = folder / OUTPUT_MARKER
    if not marker.is_file():
        return None
    try:
        data = json.loads(marker.read_text(encoding="utf-8"))
        names = data["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        return None
    return names


def _write_marker(folder: Path, command: str, names: list[str]) -> None:
    from ._version import __version__

    marker = folder / OUTPUT_MARKER
    payload = {"written_by": f"splinecontact {__version__}", "command": command, "files": names}
    with atomic_path(marker) as tmp:
        tmp.write_text(json.dumps(payload, indent=1), encoding="utf-8")


def prepare_output_folder(
    path: Path | str, *, overwrite: bool, command: str, option: str = "-o"
) -> OutputFolder:
    """Create or reuse an output folder under the package's one output rule.

    Parameters
    ----------
    path : Path or str
        The output folder.
    overwrite : bool
        Whether a folder splinecontact wrote earlier may be reused. Only the files its marker
        lists are removed; other files are left as they are.
    command : str
        Name of the command writing the folder (recorded in the marker).
    option : str
        The CLI option that named ``path``, for the error message.

    Returns
    -------
    OutputFolder
        The folder, existing and marked.

    Raises
    ------
    UnsafeOutputError
        ``path`` is a file, a protected directory (cwd, a parent of it, home, root), or a
        non-empty folder splinecontact did not create, and ``overwrite`` asks to replace it.
    OutputExistsError
        ``path`` is a non-empty folder and ``overwrite`` is false.
    """
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise UnsafeOutputError(f"{option} {folder} is a file; give a folder name")
    if folder.is_dir() and any(folder.iterdir()):
        names = _read_marker(folder)
        if not overwrite:
            raise OutputExistsError(
                f"{option} {folder} exists and is not empty; choose another folder"
                + (
                    " or pass --overwrite to replace what splinecontact wrote there"
                    if names is not None
                    else ""
                )
            )
        if is_protected_directory(folder):
            raise UnsafeOutputError(
                f"{option} {folder} is the current directory, one of its parents or the home "
                "directory; refusing to replace anything there"
            )
        if names is None:
            raise UnsafeOutputError(
                f"{option} {folder} was not written by splinecontact (no {OUTPUT_MARKER}); "
                "refusing to touch it; choose another folder"
            )
        for name in names:
            target = folder / name
            if ".." in Path(name).parts or Path(name).is_absolute():
                continue
            if target.is_file() or target.is_symlink():
                target.unlink()
        (folder / OUTPUT_MARKER).unlink()
    else:
        if not folder.parent.expanduser().resolve().is_dir():
            raise UnsafeOutputError(f"{option} {folder}: the folder {folder.parent} does not exist")
        folder.mkdir(exist_ok=True)
    out = OutputFolder(folder, command)
    _write_marker(folder, command, [])
    return out
