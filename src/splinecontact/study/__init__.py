"""Studies: ensembles of SAD simulations over a parameter grid × realizations.

The package is split by job, each module importing only those listed before it:

* :mod:`~splinecontact.study.config` — the TOML study files, validated with pydantic (their
  parameters, defaults and ranges come from :mod:`splinecontact.parameters`);
* :mod:`~splinecontact.study.limits` — ceilings on the size of a study;
* :mod:`~splinecontact.study.fingerprint` — the fingerprint of the engine code;
* :mod:`~splinecontact.study.store` — the Zarr layout, its creation, locking, checks, writing;
* :mod:`~splinecontact.study.export` — reading a store, and the netCDF-4 export;
* :mod:`~splinecontact.study.executors` — where batches run (this process, a process pool,
  Dask), behind one interface;
* :mod:`~splinecontact.study.runner` — realizations, batches, :func:`run_study` (silent: a
  progress callback);
* :mod:`~splinecontact.study.display` — the rich progress bar and summary of the command line.

Every public name is importable from ``splinecontact.study``.
"""

from __future__ import annotations

from ..errors import StudyExecutionError
from .config import (
    PathSegmentSpec,
    StudyConfig,
    format_toml_value,
    load_study,
    parse_study,
)
from .display import StudyProgressBar, print_summary
from .executors import DaskExecutor, Executor, LocalExecutor, Lost, make_executor
from .export import export_netcdf, open_study, parameter_value
from .fingerprint import engine_fingerprint
from .limits import StudyLimits, check_limits
from .runner import (
    FailedRealization,
    ProgressCallback,
    RealizationFunction,
    StudyProgress,
    StudySummary,
    realization_seed,
    run_batch,
    run_study,
    simulate_realization,
)
from .store import (
    STATUS_FAILED,
    STATUS_NOT_RUN,
    STATUS_OK,
    BatchResult,
    BatchTask,
    step_variables,
    variable_attrs,
)

__all__ = [
    "STATUS_FAILED",
    "STATUS_NOT_RUN",
    "STATUS_OK",
    "BatchResult",
    "BatchTask",
    "DaskExecutor",
    "Executor",
    "FailedRealization",
    "LocalExecutor",
    "Lost",
    "PathSegmentSpec",
    "ProgressCallback",
    "RealizationFunction",
    "StudyConfig",
    "StudyExecutionError",
    "StudyLimits",
    "StudyProgress",
    "StudyProgressBar",
    "StudySummary",
    "check_limits",
    "engine_fingerprint",
    "export_netcdf",
    "format_toml_value",
    "load_study",
    "make_executor",
    "open_study",
    "parameter_value",
    "parse_study",
    "print_summary",
    "realization_seed",
    "run_batch",
    "run_study",
    "simulate_realization",
    "step_variables",
    "variable_attrs",
]
