"""The HTML of every report, from Jinja2 templates (``*.html.j2`` beside this module).

Autoescaping is on: text reaches the page escaped unless a caller marks it as HTML it built
with these templates (:func:`html_block`). Images are embedded (base64), so a report opens
offline from anywhere. Jinja2 is imported on first use: ``import pipelines`` stays light.

Templates: ``page.html.j2`` (a whole report: title, intro, sections of tables, images and
image grids), ``table.html.j2`` (header and rows), ``list.html.j2`` (items, optionally links).
"""
from __future__ import annotations

import base64
from functools import lru_cache
from pathlib import Path

__all__ = ["render", "html_block", "embedded_image"]

_HERE = Path(__file__).resolve().parent


@lru_cache(maxsize=1)
def _environment():
    import jinja2

    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(_HERE)), autoescape=True,
                              keep_trailing_newline=False, undefined=jinja2.StrictUndefined)


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
