"""The rough-surface limit states of :func:`roughstick.reliability.failure_probability` (private).

White noise -> surface (Eqs. 33-34) -> modified-DMT curve (Eq. 16) -> adhesive energy (Eq. 13)
or pull-off pressure, through the public functions of :mod:`roughstick.surface` and
:mod:`roughstick.contact` only (``noise_map``; the numpy kernels ``modified_dmt_kernel``
and ``adhesion_summary_kernel`` behind ``rough_contact_curves`` and ``adhesion_summary``, the
same numbers without a Dataset per evaluation), so a faster contact kernel is picked up unchanged.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr

from roughstick._core.intervals import median_interval
from roughstick.contact import summary as adhesion_summary
from roughstick.contact.adhesion import summary_kernel as adhesion_summary_kernel
from roughstick.contact.modified_dmt import kernel as modified_dmt_kernel

from .._core.conventions import CURVE_VARIABLES
from .._core.materials import POLYSILICON, hertz_modulus
from .._core.remedy import argument, spell, spelled
from .._core.validate import external_stacklevel
from ..contact import (
    ValidityWarning,
    expected_surface_groups,
    fft_bem_curves,
    laplace_pressure,
    select_model,
)
from ..surface import noise_map

__all__: list[str] = []

QUANTITIES = ("adhesive_energy", "pull_off_pressure")
#: contact models of a rare-event evaluation (docs/rare_events.md: why the tail needs "fft_bem")
CONTACT_MODELS = ("modified_dmt", "fft_bem")
#: median BEM / Eq. 16 response of the failure states below which they are Eq. 16 artefacts
ARTEFACT_RATIO = 0.5
#: position of each quantity in the tuple of ``adhesion_summary_kernel``
_SUMMARY_INDEX = {"adhesive_energy": 0, "pull_off_pressure": 1, "equilibrium_distance": 2}
#: positions of the pressure and the wet fraction in the outputs of ``modified_dmt_kernel``
_PRESSURE, _WET = CURVE_VARIABLES.index("pressure"), CURVE_VARIABLES.index("wet_fraction")


#: White noise -> surface (Eqs. 33-34; the translation process with a height distribution).
NoiseToSurface = noise_map


class SurfaceResponse:
    """Response of the rough-surface model to one white-noise field (one model evaluation).

    The distance grid belongs to the surface: from first water contact ``max z + h_water``
    down by ``h_water / points_per_water_height`` to ``lower * sqrt(m0)``, then by blocks of
    ``extend * sqrt(m0)`` until the curve has an equilibrium (or the flat is below every pixel).
    A conditioned (rare) surface never falls off a grid made for typical ones. Γ and the
    pull-off are taken from the equilibrium outwards (:func:`roughstick.contact.summary`).
    ``patches > 1`` cuts the surface into that many strips along ``y`` evaluated alone (not
    periodic) and returns the largest response: a weakest-link structure simulated directly.
    ``model="fft_bem"`` evaluates the periodic zone with
    :func:`roughstick.contact.fft_bem_curves` on its own automatic grid instead (docs/rare_events.md
    for its cost). ``water_height`` is :math:`h_{water}` at this RH with
    this ``adsorbed_layer`` (:func:`roughstick.contact.water_height`): Eq. 16 takes it as given.
    """

    def __init__(self, to_surface, *, relative_humidity, quantity="adhesive_energy",
                 material=None, material2=None, adsorbed_layer="paper", connectivity=4,
                 points_per_water_height=20.0, lower=2.0, extend=0.5, periodic=True, patches=1,
                 water_height, model="modified_dmt"):
        if quantity not in QUANTITIES:
            raise ValueError(f"quantity must be one of {QUANTITIES}, got {quantity!r}.")
        self.to_surface = to_surface
        self.noise_shape = to_surface.noise_shape
        self.rh = float(relative_humidity)
        self.hw = float(water_height)
        self.sigma = math.sqrt(to_surface.variance)
        self.quantity = quantity
        material = POLYSILICON if material is None else material
        # the inputs modified_dmt_curves would derive from (rh, materials, adsorbed layer)
        self.kw = {"water_height": np.atleast_1d(self.hw),
                   "laplace_pressure": np.atleast_1d(laplace_pressure(self.rh).values),
                   "spacing": (to_surface.dy, to_surface.dx),
                   "hertz_modulus": hertz_modulus(material, material2),
                   "connectivity": int(connectivity)}
        self.step = self.hw / float(points_per_water_height)
        self.lower, self.extend = float(lower), float(extend)
        self.periodic, self.patches = bool(periodic), int(patches)
        if model not in CONTACT_MODELS:
            raise ValueError(f"model must be one of {CONTACT_MODELS}, got {model!r}.")
        if model == "fft_bem" and (not self.periodic or self.patches != 1):
            raise ValueError("model='fft_bem' solves periodic zones only: use periodic=True and "
                             "patches=1, or model='modified_dmt' for pieces and strips.")
        self.model = model
        self.bem_kw = {"material": material, "material2": material2, "adsorbed_layer": adsorbed_layer}
        if self.patches < 1 or to_surface.ny % self.patches:
            raise ValueError(f"patches={patches} must be >= 1 and divide the {to_surface.ny} rows "
                             "of the zone; choose a shape whose rows are a multiple of patches.")

    def _curves(self, z, d, periodic):
        """Pressure and wet fraction of ``z`` at the ascending distances ``d`` (Eq. 16). The
        validity of the model is the caller's to check once (docs/rare_events.md), not once per
        evaluation."""
        out = modified_dmt_kernel(z, d, periodic=periodic, **self.kw)
        return out[_PRESSURE][0], out[_WET][0]  # at the one RH

    def _bem_response(self, zc) -> float:
        c = fft_bem_curves(self.to_surface.height_array(zc), relative_humidity=self.rh,
                           progress=False, **self.bem_kw)
        return float(adhesion_summary(c, check_grid=False)[self.quantity])

    def map_response(self, z, *, periodic) -> float:
        """Response of one height map [m] (its own distance grid, see the class notes)."""
        zc = z - z.mean()
        if self.model == "fft_bem":
            return self._bem_response(zc)
        top = float(zc.max()) + self.hw
        zmin = float(zc.min())
        k_end = max(int(math.ceil((top - self.lower * self.sigma) / self.step)), 8)
        d = top - self.step * np.arange(k_end + 1)[::-1]
        p, wet = self._curves(zc, d, periodic)
        block = max(int(math.ceil(self.extend * self.sigma / self.step)), 1)
        while True:
            # this loop extends the grid until the curve has its equilibrium
            s = adhesion_summary_kernel(p, wet, d)
            if np.isfinite(float(s[_SUMMARY_INDEX["equilibrium_distance"]])) or d[0] < zmin - self.step:
                break
            more = top - self.step * np.arange(k_end + 1, k_end + block + 1)[::-1]
            k_end += block
            d = np.concatenate([more, d])
            pm, wm = self._curves(zc, more, periodic)
            p, wet = np.concatenate([pm, p]), np.concatenate([wm, wet])
        return float(s[_SUMMARY_INDEX[self.quantity]])

    def __call__(self, noise) -> float:
        z = self.to_surface(noise)
        if self.patches == 1:
            return self.map_response(z, periodic=self.periodic)
        rows = z.shape[0] // self.patches
        return max(self.map_response(np.ascontiguousarray(z[k * rows:(k + 1) * rows]), periodic=False)
                   for k in range(self.patches))


def material_token(material) -> str:
    """How a material enters a run's resume token: the name for poly-silicon and None (runs
    stored before other films could be set keep resuming), every constant otherwise (two films
    of one name but other moduli are other runs)."""
    if material is None or material == POLYSILICON:
        return getattr(material, "name", repr(material))
    return repr(material)


def zone_model(model, psd, *, shape, spacing, relative_humidity, material, material2,
               adsorbed_layer, periodic, patches) -> tuple[str, str | None]:
    """``(model, why)``: ``model`` itself, or for ``"auto"`` the cheapest of
    :data:`CONTACT_MODELS` whose measured error bound at the surface groups expected from ``psd``
    on this zone meets :data:`roughstick.contact.VALIDITY_BOUND` at every humidity (``fft_bem``:
    periodic single zones only)."""
    if model != "auto":
        return model, None
    candidates = CONTACT_MODELS if (periodic and patches == 1) else ("modified_dmt",)
    groups = expected_surface_groups(psd, shape=shape, spacing=spacing,
                                     relative_humidity=relative_humidity,
                                     material=POLYSILICON if material is None else material,
                                     material2=material2, adsorbed_layer=adsorbed_layer)
    try:
        chosen, reason = select_model(None, relative_humidity=relative_humidity, groups=groups,
                                      candidates=candidates)
    except ValueError as err:  # no model meets the accuracy: say what runs where
        raise type(err)(
            f"{err} On pieces and strips (periodic=False or patches > 1) only the modified DMT "
            "runs: evaluate periodic single zones (periodic=True, patches=1) to use fft_bem, or "
            f"pass {spell('contact_model', 'modified_dmt')} knowingly.") from None
    return chosen, f"auto -> {chosen} for every zone: {reason}"


def bem_check(ds, model, threshold, n_check):
    """Re-evaluate up to ``n_check`` failure samples of an Eq. 16 run with the FFT-BEM.

    Adds to ``ds``: ``failures_confirmed_by_bem``, the fraction of the checked failure states
    that the boundary-element model also puts above ``threshold`` (NaN: none checked), and
    ``failure_bem_ratio``, the median over them of BEM response / Eq. 16 response, with its
    95 % distribution-free interval ``failure_bem_ratio_low`` / ``_high``
    (:func:`roughstick.median_interval`; NaN with 5 states or fewer). Rare events
    select exactly the states where a cheap model may be wrong, so the result carries this
    measured check, and warns (ValidityWarning) in two cases:

    * ratio below one half: the failure states are Eq. 16 artefacts (docs/rare_events.md);
    * ratio above one half but fewer than half of the states confirmed: Eq. 16's ordinary error
      moves most failures across the threshold, so the probability carries that error (in the
      tail a small shift of the threshold changes P by a factor).

    Periodic zones of one patch only (the BEM is periodic).
    """
    noise = ds["failure_noise"].values if "failure_noise" in ds else np.empty((0, 0))
    ok, n, (ratio, lo, hi) = 0, 0, (np.nan,) * 3
    if n_check > 0 and model.periodic and model.patches == 1 and noise.shape[0] > 0:
        pick = np.unique(np.linspace(0, noise.shape[0] - 1, min(int(n_check), noise.shape[0])).astype(int))
        bem = SurfaceResponse(model.to_surface, relative_humidity=model.rh, water_height=model.hw,
                              quantity=model.quantity, model="fft_bem", **model.bem_kw)
        got = np.array([bem(noise[i]) for i in pick])  # against the stored Eq. 16 responses
        ok, n = int(np.sum(got > threshold)), int(pick.size)
        ratio, lo, hi = median_interval(got / ds["failure_response"].values[pick], confidence=0.95)
    ds["failures_confirmed_by_bem"] = xr.DataArray(ok / n if n else np.nan, attrs={
        "units": "1", "checked": n,
        "long_name": "fraction of checked failure samples whose FFT-BEM response is also above the threshold"})
    ds["failure_bem_ratio"] = xr.DataArray(ratio, attrs={
        "units": "1", "checked": n,
        "long_name": "median FFT-BEM / Eq. 16 response of the checked failure samples"})
    for name, v, side in (("failure_bem_ratio_low", lo, "lower"), ("failure_bem_ratio_high", hi, "upper")):
        ds[name] = xr.DataArray(v, attrs={  # order statistics; NaN: too few states checked to bound it
            "units": "1", "checked": n, "confidence": 0.95,
            "long_name": f"{side} end of the 95 % distribution-free interval of failure_bem_ratio"})
    with spelled(contact_model=argument("model")):  # failure_probability's argument
        rerun = spell("contact_model", "fft_bem")
    if rerun == argument("model")("fft_bem"):  # called from Python (no CLI spelling): two fidelities too
        rerun += (" (or accurate_model='fft_bem': Eq. 16 corrected by the boundary-element model on a few "
                  "hundred failure states)")
    if n and ratio < ARTEFACT_RATIO:
        what = (f"only {ok} of {n} stay above the threshold): this probability is made of modified-DMT "
                "(Eq. 16) artefacts" if ok < 0.5 * n else
                f"{ok} of {n} still exceed the threshold): Eq. 16 overstates their response "
                f"{1 / ratio:.1f} x, so this probability is likely overestimated")
        warnings.warn(
            f"the FFT-BEM gives the failure samples at RH {model.rh:g} a median {ratio:.2f} of their "
            f"Eq. 16 response ({what}. Rerun with {rerun} (docs/rare_events.md).",
            ValidityWarning, stacklevel=external_stacklevel())
    elif n and ok < 0.5 * n:
        warnings.warn(
            f"only {ok} of {n} failure samples at RH {model.rh:g} stay above the threshold with the "
            f"FFT-BEM (median BEM / Eq. 16 response {ratio:.2f}): Eq. 16's model error moves them "
            "across it, so this probability carries that error (in the tail a few % on the "
            "threshold can change P by a factor). For the boundary-element value rerun with "
            f"{rerun} (docs/rare_events.md).", ValidityWarning, stacklevel=external_stacklevel())
    return ds
