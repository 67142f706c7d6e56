"""The memory of this machine, and work refused before allocating when it cannot fit.

- :func:`physical_memory`: the bytes this process may use (the machine's, or its container's
  limit when lower);
- :func:`check_fits_in_memory`: a ``MemoryError`` naming the work, the memory it needs, the
  memory there is and the fix, before anything is allocated (surface generation, .npy reading);
- :func:`check_map_fits_in_memory`: the same for a height map put through a contact model, from
  :data:`CONTACT_BYTES_PER_PIXEL` (measured) and the map size, for eager and lazy maps.
"""

from __future__ import annotations

import os

import numpy as np

from .dask import is_lazy

__all__ = ["CONTACT_BYTES_PER_PIXEL", "physical_memory", "check_fits_in_memory", "check_map_fits_in_memory"]

#: Peak memory [bytes] per pixel of one map in each contact model (heights, spectra, labels and
#: work arrays), rounded up from the resident-memory growth measured on 512² and 1024² maps:
#: modified DMT 0.70 kB, FFT-BEM 0.56 kB in single precision (1.1 kB in double), GW (the map's
#: moments) 0.15 kB; the Tamaas BEM, not measured, is given the double-precision FFT-BEM's.
CONTACT_BYTES_PER_PIXEL = {"modified_dmt": 768, "fft_bem": 640, "fft_bem_double": 1152, "gw": 256,
                           "bem": 1152}


def physical_memory() -> float | None:
    """Bytes of memory this process may use: the machine's, or its container's limit when lower
    (cgroup); None where unknown."""
    try:
        have = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):  # pragma: no cover - not POSIX
        return None
    for limit in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(limit) as fh:
                text = fh.read().strip()
        except OSError:
            continue
        if text.isdigit() and 0 < int(text) < have:
            have = float(text)
    return have


def check_fits_in_memory(need: float, *, what: str, fix: str, detail: str = "") -> None:
    """Raise ``MemoryError`` before allocating when ``need`` bytes exceed :func:`physical_memory`:
    "<what> needs about N GiB <detail>, more than this machine's M GiB of memory; <fix>."."""
    have = physical_memory()
    if have is not None and need > have:
        raise MemoryError(
            f"{what} needs about {need / 2**30:.3g} GiB{' ' + detail if detail else ''}, more than "
            f"this machine's {have / 2**30:.3g} GiB of memory; {fix}."
        )


def check_map_fits_in_memory(height, *, model: str, what: str | None = None) -> None:
    """Refuse, before any work, a height map ``(..., y, x)`` whose one map cannot be put through
    contact model ``model`` (a key of :data:`CONTACT_BYTES_PER_PIXEL`) in this machine's memory,
    naming the map size, the memory estimated and available, and the fix (a crop that fits in
    half the memory). Lazy maps too (a map is one block: rechunking cannot help); nothing is
    computed. ``what`` names the work (default "the <model> contact model")."""
    sizes = getattr(height, "sizes", {})
    if "y" not in sizes or "x" not in sizes:
        return  # the model's own checks name the missing dimensions
    ny, nx = int(sizes["y"]), int(sizes["x"])
    per_pixel = CONTACT_BYTES_PER_PIXEL[model]
    need = float(ny) * nx * per_pixel
    have = physical_memory()
    if have is None or need <= have:
        return
    side = 2 ** int(np.floor(np.log2(max(np.sqrt(have / 2 / per_pixel), 8))))
    fix = (f"crop it (e.g. height.isel(y=slice(0, {min(ny, side)}), x=slice(0, {min(nx, side)}))), "
           "coarsen it (height.coarsen(y=2, x=2).mean() needs 4 x less) or use a smaller map")
    if is_lazy(height):
        fix += "; rechunking cannot help (each map is processed whole)"
    check_fits_in_memory(need, what=f"{what or 'the ' + model.removesuffix('_double') + ' contact model'} "
                                   f"on a {ny} x {nx} map",
                         detail=f"({ny * nx:.3g} pixels, ~{per_pixel} bytes each)", fix=fix)
