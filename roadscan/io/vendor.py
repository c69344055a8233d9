"""Instrument vendors' formats through the optional ``surfalize`` package.

``pip install 'roadscan[vendor]'`` installs it. surfalize is imported only when such a file is
read; without it the reader raises :class:`InputError` naming the extra. surfalize gives heights
and steps in micrometres with NaN at invalid points; they are converted to metres. The file
states its units, so ``units`` is ignored; ``spacing`` overrides the file's steps.

Extensions routed here (what surfalize 0.19 reads, minus those roadscan reads itself: ``.x3p``,
``.gwy``, ``.xyz`` and CAPTIF ``.dat``): Sensofar ``.plu``/``.plux``, Digital Surf ``.sur``,
``.sdf``, Keyence ``.vk3``/``.vk4``/``.vk6``/``.vk7``, Veeco/Bruker ``.opd``, Alicona ``.al3d``,
Zygo ``.zmg``/``.datx`` (surfalize 0.19 has no ``.datx`` reader: a clear error says so),
Keyence ``.zon``, ``.os3d``, ``.nms``, ``.tmd``, ``.sflz``, Olympus ``.lext``/``.oir``/``.poir``,
``.hdat``, FITS.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._common import check_file, make_heightmap, resolve_spacing
from ._registry import register_reader

__all__ = ["read_vendor", "VENDOR_EXTENSIONS", "surfalize_available"]

VENDOR_EXTENSIONS = (
    ".plu", ".plux", ".sur", ".sdf", ".vk3", ".vk4", ".vk6", ".vk7", ".opd", ".al3d", ".zmg",
    ".datx", ".zon", ".os3d", ".nms", ".tmd", ".sflz", ".lext", ".oir", ".poir", ".hdat",
    ".fits", ".fit", ".fts",
)


def surfalize_available():
    """True if the optional ``surfalize`` package can be imported."""
    try:
        import surfalize  # noqa: F401
    except ImportError:
        return False
    return True


def _import_surfalize(path):
    try:
        import surfalize  # noqa: F401
        from surfalize.file.common import FileHandler
    except ImportError:
        ext = Path(path).suffix.lower()
        raise InputError(path, f"reading {ext} needs the optional extra: "
                               "pip install 'roadscan[vendor]'") from None
    return FileHandler


@register_reader(*VENDOR_EXTENSIONS)
def read_vendor(path, spacing=None, units=None):
    """Read a vendor height file with surfalize (heights and steps converted from um to m)."""
    check_file(path)
    FileHandler = _import_surfalize(path)
    import surfalize.file as sf

    ext = Path(path).suffix.lower()
    if ext not in sf.supported_formats_read:
        raise InputError(path, f"surfalize {getattr(__import__('surfalize'), '__version__', '')} "
                               f"cannot read {ext} files")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            raw = FileHandler(str(path)).read()
    except InputError:
        raise
    except Exception as exc:  # noqa: BLE001 - the readers raise many kinds on broken files
        raise InputError(path, f"cannot read as {ext} ({exc.__class__.__name__}: {exc})") from None
    data = np.asarray(raw.data, dtype=np.float64)
    meta = {"format": ext.lstrip("."), "reader": "surfalize", "units": "um"}
    if units is not None:
        meta["units_ignored"] = units
    meta["vendor_meta"] = {str(k): str(v)[:200] for k, v in dict(raw.metadata or {}).items()}
    sp = resolve_spacing(spacing, path)
    if sp is None:
        sp = (float(raw.step_x) * 1e-6, float(raw.step_y) * 1e-6)
    return make_heightmap(path, data * 1e-6, sp[0], sp[1], meta=meta)
