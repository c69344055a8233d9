"""The HTML of every report, from Jinja2 templates (``*.html.j2`` beside this module).

Autoescaping is on: text reaches the page escaped unless a caller marks it as HTML it built
with these templates (:func:`html_block`). Images are embedded (base64), so a report opens
offline from anywhere. Jinja2 is imported on first use: ``import pipelines`` stays light.

Templates: ``page.html.j2`` (a whole report: title, intro, sections of tables, images and
image grids; :func:`write_html`), ``table.html.j2`` (header and rows; :func:`table_html`),
``list.html.j2`` (items, optionally links; :func:`list_html`), ``campaign_table.html.j2`` (the
scans of a campaign). :mod:`pipelines.output.report` re-exports the writers.
"""

from __future__ import annotations

import base64
from functools import lru_cache
from pathlib import Path

__all__ = [
    "render",
    "html_block",
    "embedded_image",
    "table_html",
    "list_html",
    "paragraph_html",
    "write_html",
    "instrument_html",
]

_HERE = Path(__file__).resolve().parent


@lru_cache(maxsize=1)
def _environment():
    import jinja2

    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(_HERE)),
        autoescape=True,
        keep_trailing_newline=False,
        undefined=jinja2.StrictUndefined,
    )


def render(name, **context):
    """The template ``name`` (e.g. ``"table.html.j2"``) rendered with ``context`` (plain text).

    Parameters
    ----------
    name : str
        Template file name.
    **context
        Template variables.

    Returns
    -------
    str
    """
    return str(_environment().get_template(name).render(**context))


def html_block(text):
    """``text`` marked as HTML (inserted as it is, not escaped): only for HTML that the report
    writers built themselves (a rendered template).

    Parameters
    ----------
    text : str
        HTML.

    Returns
    -------
    markupsafe.Markup
    """
    from markupsafe import Markup

    return Markup(str(text))


def embedded_image(path):
    """``{"data": base64 of the PNG, "alt": its file stem}`` for the page template.

    Parameters
    ----------
    path : str or Path
        A PNG.

    Returns
    -------
    dict
    """
    p = Path(path)
    return {"data": base64.b64encode(p.read_bytes()).decode("ascii"), "alt": p.stem}


def _fmt(x):
    """A table cell as text (floats to 3 significant digits; the template escapes it)."""
    if x is None:
        return "—"
    if isinstance(x, float):
        from pipelines.output.units import sig3

        return sig3(x)
    if isinstance(x, (list, tuple)):
        return ", ".join(_fmt(v) for v in x)
    return str(x)


def table_html(rows, header=None):
    """An HTML table (``templates/table.html.j2``) from rows of cells (or a dict: one row per
    key); every cell is text, escaped.

    Parameters
    ----------
    rows : list or dict
        Rows of cells.
    header : list of str, optional
        Header.

    Returns
    -------
    str
    """
    if isinstance(rows, dict):
        rows = [(k, v) for k, v in rows.items()]
    return render(
        "table.html.j2", header=[str(h) for h in header or ()], rows=[[_fmt(c) for c in row] for row in rows]
    )


def list_html(items, links=None):
    """An HTML list (``templates/list.html.j2``) of text items, escaped; ``links``: an href per
    item (None: plain items).

    Parameters
    ----------
    items : list of str
        Items.
    links : list of str, optional
        Hrefs.

    Returns
    -------
    str
    """
    items = [str(i) for i in items]
    hrefs = [str(h) if h else None for h in links] if links is not None else [None] * len(items)
    return render("list.html.j2", items=list(zip(items, hrefs)))


_CSS = """body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;color:#222}
h1{font-size:1.5em}h2{font-size:1.15em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:3px 8px;
text-align:right;font-size:.9em}th{background:#f0f0f0}td:first-child{text-align:left}
img{max-width:100%;margin:.4em 0}.grid{display:flex;flex-wrap:wrap;gap:8px}
.grid img{max-width:540px}p.note{color:#555;font-size:.9em}"""


#: labels of the instrument block (``HeightMap.meta["instrument"]``) in a report's header
_INSTRUMENT_LABELS = (
    ("vendor", "vendor"),
    ("name", "instrument"),
    ("serial", "serial"),
    ("software", "software"),
    ("acquired", "acquired"),
    ("objective", "objective"),
    ("magnification", "magnification"),
    ("lateral_resolution_m", "lateral resolution"),
    ("tip_radius_m", "tip radius"),
    ("format", "file format"),
    ("units", "file units"),
    ("undefined_points", "undefined points"),
    ("channel", "channel"),
    ("reader", "read by"),
    ("comment", "comment"),
)


def _instrument_value(key, value):
    from roadscan.units import length

    if isinstance(value, (int, float)) and not isinstance(value, bool) and key.endswith("_m"):
        return length(value)  # "5.00 µm", not "5e-06"
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def instrument_html(block):
    """One escaped line for a report's header from a scan's ``meta["instrument"]`` block
    (instrument, date, objective, units, lateral resolution, undefined points, reader); None
    when there is none.

    Parameters
    ----------
    block : dict or None
        ``meta["instrument"]``.

    Returns
    -------
    str or None
    """
    if not isinstance(block, dict) or not block:
        return None
    parts = [
        f"{label}: {_instrument_value(key, block[key])}"
        for key, label in _INSTRUMENT_LABELS
        if block.get(key) not in (None, "")
    ]
    if not parts:
        return None
    return str(render("instrument.html.j2", line=" · ".join(parts)))


def _is_png(item):
    return isinstance(item, Path) or (isinstance(item, str) and item.endswith(".png"))


def paragraph_html(text, lead=None, note=False):
    """A paragraph (``templates/paragraph.html.j2``) of escaped ``text``, with an optional bold
    ``lead``; ``note``: in the report's small grey style.

    Parameters
    ----------
    text : str
    lead : str, optional
    note : bool

    Returns
    -------
    str
    """
    return render(
        "paragraph.html.j2", text=str(text), lead=None if lead is None else str(lead), note=bool(note)
    )


def write_html(path, title, sections, intro=None):
    """Write a self-contained report (``templates/page.html.j2``, written atomically).

    ``title``: text (escaped). ``intro``: HTML (e.g. :func:`instrument_html`) or None.
    ``sections``: list of (heading, items); each item is a PNG path (embedded as base64), a
    list of PNG paths (shown side by side), or a string of HTML built by this module's writers
    (:func:`table_html`, :func:`list_html`) and inserted as it is.

    Parameters
    ----------
    path : str or Path
        Output HTML.
    title : str
        Title.
    sections : list of tuple
        (heading, items).
    intro : str, optional
        HTML at the top.

    Returns
    -------
    Path
    """
    from roadscan.io.atomic import atomic_write_text

    page = []
    for heading, items in sections:
        if not isinstance(items, (list, tuple)):
            items = [items]
        shown = []
        for item in items:
            if isinstance(item, (list, tuple)):
                shown.append(("grid", [embedded_image(p) for p in item]))
            elif _is_png(item):
                shown.append(("image", embedded_image(item)))
            else:
                shown.append(("html", html_block(item)))
        page.append((str(heading), shown))
    text = render(
        "page.html.j2",
        title=str(title),
        css=html_block(_CSS),
        sections=page,
        intro=html_block(intro) if intro else None,
    )
    atomic_write_text(path, text)
    return Path(path)
