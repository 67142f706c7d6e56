"""Plain-numpy SI kernels of the sphere models."""
