"""Sphinx configuration of roadscan's documentation site.

Build it with ``pip install -e '.[docs]'`` then ``sphinx-build -W -b html docs OUT``.
"""
import os
import re
import sys
from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(ROOT))
os.environ.setdefault("MPLBACKEND", "Agg")

project = "roadscan"
author = "the roadscan developers"
copyright = "roadscan developers, BSD-3-Clause"
try:
    release = _version("roadscan")
except PackageNotFoundError:          # an uninstalled checkout
    release = "0.1.0"
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",   # MathJax 3 shipped in the package, copied into _static/mathjax
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "md_pages",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5", "**/*.codeobj.json"]
root_doc = "index"

# -- API reference -------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = True
add_module_names = False


# -- examples ------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "abort_on_example_error": True,
    "image_scrapers": ("matplotlib",),
    # no computation-times pages: sphinx-gallery's table loads jQuery and DataTables from CDNs
    "write_computation_times": False,
}

# -- HTML ----------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"roadscan {release}"
html_static_path = ["_static"]
html_css_files = ["roadscan.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
}
html_show_sourcelink = False

suppress_warnings = ["misc.highlighting_failure"]

# Equations render with no network: MathJax 3 comes with the sphinx-mathjax-offline package
# (docs extra), which copies it into the site's _static/mathjax; the pages load it from there
# (a path relative to _static), never from a CDN (tests/test_docs_site.py checks the built site).
mathjax_path = "mathjax/tex-chtml.js"


def _plain_text_safe(app, what, name, obj, options, lines):
    """Keep plain-text formulas of docstrings from being read as reST markup.

    Docstrings write formulas such as ``|E|^2`` in plain text: a bare ``|`` is escaped (reST
    would read a substitution), and ``... `` in a summary line is written as an ellipsis
    character (autosummary would end the sentence there).
    """
    if what == "module":
        parent = name.rsplit(".", 1)[0]
        first_blank = next((k for k, line in enumerate(lines) if not line.strip()), len(lines))
        for k in range(first_blank):       # the summary autosummary shows
            lines[k] = lines[k].replace("... ", "\u2026 ")
        for k, line in enumerate(lines):   # relative module references, made absolute
            lines[k] = re.sub(r":mod:`\.(\w+)`", lambda m: f":mod:`{parent}.{m.group(1)}`", line)
    literal_indent = None
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if literal_indent is not None:
            if stripped and indent <= literal_indent:
                literal_indent = None
            else:
                continue
        parts = line.split("``")
        for k in range(0, len(parts), 2):
            parts[k] = parts[k].replace("\\|", "|").replace("|", "\\|").replace("... ", "\u2026 ")
        lines[i] = "``".join(parts)
        underlined = i + 1 < len(lines) and re.fullmatch(r"([-=~^])\1{2,}", lines[i + 1].strip())
        if not underlined:                 # a citation of the theory page becomes a link
            lines[i] = lines[i].replace("docs: Theory", ":doc:`docs: Theory </theory>`")
        if stripped.endswith("::") or stripped.startswith(".. math::") or stripped.startswith(".. code"):
            literal_indent = indent


def setup(app):
    app.connect("autodoc-process-docstring", _plain_text_safe, priority=400)
