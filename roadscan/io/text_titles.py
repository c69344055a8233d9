"""What the lines above a text table say: column titles with their units, and a preamble.

**Column titles** (the last header line above the numbers, or a ``#`` line numpy's ``savetxt``
writes; fields split by ``;``, tabs, commas, or spaces). A column's unit is read from every
common form: ``x (mm)``, ``x [mm]``, ``x {mm}``, ``x <mm>``, ``x/mm``, ``x in mm``, ``x_mm``,
``x-mm``, ``x mm``, and a units row under the names row (``x,z`` then ``mm,um``). Units:
m, cm, mm, um (also ``µm``, ``μm``, ``micron``, ``micrometre``...), nm, and their words. The
bracket, ``/`` and ``in`` forms name a unit explicitly: a token that is not a length unit
roadscan knows there (``z (a.u.)``, ``z [counts]``, ``z/V``) is returned as unknown, for the
reader to refuse unless a flag decides. The ``_``, ``-`` and space forms are units only when the
last word is a unit (``x_mm``; ``x_pos`` has no unit), and refused when it is a unit roadscan
does not convert (``z_in``, ``z_mil``).

**Preamble**: ``key: value``, ``key = value`` or ``key;value`` lines (also after ``#``). Keys
read (case and punctuation ignored): spacing (``spacing``, ``dx``, ``step``, ``x increment``,
``sampling interval``, ``pitch``... with a unit after the number or in the key, ``Spacing (mm):
0.05``), ``dy``, units (``units``/``unit`` for every column, ``x units``, ``z units``/``height
unit``/``value units``), the missing-value marker (``nodata``, ``missing value``, ``invalid
value``, ``fill value``...). A key asking for a scale (``z scale``, ``scale factor``,
``multiplier``, ``gain``) other than 1 is refused: roadscan does not apply it, and ignoring it
would misread the heights. Other keys are kept in ``meta["preamble"]``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ..errors import InputError

__all__ = ["LENGTH_UNITS", "Titles", "Preamble", "unit_of_token", "find_titles", "read_preamble"]

#: metres per unit of every spelling a title may use
LENGTH_UNITS = {}
for _canon, _f, _words in (
    ("m", 1.0, ("m", "meter", "meters", "metre", "metres")),
    ("cm", 1e-2, ("cm", "centimeter", "centimeters", "centimetre", "centimetres")),
    ("mm", 1e-3, ("mm", "millimeter", "millimeters", "millimetre", "millimetres")),
    (
        "um",
        1e-6,
        ("um", "µm", "μm", "micron", "microns", "micrometer", "micrometers", "micrometre", "micrometres"),
    ),
    ("nm", 1e-9, ("nm", "nanometer", "nanometers", "nanometre", "nanometres")),
):
    for _w in _words:
        LENGTH_UNITS[_w] = (_canon, _f)
#: units a title may name that roadscan does not convert (refused, never taken as a name)
OTHER_UNITS = {
    "in",
    "inch",
    "inches",
    "mil",
    "mils",
    "thou",
    "ft",
    "feet",
    "uin",
    "µin",
    "μin",
    "pm",
    "å",
    "angstrom",
    "angstroms",
    "km",
    "dm",
    "px",
    "pixel",
    "pixels",
    "counts",
    "v",
    "mv",
    "volt",
    "volts",
    "a.u.",
    "au",
    "arb",
}

_SPACING_KEYS = {
    "spacing",
    "dx",
    "x spacing",
    "sample spacing",
    "sampling interval",
    "sampling step",
    "sampling distance",
    "step",
    "x step",
    "step size",
    "increment",
    "x increment",
    "pitch",
    "x pitch",
    "point spacing",
    "interval",
    "delta x",
    "xspacing",
    "lateral spacing",
    "data spacing",
}
_DY_KEYS = {"dy", "y spacing", "y step", "y increment", "y pitch", "delta y", "line spacing"}
_UNIT_KEYS = {"unit", "units", "length unit", "length units", "xyz units", "xyz unit"}
_X_UNIT_KEYS = {
    "x unit",
    "x units",
    "xy unit",
    "xy units",
    "lateral unit",
    "lateral units",
    "x axis unit",
    "x axis units",
    "distance unit",
    "distance units",
    "x scale unit",
}
_Z_UNIT_KEYS = {
    "z unit",
    "z units",
    "height unit",
    "height units",
    "value unit",
    "value units",
    "vertical unit",
    "vertical units",
    "z axis unit",
    "z axis units",
    "data unit",
    "data units",
    "depth unit",
    "depth units",
}
_NODATA_KEYS = {
    "nodata",
    "no data",
    "nodata value",
    "no data value",
    "missing",
    "missing value",
    "missing data",
    "missing data value",
    "invalid",
    "invalid value",
    "void",
    "void value",
    "na value",
    "null value",
    "fill value",
    "dropout",
    "dropout value",
    "bad value",
    "invalid data value",
    "no value",
}
_SCALE_WORDS = ("scale", "factor", "multiplier", "gain")
_KEY_VALUE = re.compile(r"^#?\s*([A-Za-zµμ][^:=;,\t]*?)\s*(?::|=|;|\t|,(?=\s*[-+.\d]))\s*(.*)$")
_BRACKET = re.compile(r"[(\[{<]\s*([^)\]}>]*?)\s*[)\]}>]")
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def unit_of_token(token):
    """(canonical unit, metres per unit) of a unit spelling, or None.

    Parameters
    ----------
    token : str
        ``"mm"``, ``"µm"``, ``"Micrometres"``...

    Returns
    -------
    tuple or None
    """
    t = token.strip().strip("\"'").strip()
    if t in ("µm", "μm") or t.lower() in LENGTH_UNITS:
        return LENGTH_UNITS.get(t) or LENGTH_UNITS[t.lower()]
    return None


@dataclass
class Titles:
    """Column titles and what each says of its unit.

    Attributes
    ----------
    names : list of str
        One name per column.
    units : list
        Per column: a canonical unit (``"mm"``), None (no unit stated), or ``("?", token)``
        for a unit token roadscan does not know.
    text : str
        The title line(s) as written (for messages).
    n_lines : int
        Header lines it takes (2 with a units row).
    """

    names: list
    units: list
    text: str
    n_lines: int = 1

    @property
    def any_unit(self):
        """True when a column names a unit (known or not)."""
        return any(u is not None for u in self.units)


def _split_names(line):
    line = line.strip().lstrip("#").strip()
    for sep in (";", "\t", ","):
        if sep in line:
            return [n.strip().strip("\"'").strip() for n in line.split(sep)]
    toks = line.split()
    names = []
    for i, t in enumerate(toks):  # "x (mm) z (mm)", "x in mm z in mm"
        attach = names and (
            _BRACKET.fullmatch(t) or t.lower() == "in" or (i > 0 and toks[i - 1].lower() == "in")
        )
        if attach:
            names[-1] += " " + t
        else:
            names.append(t)
    return [n.strip("\"'") for n in names]


def _title_unit(name):
    """What the column title ``name`` says of its unit: canonical unit, None, or ("?", token)."""
    brackets = _BRACKET.findall(name)
    if brackets:
        token = re.sub(r"^(in|unit|units)\s*:?\s*", "", brackets[-1], flags=re.IGNORECASE)
        return _explicit(token)
    base = name.strip()
    m = re.fullmatch(r"(.+?)\s*/\s*([^\s/]+)", base) or re.fullmatch(
        r"(.+?)\s+in\s+(\S+)", base, re.IGNORECASE
    )
    if m:
        return _explicit(m.group(2))
    m = re.fullmatch(r"(.+?)[_\-\s.]+([^\s_\-.]+\.?)", base)
    if m:
        tok = m.group(2)
        found = unit_of_token(tok)
        if found:
            return found[0]
        if tok.lower() in OTHER_UNITS:
            return ("?", tok)
    return None


def _explicit(token):
    found = unit_of_token(token)
    return found[0] if found else ("?", token)


def _units_row(line, ncol):
    """Units of a units row (``mm;um``, ``[mm] [um]``) of ``ncol`` fields, else None."""
    names = _split_names(line)
    if len(names) != ncol:
        return None
    units = []
    for n in names:
        inner = _BRACKET.fullmatch(n.strip())
        token = inner.group(1) if inner else n
        if not token or " " in token.strip() or _NUMBER.match(token.strip()):
            return None
        units.append(_explicit(token))
    return units if any(isinstance(u, str) for u in units) else None


def find_titles(header, ncol):
    """The column titles of a table of ``ncol`` columns from its header lines, or None.

    The last header line is the title line when it splits into ``ncol`` names none of which is
    a number (a ``#`` line too: numpy's ``savetxt`` header); a units row below a names row is
    read as the units of those names. A one-column table takes a one-name title line.

    Parameters
    ----------
    header : list of str
        The lines above the numbers.
    ncol : int
        Columns of the table.

    Returns
    -------
    Titles or None
    """
    lines = [h for h in header if h.strip() and h.strip() != "#"]
    if not lines:
        return None
    last = lines[-1]
    urow = _units_row(last, ncol)
    if urow is not None:
        above = _split_names(lines[-2]) if len(lines) > 1 else None
        names = above if above is not None and len(above) == ncol else [""] * ncol
        text = (lines[-2] + " / " + last) if above is not None and len(above) == ncol else last
        return Titles(names, urow, text.strip(), 2 if text != last else 1)
    if _KEY_VALUE.match(last) and len(_split_names(last)) != ncol:
        return None
    names = _split_names(last)
    if len(names) != ncol or any(_NUMBER.match(n.replace(",", ".")) for n in names if n):
        return None
    if any(re.search(r"\d[.,]\d", n) for n in names):  # "Spacing;0,05 mm": a key and a value
        return None
    return Titles(names, [_title_unit(n) for n in names], last.strip())


@dataclass
class Preamble:
    """What a preamble of ``key: value`` lines says.

    Attributes
    ----------
    spacing : tuple or None
        (value, unit or None, line) of the x spacing.
    dy : tuple or None
        Likewise for y.
    units, x_units, z_units : tuple or None
        (canonical unit, line) for every column, the coordinates, the heights.
    nodata : float or None
        The missing-value marker.
    other : dict
        Other keys as written.
    """

    spacing: tuple | None = None
    dy: tuple | None = None
    units: tuple | None = None
    x_units: tuple | None = None
    z_units: tuple | None = None
    nodata: float | None = None
    other: dict = field(default_factory=dict)


def _norm_key(key):
    return re.sub(r"[^a-z0-9µμ]+", " ", key.lower()).strip()


def _unit_value(path, value, line):
    inner = _BRACKET.fullmatch(value.strip())
    token = (inner.group(1) if inner else value).strip()
    found = unit_of_token(token)
    if not found:
        raise InputError(
            path, f"preamble line {line!r}: {token!r} is not a length unit roadscan knows (m, cm, mm, um, nm)"
        )
    return found[0], line


def _number_unit(path, value, decimal, line):
    v = value.strip()
    if decimal == ",":
        v = v.replace(",", ".")
    parts = re.split(r"[\s;,\t]+", v, maxsplit=1)
    if not _NUMBER.match(parts[0]):
        raise InputError(path, f"preamble line {line!r}: {parts[0]!r} is not a number")
    unit = None
    if len(parts) > 1 and parts[1].strip():
        unit = _explicit(parts[1].strip().strip("[]()"))
        if not isinstance(unit, str):
            raise InputError(
                path,
                f"preamble line {line!r}: {unit[1]!r} is not a length unit "
                f"roadscan knows (m, cm, mm, um, nm)",
            )
    return float(parts[0]), unit


def read_preamble(path, lines, decimal="."):
    """The :class:`Preamble` of the header ``lines`` (module notes).

    Parameters
    ----------
    path : str or Path
        File named in errors.
    lines : list of str
        Header lines (the title line excluded).
    decimal : str
        The table's decimal mark (``","``: ``0,05`` is 0.05).

    Returns
    -------
    Preamble

    Raises
    ------
    InputError
        For a value that is not a number or unit where one is needed, and a scale key.
    """
    pre = Preamble()
    for line in lines:
        m = _KEY_VALUE.match(line.strip())
        if not m:
            continue
        raw_key, value = m.group(1), m.group(2).strip()
        key_unit = _BRACKET.search(raw_key)
        key = _norm_key(_BRACKET.sub(" ", raw_key))
        if key in _SPACING_KEYS or key in _DY_KEYS:
            v, unit = _number_unit(path, value, decimal, line)
            if unit is None and key_unit:
                unit = _explicit(key_unit.group(1))
                if not isinstance(unit, str):
                    raise InputError(
                        path,
                        f"preamble line {line!r}: {unit[1]!r} is not a length "
                        f"unit roadscan knows (m, cm, mm, um, nm)",
                    )
            if key in _SPACING_KEYS:
                pre.spacing = (v, unit, line.strip())
            else:
                pre.dy = (v, unit, line.strip())
        elif key in _UNIT_KEYS:
            pre.units = _unit_value(path, value, line.strip())
        elif key in _X_UNIT_KEYS:
            pre.x_units = _unit_value(path, value, line.strip())
        elif key in _Z_UNIT_KEYS:
            pre.z_units = _unit_value(path, value, line.strip())
        elif key in _NODATA_KEYS:
            v = value.replace(",", ".") if decimal == "," else value
            try:
                pre.nodata = float(v.split()[0])
            except (ValueError, IndexError):
                pass  # "missing: NaN" or words: nothing to mark
        elif any(w in key.split() for w in _SCALE_WORDS):
            try:
                v = float((value.replace(",", ".") if decimal == "," else value).split()[0])
            except (ValueError, IndexError):
                v = None
            if v is not None and v != 1.0:
                raise InputError(
                    path,
                    f"preamble line {line.strip()!r} asks for a scale roadscan "
                    f"does not apply: write the heights scaled, or remove the line",
                )
        else:
            pre.other[raw_key.strip()] = value
    return pre
