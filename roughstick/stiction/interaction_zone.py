r"""The interaction zone of a cantilever (paper §5.2, Table 4, Eq. 37, Figs. 19-20).

The zone behind the crack front, :math:`\Delta s \times w`, is an equivalent rough surface of
roughness :math:`\sqrt{m_{01} + m_{02}}` with Table 4's summit radius and density; its moments
(:func:`cantilever_moments`, Nayak) fix the self-affine PSD of Eq. 37 (:func:`cantilever_psd`),
from which :func:`predict_adhesive_energy` draws surfaces of the zone and computes their
adhesive energies with the ensemble machinery (:func:`roughstick.ensemble.run`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs, set_attrs
from ..datasets import TABLE4_VALUES
from ..ensemble.pipeline import distance_grid
from ..ensemble.runner import run as run_ensemble
from ..surface.moments import moments_from_asperities
from ..surface.self_affine import fit_self_affine, self_affine_psd
from .cantilever import PAPER_CANTILEVER, REFERENCES, Cantilever

__all__ = [
    "TABLE4",
    "PAPER_HUMIDITIES",
    "cantilever_moments",
    "cantilever_psd",
    "interaction_zone_shape",
    "interaction_zone_psd",
    "cantilever_distance_grid",
    "predict_adhesive_energy",
]


#: Table 4 of the paper: roughness of the two surfaces [m], mean asperity radius of the
#: equivalent surface [m], asperity density [m-2]; and the Eq. 37 cutoff of §4.1 [rad m-1].
TABLE4 = {k: TABLE4_VALUES[k] for k in ("roughness", "asperity_radius", "asperity_density", "qmax")}

_PRINTED_NOTE = (
    "The paper prints q0 = 19.4 rad/um, s0 = 6.46e3 nm^4, s1 = 6.29e-3 nm^4 for Eq. 37; solving "
    "Eq. 37 with Table 4 (N = 80.1 um^-2) gives q0 ~ 21.2 rad/um, s0 ~ 5.5e3 nm^4, "
    "s1 ~ 5.5e-3 nm^4. The printed values follow from N = 88.1 um^-2 (likely a typo in Table 4)."
)


@check_numbers(asperity_radius="length", asperity_density="positive")
def cantilever_moments(
    *,
    roughness=TABLE4["roughness"],
    asperity_radius: float = TABLE4["asperity_radius"],
    asperity_density: float = TABLE4["asperity_density"],
) -> xr.Dataset:
    r"""PSD moments of the equivalent surface of the cantilever tests (Table 4).

    Two rough surfaces in contact are replaced by their sum against a flat (paper §5.2), so the
    variances add: :math:`\mu_0 = m_{01} + m_{02}` (3.54 nm from 2.6 and 2.4 nm). With Nayak's
    relations, :math:`\mu_4 = (3\sqrt\pi/(8R))^2` and :math:`\mu_2 = \mu_4/(6\sqrt3\pi N)`.
    Thin wrapper over :func:`roughstick.surface.moments_from_asperities` with the Table 4 defaults.

    Parameters
    ----------
    roughness : sequence of float
        RMS roughness of each surface [m] (Table 4: 2.6 and 2.4 nm).
    asperity_radius : float
        Mean asperity radius of the equivalent surface [m] (220 nm: 440 nm per surface).
    asperity_density : float
        Asperity density of the equivalent surface [m-2] (80.1 µm⁻²).

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2].

    Examples
    --------
    >>> m = rs.stiction.cantilever_moments()
    >>> round(float(m.m0) ** 0.5 * 1e9, 2), round(float(m.m2), 4), round(float(m.m4) / 1e12, 2)
    (3.54, 0.0035, 9.13)
    """
    return moments_from_asperities(roughness=roughness, radius=asperity_radius, density=asperity_density)


@check_numbers(asperity_radius="length", asperity_density="positive", qmax="positive")
def cantilever_psd(
    *,
    roughness=TABLE4["roughness"],
    asperity_radius: float = TABLE4["asperity_radius"],
    asperity_density: float = TABLE4["asperity_density"],
    qmax: float = TABLE4["qmax"],
) -> xr.Dataset:
    r"""The self-affine PSD (Eq. 37) of the cantilever's equivalent surface, from Table 4.

    Parameters
    ----------
    roughness, asperity_radius, asperity_density
        See :func:`cantilever_moments`.
    qmax : float
        Cutoff wave number of Eq. 37 [rad m-1]; the paper takes 289 rad/µm from its samples.

    Returns
    -------
    xarray.Dataset
        The Eq. 37 parameters ``q0``, ``s0``, ``s1``, ``qmax``, ``exponent`` and the fit residuals
        (:func:`roughstick.surface.fit_self_affine`), plus the target moments ``m0``, ``m2``, ``m4``.
        Evaluate the PSD with ``rs.surface.self_affine_psd(q, s0=ds.s0, s1=ds.s1, q0=ds.q0, qmax=ds.qmax)``.

    Notes
    -----
    With Table 4 (N = 80.1 µm⁻²) the solution is :math:`\xi_0 \approx 21.2` rad/µm,
    :math:`s_0 \approx 5.5\times10^3` nm⁴, :math:`s_1 \approx 5.5\times10^{-3}` nm⁴. The paper
    prints 19.4 rad/µm, 6.46e3 nm⁴ and 6.29e-3 nm⁴, which come out with N = 88.1 µm⁻²
    (``asperity_density=88.1e12``); the attribute ``note`` records this.

    Examples
    --------
    >>> p = rs.stiction.cantilever_psd()
    >>> round(float(p.q0) / 1e6, 1), round(float(p.s0) * 1e36, -2), round(float(p.s1) * 1e39, 1)
    (21.2, 5500.0, 5.5)
    """
    m = cantilever_moments(roughness=roughness, asperity_radius=asperity_radius,
                           asperity_density=asperity_density)
    fit = fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=qmax)
    ds = xr.merge([fit, m[["m0", "m2", "m4"]]], combine_attrs="override")
    ds.attrs.update(
        dataset_attrs(
            "Eq. 37 PSD of the cantilever's equivalent surface (Table 4)",
            references=REFERENCES,
            roughness=list(np.atleast_1d(np.asarray(roughness, dtype=float))),
            asperity_radius=float(asperity_radius),
            asperity_density=float(asperity_density),
            note=_PRINTED_NOTE,
        )
    )
    append_history(ds, "roughstick.stiction.cantilever_psd: Table 4 -> Nayak moments -> Eq. 37")
    return ds

#: Humidities of the cantilever tests (paper §5.1): 30 to 95 % in 5 % steps.
PAPER_HUMIDITIES = tuple(round(0.30 + 0.05 * i, 2) for i in range(14))


@check_numbers(spacing="length")
def interaction_zone_shape(beam: Cantilever = PAPER_CANTILEVER, *, spacing: float = 5e-9) -> tuple[int, int]:
    r"""Pixels ``(ny, nx)`` of the interaction zone :math:`\Delta s \times w` at ``spacing``.

    ``y`` runs along the beam (:math:`\Delta s`), ``x`` across it (:math:`w`).

    Examples
    --------
    >>> rs.stiction.interaction_zone_shape()  # 2.62 µm x 30 µm at 5 nm (paper §5.2)
    (524, 6000)
    """
    spacing = float(spacing)
    if not spacing > 0:
        raise ValueError(f"spacing must be a positive length in m (e.g. 5e-9), got {spacing!r}.")
    ny = int(round(beam.interaction_zone_length / spacing))
    nx = int(round(beam.width / spacing))
    if min(ny, nx) < 8:
        raise ValueError(
            f"the interaction zone {beam.interaction_zone_length:.3g} m x {beam.width:.3g} m has only "
            f"{ny} x {nx} pixels of {spacing:.3g} m; use a finer spacing."
        )
    return ny, nx


@check_numbers(spacing="length")
def interaction_zone_psd(fit: xr.Dataset | None = None, *, beam: Cantilever = PAPER_CANTILEVER,
                         spacing: float = 5e-9, shape=None) -> xr.DataArray:
    r"""The Eq. 37 PSD evaluated exactly on the wave-vector grid of the interaction zone.

    Parameters
    ----------
    fit : xarray.Dataset, optional
        Eq. 37 parameters (``q0``, ``s0``, ``s1``, ``qmax``); default :func:`cantilever_psd`.
    beam : Cantilever
        Sets the zone when ``shape`` is None (:func:`interaction_zone_shape`).
    spacing : float
        Pixel size [m].
    shape : (int, int), optional
        Pixels ``(ny, nx)``.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(qy, qx)``, centred ascending coords (fftshift order) of the
        ``shape`` grid, so :func:`roughstick.generate_surfaces` uses it without interpolation.

    Examples
    --------
    >>> p = rs.stiction.interaction_zone_psd(shape=(64, 512))
    >>> p.sizes["qy"], p.sizes["qx"], p.attrs["units"]
    (64, 512, 'm4')
    """
    if fit is None:
        fit = cantilever_psd()
    shape = interaction_zone_shape(beam, spacing=spacing) if shape is None else shape
    return _psd_on_grid(fit, tuple(int(v) for v in np.broadcast_to(shape, 2)), spacing)


def _psd_on_grid(fit: xr.Dataset, shape, spacing) -> xr.DataArray:
    """The Eq. 37 PSD of ``fit`` evaluated exactly on the FFT grid of ``shape`` (no interpolation)."""
    missing = [k for k in ("q0", "s0", "s1", "qmax") if k not in fit]
    if missing:
        raise ValueError(f"the PSD Dataset lacks the Eq. 37 parameters {missing}; pass rs.stiction.cantilever_psd(...).")
    ny, nx = shape
    qy = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(ny, spacing))
    qx = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(nx, spacing))
    qmag = xr.DataArray(np.hypot(qy[:, None], qx[None, :]), dims=("qy", "qx"),
                        coords={"qy": qy, "qx": qx}, attrs={"units": "rad m-1"})
    out = self_affine_psd(qmag, s0=float(fit.s0), s1=float(fit.s1), q0=float(fit.q0), qmax=float(fit.qmax))
    out = set_attrs(out.rename("psd"), "psd", spacing_x=float(spacing), spacing_y=float(spacing))
    return out.drop_vars([c for c in out.coords if c not in ("qx", "qy")])


@renamed_keywords(num="n_distance")
@check_numbers(lower="finite", n_distance="count")
def cantilever_distance_grid(psd, *, shape, n, relative_humidity, adsorbed_layer="paper",
                             lower: float = 1.0, n_distance: int = 200,
                             height_distribution=None) -> xr.DataArray:
    r"""Distance grid for the interaction-zone ensembles, shared by both adsorbed-layer models.

    :func:`roughstick.ensemble.distance_grid` with its top set by the larger of the water heights
    of ``adsorbed_layer`` and of the paper's layer, so the runs with and without the layer use the
    same grid (identical Γ below 65 % RH, same surfaces), and its bottom at ``lower``
    :math:`\sqrt{m_0}`; with a ``height_distribution`` (of non-Gaussian surfaces) its top reaches
    that distribution's tallest summits.

    Notes
    -----
    Eq. 13 integrates every attractive part of the curve. On the Table 4 surface the modified
    DMT repulsion peaks near :math:`0.8\sqrt{m_0}` and falls again deeper down (asperities merge
    into a few huge, flat fitted spheres), so a grid reaching far below the equilibrium picks up a
    spurious second attractive region. ``lower = 1`` keeps the bottom in the repulsive range for
    the paper's cantilever zone. Where a zone's curve has no stable zero crossing on this grid,
    :func:`roughstick.ensemble.run` extends that realization's grid down to its lowest pixel
    (and up past its highest point plus the water height), flags it in ``grid_extension``, and
    reports a curve attractive again deep in contact in ``attractive_at_floor`` (Γ and the
    equilibrium come from the outermost stable crossing, the separation path).

    Examples
    --------
    >>> psd = rs.stiction.interaction_zone_psd(shape=(64, 512))
    >>> d = rs.stiction.cantilever_distance_grid(psd, shape=(64, 512), n=4, relative_humidity=[0.5, 0.9])
    >>> d.size, round(float(d[-1]) * 1e9, 1)  # points, top of the grid in nm
    (200, 36.4)
    """
    grids = [distance_grid(psd, shape=shape, n=n, relative_humidity=relative_humidity,
                           adsorbed_layer=layer, lower=lower, n_distance=n_distance,
                           height_distribution=height_distribution)
             for layer in (adsorbed_layer, "paper")]
    return grids[int(np.argmax([float(g[-1]) for g in grids]))]


@check_numbers(n="count", spacing="length", seed="seed")
def predict_adhesive_energy(
    psd=None,
    *,
    beam: Cantilever = PAPER_CANTILEVER,
    relative_humidity=PAPER_HUMIDITIES,
    n: int = 20,
    spacing: float = 5e-9,
    shape=None,
    adsorbed_layer="paper",
    seed=0,
    chunks=None,
    output=None,
    **ensemble_kwargs,
) -> xr.Dataset:
    r"""Monte-Carlo prediction of Γ for the cantilever's interaction zone (paper §5.2, Fig. 20).

    Generates ``n`` equivalent surfaces of the interaction zone :math:`\Delta s \times w` from
    the PSD, computes their rough-surface modified-DMT curves at each humidity and reduces them
    to the apparent adhesive energy (Eq. 13), through :func:`roughstick.ensemble.run`.

    Parameters
    ----------
    psd : xarray.Dataset, xarray.DataArray or None
        ``None``: the Table 4 -> Eq. 37 PSD (:func:`cantilever_psd`); a Dataset of Eq. 37
        parameters (``q0``, ``s0``, ``s1``, ``qmax``, e.g. ``cantilever_psd(asperity_density=...)``),
        evaluated exactly on the surface's wave-vector grid; or any PSD DataArray accepted by
        :func:`roughstick.ensemble.run` (e.g. measured from AFM maps of the real films).
    beam : Cantilever
        Sets the interaction zone (``interaction_length`` x ``width``).
    relative_humidity : sequence of float
        Fractions in (0, 1); default 30 to 95 % in 5 % steps.
    n : int or "auto"
        Number of surfaces (see :func:`roughstick.ensemble.run`).
    spacing : float
        Pixel size [m] (5 nm in the paper).
    shape : (int, int), optional
        Pixels ``(ny, nx)``; default :func:`interaction_zone_shape` (524 x 6000 for the paper's
        beams at 5 nm). A smaller shape is a different interaction area (fewer, lower high
        asperities: Γ is biased up at low RH, paper §4.3 and Fig. 16a): use it only for quick looks.
    adsorbed_layer : {"paper", "none"} or callable
        ``"paper"``: 0.9 nm per surface above 65 % RH (Fig. 20b); ``"none"``: Fig. 20a.
    seed, chunks, output, **ensemble_kwargs
        Passed to :func:`roughstick.ensemble.run` (``output`` streams and resumes;
        ``height_distribution=`` a distribution Dataset for non-Gaussian surfaces). The default
        ``distance`` grid is :func:`cantilever_distance_grid` (with that distribution).
        One contact model runs on every surface (``model``, default ``"auto"``: never a
        multi-fidelity plan, whose ``adhesive_energy`` would be the cheap model's), because the
        sample is counted surface by surface.

    Returns
    -------
    xarray.Dataset
        The ensemble (lazy unless streamed); ``adhesive_energy`` over ``(realization, rh)`` is
        what :func:`roughstick.reliability.stuck_probability` and :func:`.risk_summary` take.
        Attrs record the beam and the interaction zone.

    Examples
    --------
    >>> ds = rs.stiction.predict_adhesive_energy(n=2, shape=(32, 128), relative_humidity=[0.5, 0.9],
    ...                                          seed=1)
    >>> ds.adhesive_energy.dims
    ('realization', 'rh')
    """
    shp = interaction_zone_shape(beam, spacing=spacing) if shape is None else tuple(int(v) for v in np.broadcast_to(shape, 2))
    if psd is None:
        psd = cantilever_psd()
    if isinstance(psd, xr.Dataset):
        missing = [k for k in ("q0", "s0", "s1", "qmax") if k not in psd]
        if missing:
            raise ValueError(f"psd Dataset lacks the Eq. 37 parameters {missing}; pass rs.stiction.cantilever_psd(...).")
        grid_psd = _psd_on_grid(psd, shp, spacing)
    elif isinstance(psd, xr.DataArray):
        grid_psd = psd
    else:
        raise TypeError(f"psd must be None, an Eq. 37 Dataset or a PSD DataArray, got {type(psd).__name__}.")
    if ensemble_kwargs.get("accurate_model") not in (None, False):
        raise ValueError(
            "predict_adhesive_energy returns a sample of Γ counted surface by surface, so one model "
            f"runs on every surface: drop accurate_model={ensemble_kwargs['accurate_model']!r} "
            "(model= picks the model), or build a multi-fidelity band with "
            "rs.ensemble.run(..., accurate_model=...) and rs.ensemble.confidence_band.")
    ensemble_kwargs["accurate_model"] = False
    rh = list(relative_humidity)
    if ensemble_kwargs.get("distance") is None:
        heights = ensemble_kwargs.get("height_distribution")  # non-Gaussian: taller summits
        ensemble_kwargs["distance"] = cantilever_distance_grid(
            grid_psd, shape=shp, n=ensemble_kwargs.get("n_max", 3000) if n == "auto" else n,
            relative_humidity=rh, adsorbed_layer=adsorbed_layer,
            height_distribution=heights if isinstance(heights, xr.Dataset) else None)
    ds = run_ensemble(grid_psd, n=n, relative_humidity=rh, spacing=spacing, shape=shp,
                      seed=seed, chunks=chunks, adsorbed_layer=adsorbed_layer, output=output, **ensemble_kwargs)
    ds.attrs.update({**beam.attrs(), "interaction_zone_shape": list(shp),
                     "interaction_zone_area": float(shp[0] * shp[1] * spacing**2)})
    if isinstance(adsorbed_layer, str):
        ds.attrs["adsorbed_layer_model"] = adsorbed_layer
    append_history(ds, f"roughstick.stiction.predict_adhesive_energy: interaction zone {shp[0]} x {shp[1]} px at {spacing:.3g} m")
    return ds
