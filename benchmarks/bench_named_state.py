"""The modified DMT's compiled kernels with named state against the index-slot version, in one process.

The kernels of ``roughstick.contact.modified_dmt`` take their state as named structures
(namedtuples of arrays, record arrays, a ``GridPolicy``) instead of 33-argument lists and
``scal[_NEXTB]``-style index slots. This script loads the earlier kernels from git (the
``_rough_*`` modules and ``rough.py``'s automatic grid at ``--base``, by default the commit before
the change) beside the present ones and times the default call of the modified DMT (the automatic
grid of every humidity, refined for Γ: ``modified_dmt_curves(height, relative_humidity=...)``
without the Dataset) on the bundled 1024 x 1024 maps S1A and S2A and on a 256 x 256 crop,
alternating old and new, and checks that every output is bit-identical.

    python benchmarks/bench_named_state.py [--base 9d25e98] [--repeats 5]
"""

from __future__ import annotations

import argparse
import importlib
import pathlib
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

import roughstick as rs
from roughstick.contact.modified_dmt._grid import auto_curves

ROOT = pathlib.Path(__file__).resolve().parents[1]
_OLD = ("_rough_kernels", "_rough_tail", "_rough_fit", "_rough_lm", "_rough_search", "rough")


def load_base(commit: str, where: pathlib.Path):
    """The index-slot kernels of ``commit`` as a package ``rough_base`` (imports made absolute)."""
    pkg = where / "rough_base"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    for name in _OLD:
        text = subprocess.run(["git", "show", f"{commit}:roughstick/contact/{name}.py"], cwd=ROOT,
                              check=True, capture_output=True, text=True).stdout
        text = re.sub(r"^from \.\.(\w)", r"from roughstick.\1", text, flags=re.M)
        text = text.replace("from .adhesion import adhesion_summary_kernel",
                            "from roughstick.contact.adhesion import summary_kernel as adhesion_summary_kernel")
        text = text.replace("from .meniscus import", "from roughstick.contact.meniscus import")
        (pkg / f"{name}.py").write_text(text)
    sys.path.insert(0, str(where))
    return importlib.import_module("rough_base.rough")


def case(height, rh):
    z = np.asarray(height.transpose("y", "x").values, dtype=float)
    dx = float(height.x[1] - height.x[0])
    hw = rs.contact.water_height(rh).values
    dp = rs.contact.laplace_pressure(rh).values
    return z, hw, dp, dict(dx=dx, dy=dx, K=rs.materials.hertz_modulus(), periodic=False, connectivity=4, n=None)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", default="9d25e98", help="commit of the index-slot kernels")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    rh = np.array([0.3, 0.5, 0.6, 0.7, 0.8, 0.9])
    maps = {"S1A 1024^2": rs.datasets.load_sample("S1A"), "S2A 1024^2": rs.datasets.load_sample("S2A")}
    maps["S1A 256^2"] = maps["S1A 1024^2"].isel(x=slice(0, 256), y=slice(0, 256))
    with tempfile.TemporaryDirectory() as tmp:
        old = load_base(args.base, pathlib.Path(tmp))
        print(f"named state (this tree) against index slots ({args.base}), {args.repeats} repeats "
              "each, alternating; seconds per default call (six humidities)")
        for name, h in maps.items():
            z, hw, dp, kw = case(h, rh)
            a = old._auto_curves(z, hw, dp, **kw)  # compiles both, and checks the outputs
            b = auto_curves(z, hw, dp, **kw)
            same = np.array_equal(a[0], b[0]) and all(
                np.array_equal(x, y, equal_nan=True) for x, y in zip(a[1], b[1], strict=True))
            times = {"old": [], "new": []}
            for _ in range(args.repeats):
                for which, f in (("old", old._auto_curves), ("new", auto_curves)):
                    t0 = time.perf_counter()
                    f(z, hw, dp, **kw)
                    times[which].append(time.perf_counter() - t0)
            t_old, t_new = (np.median(times[k]) for k in ("old", "new"))
            print(f"{name}: {b[0].size} distances, bit-identical: {same}; old {t_old:.3f} s, new "
                  f"{t_new:.3f} s (medians; minima {min(times['old']):.3f}, {min(times['new']):.3f}); "
                  f"new/old {t_new / t_old:.3f} (medians), {min(times['new']) / min(times['old']):.3f} (minima)")


if __name__ == "__main__":
    main()
