"""brdfpy: fast reflectance models (BRDFs) and a CPU software rasterizer with a Rust core."""

from brdfpy._brdfpy import __version__

__all__ = ["__version__"]
