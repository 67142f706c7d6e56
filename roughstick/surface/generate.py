r"""Random surfaces from a power spectral density, lazily and reproducibly (paper §4.2, Eqs. 33-35).

A stationary Gaussian random surface with 2D PSD :math:`s(q_x, q_y)` (normalised so that
:math:`\iint s\,dq_x\,dq_y = m_0`, docs/architecture.md) is synthesised on an
:math:`N_y \times N_x` periodic grid of spacing :math:`(\Delta_y, \Delta_x)` as

.. math::

    z(x_k, y_l) = \sum_{j} \sqrt{s(\mathbf q_j)\,\Delta q_x \Delta q_y}\;\xi_j\,
                  e^{i(q_{x,j} x_k + q_{y,j} y_l)},
    \qquad \Delta q = 2\pi / (N\Delta),

over the FFT wave-vector grid, with complex amplitudes :math:`\xi_j` Hermitian-symmetric
(:math:`\xi_{-j} = \bar\xi_j`, so :math:`z` is real) and :math:`E|\xi_j|^2 = 1`. This is Eq. 33
of the paper written with the project's PSD normalisation: the paper's :math:`s_Z` is
:math:`(2\pi)^2` times ours and its Eq. 33 divides by :math:`(2\pi)^2` again, and the paper's
factor :math:`\sqrt 2\,\mathrm{Re}(\dots)` over the full plane equals the Hermitian sum here.
Eq. 34 (the sum on the sampling points) is one inverse real FFT per surface. Then
:math:`E[z^2] = \sum_j s(\mathbf q_j)\Delta q_x\Delta q_y`, the PSD integrated over the target
grid, and the ensemble periodogram equals :math:`s` at every grid wave vector.

References
----------
Shinozuka, M., Deodatis, G. (1991). Simulation of stochastic processes by spectral
representation. Appl. Mech. Rev. 44, 191-204. https://doi.org/10.1115/1.3119501
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib
import numbers
import threading
import warnings
from collections.abc import Sequence

import dask
import dask.array as dsa
import numpy as np
import xarray as xr
from dask.delayed import Delayed

from .._core import units as _units
from .._core.arguments import check_numbers
from .._core.conventions import append_history, set_attrs
from .._core.dask import as_seed_sequence, is_lazy
from .._core.memory import check_fits_in_memory
from .._core.references import PAPER, cite
from .._core.validate import as_length, external_stacklevel
from ._generate_kernels import _centred_full, _filter, _generate_block
from ._marginal_kernels import cached_setup, marginal_block
from .distribution import as_height_distribution
from .spectrum import interpolate_psd, isotropic_to_2d

__all__ = ["generate_surfaces", "surface_filter", "ExtrapolatedPSDWarning"]

REFERENCES = cite("shinozuka1991", (PAPER, "Eqs. 33-35, spectral representation by inverse FFT"))
#: How a height distribution is imposed (docs/generation.md): the default first.
DISTRIBUTION_METHODS = ("translation", "iaaft")
_METHOD_REFERENCES = {"translation": cite("shields2011", "johnson1949"),
                      "iaaft": cite("schreiber1996", "perez-rafols2019")}

_AMPLITUDES = ("rayleigh", "fixed")
_DTYPES = {"float64": np.float64, "float32": np.float32}
#: default chunk size along ``realization`` in bytes of output (auto chunks)
_AUTO_CHUNK_BYTES = 64 * 2**20


# --------------------------------------------------------------------------------------------
# argument handling
# --------------------------------------------------------------------------------------------
def _as_int(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        if isinstance(value, numbers.Real) and float(value).is_integer():
            hint = f" Pass {int(value)}."
        else:
            hint = ""
        raise ValueError(f"{name} must be an integer, got {value!r}.{hint}")
    return int(value)


def _pair(value, name: str):
    """A scalar or a (y, x) pair → tuple of two."""
    if value is None:
        return None
    if isinstance(value, bytes) or (isinstance(value, str) and name == "shape"):
        raise ValueError(f"{name} must be a number or a (y, x) pair, got {value!r}.")
    if isinstance(value, str):  # a length with its unit, e.g. "5 nm"
        return value, value
    if isinstance(value, Sequence) or isinstance(value, np.ndarray):
        vals = list(np.asarray(value, dtype=object).ravel())
        if len(vals) != 2:
            raise ValueError(f"{name} must be a number or a (y, x) pair, got {value!r}.")
        return vals[0], vals[1]
    return value, value


def _length(value, name: str) -> float:
    return as_length(value, name=name)


def _grid(psd, shape, size, spacing):
    """Resolve ((ny, nx), (dy, dx)) from two of shape, size, spacing (each scalar or (y, x))."""
    shape_p, size_p, spacing_p = _pair(shape, "shape"), _pair(size, "size"), _pair(spacing, "spacing")
    if shape_p is None and size_p is None and isinstance(psd, xr.DataArray) and psd.ndim == 2:
        shape_p = psd.shape if psd.dims != ("qx", "qy") else psd.shape[::-1]
    if spacing_p is None and not (shape_p is not None and size_p is not None):
        if isinstance(psd, xr.DataArray) and "spacing_x" in psd.attrs and "spacing_y" in psd.attrs:
            spacing_p = (psd.attrs["spacing_y"], psd.attrs["spacing_x"])
        else:
            raise ValueError(
                "spacing is required (the pixel size in m, e.g. spacing=5e-9), unless shape and "
                "size are both given or the PSD carries attrs spacing_x and spacing_y."
            )
    if spacing_p is not None:
        spacing_p = tuple(_length(v, f"spacing[{a}]") for v, a in zip(spacing_p, "yx", strict=True))
    if size_p is not None:
        size_p = tuple(_length(v, f"size[{a}]") for v, a in zip(size_p, "yx", strict=True))
    if shape_p is not None:
        shape_p = tuple(_as_int(v, f"shape[{a}]") for v, a in zip(shape_p, "yx", strict=True))
    if shape_p is None:
        if size_p is None:
            raise ValueError("give shape=(ny, nx) or size=(Ly, Lx) [m] of the surfaces.")
        ratio = [L / d for L, d in zip(size_p, spacing_p, strict=True)]
        if not all(abs(r - round(r)) <= 1e-6 * max(r, 1.0) for r in ratio):
            raise ValueError(
                f"size {size_p} m is not a whole number of pixels of spacing {spacing_p} m "
                f"({ratio[0]:.6g} x {ratio[1]:.6g}); pass shape=(ny, nx) instead, or a size that "
                "is a multiple of the spacing."
            )
        shape_p = tuple(int(round(r)) for r in ratio)
    elif spacing_p is None:
        spacing_p = tuple(L / n for L, n in zip(size_p, shape_p, strict=True))
    elif size_p is not None:
        expected = tuple(n * d for n, d in zip(shape_p, spacing_p, strict=True))
        if not np.allclose(expected, size_p, rtol=1e-6, atol=0):
            raise ValueError(
                f"shape {shape_p} with spacing {spacing_p} m gives size {expected} m, not "
                f"{size_p} m: give only two of shape, size and spacing."
            )
    for v, a in zip(shape_p, "yx", strict=True):
        if v < 2:
            raise ValueError(f"shape[{a}] must be at least 2 pixels, got {v}.")
    for d, a in zip(spacing_p, "yx", strict=True):
        if d > 1e-3:  # the same plausibility bound as a height map's pixels (validate_height)
            raise ValueError(
                f"spacing[{a}] = {d:.4g} m: implausible for a MEMS surface; spacing is in metres "
                f"(was it typed in nm? then spacing={d:g}e-9)."
            )
    _check_fits_in_memory(shape_p)
    return shape_p, spacing_p


def _check_fits_in_memory(shape) -> None:
    """Refuse, before allocating, a map whose filter and one realization cannot fit in memory."""
    ny, nx = shape
    # float64 filter (ny, nx/2+1) + its complex spectrum + the real map: ~ 4 x 8 bytes per pixel
    need = 32.0 * ny * (nx // 2 + 1) + 8.0 * ny * nx
    check_fits_in_memory(need, what=f"a {ny} x {nx} surface", detail="for its spectral filter and one map",
                         fix="use a smaller shape or size (or a coarser spacing)")


def _realizations(n, realizations):
    if n is not None:
        n = _as_int(n, "n")
        if n < 1:
            raise ValueError(f"n (the number of surfaces) must be at least 1, got {n}.")
    if realizations is None:
        if n is None:
            raise ValueError("give n (number of surfaces) or realizations (their indices).")
        return np.arange(n, dtype=np.int64)
    idx = np.atleast_1d(np.asarray(realizations))
    if idx.ndim != 1 or idx.size == 0:
        raise ValueError(f"realizations must be a non-empty 1-D list of indices, got {realizations!r}.")
    if not np.issubdtype(idx.dtype, np.integer):
        raise ValueError(f"realizations must be integers, got {realizations!r}.")
    if idx.min() < 0:
        raise ValueError(f"realization indices must be >= 0, got {idx.min()}.")
    if n is not None and idx.max() >= n:
        raise ValueError(f"realization index {idx.max()} is out of range for n={n}.")
    return idx.astype(np.int64)


def _chunk_tuple(chunks, count: int, ny: int, nx: int, itemsize: int):
    if isinstance(chunks, dict):
        unknown = set(chunks) - {"realization", "y", "x"}
        if unknown:
            raise ValueError(f"chunks has unknown dimensions {sorted(unknown)}; the dims are "
                             "('realization', 'y', 'x').")
        for dim, full in (("y", ny), ("x", nx)):
            c = chunks.get(dim, -1)
            if c not in (-1, None, full) and not (isinstance(c, tuple) and c == (full,)):
                raise ValueError(
                    f"chunks={chunks!r} splits {dim!r}, but each surface is one inverse FFT and is "
                    f"generated whole. Chunk over realization only, e.g. chunks={{'realization': 8}}, "
                    f"and rechunk afterwards with .chunk({{{dim!r}: ...}}) if you must."
                )
        chunks = chunks.get("realization", "auto")
    if chunks is None or chunks == "auto":
        size = max(1, _AUTO_CHUNK_BYTES // (ny * nx * itemsize))
        chunks = size
    if chunks == -1:
        chunks = count
    if isinstance(chunks, (tuple, list)):
        parts = tuple(_as_int(c, "chunks") for c in chunks)
        if sum(parts) != count or min(parts) < 1:
            raise ValueError(f"chunks {parts} must be positive and sum to the {count} realizations.")
        return parts
    size = _as_int(chunks, "chunks")
    if size < 1:
        raise ValueError(f"chunks must be >= 1 (realizations per chunk), got {size}.")
    full, rest = divmod(count, size)
    return (size,) * full + ((rest,) if rest else ())


# --------------------------------------------------------------------------------------------
# the PSD on the target grid
# --------------------------------------------------------------------------------------------
def _psd_factor(psd: xr.DataArray) -> float:
    """Factor to m4 of the PSD's units (a 2D density, sum * dqx * dqy = height variance)."""
    return _units.factor(psd.attrs.get("units"), "length4", name="the PSD")


def _q_coord(psd: xr.DataArray, dim: str) -> np.ndarray:
    if dim not in psd.coords:
        raise ValueError(f"the PSD needs a coordinate {dim!r} in rad m-1.")
    c = psd[dim]
    if "units" in c.attrs:
        c = _units.require(c, "wavevector", name=dim)
    vals = np.asarray(c.values, dtype=float)
    if vals.size < 2 or not np.all(np.diff(vals) > 0):
        raise ValueError(f"PSD coordinate {dim!r} must be strictly ascending with >= 2 points; "
                         f"sort it with psd.sortby({dim!r}).")
    return vals


def _target_q(ny, nx, dy, dx):
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    qx = 2 * np.pi * np.fft.rfftfreq(nx, dx)
    return qy, qx


def _check_cover(target_max: float, available: float, axis: str, spacing: float):
    if target_max > available * (1 + 1e-9):
        finest = np.pi / available
        raise ValueError(
            f"the PSD covers |q{axis}| <= {available:.6g} rad m-1, but spacing_{axis}={spacing:.6g} m "
            f"needs wave numbers up to {target_max:.6g} rad m-1 (Nyquist). Use a spacing >= "
            f"{finest:.6g} m, or a PSD that extends to the Nyquist wave number of this spacing "
            "(e.g. estimated on a map with that pixel size, or an analytic PSD given as a callable)."
        )


class ExtrapolatedPSDWarning(UserWarning):
    """Generated surfaces are larger than the scan their PSD was measured on: the PSD below the
    lowest measured wave number (the longest wavelengths of the surfaces) is extrapolated."""


#: set (per thread, per task) by :func:`extrapolation_said_once`
_EXTRAPOLATION_SAID = contextvars.ContextVar("roughstick_extrapolation_said", default=False)


@contextlib.contextmanager
def extrapolation_said_once():
    """Inside, :class:`ExtrapolatedPSDWarning` is not raised: for callers that said it once
    already (an ensemble, before its graph). Unlike ``warnings.catch_warnings``, which swaps the
    process-wide filters and is not thread-safe, this is a context variable: dask's threads
    running other blocks, and the user's own filters, are untouched."""
    token = _EXTRAPOLATION_SAID.set(True)
    try:
        yield
    finally:
        _EXTRAPOLATION_SAID.reset(token)


def _warn_if_extrapolated(needed_length: float, measured_length: float, how: str) -> None:
    """Say when the surfaces outgrow the scan behind the PSD (ExtrapolatedPSDWarning), once."""
    if needed_length > measured_length * (1 + 1e-6) and not _EXTRAPOLATION_SAID.get():
        warnings.warn(
            f"the generated surfaces ({needed_length * 1e6:.3g} µm) are larger than the scan the "
            f"PSD was measured on ({measured_length * 1e6:.3g} µm, {how}): their low-q PSD (the "
            "wavelengths longer than that scan) is extrapolated. Generate surfaces no larger "
            "than the scan (size= or shape x spacing), or estimate the PSD on fewer, larger "
            "sub-maps so that it reaches lower q.",
            ExtrapolatedPSDWarning, stacklevel=external_stacklevel(),
        )


def _values_checked(s: np.ndarray, what: str) -> np.ndarray:
    if not np.all(np.isfinite(s)):
        raise ValueError(f"the {what} contains NaN or infinite values; fill or drop them first.")
    if np.any(s < 0):
        raise ValueError(f"the {what} has negative values (min {s.min():.3g}); a PSD is >= 0. "
                         "Clip them with psd.clip(min=0) if they are round-off.")
    if not np.any(s > 0):
        raise ValueError(f"the {what} is zero everywhere: the surfaces would be flat (m0 = 0). "
                         "Check its values (units m4) and its q coordinate (rad m-1).")
    return s


_ON_GRID: dict = {}  # the last few interpolated PSDs, by content (an ensemble asks once per block)
_ON_GRID_LOCK = threading.Lock()


def _psd_2d_on_grid(values, qy_c, qx_c, ny, nx, dy, dx, factor):
    """A centred 2D PSD interpolated onto the rfft half-plane of the target grid
    (``roughstick.surface.spectrum.interpolate_psd``: bilinear, periodic extension by one row/column).
    Read-only; kept for the next call with the same PSD values, coordinates and grid."""
    values = np.ascontiguousarray(values, dtype=float)
    key = (*(hashlib.sha1(np.ascontiguousarray(a, dtype=float)).hexdigest() for a in (values, qy_c, qx_c)),
           ny, nx, dy, dx, factor)
    with _ON_GRID_LOCK:
        hit = _ON_GRID.get(key)
    if hit is not None:
        return hit
    values = _values_checked(values * factor, "PSD")
    src = xr.DataArray(values, dims=("qy", "qx"), coords={"qy": qy_c, "qx": qx_c},
                       attrs={"units": "m4", "spacing_x": dx, "spacing_y": dy})
    full = np.fft.ifftshift(np.asarray(interpolate_psd(src, shape=(ny, nx)).values))
    out = np.ascontiguousarray(full[:, : nx // 2 + 1])
    out.flags.writeable = False
    with _ON_GRID_LOCK:
        _ON_GRID[key] = out
        while len(_ON_GRID) > 4:
            _ON_GRID.pop(next(iter(_ON_GRID)))
    return out


def _psd_iso_on_grid(values, q_c, qy, qx, factor):
    """An isotropic PSD at |q| of the half-plane (``roughstick.surface.spectrum.isotropic_to_2d``: linear in
    log s between samples, zero beyond the last q, the first value below the first q)."""
    values = _values_checked(np.asarray(values, dtype=float) * factor, "isotropic PSD")
    src = xr.DataArray(values, dims=("q",), coords={"q": q_c}, attrs={"units": "m4"})
    return np.asarray(isotropic_to_2d(src, qx, qy).values)


def _half_plane_power(psd, ny, nx, dy, dx):
    """(ny, nx//2+1) array P = s(q) dqx dqy on the rfft grid, or a Delayed of it (lazy PSD).

    Also returns a short description of how the PSD was mapped (for ``history``).
    """
    qy, qx = _target_q(ny, nx, dy, dx)
    dq2 = (2 * np.pi / (ny * dy)) * (2 * np.pi / (nx * dx))
    if callable(psd) and not isinstance(psd, xr.DataArray):
        q = np.hypot(qy[:, None], qx[None, :])
        s = psd(q.ravel())  # 1-D, so e.g. lambda q: rs.surface.self_affine_psd(q, ...) works as is
        s = np.asarray(s.values if isinstance(s, xr.DataArray) else s, dtype=float)
        if s.size != q.size:
            raise ValueError(
                f"the PSD callable returned {s.size} values for {q.size} wave numbers; it must "
                "map a 1-D array of |q| [rad m-1] to s(|q|) [m4] elementwise."
            )
        s = s.reshape(q.shape)
        return _values_checked(s, "PSD returned by the callable") * dq2, "isotropic callable s(|q|)"
    if not isinstance(psd, xr.DataArray):
        raise TypeError(
            "psd must be an xarray.DataArray over (qy, qx) or (q), or a callable |q| -> s(|q|) "
            f"[m4]; got {type(psd).__name__}."
        )
    if set(psd.dims) == {"qx"}:
        raise ValueError(
            "this is a profile PSD (1-D, over qx, from line scans): generating a 2-D surface needs "
            "a 2D PSD ('qy', 'qx') or an isotropic one ('q',). Recovering an isotropic PSD from "
            "profiles assumes isotropy (an inverse Abel transform) and roughstick does not do it: "
            "measure a 2-D map, or fit a self-affine PSD (roughstick.surface.self_affine_psd) to the "
            "profile's moments."
        )
    factor = _psd_factor(psd)
    dims = set(psd.dims)
    if dims == {"qy", "qx"}:
        psd = psd.transpose("qy", "qx")
        qy_c, qx_c = _q_coord(psd, "qy"), _q_coord(psd, "qx")
        _check_cover(np.abs(qy).max(), np.abs(qy_c).max(), "y", dy)
        _check_cover(np.abs(qx).max(), np.abs(qx_c).max(), "x", dx)
        # a 2D PSD on a q grid of step dq was measured on a scan 2 pi / dq long
        # one warning for the map: the axis that outgrows its scan the most
        excess = [(n_pix * d / (2 * np.pi / float(np.min(np.diff(q_c)))), n_pix * d,
                   2 * np.pi / float(np.min(np.diff(q_c))), axis)
                  for n_pix, d, q_c, axis in ((ny, dy, qy_c, "y"), (nx, dx, qx_c, "x"))]
        _, needed, measured, axis = max(excess)
        _warn_if_extrapolated(needed, measured, f"its q{axis} step")
        same = (
            qy_c.size == ny and qx_c.size == nx
            and np.allclose(qy_c, np.fft.fftshift(qy), rtol=1e-9, atol=0)
            and np.allclose(qx_c, np.fft.fftshift(2 * np.pi * np.fft.fftfreq(nx, dx)), rtol=1e-9, atol=0)
        )
        m = nx // 2 + 1

        def build(values):
            if same:
                s = np.fft.ifftshift(_values_checked(np.asarray(values, float) * factor, "PSD"))
                return s[:, :m] * dq2
            return _psd_2d_on_grid(values, qy_c, qx_c, ny, nx, dy, dx, factor) * dq2

        if not same and min(ny, nx) < 8:
            raise ValueError(f"interpolating a 2D PSD needs a target of at least 8 x 8 pixels, "
                             f"got {ny} x {nx}; use a callable or isotropic PSD for tiny grids.")
        how = "2D PSD on the same grid" if same else "2D PSD interpolated bilinearly (interpolate_psd)"
    elif dims == {"q"}:
        q_c = _q_coord(psd, "q")
        nyq = np.hypot(0, max(np.abs(qy).max(), np.abs(qx).max()))
        _check_cover(nyq, q_c.max(), "y" if np.abs(qy).max() >= np.abs(qx).max() else "x",
                     dy if np.abs(qy).max() >= np.abs(qx).max() else dx)
        # below its first q > 0 the isotropic PSD holds its first value: exact for a PSD flat
        # there (Eq. 37 below its roll-off, e.g. self_affine_psd), extrapolated for a measured one
        pos = np.flatnonzero(q_c > 0)
        flat = (not is_lazy(psd) and pos.size >= 2
                and np.isclose(float(psd.values[pos[0]]), float(psd.values[pos[1]]), rtol=1e-9, atol=0))
        if pos.size and not flat:
            _warn_if_extrapolated(max(ny * dy, nx * dx), 2 * np.pi / float(q_c[pos[0]]),
                                  "2 pi / its lowest q")

        def build(values):
            return _psd_iso_on_grid(values, q_c, qy, qx, factor) * dq2

        how = "isotropic PSD interpolated log-linearly on |q| (isotropic_to_2d)"
    else:
        raise ValueError(
            f"the PSD has dims {psd.dims}; expected ('qy', 'qx') or ('q',). Average a stack of "
            "PSDs first (e.g. psd.mean('map')) or select one."
        )
    if is_lazy(psd):
        return dask.delayed(build, pure=True)(psd.data), how
    return build(psd.values), how


def surface_filter(psd, *, shape=None, size=None, spacing=None) -> xr.DataArray:
    r"""The PSD on the target grid exactly as :func:`generate_surfaces` uses it (Eq. 33).

    The PSD mapped onto the target FFT grid (interpolated when the grids differ, even in
    :math:`q_y` on the self-conjugate columns), centred (fftshift order). Each mode carries the
    power :math:`s(\mathbf q)\Delta q_x \Delta q_y`; their sum is the expected variance of the
    generated heights.

    Parameters
    ----------
    psd, shape, size, spacing
        As in :func:`generate_surfaces`.

    Returns
    -------
    xarray.DataArray
        ``psd`` over ``(qy, qx)`` [m4] on the target grid: ``(psd * dqx * dqy).sum()`` is the
        expected height variance of the surfaces.

    Examples
    --------
    >>> s = rs.surface.surface_filter(lambda q: np.where(q < 2e8, 1e-34, 0.0), shape=8, spacing=5e-9)
    >>> s.dims, s.shape
    (('qy', 'qx'), (8, 8))
    """
    (ny, nx), (dy, dx) = _grid(psd, shape, size, spacing)
    qy, _ = _target_q(ny, nx, dy, dx)
    qx = 2 * np.pi * np.fft.fftfreq(nx, dx)
    dq2 = (2 * np.pi / (ny * dy)) * (2 * np.pi / (nx * dx))
    P, _ = _half_plane_power(psd, ny, nx, dy, dx)
    if isinstance(P, Delayed):
        data = dsa.from_delayed(dask.delayed(_centred_full)(P, nx, dq2), (ny, nx), dtype=float)
    else:
        data = _centred_full(P, nx, dq2)
    out = xr.DataArray(
        data,
        dims=("qy", "qx"),
        coords={"qy": np.fft.fftshift(qy), "qx": np.fft.fftshift(qx)},
        name="psd",
    )
    return set_attrs(out, "psd", spacing_x=dx, spacing_y=dy)


# --------------------------------------------------------------------------------------------
# public
# --------------------------------------------------------------------------------------------
def _seed_root(seed):
    if seed is None:
        # draw a recordable 63-bit root seed from OS entropy
        seed = int(np.random.SeedSequence().generate_state(2, np.uint64)[0] >> np.uint64(1))
    root = as_seed_sequence(seed)
    entropy = root.entropy
    recorded = int(entropy) if int(entropy) < 2**63 else str(entropy)
    return root, recorded


@check_numbers(seed="seed")
def generate_surfaces(
    psd,
    *,
    n: int | None = None,
    shape=None,
    size=None,
    spacing=None,
    seed=None,
    chunks="auto",
    dtype="float64",
    amplitude: str = "rayleigh",
    realizations=None,
    height_distribution=None,
    distribution_method: str = "translation",
) -> xr.DataArray:
    r"""Lazy ensemble of periodic random surfaces with a given PSD (Eqs. 33-35), Gaussian or with
    a given height distribution.

    Each surface is the spectral representation of Eq. 33 evaluated on the grid by one inverse
    real FFT (Eq. 34): complex amplitudes :math:`\sqrt{s(\mathbf q)\Delta q_x\Delta q_y}\,\xi`
    with Hermitian symmetry, so the surface is real and periodic. With the project's PSD
    normalisation (:math:`\iint s = m_0`) the expected height variance is
    :math:`\sum s\,\Delta q_x\Delta q_y` over the target grid, and :math:`m_2, m_4` are the
    corresponding :math:`q_x^2, q_x^4` moments; the paper's :math:`(2\pi)^{-2}` of Eq. 33 is
    absorbed in that normalisation. A PSD estimated on a smaller map is interpolated onto the
    finer wave-number grid of the larger surface (§4.2.1, the interpolation route after Eq. 35).

    Nothing is computed until asked: the result is a dask-backed DataArray chunked over
    ``realization`` only. Realization ``k`` draws its amplitudes from its own generator
    ``roughstick._core.dask.realization_rng(SeedSequence(seed), k)``, so the values are bit-identical
    whatever the chunking, the number of workers or the order of evaluation, and any realization
    can be regenerated alone (``realizations=[k]``).

    Parameters
    ----------
    psd : xarray.DataArray or callable
        2D PSD over ``(qy, qx)`` (ascending centred coords in rad m-1, e.g. from
        ``roughstick.surface.power_spectrum``; bilinearly interpolated by ``roughstick.surface.interpolate_psd``
        when the target grid differs), an isotropic PSD over ``(q,)`` (evaluated at
        :math:`|\mathbf q|` by ``roughstick.surface.isotropic_to_2d``: log-linear, zero beyond its
        largest ``q``, so the grid corners beyond it are zero), or a callable mapping a 1-D
        array of :math:`|\mathbf q|` [rad m-1] to :math:`s(|\mathbf q|)` [m4] (array or
        DataArray, e.g.
        ``lambda q: rs.surface.self_affine_psd(q, s0=..., s1=..., q0=..., qmax=...)``).
        DataArrays need ``units`` ``m4`` (or ``nm4``, ``um4``). A dask-backed PSD stays lazy.
    n : int, optional
        Number of surfaces (realizations ``0 .. n-1``), >= 1.
    shape : int or (int, int), optional
        Pixels ``(ny, nx)``; any sizes >= 2 (powers of two are not required). Default for a 2D
        PSD DataArray without ``size``: the PSD grid shape.
    size : float, str or (float, float), optional
        Physical size ``(Ly, Lx)`` [m], or with its unit (``"1.28 um"``); with ``spacing`` it
        must be a whole number of pixels.
    spacing : float, str or (float, float), optional
        Pixel size ``(dy, dx)`` [m], or with its unit (``"5 nm"``). Two of ``shape``, ``size``, ``spacing`` are needed; if
        ``spacing`` is missing it is taken from the PSD's ``spacing_y``/``spacing_x`` attrs.
    seed : int, numpy.random.SeedSequence, numpy.random.Generator or None
        Root seed; recorded in ``attrs['seed']``. ``None`` draws a fresh root seed (recorded).
    chunks : int, tuple, dict or "auto"
        Realizations per chunk (``"auto"``: about 64 MiB per chunk). A dict may only chunk
        ``realization``: splitting ``y`` or ``x`` raises, since each surface is one FFT.
    dtype : {"float64", "float32"}
        Output precision. The random amplitudes are drawn identically in both, so a float32
        surface is the float64 one to single-precision FFT round-off (docs/generation.md).
    amplitude : {"rayleigh", "fixed"}
        ``"rayleigh"``: the :math:`\zeta` of Eq. 33, Rayleigh modulus with uniform phase, i.e. a
        complex Gaussian amplitude: the surfaces are exactly Gaussian. ``"fixed"``: modulus
        :math:`\sqrt{s\Delta q^2}` exactly with uniform random phase (Shinozuka's form): every
        surface has exactly the target periodogram and variance; heights are Gaussian only
        asymptotically.
    realizations : sequence of int, optional
        Generate only these realization indices (coordinate ``realization`` holds them), e.g.
        ``[k]`` to regenerate surface ``k`` of an ensemble.
    height_distribution : xarray.Dataset, optional
        The height distribution of the surfaces (:func:`roughstick.surface.height_distribution`:
        the empirical one of measured maps, or a Johnson one from skewness and kurtosis); None
        (default): Gaussian surfaces, exactly as without it. The PSD sets the rms height, the
        distribution the shape (a UserWarning says when the distribution's own rms height is
        more than 10 % off the PSD's).
    distribution_method : {"translation", "iaaft"}
        How the distribution is imposed (docs/generation.md): ``"translation"`` (default),
        :math:`z = \sigma T(g)` of a Gaussian surface :math:`g` whose spectrum is pre-corrected so
        that :math:`z` has the PSD (the distribution exact in law; one Gaussian surface and a table
        look-up each); ``"iaaft"``, alternating Fourier-amplitude and rank remaps of the Gaussian
        surface (every surface has exactly the distribution's quantiles, so the same tallest
        point; an order of magnitude dearer, and it whitens a PSD with a cutoff). Either way
        realization ``k`` starts from the Gaussian surface ``k``, so the results are as
        reproducible and chunk-independent as the Gaussian ones.

    Returns
    -------
    xarray.DataArray
        ``height`` [m] over ``(realization, y, x)``, pixel-centre coords ``x``, ``y`` [m], attrs
        ``periodic=1``, ``seed``, ``amplitude``, ``history``; with a height distribution also
        ``height_distribution`` (its family) and ``distribution_method``.

    Raises
    ------
    ValueError
        The PSD grid does not reach the Nyquist wave number :math:`\pi/\Delta` of ``spacing``
        along an axis (no silent zero-fill: choose a coarser spacing or a PSD that covers it);
        ``n < 1``; non-integer ``shape``; size not a multiple of spacing; a PSD grid that does
        not reach the Nyquist wave number of ``spacing``; negative or NaN PSD values; chunks that
        split ``x`` or ``y``; unknown ``dtype`` or ``amplitude``.

    Examples
    --------
    >>> s = lambda q: np.where(q < 3e8, 1e-34, 0.0)
    >>> h = rs.surface.generate_surfaces(s, n=4, shape=(16, 24), spacing=5e-9, seed=1, chunks=2)
    >>> h.dims, h.shape, h.chunks[0], h.attrs["periodic"], h.attrs["seed"]
    (('realization', 'y', 'x'), (4, 16, 24), (2, 2), 1, 1)
    >>> bool((h.isel(realization=[3]) == rs.surface.generate_surfaces(
    ...     s, realizations=[3], shape=(16, 24), spacing=5e-9, seed=1)).all())
    True
    >>> skewed = rs.surface.height_distribution(skewness=1.0, kurtosis=5.0)
    >>> z = rs.surface.generate_surfaces(s, n=4, shape=64, spacing=5e-9, seed=1,
    ...                                  height_distribution=skewed).values
    >>> z.shape, bool(abs(z.max()) > abs(z.min()))
    ((4, 64, 64), True)
    """
    if amplitude not in _AMPLITUDES:
        raise ValueError(f"amplitude must be one of {_AMPLITUDES}, got {amplitude!r}.")
    key = np.dtype(dtype).name if not isinstance(dtype, str) else dtype
    if key not in _DTYPES:
        raise ValueError(f"dtype must be 'float64' or 'float32', got {dtype!r}.")
    out_dtype = _DTYPES[key]
    indices = _realizations(n, realizations)
    (ny, nx), (dy, dx) = _grid(psd, shape, size, spacing)
    chunk_sizes = _chunk_tuple(chunks, indices.size, ny, nx, np.dtype(out_dtype).itemsize)
    root, recorded_seed = _seed_root(seed)

    dist = _distribution(height_distribution, distribution_method)
    P, how = _half_plane_power(psd, ny, nx, dy, dx)
    if dist is not None:
        block, setup, kind = _marginal_setup(P, nx, ny, dist, distribution_method, amplitude)
        extra_kw = {"setup": setup, "method": distribution_method}
        words = "non-Gaussian"
    else:
        block, kind, words = _generate_block, "Eqs. 33-34", "Gaussian"
        if isinstance(P, Delayed):  # lazy PSD: the filter is a task of the graph
            filt = dask.delayed(_filter, pure=True)(P, nx, amplitude)
        else:  # computed once here, held by one graph node shared by all chunks
            filt = dask.delayed(_filter(P, nx, amplitude), pure=True)
        extra_kw = {"filt": filt}

    token = dask.base.tokenize(
        *extra_kw.values(), root.entropy, tuple(root.spawn_key), ny, nx, amplitude, key, indices,
        chunk_sizes
    )
    idx = dsa.from_array(indices, chunks=(chunk_sizes,), name=f"realization-index-{token}")
    data = idx.map_blocks(
        block,
        **extra_kw,
        entropy=root.entropy,
        spawn_key=tuple(root.spawn_key),
        ny=ny,
        nx=nx,
        amplitude=amplitude,
        out_dtype=out_dtype,
        new_axis=[1, 2],
        chunks=(chunk_sizes, (ny,), (nx,)),
        dtype=out_dtype,
        meta=np.empty((0, 0, 0), dtype=out_dtype),
        name=f"generate-surfaces-{token}",
    )
    da = xr.DataArray(
        data,
        dims=("realization", "y", "x"),
        coords={
            "realization": indices,
            "y": (np.arange(ny) + 0.5) * dy,
            "x": (np.arange(nx) + 0.5) * dx,
        },
        name="height",
    )
    extra = {"periodic": 1, "seed": recorded_seed, "amplitude": amplitude, "references": REFERENCES}
    if root.spawn_key:
        extra["seed_spawn_key"] = list(root.spawn_key)
    if dist is not None:
        extra.update(height_distribution=dist.attrs["family"], distribution_method=distribution_method,
                     references=cite("shinozuka1991", (PAPER, "Eqs. 33-35"))
                     + "; " + _METHOD_REFERENCES[distribution_method])
    da = set_attrs(da, "height", **extra)
    append_history(
        da,
        f"generate_surfaces: {indices.size} periodic {words} surfaces {ny}x{nx} at "
        f"{dy:.6g}x{dx:.6g} m from {how} ({kind}, amplitude={amplitude}, dtype={key}, "
        f"seed={recorded_seed})",
    )
    return da


def _distribution(height_distribution, method):
    """The checked height distribution, or None for Gaussian surfaces (also for a normal one)."""
    if method not in DISTRIBUTION_METHODS:
        raise ValueError(f"distribution_method must be one of {DISTRIBUTION_METHODS}, got {method!r}.")
    if height_distribution is None:
        return None
    dist = as_height_distribution(height_distribution)
    return None if dist.attrs.get("family") == "normal" else dist


def _marginal_setup(P, nx, ny, dist, method, amplitude):
    """The block kernel, its (delayed) setup and a description of the height distribution and
    of how it is imposed; says when the distribution's rms height is not the PSD's."""
    table = np.asarray(dist["height"].values, dtype=float)
    moments = f"skewness {dist.attrs['skewness']:.3g}, kurtosis {dist.attrs['kurtosis']:.3g}"
    if isinstance(P, Delayed):
        setup = dask.delayed(cached_setup, pure=True)(method, P, nx, ny, table, amplitude)
        return marginal_block, setup, f"{dist.attrs['family']} heights ({moments}) by {method}"
    rms = float(dist.attrs.get("rms_height", np.nan))
    psd_rms = float(np.sqrt(_centred_full(P, nx, 1.0).sum()))
    if np.isfinite(rms) and abs(rms / psd_rms - 1) > 0.1:
        warnings.warn(
            f"the height distribution's rms height ({rms * 1e9:.3g} nm) differs from the PSD's on "
            f"this grid ({psd_rms * 1e9:.3g} nm) by {100 * (rms / psd_rms - 1):+.0f} %: the surfaces "
            "take the PSD's rms height and the distribution's shape (skewness, kurtosis, tails).",
            UserWarning, stacklevel=external_stacklevel())
    setup = cached_setup(method, P, nx, ny, table, amplitude)
    return (marginal_block, dask.delayed(setup, pure=True),
            f"{dist.attrs['family']} heights ({moments}) imposed by {setup[-1]}")
