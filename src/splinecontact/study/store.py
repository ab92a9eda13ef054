"""The study store: the Zarr layout, its creation, locking, checking and writing.

Store schema (:func:`splinecontact.study.open_study`): dimensions = the swept parameters
(named as the parameters, in study-file order), ``realization``, ``step``; every variable of
``STEP_VARIABLES`` on (grid…, realization, step) (a study with a ``[[path]]`` also
``PATH_STEP_VARIABLES``: u_T, slipping contacts, dissipated work, held F_N; see
:func:`step_variables`) and of ``SCALAR_VARIABLES`` on (grid…, realization), float64 (NaN where
not run or failed); ``status`` int8 (0 not run, 1 ok, 2 failed); ``error`` (message, "" if ok);
``seed_spawn_key`` (realization). Attributes: every fixed parameter under its name (parameters
left at the engine default ``None``, e.g. ``g_star``, are absent), ``study_toml``,
``study_seed``, ``splinecontact_version``, ``engine_fingerprint``, ``started``, ``finished``.
Every variable's ``units`` and ``long_name`` come from one function, :func:`variable_attrs`.

The main process alone writes the store, batch by batch as they finish: first the data, then
``error``, and ``status`` last, so a batch whose data are not all written is not marked done
(each chunk file is replaced atomically).

Safety: ``overwrite`` discards only a recognisable study store of another study (never another
folder, the current directory, its parents, home or root, nor a store another run holds); an
existing store is checked chunk by chunk before a run continues it, and damage is reported as
:class:`~splinecontact.errors.StudyStoreError` naming it.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import errno
import fcntl
import itertools
import json
import os
import shutil
import uuid
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from .. import schema
from .._version import __version__
from ..errors import StudyConfigError, StudyStoreError, UnsafeOutputError
from ..outputs import is_protected_directory
from ..results import PATH_STEP_VARIABLES, SCALAR_VARIABLES, STEP_VARIABLES
from .config import PARAMETERS, StudyConfig, parse_study
from .fingerprint import engine_fingerprint

__all__ = [
    "STATUS_FAILED",
    "STATUS_NOT_RUN",
    "STATUS_OK",
    "BatchResult",
    "BatchTask",
    "step_variables",
    "variable_attrs",
]

STATUS_NOT_RUN = 0
STATUS_OK = 1
STATUS_FAILED = 2

#: Target size of one chunk of a per-step variable [bytes].
_CHUNK_BYTES = 2**20


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


# --- what a batch writes ------------------------------------------------------------------------


@dataclass(frozen=True)
class BatchTask:
    """Realizations ``start … stop−1`` at one grid point.

    Attributes
    ----------
    grid_index : tuple of int
        Position in each swept parameter's list (empty if nothing is swept).
    start, stop : int
        Realization range.
    parameters : dict
        The full parameter set of the grid point.
    study_seed : int
        Entropy of the study's SeedSequence.
    n_step_records : int
        Length of the stored step dimension (largest ``steps`` of the study + 1).
    """

    grid_index: tuple[int, ...]
    start: int
    stop: int
    parameters: dict[str, Any]
    study_seed: int
    n_step_records: int


@dataclass(frozen=True, eq=False)
class BatchResult:
    """What a batch sends back: curves (n, n_step_records), scalars (n,), status, messages."""

    task: BatchTask
    curves: dict[str, NDArray[np.float64]]
    scalars: dict[str, NDArray[np.float64]]
    status: NDArray[np.int8]
    errors: tuple[str, ...]


def step_variables(has_path: bool) -> dict[str, tuple[str, str]]:
    """Per-step variables stored by a study: name -> (units, description).

    A study with a load path also stores :data:`~splinecontact.results.PATH_STEP_VARIABLES`
    (u_T, slipping contacts, dissipated work, the held F_N); one without keeps the plain layout.
    """
    return {**STEP_VARIABLES, **PATH_STEP_VARIABLES} if has_path else dict(STEP_VARIABLES)


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")


def _coord_values(values: Sequence[Any]) -> NDArray[Any]:
    if all(isinstance(v, str) for v in values):
        return np.array(values, dtype=object)
    if all(isinstance(v, int) for v in values):
        return np.array(values, dtype=np.int64)
    return np.array(values, dtype=np.float64)


#: The store's own variables and coordinates: name -> (units, long_name or None).
_STORE_VARIABLES: dict[str, tuple[str, str | None]] = {
    "status": ("1", "0 = not run, 1 = ok, 2 = failed"),
    "error": ("", "exception of a failed realization ('' if ok)"),
    "seed_spawn_key": ("1", "spawn key (r,) of the realization's numpy SeedSequence"),
    "realization": ("1", None),
    "step": ("1", None),
}


def variable_attrs(name: str) -> dict[str, Any]:
    """The ``units`` and ``long_name`` the store writes for variable or coordinate ``name``.

    The one place the store's variable attributes come from: the results' per-step and scalar
    variables (:mod:`splinecontact.results`), the swept parameters (the parameter registry) and
    the store's own (``status``, ``error``, ``seed_spawn_key``, ``realization``, ``step``). A
    coded variable (``force_control``) also gets the CF ``flag_values`` (as stored: float64,
    NaN where not run) and ``flag_meanings`` of :mod:`splinecontact.schema`.

    Raises
    ------
    KeyError
        ``name`` is none of these.
    """
    table: dict[str, tuple[str, str | None]] = {
        **STEP_VARIABLES,
        **PATH_STEP_VARIABLES,
        **SCALAR_VARIABLES,
        **_STORE_VARIABLES,
    }
    if name in table:
        units, long_name = table[name]
    else:
        units, long_name = PARAMETERS[name].unit, PARAMETERS[name].description
    out: dict[str, Any] = {"units": units}
    if long_name is not None:
        out["long_name"] = long_name
    if flags := (schema.VARIABLES[name].flags if name in schema.VARIABLES else ()):
        out["flag_values"] = [float(code) for code in range(len(flags))]
        out["flag_meanings"] = " ".join(flags)
    return out


def _template(config: StudyConfig) -> tuple[xr.Dataset, dict[str, dict[str, Any]]]:
    import dask.array as da

    R = config.study.realizations
    S = config.max_steps + 1
    grid_dims = config.swept_names
    grid_shape = config.grid_shape
    ones = (1,) * len(grid_dims)
    chunk_r = max(1, min(R, _CHUNK_BYTES // (8 * S)))
    step_dims = (*grid_dims, "realization", "step")
    real_dims = (*grid_dims, "realization")
    data_vars: dict[str, Any] = {}
    encoding: dict[str, dict[str, Any]] = {}
    for name in step_variables(config.path is not None):
        data = da.full((*grid_shape, R, S), np.nan, chunks=(*ones, chunk_r, S))
        data_vars[name] = (step_dims, data, variable_attrs(name))
        encoding[name] = {"_FillValue": np.nan, "chunks": (*ones, chunk_r, S)}
    for name in SCALAR_VARIABLES:
        data = da.full((*grid_shape, R), np.nan, chunks=(*ones, chunk_r))
        data_vars[name] = (real_dims, data, variable_attrs(name))
        encoding[name] = {"_FillValue": np.nan, "chunks": (*ones, chunk_r)}
    data_vars["status"] = (
        real_dims,
        np.zeros((*grid_shape, R), dtype=np.int8),
        variable_attrs("status"),
    )
    encoding["status"] = {"_FillValue": None, "chunks": (*ones, chunk_r)}
    data_vars["error"] = (
        real_dims,
        np.full((*grid_shape, R), "", dtype=object),
        variable_attrs("error"),
    )
    encoding["error"] = {"chunks": (*ones, chunk_r)}
    data_vars["seed_spawn_key"] = (
        ("realization",),
        np.arange(R, dtype=np.int64),
        {
            **variable_attrs("seed_spawn_key"),
            "entropy": str(config.study.seed),
            "seed_rule": "SeedSequence(entropy=study_seed, spawn_key=(r,)) "
            "= SeedSequence(study_seed).spawn(realizations)[r]",
        },
    )
    coords: dict[str, Any] = {
        "realization": (
            "realization",
            np.arange(R, dtype=np.int64),
            variable_attrs("realization"),
        ),
        "step": ("step", np.arange(S, dtype=np.int64), variable_attrs("step")),
    }
    for name, values in config.swept:
        coords[name] = (name, _coord_values(values), variable_attrs(name))
    attrs: dict[str, Any] = {
        name: value for name, value in config.fixed_parameters.items() if value is not None
    }
    attrs.update(
        {
            "title": f"splinecontact study {config.study.name}",
            "study_name": config.study.name,
            "study_toml": config.to_toml(),
            "study_seed": config.study.seed,
            "splinecontact_version": __version__,
            "engine_fingerprint": engine_fingerprint(),
            "units_convention": (
                "lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness"
            ),
            "started": _now(),
            "finished": "",
        }
    )
    if config.law is not None:  # the contact law, as single results record it
        from ..contact.laws import law_record, make_law

        attrs.update(law_record(make_law(**config.law.as_dict())))
    return xr.Dataset(data_vars, coords=coords, attrs=attrs), encoding


def _try_lock(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def _remove_stale_creations(path: Path) -> None:
    """Delete the temporary stores a killed run left beside ``path``.

    A run holds a lock on its temporary store while it builds it, so the temporary store of a
    live concurrent run is never touched: only those nobody holds are removed.
    """
    for stale in path.parent.glob(f".{path.name}.creating-*"):
        if stale.is_symlink() or not stale.is_dir():
            continue
        try:
            fd = os.open(stale, os.O_RDONLY)
        except OSError:
            continue
        try:
            if _try_lock(fd):
                shutil.rmtree(stale, ignore_errors=True)
        finally:
            os.close(fd)


def _create_store(path: Path, config: StudyConfig) -> bool:
    """Create the empty store atomically (built beside ``path``, then renamed).

    Returns False, leaving ``path`` as it is, if another run created the store first.
    """
    if not path.parent.expanduser().resolve().is_dir():
        raise StudyStoreError(
            f"cannot create the store {path}: the folder {path.parent} does not exist"
        )
    _remove_stale_creations(path)
    while True:
        tmp = path.with_name(f".{path.name}.creating-{uuid.uuid4().hex}")
        os.mkdir(tmp)
        fd = os.open(tmp, os.O_RDONLY)
        # Another run's clean-up may have taken it between mkdir and lock: then use a new name.
        if _try_lock(fd) and os.fstat(fd).st_nlink > 0:
            break
        os.close(fd)
    try:
        dataset, encoding = _template(config)
        dataset.to_zarr(tmp, mode="w-", encoding=encoding, consolidated=False, compute=False)
        try:
            os.rename(tmp, path)
        except OSError as exc:
            if exc.errno in (errno.ENOTEMPTY, errno.EEXIST) and path.exists():
                return False  # a concurrent run created it first
            raise
        return True
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
        os.close(fd)


def _root_metadata(path: Path) -> dict[str, Any] | None:
    """The attributes of the store's root group if ``path`` is recognisably a study store.

    Returns None when ``path`` carries no study metadata at all (not a store).

    Raises
    ------
    StudyStoreError
        The root metadata exists but cannot be read (a damaged store).
    """
    meta = path / "zarr.json"
    if not meta.is_file():
        return None
    try:
        data = json.loads(meta.read_bytes())
    except (OSError, ValueError) as exc:
        raise StudyStoreError(
            f"store {path} is damaged: its root metadata zarr.json cannot be read "
            f"({_one_line(exc)}); it cannot be used or replaced: restore it from a copy, or "
            "remove it yourself and run again"
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("attributes"), dict):
        return None
    attrs: dict[str, Any] = data["attributes"]
    return attrs if "study_toml" in attrs else None


def _read_store_attrs(path: Path) -> dict[str, Any] | None:
    try:
        return _root_metadata(path)
    except StudyStoreError:
        return None


def _stored_config(path: Path, attrs: Mapping[str, Any]) -> StudyConfig:
    """The study a store was written for (its ``study_toml`` attribute)."""
    import tomllib

    text = attrs.get("study_toml")
    if not isinstance(text, str):
        raise StudyStoreError(
            f"store {path} is damaged: its attribute study_toml is not text ({text!r:.60})"
        )
    try:
        return parse_study(tomllib.loads(text), source=f"{path} (stored)")
    except (tomllib.TOMLDecodeError, StudyConfigError, RecursionError) as exc:
        raise StudyStoreError(
            f"store {path} is damaged: its attribute study_toml is not a valid study "
            f"({_one_line(exc)})"
        ) from None


def _foreign_entry(path: Path) -> Path | None:
    """The first file or link under ``path`` that is not part of a Zarr store, if any."""
    for root, dirs, files in os.walk(path):
        here = Path(root)
        for name in [*dirs, *files]:
            item = here / name
            rel = item.relative_to(path).parts
            if item.is_symlink():
                return item
            if name in dirs:
                continue
            if rel == ("zarr.json",) or (len(rel) == 2 and rel[1] == "zarr.json"):
                continue
            if len(rel) >= 3 and rel[1] == "c":
                continue  # a chunk file (or a partial one) of an array
            return item
    return None


def _first_difference(a: Any, b: Any, prefix: str = "") -> str | None:
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        for key in list(a) + [k for k in b if k not in a]:
            where = f"{prefix}.{key}" if prefix else str(key)
            if key not in a:
                return f"{where}: absent in the store, {b[key]!r} in the study file"
            if key not in b:
                return f"{where}: {a[key]!r} in the store, absent in the study file"
            diff = _first_difference(a[key], b[key], where)
            if diff:
                return diff
        if list(a) != list(b):
            return f"{prefix}: order {list(a)} in the store, {list(b)} in the study file"
        return None
    if a != b or type(a) is not type(b):
        return f"{prefix}: {a!r} in the store, {b!r} in the study file"
    return None


def _prepare_store(path: Path, config: StudyConfig, *, overwrite: bool) -> bool:
    """Create the store, or check that the existing one holds this study (or discard it).

    Only a directory that is recognisably a study store (its own root metadata, nothing but
    Zarr files in it) is ever discarded, and only with ``overwrite``, never the current
    directory, one of its parents, the home directory or the root, and never while another run
    holds its lock. Anything else is refused and left untouched.

    Returns True if the store was created by this call (it holds no results yet).
    """
    for _ in range(3):
        if not (path.exists() or path.is_symlink()):
            if _create_store(path, config):
                return True
            continue  # a concurrent run created it: check it like any existing store
        attrs = None if not path.is_dir() else _root_metadata(path)
        if attrs is None:
            raise StudyStoreError(
                f"{path} exists and is not a splinecontact study store; choose another "
                "output path (--overwrite replaces only a study store)"
            )
        try:
            stored = _stored_config(path, attrs)
        except StudyStoreError as exc:
            if not overwrite:
                raise StudyStoreError(f"{exc}; --overwrite discards it and starts again") from None
        else:
            diff = _first_difference(stored.identity(), config.identity())
            version = attrs.get("splinecontact_version")
            if diff is None and version != __version__:
                diff = f"splinecontact version {version} wrote the store, this is {__version__}"
            fingerprint = attrs.get("engine_fingerprint")
            if diff is None and fingerprint != engine_fingerprint():
                diff = (
                    "the simulation code changed since the store was started (engine "
                    f"fingerprint {fingerprint} in the store, {engine_fingerprint()} now)"
                )
            if diff is None:
                return False
            if not overwrite:
                raise StudyStoreError(
                    f"store {path} belongs to a different study ({diff}); use another output "
                    "path, or --overwrite to discard the store and start again"
                )
        _discard_store(path)
        overwrite = False
    raise StudyStoreError(f"store {path} keeps changing under this run; is another run using it?")


def _discard_store(path: Path) -> None:
    """Remove the study store ``path`` (already recognised as one), under its lock."""
    if path.is_symlink():
        raise UnsafeOutputError(
            f"-o {path} is a symbolic link; refusing to replace it; give the store's real path"
        )
    if is_protected_directory(path):
        raise UnsafeOutputError(
            f"-o {path} is the current directory, one of its parents or the home directory; "
            "refusing to replace it"
        )
    with _locked(path):  # refuse to discard a store another run is writing
        foreign = _foreign_entry(path)
        if foreign is not None:
            raise UnsafeOutputError(
                f"-o {path} holds {foreign.relative_to(path)}, which is not part of a study "
                "store; refusing to discard it; move your files out or choose another path"
            )
        shutil.rmtree(path)


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    """Hold an exclusive lock on the store directory (released even by kill -9)."""
    fd = os.open(path, os.O_RDONLY)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise StudyStoreError(
                f"store {path} is being written by another running study; wait for it to end"
            ) from None
        yield
    finally:
        os.close(fd)


def _remove_partial_files(path: Path) -> None:
    """Delete chunk files left half-written by an interrupted run (zarr's ``*.partial``)."""
    for partial in path.rglob("*.partial"):
        partial.unlink(missing_ok=True)


_ARRAYS = (*STEP_VARIABLES, *SCALAR_VARIABLES, "error", "status")


def _array_names(config: StudyConfig) -> tuple[str, ...]:
    """The arrays a run of ``config`` writes."""
    steps = step_variables(config.path is not None)
    return (*steps, *SCALAR_VARIABLES, "error", "status")


_STATUS_CODES = (STATUS_NOT_RUN, STATUS_OK, STATUS_FAILED)


def _open_arrays(
    path: Path, mode: str, names: Sequence[str] = _ARRAYS
) -> tuple[Any, dict[str, Any]]:
    """The root group and the arrays a run writes, or a StudyStoreError naming what is missing."""
    import zarr

    try:
        group = zarr.open_group(path, mode=mode)  # type: ignore[arg-type]
    except Exception as exc:
        raise StudyStoreError(
            f"store {path} is damaged: it cannot be opened ({_one_line(exc)})"
        ) from None
    arrays: dict[str, Any] = {}
    for name in names:
        try:
            arrays[name] = group[name]
        except KeyError:
            raise StudyStoreError(
                f"store {path} is damaged: the array {name!r} is missing ({name}/zarr.json)"
            ) from None
        except Exception as exc:
            raise StudyStoreError(
                f"store {path} is damaged: the array {name!r} cannot be opened ({_one_line(exc)})"
            ) from None
    return group, arrays


def _chunk_regions(shape: Sequence[int], chunks: Sequence[int]) -> Iterator[tuple[slice, ...]]:
    ranges = [range(0, n, c) for n, c in zip(shape, chunks, strict=True)]
    for starts in itertools.product(*ranges):
        yield tuple(slice(a, min(a + c, n)) for a, c, n in zip(starts, chunks, shape, strict=True))


def _check_status_codes(path: Path, status: NDArray[Any]) -> None:
    bad = ~np.isin(status, _STATUS_CODES)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        raise StudyStoreError(
            f"store {path} is damaged: status holds the unknown code {int(status[where])} at "
            f"{where} (codes: 0 not run, 1 ok, 2 failed)"
        )


def _verify_store(path: Path, arrays: Mapping[str, Any], config: StudyConfig) -> None:
    """Check shapes, decode every chunk and check the status codes; name the first damage."""
    realizations = config.study.realizations
    shapes = {name: (*config.grid_shape, realizations) for name in _array_names(config)}
    for name in step_variables(config.path is not None):
        shapes[name] = (*config.grid_shape, realizations, config.max_steps + 1)
    for name, array in arrays.items():
        if tuple(array.shape) != shapes[name]:
            raise StudyStoreError(
                f"store {path} is damaged: the array {name!r} has shape {tuple(array.shape)}, "
                f"the study needs {shapes[name]}"
            )
        for region in _chunk_regions(array.shape, array.chunks):
            try:
                block = array[region]
            except MemoryError:
                raise
            except Exception as exc:
                chunk = tuple(r.start // c for r, c in zip(region, array.chunks, strict=True))
                raise StudyStoreError(
                    f"store {path} is damaged: chunk {'/'.join(map(str, chunk))} of {name!r} "
                    f"cannot be read ({_one_line(exc)}); restore the store from a copy, or run "
                    "with --overwrite to start again"
                ) from None
            if name == "status":
                _check_status_codes(path, np.asarray(block))


class _Writer:
    """Writes finished batches into the store: data, then ``error``, then ``status``."""

    def __init__(self, path: Path, names: Sequence[str] = _ARRAYS) -> None:
        self.path = path
        self.names = tuple(names)
        # Read-only until something is written: a run with nothing to do works on a read-only
        # store and changes nothing.
        self.group, self.arrays = _open_arrays(path, "r", self.names)
        self._writable = False

    def _make_writable(self) -> None:
        if not self._writable:
            self.group, self.arrays = _open_arrays(self.path, "r+", self.names)
            self._writable = True

    def status(self) -> NDArray[np.int8]:
        try:
            status = np.asarray(self.arrays["status"][...])
        except MemoryError:
            raise
        except Exception as exc:
            raise StudyStoreError(
                f"store {self.path} is damaged: 'status' cannot be read ({_one_line(exc)})"
            ) from None
        _check_status_codes(self.path, status)
        return status.astype(np.int8)

    def write(self, result: BatchResult) -> None:
        self._make_writable()
        task = result.task
        region = (*task.grid_index, slice(task.start, task.stop))
        for name in result.curves:
            self.arrays[name][(*region, slice(None))] = result.curves[name]
        for name in SCALAR_VARIABLES:
            self.arrays[name][region] = result.scalars[name]
        self.arrays["error"][region] = np.array(result.errors, dtype=object)
        self.arrays["status"][region] = result.status

    def finished(self) -> bool:
        return bool(self.group.attrs.get("finished"))

    def finish(self) -> None:
        self._make_writable()
        self.group.attrs.update({"finished": _now()})
