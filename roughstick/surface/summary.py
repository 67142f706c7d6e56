r"""The paper's §4.1 chains on a set of maps: roughness statistics (Table 2) and PSD summary
(Tables 2-3, Fig. 12, Eq. 32), built from the spectrum and moment estimators of this subpackage."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs
from .._core.dask import is_lazy
from .._core.references import PAPER, cite
from .gaussianity import height_diagnostics
from .moments import (
    NAYAK_REFERENCE,
    asperity_statistics,
    choose_cutoff,
    psd_moments,
    roughness_moments,
)
from .spectrum import psd_isotropic, submap_psd, submap_variance_check
from .topography import validate_height

__all__ = ["roughness_statistics", "psd_summary"]


@check_numbers(seed="seed")
def roughness_statistics(
    height: xr.DataArray,
    *,
    method: str = "spline",
    direction: str = "mean",
    qmax=None,
    diagnostics: bool = True,
    seed=0,
) -> xr.Dataset:
    """Table 2/3-style statistics of height maps: moments, rms values and summit statistics,
    and whether their heights are Gaussian.

    Parameters
    ----------
    height : xarray.DataArray
        Levelled topography, dims ``(..., y, x)``, units length.
    method, direction, qmax
        As in :func:`roughness_moments`.
    diagnostics : bool, default True
        Add the height-distribution diagnostics of each map (:func:`height_diagnostics`: its
        skewness, kurtosis and 99th/99.9th height percentiles against the sampling intervals of
        Gaussian surfaces with its PSD, and the verdict ``gaussian``). They cost 50 Gaussian
        surfaces of the map's size per map (about 0.5 s for 512 x 512 pixels) and need the heights
        in memory: a dask-backed input gets none.
    seed : int, default 0
        Root seed of the diagnostics' surrogates.

    Returns
    -------
    xarray.Dataset
        ``m0``, ``m2``, ``m4``, ``rms_height`` [m], ``rms_slope`` [1], ``skewness``,
        ``kurtosis`` [1], the fields of :func:`asperity_statistics` and, with ``diagnostics``,
        those of :func:`height_diagnostics` (``skewness_gaussian_lower`` ...,
        ``tail_quantile``, ``gaussian``).

    Examples
    --------
    >>> h = rs.surface.generate_surfaces(rs.datasets.family_psd("S1"), n=1, shape=64,
    ...                                  spacing=5e-9, seed=3).isel(realization=0).compute()
    >>> st = rs.surface.roughness_statistics(h)
    >>> round(float(st.rms_height) * 1e9, 2), bool(st.gaussian)
    (3.79, True)
    """
    m = roughness_moments(height, method=method, direction=direction, qmax=qmax)
    ds = asperity_statistics(m)
    h = validate_height(height)
    zc = h - h.mean(("y", "x"))
    sd = np.sqrt((zc**2).mean(("y", "x")))
    ds["rms_height"] = np.sqrt(ds.m0).assign_attrs(units="m", long_name="rms height sqrt(m0)")
    ds["rms_slope"] = np.sqrt(ds.m2).assign_attrs(units="1", long_name="rms slope sqrt(m2)")
    ds["skewness"] = ((zc**3).mean(("y", "x")) / sd**3).assign_attrs(
        units="1", long_name="height skewness")
    ds["kurtosis"] = ((zc**4).mean(("y", "x")) / sd**4).assign_attrs(
        units="1", long_name="height kurtosis")
    ds.attrs = dataset_attrs(f"roughness statistics ({method})", references=NAYAK_REFERENCE,
                             direction=direction)
    if diagnostics and not is_lazy(h):
        diag = height_diagnostics(h, seed=seed)
        # the map's own skewness and kurtosis stay as computed above (equal for a levelled map)
        ds = ds.assign({k: v for k, v in diag.data_vars.items() if k not in ("skewness", "kurtosis")})
        ds.attrs.update(diagnostics=diag.attrs["interval_method"], verdict=diag.attrs["verdict"],
                        diagnostics_confidence=diag.attrs["confidence"])
    elif diagnostics:
        ds.attrs["diagnostics"] = ("not computed: the heights are dask-backed (call "
                                   "roughstick.surface.height_diagnostics on them in memory)")
    append_history(ds, f"roughness_statistics: method={method!r}, direction={direction!r}")
    return ds


@check_numbers(n="count")
def psd_summary(
    height: xr.DataArray,
    *,
    n: int = 16,
    qmax=None,
    window: str | None = "auto",
    match=("m2", "m4"),
) -> xr.Dataset:
    r"""The paper's §4.1 chain on a set of maps: spatial variances, averaged PSD, cutoff, Eq. 32.

    Parameters
    ----------
    height : xarray.DataArray
        Levelled maps ``(..., y, x)`` of one sample (leading dims are the measurements).
    n : int
        Sub-maps per map for the PSD (Eq. 31; 16 is the paper's scheme 3).
    qmax : float, optional
        Fixed cutoff [rad m-1] (Table 3: 289 rad/µm); default: chosen by :func:`choose_cutoff`.
    window : str or None, default "auto"
        Window for :func:`submap_psd` (``"auto"``: Hann for sub-maps and non-periodic maps;
        ``None``: none, as the paper's Table 3).
    match : sequence of str
        Moments matched by :func:`choose_cutoff`.

    Returns
    -------
    xarray.Dataset
        ``psd`` (qy, qx) and ``psd_isotropic`` (q) [m4]; ``spatial_m0/m2/m4`` (mean over maps of
        the cubic-spline variances, as Table 2); ``m0/m2/m4`` PSD moments at ``qmax``;
        ``residual_*`` (PSD / spatial − 1); ``relative_std`` (Eq. 32) and ``n_maps``.
    """
    h = validate_height(height)
    lead = list(h.dims[:-2])
    spatial = roughness_moments(h)
    spatial = spatial.mean(lead, keep_attrs=True) if lead else spatial
    s = submap_psd(h, n=n, window=window)
    if qmax is None:
        cut = choose_cutoff(s, spatial, match=match)
    else:
        cut = psd_moments(s, qmax=qmax)
        for k in ("m0", "m2", "m4"):
            cut[f"residual_{k}"] = (cut[k] / spatial[k] - 1).assign_attrs(
                units="1", long_name=f"relative error of PSD {k} vs spatial")
    chk = submap_variance_check(h, n=n)
    ds = xr.Dataset({"psd": s, "psd_isotropic": psd_isotropic(s).rename({"n_samples": "n_ring"})})
    ds["n_ring"].attrs = {"units": "1", "long_name": "number of 2D PSD samples in the ring"}
    for k in ("m0", "m2", "m4"):
        ds[f"spatial_{k}"] = spatial[k].assign_attrs(
            long_name=f"spatial {spatial[k].attrs['long_name']} (cubic splines, mean over maps)")
        ds[k] = cut[k].assign_attrs(long_name=f"PSD moment {k} up to qmax")
        ds[f"residual_{k}"] = cut[f"residual_{k}"]
    ds["qmax"] = xr.DataArray(cut["qmax"]).assign_attrs(units="rad m-1", long_name="cutoff wave number")
    ds["relative_std"] = chk["relative_std"]
    ds.attrs = dataset_attrs(
        "PSD and roughness statistics of AFM maps (paper §4.1, Tables 2-3, Fig. 12)",
        references=cite((PAPER, "section 4.1, Eqs. 26-32"), "nayak1971"),
        n_submaps=n, n_maps=int(np.prod([h.sizes[d] for d in lead])) if lead else 1,
        window=str(window),
    )
    append_history(ds, f"psd_summary: n={n}, qmax={'chosen' if qmax is None else qmax}")
    return ds
