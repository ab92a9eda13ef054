"""Reading a study store: the dataset, parameter values, and the netCDF-4 export."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..errors import OutputError, StudyStoreError, UnsafeOutputError
from ..outputs import atomic_path, check_output_file
from ..results import SCALAR_VARIABLES
from .config import PARAMETERS
from .store import (
    _array_names,
    _check_status_codes,
    _one_line,
    _open_arrays,
    _root_metadata,
    _stored_config,
    step_variables,
)

__all__ = ["export_netcdf", "open_study", "parameter_value"]


def open_study(path: str | Path) -> xr.Dataset:
    """Load a study store into memory as an :class:`xarray.Dataset`.

    The schema is described in :mod:`splinecontact.study.store`.

    Raises
    ------
    StudyStoreError
        If ``path`` is not a study store.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from splinecontact.study import run_study, open_study
    >>> config = {"study": {"name": "tiny", "seed": 1, "realizations": 2},
    ...           "fixed": {"n_points": 2048, "length": 10.0, "steps": 20},
    ...           "sweep": {"dimension": [1.3, 1.7]}}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     summary = run_study(config, pathlib.Path(folder) / "tiny.zarr", workers=1)
    ...     ds = open_study(pathlib.Path(folder) / "tiny.zarr")
    >>> dict(ds.sizes)
    {'dimension': 2, 'realization': 2, 'step': 21}
    >>> ds["normal_force"].attrs["units"]
    'mN/µm'
    """
    path = Path(path)
    if not path.exists():
        raise StudyStoreError(f"study store {path}: no such directory")
    attrs = _root_metadata(path) if path.is_dir() else None
    if attrs is None:
        raise StudyStoreError(f"{path} is not a splinecontact study store")
    config = _stored_config(path, attrs)
    names = _array_names(config)
    _open_arrays(path, "r", names)  # names a missing array
    try:
        ds = xr.open_zarr(path, consolidated=False)
    except Exception as exc:
        raise StudyStoreError(
            f"store {path} is damaged: it cannot be opened ({_one_line(exc)})"
        ) from None
    with ds:
        for name, variable in ds.variables.items():
            try:
                variable.load()
            except MemoryError:
                raise
            except Exception as exc:
                raise StudyStoreError(
                    f"store {path} is damaged: {name!r} cannot be read ({_one_line(exc)})"
                ) from None
        loaded = ds.load()
    expected = (*config.grid_shape, config.study.realizations)
    for name in (*names, "seed_spawn_key"):
        if name not in loaded.data_vars:
            raise StudyStoreError(f"store {path} is damaged: the variable {name!r} is missing")
    if loaded["status"].shape != expected or loaded.sizes.get("step") != config.max_steps + 1:
        raise StudyStoreError(
            f"store {path} is damaged: its arrays do not have the shape of its study "
            f"(status {loaded['status'].shape}, the study needs {expected})"
        )
    _check_status_codes(path, loaded["status"].values)
    # Variable-length strings come back as numpy's StringDType: use plain str objects.
    for name in list(loaded.variables):
        var = loaded.variables[name]
        if var.dtype.kind == "T":
            loaded[name] = var.copy(data=np.asarray(var.values, dtype=object))
    order = [
        *step_variables(config.path is not None),
        *SCALAR_VARIABLES,
        "status",
        "error",
        "seed_spawn_key",
    ]
    order += [name for name in loaded.data_vars if name not in order]
    return loaded[order]


def parameter_value(ds: xr.Dataset, name: str, **grid_index: int) -> Any:
    """The value of simulation parameter ``name`` in a study dataset.

    Looks in the coordinates (swept parameters) first, then in the attributes (fixed ones).

    Parameters
    ----------
    ds : xarray.Dataset
        A study (:func:`open_study`), or a selection of one.
    name : str
        A name of :data:`splinecontact.parameters.PARAMETERS`.
    **grid_index : int
        Positions along swept dimensions, e.g. ``dimension=3``; only ``name``'s is used.

    Returns
    -------
    object
        The value; for a swept parameter without a position, the array of its values (or the
        scalar if ``ds`` was selected at one value); ``None`` for a parameter left at the engine
        default.
    """
    if name in ds.coords:
        coord = ds.coords[name]
        if name in grid_index:
            return coord.values[int(grid_index[name])].item() if coord.ndim else coord.item()
        return coord.item() if coord.ndim == 0 else coord.values
    if name in ds.attrs:
        return ds.attrs[name]
    if name in PARAMETERS:
        return None
    raise StudyStoreError(f"{name!r} is not a study parameter; known: {', '.join(PARAMETERS)}")


def _write_bytes(path: Path, data: memoryview) -> None:
    """Write ``data`` to the new file ``path`` and flush it to disk."""
    with open(path, "xb") as file:
        file.write(data)
        file.flush()
        os.fsync(file.fileno())


def _remove_dead_temporaries(target: Path) -> None:
    """Remove temporary files of earlier exports to ``target`` whose process is gone (kill -9)."""
    for tmp in target.parent.glob(f".{target.stem}.tmp-*-*{target.suffix}"):
        pid_text = tmp.name.removeprefix(f".{target.stem}.tmp-").split("-", 1)[0]
        if not pid_text.isdigit() or int(pid_text) == os.getpid() or not tmp.is_file():
            continue
        try:
            os.kill(int(pid_text), 0)
        except ProcessLookupError:
            tmp.unlink(missing_ok=True)
        except OSError:
            continue


def export_netcdf(store: str | Path, target: str | Path, *, overwrite: bool = False) -> Path:
    """Write a study store as one netCDF-4 file (h5netcdf engine) and return its path.

    The file is written whole to a temporary name beside ``target`` and renamed into place, so
    an interruption or a full disk leaves no partial file and an earlier file intact.

    Parameters
    ----------
    store : path
        The study store (:func:`run_study`).
    target : path
        The netCDF file to write.
    overwrite : bool
        Replace ``target`` if it exists (never a file inside ``store``).

    Raises
    ------
    StudyStoreError
        ``store`` is not a study store, or is damaged.
    OutputExistsError
        ``target`` exists and ``overwrite`` is false.
    UnsafeOutputError
        ``target`` is a folder, lies inside ``store``, or its folder does not exist.
    OutputError
        The file cannot be written (full disk, permissions); nothing is left behind.
    """
    store = Path(store)
    target = Path(target)
    if store.exists():
        resolved, root = target.expanduser().resolve(), store.expanduser().resolve()
        if resolved == root or root in resolved.parents:
            raise UnsafeOutputError(
                f"--netcdf {target} is inside the study store {store}; refusing to write there"
            )
    target = check_output_file(target, overwrite=overwrite, option="--netcdf")
    ds = open_study(store)
    try:
        data = ds.to_netcdf(engine="h5netcdf", invalid_netcdf=False)
    except ImportError as exc:
        raise StudyStoreError(
            f"cannot write {target}: netCDF-4 writing needs h5py ({exc}); install it with "
            "`pip install h5py`"
        ) from None
    _remove_dead_temporaries(target)
    try:
        with atomic_path(target) as tmp:
            _write_bytes(tmp, data)
    except OSError as exc:
        reason = exc.strerror or _one_line(exc)
        raise OutputError(
            f"--netcdf {target}: cannot be written ({reason}); nothing was written"
        ) from None
    return target
