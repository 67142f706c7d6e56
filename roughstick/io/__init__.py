"""Readers and writers: AFM maps (afm.py) and CF NetCDF (netcdf.py)."""
