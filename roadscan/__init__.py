"""roadscan: road-surface metrology (reading, stitching, levelling, spectra, fits, rain fill).

roadscan does not import ``friction`` or ``pipelines``.
"""
from .errors import InputError
from .heightmap import HeightMap, Profile
from .spectrum_types import Spectrum, Spectrum2D

__all__ = ["InputError", "HeightMap", "Profile", "Spectrum", "Spectrum2D"]
__version__ = "0.1.0"
