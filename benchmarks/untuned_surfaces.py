"""The default calls on random self-affine surfaces nobody tuned on: do they agree, and warn?

    nice -n 5 python benchmarks/untuned_surfaces.py [SEED] [N]
    nice -n 5 python benchmarks/untuned_surfaces.py families
    nice -n 5 python benchmarks/untuned_surfaces.py resolution [SEED] [N] [MODEL]
    nice -n 5 python benchmarks/untuned_surfaces.py resolution families [MODEL]

``families``: the BEM's default grid on one 64² map (seed 0, 5 nm) of S1, S2, Table 4 and the
smooth family at RH 0.05, 0.5 and 0.9 on poly-Si: Γ of ``rough_contact_curves(h, model="bem")``
on the grid it had before (40 points from max z - max(h_water, 0.5 σ) to max z + h_water) and
on its default now (fft_bem's automatic grid), each against the fft_bem default call, with times.

``resolution``: on the same N untuned surfaces, how much fft_bem's Γ moves with the pixel
(``rs.contact.resolution_study(h, factors=(0.5, 1, 2))``: block averages of 2 x 2 pixels, and a
band-limited Fourier interpolation onto pixels half as large), against the wetted-neck radius in
pixels (``neck_pixels`` of ``rs.contact.surface_groups``) and whether ``rough_contact_curves(h,
model=MODEL)`` (default "fft_bem") warned that the pixel does not resolve the water necks; a
summary per RH and over all maps. ``resolution families``: the same on the 64² maps
(seed 0) of S1, S2, Table 4 and the smooth family at RH 1e-3, 0.05, 0.5 and 0.9 on poly-Si.

N surfaces (default 60, seed 1): Hurst exponent 0.3-1.0, pixel 2-20 nm, roll-off 3-100 pixels
per wavelength, shapes 64², 33 x 65, 96 x 128, 97², 128², rms 0.3-30 nm (log-uniform), RH 1e-3,
0.05, 0.3, 0.6 or 0.95, E 10, 50 or 164 GPa. For each, the calls a user makes:
``rough_contact_curves(h, model=...)`` with "auto", "fft_bem" and the default "modified_dmt",
then ``adhesion_summary``. Prints the model auto chose, Γ, the warnings each call raised, and
the relative Γ difference of auto and of the modified DMT to fft_bem; then a summary per choice.
At RH <= 1e-3 also fft_bem and the Tamaas BEM on a fine uniform grid, 400 points from the bottom
of fft_bem's automatic grid to max z + max(6 h_water, 1.5 x the automatic grid's top above max z)
(a one-pixel neck can hold several h_water above max z, and a large retraction step can drop it):
their Γ and the highest distance still attractive, in h_water above max z.
"""

import sys
import time
import warnings

import numpy as np

import roughstick as rs

SHAPES = [(64, 64), (33, 65), (96, 128), (97, 97), (128, 128)]


def case(rng, k):
    H = rng.uniform(0.3, 1.0)
    spacing = 10 ** rng.uniform(np.log10(2e-9), np.log10(20e-9))
    qmax = np.pi / spacing
    q0 = qmax / 10 ** rng.uniform(0.5, 2.0)
    s0 = 1e-33
    s1 = s0 * (qmax / q0) ** (-2 * (1 + H))
    shape = SHAPES[rng.integers(len(SHAPES))]
    sigma = 10 ** rng.uniform(np.log10(0.3e-9), np.log10(30e-9))
    rh = float(rng.choice([1e-3, 0.05, 0.3, 0.6, 0.95]))
    E = float(rng.choice([10e9, 50e9, 164e9]))

    def psd(q):
        return rs.surface.self_affine_psd(q, s0=s0, s1=s1, q0=q0, qmax=qmax)

    h = rs.surface.generate_surfaces(psd, n=1, shape=shape, spacing=spacing, seed=k).isel(realization=0).compute()
    h = ((h - h.mean()) * (sigma / float(h.std()))).assign_attrs(units="m")
    desc = (f"{k:3d} H {H:.2f} dx {spacing * 1e9:5.1f} nm 2pi/q0 {2 * np.pi / q0 / spacing:5.1f} px "
            f"{shape} rms {sigma * 1e9:6.2f} nm RH {rh} E {E / 1e9:.0f} GPa")
    return h, rh, rs.Material(youngs_modulus=E), desc


def call(h, rh, mat, model):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t = time.perf_counter()
        c = rs.contact.curves(h, relative_humidity=rh, model=model, material=mat)
        g = float(rs.contact.summary(c).adhesive_energy)
        dt = time.perf_counter() - t
    return g, c.attrs.get("contact_model", model), dt, sorted({x.category.__name__ for x in w})


def extended(h, rh, mat):
    """fft_bem and bem on a fine uniform grid across fft_bem's automatic grid and beyond."""
    hw, zmax = float(rs.contact.water_height(rh)), float(h.max())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = rs.contact.fft_bem_curves(h, relative_humidity=rh, material=mat).distance.values
        ext = np.linspace(d[0], zmax + max(6 * hw, 1.5 * (d[-1] - zmax)), 400)
        out, gammas = [], []
        for name, fn in (("fft_bem", rs.contact.fft_bem_curves), ("bem", rs.contact.bem_curves)):
            c = fn(h, relative_humidity=rh, material=mat, distance=ext)
            att = np.flatnonzero(c.pressure.values < 0)
            top = (float(c.distance[att[-1]]) - zmax) / hw if att.size else np.nan
            gammas.append(float(rs.contact.summary(c).adhesive_energy))
            out.append(f"{name} Γ {gammas[-1]:.3e} (attractive up to {top:.2f} h_water)")
    return (f"fine grid (automatic grid top {(d[-1] - zmax) / hw:.2f} h_water above max z): "
            + "; ".join(out)), gammas[0]


def families():
    for fam in ("S1", "S2", "table4", "smooth"):
        h = rs.datasets.surface_family(fam, shape=(64, 64), seed=0, n=1).isel(realization=0).compute()
        z = h.values
        for rh in (0.05, 0.5, 0.9):
            hw = float(rs.contact.water_height(rh))
            old = np.linspace(max(z.max() - max(hw, 0.5 * z.std()), z.mean() + 0.5 * z.std()),
                              z.max() + hw, 40)
            out = {}
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                for name, kw in (("fft_bem", dict(model="fft_bem")), ("bem old grid", dict(model="bem", distance=old)),
                                 ("bem default", dict(model="bem"))):
                    t = time.perf_counter()
                    c = rs.contact.curves(h, relative_humidity=rh, **kw)
                    out[name] = (float(rs.contact.summary(c).adhesive_energy), time.perf_counter() - t)
            g0 = out["fft_bem"][0]
            print(f"{fam:7s} RH {rh}: fft_bem Γ {g0:.4e} J/m2 ({out['fft_bem'][1]:.2f} s) | "
                  + " | ".join(f"{k}: Γ/Γ_fft_bem - 1 = {v[0] / g0 - 1:+.4f} ({v[1]:.2f} s)"
                               for k, v in out.items() if k != "fft_bem"), flush=True)


def untuned_cases(seed, n):
    rng = np.random.default_rng(seed)
    for k in range(n):
        yield case(rng, k)


def family_cases():
    """The four families' 64² maps (seed 0, 5 nm, poly-Si) at RH 1e-3, 0.05, 0.5 and 0.9."""
    for fam in ("S1", "S2", "table4", "smooth"):
        h = rs.datasets.surface_family(fam, shape=(64, 64), seed=0, n=1).isel(realization=0).compute()
        for rh in (1e-3, 0.05, 0.5, 0.9):
            yield h, rh, rs.Material(), f"{fam:7s} 64² seed 0 RH {rh}"


def resolution(cases, model="fft_bem"):
    rows = []
    for h, rh, mat, desc in cases:
        neck = float(rs.contact.surface_groups(h, relative_humidity=rh).neck_pixels)
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            rs.contact.curves(h, relative_humidity=rh, material=mat, model=model)
            warned = any(issubclass(x.category, rs.ValidityWarning) and "water necks" in str(x.message)
                         for x in w)
            r = rs.contact.resolution_study(h, relative_humidity=rh, material=mat, model=model)
        ch = r.relative_change_adhesive_energy.values.ravel()  # pixel sizes ascending: finer, native, coarser
        rows.append((rh, ch[0], ch[2], warned, neck))
        print(f"{desc} | neck {neck:.2f} px | Γ change: pixels / 2 (Fourier) {ch[0]:+.3f}, pixels x 2 "
              f"(block mean) {ch[2]:+.3f} | default call warned (pixel): {warned}", flush=True)
    for rh in sorted({r[0] for r in rows}):
        sel = [r for r in rows if r[0] == rh]
        fine, coarse = (np.abs([r[i] for r in sel]) for i in (1, 2))
        moved = (fine > 0.1) | (coarse > 0.1)
        print(f"RH {rh}: {len(sel)} cases; |Γ change| > 10 % at half the pixel in {int((fine > 0.1).sum())}, "
              f"at twice the pixel in {int((coarse > 0.1).sum())} (median {np.median(fine):.2f} / "
              f"{np.median(coarse):.2f}); of the {int(moved.sum())} moved, "
              f"{sum(r[3] for r, m in zip(sel, moved) if m)} warned by the default call")
    fine = np.abs([r[1] for r in rows]) > 0.1
    warned = np.array([r[3] for r in rows])
    print(f"{model}: warned (neck < {rs.contact.RESOLVED_NECK_PIXELS:g} px) {int(warned.sum())} of {len(rows)} maps, "
          f"{int((fine & warned).sum())} of them moved > 10 % at half the pixel; not warned "
          f"{int((~warned).sum())}, {int((fine & ~warned).sum())} of them moved")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "families":
        return families()
    if len(sys.argv) > 1 and sys.argv[1] == "resolution":
        args = sys.argv[2:]
        model = args.pop() if args and not args[-1].isdigit() and args[-1] != "families" else "fft_bem"
        if args and args[0] == "families":
            return resolution(family_cases(), model)
        return resolution(untuned_cases(int(args[0]) if args else 1, int(args[1]) if len(args) > 1 else 60),
                          model)
    seed = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 60
    rng = np.random.default_rng(seed)
    rows, low = [], []
    for k in range(n):
        h, rh, mat, desc = case(rng, k)
        res = {m: call(h, rh, mat, m) for m in ("auto", "fft_bem", "modified_dmt")}
        gf = res["fft_bem"][0]
        err = {m: abs(res[m][0] - gf) / abs(gf) if gf else np.nan for m in ("auto", "modified_dmt")}
        rows.append((res["auto"][1], rh, err["auto"], bool(res["auto"][3])))
        if rh <= 1e-3:
            line, g_fine = extended(h, rh, mat)
            low.append((res["fft_bem"][0] / g_fine - 1, bool(res["fft_bem"][3])))
            print("     " + line, flush=True)
        print(f"{desc} | auto -> {res['auto'][1]}: Γ {res['auto'][0]:.3e} J/m2 {res['auto'][2]:.2f} s "
              f"{res['auto'][3]} | fft_bem {gf:.3e} {res['fft_bem'][2]:.2f} s {res['fft_bem'][3]} | "
              f"|auto/fft_bem - 1| {err['auto']:.3f}, modified DMT {err['modified_dmt']:.3f} "
              f"{res['modified_dmt'][3]}", flush=True)
    if low:
        e = np.array([x[0] for x in low])
        ok = np.abs(e) <= 0.02
        print(f"fft_bem default call at RH <= 1e-3 against fft_bem on the fine grid: {len(low)} cases, "
              f"{int(ok.sum())} within 2 % (largest {np.abs(e[ok]).max() if ok.any() else np.nan:.3f}); "
              f"the other {int((~ok).sum())}: Γ/Γ_fine - 1 = {np.round(e[~ok], 2).tolist()}, "
              f"{sum(w for (x, w), o in zip(low, ok) if not o)} of them warned")
    for chosen in sorted({r[0] for r in rows}):
        for low in (True, False):
            sel = [r for r in rows if r[0] == chosen and (r[1] <= 1e-3) == low]
            if not sel:
                continue
            e = np.array([r[2] for r in sel])
            print(f"auto -> {chosen}, RH {'<= 1e-3' if low else '>= 0.05'}: {len(sel)} cases, "
                  f"|Γ/Γ_fft_bem - 1| median {np.median(e):.3f}, largest {e.max():.3f}; "
                  f"{sum(r[3] for r in sel)} warned")


if __name__ == "__main__":
    main()
