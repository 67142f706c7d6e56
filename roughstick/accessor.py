"""The ``.rough`` accessor on DataArray and Dataset: thin forwarding to public functions only."""

from __future__ import annotations

import xarray as xr

__all__: list[str] = []


class _Forward:
    def __init__(self, obj):
        self._obj = obj

    def __getattr__(self, name):
        import roughstick

        if name.startswith("_") or name not in roughstick.__dict__ or not callable(roughstick.__dict__[name]):
            raise AttributeError(f"roughstick has no public function {name!r} to forward .rough.{name} to")
        func = roughstick.__dict__[name]

        def call(*args, **kwargs):
            return func(self._obj, *args, **kwargs)

        call.__doc__ = func.__doc__
        call.__name__ = name
        return call

    def __dir__(self):
        import roughstick

        return [n for n in getattr(roughstick, "__all__", []) if callable(getattr(roughstick, n, None))]


@xr.register_dataarray_accessor("rough")
class RoughDataArrayAccessor(_Forward):
    """``da.rough.f(...)`` calls ``roughstick.f(da, ...)``."""


@xr.register_dataset_accessor("rough")
class RoughDatasetAccessor(_Forward):
    """``ds.rough.f(...)`` calls ``roughstick.f(ds, ...)``."""
