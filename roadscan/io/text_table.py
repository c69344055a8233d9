"""Parse a numeric text table with optional header lines (shared by the text readers).

A table is a block of lines of numbers separated by commas, semicolons, tabs or spaces
(``nan``/``NaN`` allowed), after any header lines. Header lines are everything before the first
all-numeric line; lines starting with ``#`` are comments anywhere. Every data line must have the
same number of values.

Decimal mark (one rule, :func:`decimal_mark`; FORMATS.md "Text files"): a comma is a decimal
mark when the data's fields are separated by semicolons or tabs (``1,234;2,5``), or by spaces
with no comma acting as a separator (``1,5 2,5``); otherwise commas separate fields and the dot
is the decimal mark (``1.5,2.5``, ``1.5, 2.5``). Refused in one line: a field with two marks
(``1.234,5``, ``1,234.5``, ``1,234,567``: thousands separators), digits grouped by spaces inside
a semicolon-separated field, both marks used as decimals in one file, and commas that both
separate fields and sit between digits (``1,5, 2,5``: ambiguous).
"""
from __future__ import annotations

import io
import re
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ._common import check_file, get_max_pixels, default_max_pixels

__all__ = ["Table", "read_table", "read_text", "column_units", "decimal_mark"]

ESRI_KEYS = {"ncols", "nrows", "xllcorner", "yllcorner", "xllcenter", "yllcenter", "cellsize",
             "dx", "dy", "nodata_value"}
_SPLIT = re.compile(r"[,;\s]+")


@dataclass
class Table:
    """Numbers of a text table and the lines above them.

    Attributes
    ----------
    values : ndarray, shape (rows, columns)
        The numbers.
    header : list of str
        The lines above them.
    first_line : int
        Line number of the first numeric row.
    decimal : str
        Decimal mark.
    """

    values: np.ndarray                      # (rows, columns) float64
    header: list = field(default_factory=list)   # header lines (stripped), comments included
    first_line: int = 1                     # 1-based line number of the first data row
    decimal: str = "."                      # decimal mark of the data ("." or ",")


def read_text(path):
    """The file's text (UTF-8, with or without BOM; Latin-1 as fallback).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    str
    """
    p = check_file(path)
    size = p.stat().st_size
    limit = get_max_pixels() or default_max_pixels()
    if size // 2 > limit:   # a value takes at least 2 characters (digit and separator)
        raise InputError(path, f"text file of {size / 1e6:.4g} MB may hold up to {size // 2:.3g} values, "
                               f"above the limit of {limit:.3g} points; raise it with {{max_pixels}} N",
                         "max_pixels")
    raw = p.read_bytes()
    if b"\x00" in raw[:4096]:
        raise InputError(path, "binary file, not a text table")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    if not text.strip():
        raise InputError(path, "empty file")
    return text


def _tokens(line):
    return [t for t in _SPLIT.split(line.strip()) if t]


def _is_numeric(tokens):
    if not tokens:
        return False
    try:
        for t in tokens:
            float(t)
    except ValueError:
        return False
    return True


_TWO_MARKS = re.compile(r"\d*[.,]\d*[.,]\d[\d.,]*")          # 1.234,5  1,234.5  1,234,567
_SPACED_DIGITS = re.compile(r"\d[ \u00a0\u202f]+\d")    # 1 234,5 inside a ';' field
_COMMA_SEP = re.compile(r",[ \t]|[ \t],|,$|^,|,,", re.MULTILINE)  # a comma separating fields
_COMMA_IN_NUMBER = re.compile(r"\d,\d")
_SPACE_BETWEEN = re.compile(r"[\d.][ \t]+[-+.\dnN]")
_DECIMAL_COMMA_PARTS = re.compile(r"(?:^|,)\s*(-0|[-+]?0\d+)\s*(?=,|$)", re.MULTILINE)


def decimal_mark(path, block):
    """The decimal mark (``"."`` or ``","``) of the data lines ``block`` (one string).

    The rule (module notes): commas are decimal marks when the fields are separated by
    semicolons or tabs, or by spaces with no comma separating fields; else they separate
    fields. Thousands separators, mixed marks and ambiguous commas raise :class:`InputError`.

    Parameters
    ----------
    path : str or Path
        File named in errors.
    block : str
        The data lines.

    Returns
    -------
    str
        ``"."`` or ``","``.
    """
    if "," not in block:
        _check_grouped_thousands(path, block, ".")
        return "."
    if ";" in block or "\t" in block:
        sep = "semicolon" if ";" in block else "tab"
        where = "separated by semicolons" if sep == "semicolon" else "separated by tabs"
    elif _SPACE_BETWEEN.search(block) and not _COMMA_SEP.search(block):
        where = "separated by spaces"
    else:
        if _COMMA_IN_NUMBER.search(block) and re.search(r",[ \t]|[ \t],", block):
            raise InputError(path, "ambiguous commas: they both separate fields and sit between "
                                   "digits (decimal commas?); separate fields with ';' or tabs")
        # no decimal point at all, and fields an integer writer never makes ('-0', '0056'): the
        # commas are decimal commas that also separate fields (0,1609,-0,0056 is 0.1609;-0.0056)
        m = None if "." in block else _DECIMAL_COMMA_PARTS.search(block)
        if m:
            raise InputError(path, f"comma-separated numbers without a decimal point, with a field "
                                   f"{m.group(1)!r} no integer column holds: decimal commas used as "
                                   f"field separators too? separate fields with ';' or tabs")
        return "."   # comma-separated fields, dot decimals
    m = _TWO_MARKS.search(block)
    if m:
        raise InputError(path, f"{m.group(0)!r} has a thousands separator (fields {where}, "
                               f"commas are decimal marks); write numbers without grouping")
    if where.endswith("semicolons"):
        m = _SPACED_DIGITS.search(block)
        if m:
            raise InputError(path, f"{m.group(0)!r}: digits grouped by spaces in a field "
                                   f"(thousands separator?); write numbers without grouping")
    if re.search(r"\d\.\d", block):
        raise InputError(path, f"both '.' and ',' are used as decimal marks (fields {where}); "
                               f"use one")
    bad = re.search(r"(?<!\d),|,(?!\d)", block)
    if bad:
        raise InputError(path, f"a comma not between digits in fields {where} (commas are "
                               f"decimal marks there)")
    _check_grouped_thousands(path, block, ",")
    return ","


def _check_grouped_thousands(path, block, mark):
    """Refuse integers grouped by one thousands separator read as decimals: ``160,878`` (or
    ``160.878``) beside plain ``44`` in the same column, every marked field with exactly three
    digits after the mark and none with integer part 0 (a decimal writer gives ``0,044``; a
    grouping one gives ``44``). Read as decimals the heights would be 1000 times too small."""
    sep = r"[;\s]+" if mark == "," else r"[,;\s]+"
    rows = [re.split(sep, line.strip()) for line in block.splitlines()[:2000] if line.strip()]
    if not rows or any(len(r) != len(rows[0]) for r in rows):
        return
    m = re.escape(mark)
    marked = [f for r in rows for f in r if mark in f]
    if len(marked) < 10 or not all(re.fullmatch(rf"[-+]?[1-9]\d{{0,2}}{m}\d{{3}}", f) for f in marked):
        return
    for j in range(len(rows[0])):
        col = [r[j] for r in rows]
        plain = [f for f in col if re.fullmatch(r"[-+]?\d{1,3}", f)]
        if plain and any(mark in f for f in col):
            raise InputError(path, f"{next(f for f in col if mark in f)!r} beside {plain[0]!r} in one "
                                   f"column: '{mark}' groups thousands (integers), not decimals; "
                                   f"write numbers without grouping")


def read_table(path, text=None):
    """Parse ``path`` into a :class:`Table`; raises :class:`InputError` for ragged or non-numeric
    rows, or when there is no numeric row at all.

    Parameters
    ----------
    path : str or Path
        The file.
    text : str, optional
        Its text, when already read.

    Returns
    -------
    Table
    """
    if text is None:
        text = read_text(path)
    lines = text.splitlines()
    header, start = [], None
    for i, line in enumerate(lines):
        s = line.strip()
        if not s:
            continue
        if s.startswith("#") or not _is_numeric(_tokens(s)):
            header.append(s)
            continue
        start = i
        break
    if start is None:
        raise InputError(path, "no numeric data found")
    rows = [i for i in range(start, len(lines)) if not lines[i].lstrip().startswith("#")]
    decimal = decimal_mark(path, "\n".join(lines[i].strip() for i in rows))
    if decimal == ",":
        lines = list(lines)
        for i in rows:
            lines[i] = lines[i].replace(",", ".")
    first = lines[start].strip()
    ncol0 = len(_tokens(first))
    for h in header:
        toks = _tokens(h)
        if (not h.startswith("#") and toks[0].lower() not in ESRI_KEYS and len(toks) == ncol0
                and 2 * sum(_is_numeric([t]) for t in toks) >= len(toks)):
            word = next(t for t in toks if not _is_numeric([t]))
            raise InputError(path, f"non-numeric value {word!r} in a data row above line {start + 1}")
    ncol = ncol0
    # fast path: numpy's C parser; anything it refuses goes through the checks below, which
    # accept the same syntax or name the line that is wrong
    delim = ";" if ";" in first else ("," if "," in first else None)
    try:
        fast = np.loadtxt(io.StringIO("\n".join(lines[start:])), delimiter=delim, comments="#",
                          ndmin=2, dtype=np.float64)
    except ValueError:
        fast = None
    if fast is not None and fast.shape[1] == ncol:
        return Table(fast, header, start + 1, decimal)
    data_lines, numbers = [], []
    for i in range(start, len(lines)):
        s = lines[i].strip()
        if not s or s.startswith("#"):
            continue
        data_lines.append(i)
        numbers.append(s)
    sep_comma = delim is not None
    counts = np.fromiter((len(_tokens(s)) for s in numbers), dtype=np.int64, count=len(numbers))
    # an empty field between two commas ("1,,2") is a missing value, not a separator
    if sep_comma:
        empty = [k for k, s in enumerate(numbers) if re.search(r"[,;]\s*[,;]|^[,;]|[,;]$", s)]
        if empty:
            k = empty[0]
            raise InputError(path, f"empty field on line {data_lines[k] + 1}")
    bad = np.flatnonzero(counts != ncol)
    if bad.size:
        k = int(bad[0])
        raise InputError(path, f"ragged rows: line {data_lines[k] + 1} has {counts[k]} values, "
                               f"line {data_lines[0] + 1} has {ncol}")
    try:
        values = np.array(_SPLIT.split(" ".join(numbers).strip()), dtype=np.float64)
    except ValueError:
        for k, s in enumerate(numbers):
            if not _is_numeric(_tokens(s)):
                word = next(t for t in _tokens(s) if not _is_numeric([t]))
                raise InputError(path, f"non-numeric value {word!r} on line {data_lines[k] + 1}") from None
        raise InputError(path, "non-numeric values") from None
    return Table(values.reshape(len(numbers), ncol), header, data_lines[0] + 1, decimal)


_UNIT_IN_NAME = re.compile(r"[\(\[]\s*(m|mm|um|µm|μm|nm)\s*[\)\]]", re.IGNORECASE)


def column_units(header_line):
    """Units named in a column-title line, e.g. ``"x (mm), z (mm)"`` -> ``["mm", "mm"]``.

    Returns None when the last header line is not a list of titles with units for every column.

    Parameters
    ----------
    header_line : str
        A title line.

    Returns
    -------
    list of str or None
    """
    if header_line is None or header_line.startswith("#"):
        return None
    names = [n for n in re.split(r"[,;\t]|\s{2,}", header_line.strip()) if n.strip()]
    if len(names) < 2:
        names = _tokens(header_line)
    found = [_UNIT_IN_NAME.search(n) for n in names]
    if not names or not all(found):
        return None
    return [m.group(1) for m in found]
