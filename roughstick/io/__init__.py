"""Readers and writers: AFM maps (:mod:`.afm`, vendor formats through SurfaceTopography) and CF
NetCDF (:mod:`.netcdf`, checked and atomic writes)."""

from . import afm, netcdf
from .afm import *  # noqa: F403
from .netcdf import *  # noqa: F403

__all__ = [name for mod in (afm, netcdf) for name in mod.__all__]
