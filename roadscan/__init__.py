"""roadscan: road-surface metrology (reading, stitching, levelling, spectra, fits, rain fill).

roadscan does not import ``friction`` or ``pipelines``.

Imports are on demand: ``import roadscan`` loads only :mod:`roadscan.errors`; the names below
(``HeightMap``, ``Spectrum``...) load their module (and numpy) when first used, so a command's
``--help`` stays fast. The submodules (``roadscan.spectrum``, ``roadscan.level``...) import
numpy and the parts of scipy they need; none imports matplotlib, ``scipy.optimize`` or
``scipy.signal`` at import time (guarded by ``tests/test_imports.py``).
"""
from importlib import import_module

from .errors import InputError

__all__ = ["InputError", "HeightMap", "Profile", "Spectrum", "Spectrum2D"]
__version__ = "0.1.0"

_LAZY = {"HeightMap": ".heightmap", "Profile": ".heightmap",
         "Spectrum": ".spectrum_types", "Spectrum2D": ".spectrum_types"}


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
