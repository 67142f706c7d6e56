"""TOML pieces shared by the command-line tests (one copy of each; tests/ is on sys.path)."""

#: The [psd] table of a run from spectral moments (the paper's S1-like m0, m2, m4).
MOMENTS_PSD = """
[psd]
source = "moments"
m0 = "15.7 nm2"
m2 = 0.040
m4 = "5.08e-4 nm-2"
qmax = "289 rad/um"
"""

#: A small sharp-front beam configuration (three laws of 16 x 16 patches, two lengths).
SMALL_BEAM = """
[beam]
lengths = ["100 um", "300 um"]
[surface]
spacing = "20 nm"
shape = [16, 16]
[ensemble]
relative_humidity = [0.3, 0.9]
n = 20
[bank]
laws = 3
model = "modified_dmt"  # the paper's model: its bank tail is re-checked with the BEM
"""
