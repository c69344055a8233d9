"""Lateral size of an instrument file checked against the kind of instrument that wrote it.

A vendor file read with the wrong length unit does not look wrong to a reader: the NanoFocus
``.nms`` files once came out of SurfaceTopography 1.27 with 0.31 m pixels, a 160 m field
from a confocal microscope. Each SurfaceTopography format id maps to an instrument kind with
the pixel and field ranges such instruments can have:

=============================  =============  ===========  ===============================
kind                           pixel [m]      field [m]    formats
=============================  =============  ===========  ===============================
scanning-probe microscope      1e-12 .. 1e-4  <= 2e-3      di, ibw, mi, mdt, ezd, jpk, bcr,
                                                           wsxm, ps
optical profiler/microscope    1e-9 .. 1e-3   <= 1         plu, plux, opd, opdx, datx,
                                                           metropro, al3d, vk, zon, lext,
                                                           oir, poir, nms, frt, zmg, os3d
surface metrology file         1e-12 .. 1e-2  <= 1         sur, mnt, sdf, tmd, qep
=============================  =============  ===========  ===============================

(scanning-probe scanners span at most ~200 um, optical profilers' stitched fields tens of
centimetres; formats not listed, such as NetCDF, HDF5, MATLAB, x,y,z text or SRTM ``.hgt``,
hold any scale and are not checked). Outside the range the file is refused in one line; a user
who knows the spacing passes ``--spacing`` with ``--override-calibration``.

Known reader unit slip, corrected and reported: SurfaceTopography 1.27 reads the NanoFocus
header's grid spacing as millimetres; the files' spacing is in nanometres (0.3125 um pixels, a
160 um field for 512 points, the field of a NanoFocus confocal objective, come out 1e6 times too
large). When its pixel exceeds 1 mm, the spacing is divided by 1e6 and a warning says so.
"""

from __future__ import annotations

from ..errors import InputError
from ..units import length as _len

__all__ = ["KINDS", "kind_of", "check_lateral", "fix_reader_units"]

_SPM = ("di", "ibw", "mi", "mdt", "ezd", "jpk", "bcr", "wsxm", "ps")
_OPTICAL = (
    "plu",
    "plux",
    "opd",
    "opdx",
    "datx",
    "metropro",
    "al3d",
    "vk",
    "zon",
    "lext",
    "oir",
    "poir",
    "nms",
    "frt",
    "zmg",
    "os3d",
)
_ANY_SURFACE = ("sur", "mnt", "sdf", "tmd", "qep")  # containers of any profiler's data
#: kind -> (smallest pixel, largest pixel, largest field) [m]
KINDS = {
    "scanning-probe microscope": (1e-12, 1e-4, 2e-3),
    "optical profiler or microscope": (1e-9, 1e-3, 1.0),
    "surface metrology file": (1e-12, 1e-2, 1.0),
}
_KIND_OF = {
    **{f: "scanning-probe microscope" for f in _SPM},
    **{f: "optical profiler or microscope" for f in _OPTICAL},
    **{f: "surface metrology file" for f in _ANY_SURFACE},
}


def kind_of(fmt):
    """Instrument kind of a SurfaceTopography format id, or None (any scale).

    Parameters
    ----------
    fmt : str
        SurfaceTopography format id.

    Returns
    -------
    str or None
        The instrument kind.
    """
    return _KIND_OF.get(str(fmt).lower())


def check_lateral(path, fmt, name, dx, dy, nx, ny):
    """Refuse spacings [m] or a field implausible for the instrument kind of format ``fmt``.

    Parameters
    ----------
    path : str or Path
        File named in the error.
    fmt : str
        Format id.
    name : str
        Format name for the message.
    dx, dy : float
        Spacings [m].
    nx, ny : int
        Grid size.

    Returns
    -------
    None
        Raises :class:`roadscan.InputError` when implausible.
    """
    kind = kind_of(fmt)
    if kind is None:
        return
    lo, hi, field_max = KINDS[kind]
    field = max(dx * nx, dy * ny)
    pixel = max(dx, dy)
    small = min(dx, dy)
    if small < lo or pixel > hi or field > field_max:
        raise InputError(
            path,
            f"a {name} file ({kind}) giving {_len(dx)} x {_len(dy)} pixels and "
            f"a {_len(dx * nx)} x {_len(dy * ny)} field: implausible for that "
            f"instrument (a unit error in the file or its reader); if you know "
            f"the spacing, pass {{spacing}} DX[,DY] {{override_calibration}}",
            ("spacing", "override_calibration"),
        )


def fix_reader_units(fmt, dx, dy, meta):
    """(dx, dy) [m] with the known unit slips of SurfaceTopography's readers corrected; the
    correction is noted in ``meta["read_warnings"]`` and ``meta["reader_unit_fix"]``.

    Parameters
    ----------
    fmt : str
        Format id.
    dx, dy : float
        Spacings as read [m].
    meta : dict
        Reader metadata (updated).

    Returns
    -------
    tuple of float
        (dx, dy) [m].
    """
    if str(fmt).lower() == "nms" and max(dx, dy) > 1e-3:
        fixed = (dx * 1e-6, dy * 1e-6)
        note = (
            f"NanoFocus header spacing read as nanometres ({_len(fixed[0])} pixels; "
            f"SurfaceTopography reads it as millimetres: {_len(dx)})"
        )
        meta["reader_unit_fix"] = note
        meta.setdefault("read_warnings", []).append(note)
        return fixed
    return dx, dy
