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
from ._common import check_file, default_max_pixels, get_max_pixels

__all__ = ["Table", "read_table", "read_text", "column_units", "decimal_mark"]

ESRI_KEYS = {
    "ncols",
    "nrows",
    "xllcorner",
    "yllcorner",
    "xllcenter",
    "yllcenter",
    "cellsize",
    "dx",
    "dy",
    "nodata_value",
}
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
    markers : list of str
        The missing-value markers found (upper case; ``"(empty field)"`` for empty fields).
    """

    values: np.ndarray  # (rows, columns) float64
    header: list = field(default_factory=list)  # header lines (stripped), comments included
    first_line: int = 1  # 1-based line number of the first data row
    decimal: str = "."  # decimal mark of the data ("." or ",")
    markers: list = field(default_factory=list)  # missing-value markers found (upper case)


def read_text(path):
    """The file's text (UTF-8, with or without BOM; UTF-16 with its BOM; Latin-1 as fallback).

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
    if size // 2 > limit:  # a value takes at least 2 characters (digit and separator)
        raise InputError(
            path,
            f"text file of {size / 1e6:.4g} MB may hold up to {size // 2:.3g} values, "
            f"above the limit of {limit:.3g} points; raise it with {{max_pixels}} N",
            "max_pixels",
        )
    raw = p.read_bytes()
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):  # UTF-16 ("Unicode text" of spreadsheets)
        try:
            text = raw.decode("utf-16")
        except UnicodeDecodeError:
            raise InputError(path, "starts as UTF-16 text but does not decode as UTF-16") from None
        if not text.strip():
            raise InputError(path, "empty file")
        return text
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


_TWO_MARKS = re.compile(r"\d*[.,]\d*[.,]\d[\d.,]*")  # 1.234,5  1,234.5  1,234,567
_SPACED_DIGITS = re.compile(r"\d[ \u00a0\u202f]+\d")  # 1 234,5 inside a ';' field
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
            raise InputError(
                path,
                "ambiguous commas: they both separate fields and sit between "
                "digits (decimal commas?); separate fields with ';' or tabs",
            )
        # no decimal point at all, and fields an integer writer never makes ('-0', '0056'): the
        # commas are decimal commas that also separate fields (0,1609,-0,0056 is 0.1609;-0.0056)
        m = None if "." in block else _DECIMAL_COMMA_PARTS.search(block)
        if m:
            raise InputError(
                path,
                f"comma-separated numbers without a decimal point, with a field "
                f"{m.group(1)!r} no integer column holds: decimal commas used as "
                f"field separators too? separate fields with ';' or tabs",
            )
        return "."  # comma-separated fields, dot decimals
    m = _TWO_MARKS.search(block)
    if m:
        raise InputError(
            path,
            f"{m.group(0)!r} has a thousands separator (fields {where}, "
            f"commas are decimal marks); write numbers without grouping",
        )
    if where.endswith("semicolons"):
        m = _SPACED_DIGITS.search(block)
        if m:
            raise InputError(
                path,
                f"{m.group(0)!r}: digits grouped by spaces in a field "
                f"(thousands separator?); write numbers without grouping",
            )
    if re.search(r"\d\.\d", block):
        raise InputError(path, f"both '.' and ',' are used as decimal marks (fields {where}); use one")
    bad = re.search(r"(?<!\d),|,(?!\d)", block)
    if bad:
        raise InputError(
            path, f"a comma not between digits in fields {where} (commas are decimal marks there)"
        )
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
            raise InputError(
                path,
                f"{next(f for f in col if mark in f)!r} beside {plain[0]!r} in one "
                f"column: '{mark}' groups thousands (integers), not decimals; "
                f"write numbers without grouping",
            )


#: missing-value markers read as dropouts (NaN), as whole fields, case ignored (FORMATS.md)
MISSING_MARKERS = (
    "NA",
    "N/A",
    "n.a.",
    "#N/A",
    "#NA",
    "#NV",
    "null",
    "none",
    "nil",
    "missing",
    "-",
    "--",
    "*",
    "***",
    "1.#QNAN",
    "-1.#IND",
)
_MARKER = re.compile(
    r"(?<![^,;\s])(?:#N/?A|#NV|N/A|NA|n\.a\.|null|none|nil|missing|-{1,2}|\*+|"
    r"[-+]?1\.#(?:QNAN|SNAN|IND)0*)(?![^,;\s])",
    re.IGNORECASE,
)
_EMPTY_FIELD = re.compile(r"(?:(?<=[,;\t])|^)[ ]*(?=[,;\t]|$)", re.MULTILINE)
_MAYBE_MARKER = re.compile(r"[^-\d\s.,;+eEnaNA]|-(?![\d.])|(?<![nN])[aA]|[nN][aA](?![nN])")
_MARKER_START = re.compile(r"#N/?A\b|#NV\b", re.IGNORECASE)


def _comment(s):
    """True for a comment line (``#`` first, but not a ``#N/A`` field)."""
    return s.startswith("#") and not _MARKER_START.match(s)


def _is_data(s):
    """A data line: every field a number or a missing-value marker, at least one number (or
    two fields: a row of dropouts)."""
    toks = _tokens(s)
    if not toks:
        return False
    n_num = 0
    for t in toks:
        try:
            float(t)
            n_num += 1
        except ValueError:
            if not _MARKER.fullmatch(t):
                return False
    return n_num > 0 or len(toks) > 1


def _key_value(s):
    return re.match(r"^#?\s*[A-Za-z\u00b5\u03bc][^:=]*[:=]", s) is not None


def _dropout_fields(block):
    """``block`` (decimal points) with every missing value written ``nan``: the markers, a
    trailing comment removed, empty fields of ``,``/``;``/tab rows; and the markers found."""
    markers = []
    if _MAYBE_MARKER.search(block):
        markers = sorted({m.upper() for m in _MARKER.findall(block)})
        if markers:
            block = _MARKER.sub("nan", block)
    if "#" in block:  # "1 2  # note": a trailing comment
        block = re.sub(r"[ \t]*#.*$", "", block, flags=re.MULTILINE)
    data = block.split("\n")
    if not re.search(r"[,;]", block) and all("\t\t" in d for d in data):
        return re.sub(r"\t+", "\t", block), markers  # tabs aligning columns, not empty fields
    if re.search(r"[,;\t]", block):
        if all(d and d[-1] in ",;\t" for d in data):  # a separator closing every row
            block = "\n".join(d[:-1].rstrip() for d in data)
        if _EMPTY_FIELD.search(block):
            block = _EMPTY_FIELD.sub("nan", block)
            markers.append("(empty field)")
    return block, markers


def _check_header_rows(path, header, ncol0, start):
    """Refuse a header line that is a data row with a word in it (``1 2 abc 4``)."""
    for h in header:
        toks = _tokens(h)
        if (
            not h.startswith("#")
            and toks[0].lower() not in ESRI_KEYS
            and len(toks) == ncol0
            and not _key_value(h)
            and 2 * sum(_is_numeric([t]) for t in toks) >= len(toks)
        ):
            word = next(t for t in toks if not _is_numeric([t]))
            raise InputError(path, f"non-numeric value {word!r} in a data row above line {start + 1}")


def read_table(path, text=None):
    """Parse ``path`` into a :class:`Table`; raises :class:`InputError` for ragged or non-numeric
    rows, or when there is no numeric row at all.

    Missing values are dropouts (NaN): ``nan`` in any case, the :data:`MISSING_MARKERS` as
    whole fields, and empty fields of ``;``, ``,`` or tab separated rows (``1;;3``); a separator
    ending every row (``1;2;``) closes the row, it opens no column.

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
        if _comment(s) or not _is_data(s):
            header.append(s)
            continue
        start = i
        break
    if start is None:
        raise InputError(path, "no numeric data found")
    if "#" in text:
        rows = [i for i in range(start, len(lines)) if lines[i].strip() and not _comment(lines[i].strip())]
    else:
        rows = [i for i in range(start, len(lines)) if lines[i].strip()]
    if "\t" in text:
        data = [lines[i].strip(" \r\n\f\v") for i in rows]
        if 2 * sum("\t" in d.strip() for d in data) < len(data):  # tabs do not separate fields:
            data = [d.strip() for d in data]  # leading/trailing ones are blanks
    else:
        data = [lines[i].strip() for i in rows]
    block = "\n".join(data)
    decimal = decimal_mark(path, block)
    if decimal == ",":
        block = block.replace(",", ".")
    first = block[: block.find("\n")] if "\n" in block else block
    delim = ";" if ";" in first else ("," if "," in first else None)
    markers = []
    try:  # fast path: numpy's C parser on a table without markers
        fast = np.loadtxt(io.StringIO(block), delimiter=delim, comments=None, ndmin=2, dtype=np.float64)
    except ValueError:
        fast = None
        block, markers = _dropout_fields(block)
        data = block.split("\n")
        first = data[0]
    ncol0 = len(_tokens(first))
    _check_header_rows(path, header, ncol0, start)
    if fast is not None and fast.shape[1] == ncol0:
        return Table(fast, header, start + 1, decimal, markers)
    ncol = ncol0
    delim = ";" if ";" in first else ("," if "," in first else None)
    try:
        fast = np.loadtxt(io.StringIO(block), delimiter=delim, comments=None, ndmin=2, dtype=np.float64)
    except ValueError:
        fast = None
    if fast is not None and fast.shape[1] == ncol:
        return Table(fast, header, start + 1, decimal, markers)
    # anything numpy refuses goes through the checks below, which name the line that is wrong
    counts = np.fromiter((len(_tokens(s)) for s in data), dtype=np.int64, count=len(data))
    bad = np.flatnonzero(counts != ncol)
    if bad.size:
        k = int(bad[0])
        raise InputError(
            path, f"ragged rows: line {rows[k] + 1} has {counts[k]} values, line {rows[0] + 1} has {ncol}"
        )
    try:
        values = np.array(_SPLIT.split(" ".join(data).strip()), dtype=np.float64)
    except ValueError:
        for k, s in enumerate(data):
            if not _is_numeric(_tokens(s)):
                word = next(t for t in _tokens(s) if not _is_numeric([t]))
                raise InputError(path, f"non-numeric value {word!r} on line {rows[k] + 1}") from None
        raise InputError(path, "non-numeric values") from None
    return Table(values.reshape(len(data), ncol), header, rows[0] + 1, decimal, markers)


def column_units(header_line):
    """Units named in a column-title line, e.g. ``"x (mm), z (um)"`` -> ``["mm", "um"]``, in
    every form :mod:`roadscan.io.text_titles` reads (``x_mm``, ``x [mm]``, ``x/mm``...).

    Returns None when the line is a comment or does not name a length unit for every column.

    Parameters
    ----------
    header_line : str
        A title line.

    Returns
    -------
    list of str or None
    """
    from .text_titles import _split_names, find_titles

    if header_line is None or header_line.startswith("#"):
        return None
    titles = find_titles([header_line], len(_split_names(header_line)))
    if titles is None or len(titles.units) < 1 or not all(isinstance(u, str) for u in titles.units):
        return None
    return list(titles.units)
