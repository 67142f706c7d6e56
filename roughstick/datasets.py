r"""Data shipped inside the package: sample maps, their PSDs, the paper's tables, surface families.

Like ``xarray.tutorial`` and ``skimage.data``, everything here is installed with roughstick (the
files live in ``roughstick/data/``; ``data_samples/`` at the top of the repository links to them), so
a wheel install runs the demo on the same data as a checkout.

- :func:`load_sample`, :func:`sample_maps`: the six synthetic stand-ins of the paper's AFM
  measurements S1A-S1C and S2A-S2C (1024², 5 nm; ``data_samples/README.md`` says how they were
  made); :func:`sample_psd`: their PSD by the paper's scheme 3, cut at 289 rad/µm;
- :func:`paper_table`: Tables 1, 3 and 4 of the paper as Datasets (the values tests and
  benchmarks compare with);
- :func:`family_parameters`, :func:`family_psd`, :func:`surface_family`: the five surface
  families the accuracy and speed of the contact models are measured on (below;
  docs/accuracy.md);
- :func:`validity_map_path`: the measured model-error table read by
  :func:`roughstick.contact.validity_map`;
- :func:`example_configs`: the example TOML configurations of ``roughstick run``, ``risk`` and
  ``beam`` (``examples/*.toml`` of the repository; ``roughstick examples --out DIR`` copies them).

Wherever a height map path is accepted (:func:`roughstick.io.read_afm`, ``roughstick psd``,
``roughstick curves``, ``[psd] files`` of a config) the sample maps are named ``bundled:S1A`` ...
``bundled:S2C`` (a real file of that name wins).

Surface families (Eq. 37 parameters; all cut at :math:`\xi_{max}` = 289 rad/µm):

==========  ==================================================  ==========================================
family      Eq. 37 parameters                                   why it matters
==========  ==================================================  ==========================================
``S1``      the PSD the S1 samples were drawn from:             the paper's rough sample
            ξ0 = 58.5 rad/µm, rms 3.96 nm
``S2``      that of the S2 samples: ξ0 = 77.4 rad/µm,           many small asperities
            rms 2.08 nm
``table4``  Table 4 → Nayak moments → Eq. 37 (N = 80.1 µm⁻²):   the paper's cantilever surface (§5):
            ξ0 ≈ 21.2 rad/µm, rms 3.54 nm                       smoother, larger asperities
``smooth``  rms 2 nm, Hurst 0.8, roll-off 2e7 rad/m (314 nm)    deep contact (5-10 % contact fraction),
                                                                large merged asperities
``rough``   rms 8 nm, Hurst 0.5, roll-off 5e7 rad/m (126 nm)    a rougher self-affine film
==========  ==================================================  ==========================================

A *soft material* case is any family with a :class:`roughstick.Material` of E* 1-20 GPa (the
modified DMT's stiff-body assumption fails there).
"""

from __future__ import annotations

import functools
import pathlib
from importlib import resources

import numpy as np
import xarray as xr

from ._core.conventions import dataset_attrs
from ._core.references import PAPER, cite
from .io.afm import BUNDLED_MAPS, bundled_map_file, read_afm
from .surface.generate import generate_surfaces
from .surface.moments import moments_from_asperities, self_affine_moments
from .surface.self_affine import fit_self_affine, self_affine_psd
from .surface.spectrum import submap_psd
from .surface.topography import level

__all__ = [
    "SAMPLES",
    "FAMILIES",
    "QMAX_PAPER",
    "sample_path",
    "load_sample",
    "sample_maps",
    "sample_psd",
    "paper_table",
    "family_parameters",
    "family_psd",
    "surface_family",
    "validity_map_path",
    "example_configs",
]

#: Names of the bundled sample maps (synthetic stand-ins of the paper's S1 and S2 measurements).
SAMPLES = BUNDLED_MAPS
#: Names of the surface families (:func:`family_parameters`).
FAMILIES = ("S1", "S2", "table4", "smooth", "rough")
#: The paper's PSD cutoff :math:`\xi_{max}` of Table 3 [rad m-1].
QMAX_PAPER = 289e6

#: Table 1: adhesive energy [J] of a poly-Si sphere on a poly-Si flat (rows: model; columns:
#: (RH, R) = (0.3, 100 nm), (0.3, 800 nm), (0.5, 100 nm), (0.5, 800 nm), (0.7, 100 nm),
#: (0.7, 800 nm)).
_TABLE1 = {
    "maugis": [5.11e-17, 4.75e-16, 8.07e-17, 7.25e-16, 3.72e-16, 3.14e-15],
    "dmt": [5.11e-17, 4.95e-16, 8.05e-17, 7.32e-16, 3.68e-16, 3.16e-15],
    "modified_dmt": [5.18e-17, 5.22e-16, 8.08e-17, 7.49e-16, 3.68e-16, 3.18e-15],
}
#: Table 3: spatial variances (cubic splines) and PSD moments cut at 289 rad/µm, SI.
_TABLE3 = {
    "S1": {"spatial": (15.7e-18, 0.041, 5.00e14), "psd": (15.7e-18, 0.040, 5.08e14)},
    "S2": {"spatial": (4.30e-18, 0.023, 4.04e14), "psd": (4.32e-18, 0.021, 3.99e14)},
}
#: Table 4: RMS roughness of the two surfaces [m], mean asperity radius of the equivalent surface
#: [m], asperity density [m-2]; the Eq. 37 cutoff [rad m-1]; the Eq. 37 solution as printed.
TABLE4_VALUES = {"roughness": (2.6e-9, 2.4e-9), "asperity_radius": 220e-9, "asperity_density": 80.1e12,
                 "qmax": QMAX_PAPER, "printed_q0": 19.4e6, "printed_s0": 6.46e-33, "printed_s1": 6.29e-39}


# ------------------------------------------------------------------------------ sample maps


def _data(name: str) -> pathlib.Path:
    path = resources.files("roughstick").joinpath("data", name)
    if not path.is_file():
        raise FileNotFoundError(
            f"the bundled data file {name!r} is missing from {path}: the installation is incomplete "
            "(reinstall roughstick; from a checkout, `pip install .`)."
        )
    return pathlib.Path(str(path))


def sample_path(name: str) -> pathlib.Path:
    """Path of the bundled sample map ``name`` (one of :data:`SAMPLES`), inside the package."""
    if name not in SAMPLES:
        raise ValueError(f"unknown sample {name!r}; the bundled samples are {SAMPLES}.")
    return bundled_map_file(name)


def load_sample(name: str) -> xr.DataArray:
    """The bundled sample map ``name`` as a ``height`` DataArray (y, x) in m (not levelled).

    Examples
    --------
    >>> h = rs.datasets.load_sample("S1A")
    >>> h.shape, int(h.attrs["periodic"]), h.attrs["units"]
    ((1024, 1024), 0, 'm')
    """
    return read_afm(sample_path(name), levelling="none")


def sample_maps(sample: str = "S1", *, method: str = "plane") -> xr.DataArray:
    """The three maps of ``sample`` ("S1" or "S2"), levelled, over ``(map, y, x)``."""
    names = [n for n in SAMPLES if n[:2] == sample]
    if not names:
        raise ValueError(f"unknown sample {sample!r}; use 'S1' or 'S2'.")
    maps = [level(load_sample(n), method=method) for n in names]
    out = xr.concat(maps, dim="map", coords="minimal", compat="override", join="override",
                    combine_attrs="drop_conflicts")
    return out.assign_coords(map=names)


def sample_psd(sample: str = "S1", *, qmax: float = QMAX_PAPER, submaps: int = 16) -> xr.DataArray:
    """PSD of the three bundled maps of ``sample`` (scheme 3 of §4.1: ``submaps`` sub-maps per map,
    averaged, Eq. 31, no window as in the paper), zero beyond ``qmax`` [rad m-1]; the PSD the
    demo and the ensembles start from."""
    psd = submap_psd(sample_maps(sample), n=submaps, window=None)
    out = psd.where(abs(psd.qx + 1j * psd.qy) <= qmax, 0.0)
    out.attrs = {**psd.attrs, "qmax_cutoff": qmax, "sample": sample}
    return out


# ------------------------------------------------------------------------------ paper tables


def paper_table(number: int) -> xr.Dataset:
    """Table 1, 3 or 4 of the paper as a Dataset (SI units, CF attributes).

    - 1: ``adhesive_energy`` [J] over ``(model, rh, radius)``;
    - 3: ``m0`` [m2], ``m2`` [1], ``m4`` [m-2] over ``(sample, estimate)`` with estimate
      ``"spatial"`` (cubic-spline variances) or ``"psd"`` (PSD moments at ``qmax``);
    - 4: ``roughness`` over ``surface``, ``asperity_radius``, ``asperity_density``, ``qmax``, and
      the Eq. 37 solution as printed (``printed_q0``, ``printed_s0``, ``printed_s1``; the paper
      prints it for N = 88.1 µm⁻², not Table 4's 80.1: tests/surface/test_self_affine.py).

    Examples
    --------
    >>> float(rs.datasets.paper_table(3).m0.sel(sample="S2", estimate="psd")) * 1e18
    4.32
    """
    refs = cite((PAPER, f"Table {number}"))
    if number == 1:
        models = list(_TABLE1)
        vals = np.array([_TABLE1[m] for m in models]).reshape(len(models), 3, 2)
        ds = xr.Dataset(
            {"adhesive_energy": (("model", "rh", "radius"), vals,
                                 {"units": "J", "long_name": "work to separate the sphere from the flat"})},
            coords={"model": models, "rh": ("rh", [0.3, 0.5, 0.7], {"units": "1", "long_name": "relative humidity"}),
                    "radius": ("radius", [100e-9, 800e-9], {"units": "m", "long_name": "sphere radius"})},
        )
    elif number == 3:
        samples, est = list(_TABLE3), ["spatial", "psd"]
        arr = np.array([[_TABLE3[s][e] for e in est] for s in samples])
        ds = xr.Dataset(
            {k: (("sample", "estimate"), arr[..., i], {"units": u, "long_name": ln})
             for i, (k, u, ln) in enumerate((("m0", "m2", "variance of height"),
                                             ("m2", "1", "variance of slope in one direction"),
                                             ("m4", "m-2", "variance of curvature in one direction")))},
            coords={"sample": samples, "estimate": est},
        )
        ds.attrs["qmax"] = QMAX_PAPER
    elif number == 4:
        v = TABLE4_VALUES
        ds = xr.Dataset({
            "roughness": ("surface", list(v["roughness"]), {"units": "m", "long_name": "rms roughness of each surface"}),
            "asperity_radius": ((), v["asperity_radius"], {"units": "m", "long_name": "mean asperity radius of the equivalent surface"}),
            "asperity_density": ((), v["asperity_density"], {"units": "m-2", "long_name": "asperity density of the equivalent surface"}),
            "qmax": ((), v["qmax"], {"units": "rad m-1", "long_name": "cutoff wave number of Eq. 37"}),
            "printed_q0": ((), v["printed_q0"], {"units": "rad m-1", "long_name": "roll-off of Eq. 37 as printed"}),
            "printed_s0": ((), v["printed_s0"], {"units": "m4", "long_name": "plateau of Eq. 37 as printed"}),
            "printed_s1": ((), v["printed_s1"], {"units": "m4", "long_name": "PSD at qmax as printed"}),
        }, coords={"surface": [1, 2]})
    else:
        raise ValueError(f"the bundled tables are 1, 3 and 4 (Table 2 is an image in the paper); got {number!r}.")
    ds.attrs.update(dataset_attrs(f"Table {number} of the paper", references=refs))
    return ds


# ------------------------------------------------------------------------------ surface families


def _eq37(*, rms: float, hurst: float, q0: float, qmax: float = QMAX_PAPER) -> dict:
    """Eq. 37 parameters of a self-affine PSD of given rms, Hurst exponent and roll-off."""
    beta = -2.0 * (1.0 + hurst)
    s1_over_s0 = (qmax / q0) ** beta
    m = self_affine_moments(s0=1.0, s1=s1_over_s0, q0=q0, qmax=qmax)
    s0 = rms**2 / float(m.m0)
    return dict(s0=s0, s1=s0 * s1_over_s0, q0=q0, qmax=qmax)


@functools.cache
def _family_parameters(name: str) -> tuple:
    if name in ("S1", "S2"):  # the PSD the bundled samples were drawn from (attrs of the files)
        with xr.open_dataset(sample_path(f"{name}A"), engine="netcdf4") as ds:
            a = ds.attrs
            p = dict(s0=float(a["psd_s0"]), s1=float(a["psd_s1"]), q0=float(a["psd_q0"]),
                     qmax=float(a["psd_qmax"]))
    elif name == "table4":
        v = TABLE4_VALUES
        m = moments_from_asperities(roughness=v["roughness"], radius=v["asperity_radius"],
                                    density=v["asperity_density"])
        fit = fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=v["qmax"])
        p = dict(s0=float(fit.s0), s1=float(fit.s1), q0=float(fit.q0), qmax=float(fit.qmax))
    elif name == "smooth":
        p = _eq37(rms=2e-9, hurst=0.8, q0=2e7)
    elif name == "rough":
        p = _eq37(rms=8e-9, hurst=0.5, q0=5e7)
    else:
        raise ValueError(f"unknown surface family {name!r}; one of {FAMILIES}.")
    return tuple(sorted(p.items()))


def family_parameters(name: str) -> dict:
    """Eq. 37 parameters ``s0``, ``s1`` [m4], ``q0``, ``qmax`` [rad m-1] of the family ``name``.

    Examples
    --------
    >>> p = rs.datasets.family_parameters("smooth")
    >>> round(float(rs.surface.self_affine_moments(**p).m0) ** 0.5 * 1e9, 6)  # rms height, nm
    2.0
    """
    return dict(_family_parameters(name))


def family_psd(name: str):
    """The PSD of family ``name`` as a callable ``q -> s(q)`` (Eq. 37 evaluated exactly on any
    grid, :func:`roughstick.surface.self_affine_psd`), accepted by :func:`roughstick.surface.generate_surfaces`."""
    p = family_parameters(name)

    def psd(q):
        return self_affine_psd(q, **p)

    psd.__name__ = psd.__qualname__ = f"family_psd_{name}"
    return psd


def surface_family(name: str, *, shape=(256, 256), spacing: float = 5e-9, seed=0, n: int | None = None):
    """Periodic surfaces of family ``name``: one eager map (``n=None``) or a lazy ensemble of ``n``.

    Parameters
    ----------
    name : {"S1", "S2", "table4", "smooth", "rough"}
        See the module docstring.
    shape : (int, int)
        Pixels ``(ny, nx)``.
    spacing : float
        Pixel size [m] (5 nm, as the samples).
    seed : int or numpy.random.SeedSequence
        Root seed (realization k uses its child k, :func:`roughstick.surface.generate_surfaces`).
    n : int, optional
        Number of realizations; None returns realization 0 computed, over ``(y, x)``.
    """
    ens = generate_surfaces(family_psd(name), n=1 if n is None else n, shape=shape, spacing=spacing,
                            seed=seed)
    return ens.isel(realization=0).compute() if n is None else ens


# ------------------------------------------------------------------------------ other data


def validity_map_path() -> pathlib.Path:
    """Path of the measured validity map (docs/accuracy.md says how it was measured)."""
    return _data("validity_map.csv")


def example_configs() -> dict[str, pathlib.Path]:
    """The example configurations shipped with roughstick: ``{file name: path inside the package}``.

    The same files as ``examples/*.toml`` of the repository (``roughstick/data/examples/`` links
    to them); their maps are named ``bundled:S1A`` ..., so a copy runs anywhere. ``roughstick
    examples --out DIR`` writes copies to run and edit (their output folders are relative to the
    copy).

    Examples
    --------
    >>> "risk.toml" in rs.datasets.example_configs()
    True
    """
    folder = resources.files("roughstick").joinpath("data", "examples")
    found = {p.name: pathlib.Path(str(p)) for p in folder.iterdir() if p.name.endswith(".toml")} \
        if folder.is_dir() else {}
    if not found:
        raise FileNotFoundError(
            f"the example configurations are missing from {folder}: the installation is incomplete "
            "(reinstall roughstick; from a checkout, `pip install .`).")
    return dict(sorted(found.items()))
