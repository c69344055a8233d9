"""roadscan: road-surface metrology (reading, stitching, levelling, spectra, fits, rain fill).

roadscan does not import ``friction`` or ``pipelines``.

Imports are on demand: ``import roadscan`` loads only :mod:`roadscan.errors`; the names below
(``HeightMap``, ``Spectrum``, ``psd_area``...) load their module (and numpy) when first used, so a
command's ``--help`` stays fast. The submodules (``roadscan.spectrum``, ``roadscan.level``...) import
numpy and the parts of scipy they need; none imports matplotlib, ``scipy.optimize`` or
``scipy.signal`` at import time (guarded by ``tests/test_imports.py``).
"""

import lazy_loader

from .errors import InputError, RoadscanWarning

__all__ = ["InputError", "RoadscanWarning", "HeightMap", "Profile", "Spectrum", "Spectrum2D", "psd_area"]
__version__ = "0.1.0"

#: public name -> the submodule that defines it, loaded on first use (``lazy_loader``, the
#: mechanism scikit-image uses; PEP 562)
_HOMES = {
    "heightmap": ["HeightMap", "Profile"],
    "spectrum_types": ["Spectrum", "Spectrum2D"],
    "spectrum": ["psd_area"],
}
__getattr__, _, _ = lazy_loader.attach(__name__, submod_attrs=_HOMES)


def __dir__():
    return sorted(set(globals()) | set(__all__))
