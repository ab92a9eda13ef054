"""Diagnostics of the method: F_N split into its normal and tangential-spring parts (eq. 14)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .ensemble import _require, ok_mask

__all__ = ["force_split"]


def force_split(ds: xr.Dataset) -> xr.Dataset:
    """Split of F_N into its normal-force and tangential-spring parts (eq. 14), tilted contacts.

    Returns
    -------
    xarray.Dataset
        On (grid…, realization, step): ``normal_part_fraction`` and ``tangential_part_fraction``
        (parts of F_N over F_N, NaN where F_N = 0) [1] and ``tilted_fraction`` (accepted contacts
        whose repulsive direction points below horizontal, over accepted contacts; NaN without
        contacts) [1]. Unsuccessful realizations are NaN.
    """
    names = [
        "normal_force",
        "normal_force_normal_part",
        "normal_force_tangential_part",
        "n_contacts",
        "n_tilted_contacts",
    ]
    _require(ds, [*names, "status"])
    ok = ok_mask(ds)
    fn = ds["normal_force"].where(ok)
    nc = ds["n_contacts"].where(ok)
    with np.errstate(invalid="ignore", divide="ignore"):
        normal = (ds["normal_force_normal_part"].where(ok) / fn.where(fn != 0)).assign_attrs(
            units="1", long_name="fraction of F_N from the local normal forces"
        )
        tangential = (
            ds["normal_force_tangential_part"].where(ok) / fn.where(fn != 0)
        ).assign_attrs(units="1", long_name="fraction of F_N from the local tangential forces")
        tilted = (ds["n_tilted_contacts"].where(ok) / nc.where(nc > 0)).assign_attrs(
            units="1", long_name="fraction of accepted contacts tilted past horizontal"
        )
    return xr.Dataset(
        {
            "normal_part_fraction": normal,
            "tangential_part_fraction": tangential,
            "tilted_fraction": tilted,
        }
    )
