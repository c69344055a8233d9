"""The documentation site's sources: the API pages name the entry points the site must
document, and the gallery has examples that draw figures. (The site itself is built by CI:
``sphinx-build -W -b html docs OUT``.)"""

import ast
import os
import re
import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def test_api_pages_name_the_entry_points():
    text = {p.stem: p.read_text() for p in (DOCS / "api").glob("*.rst")}
    assert "pipelines.analyse" in text["pipelines"]
    assert re.search(r"^\s+mu_isothermal$", text["friction"], flags=re.M)
    assert re.search(r"^\s+mu_flash$", text["friction"], flags=re.M)
    assert re.search(r"^\s+psd_area$", text["roadscan"], flags=re.M)


def test_the_documented_names_exist():
    import friction
    import pipelines
    import roadscan

    assert callable(pipelines.analyse) and callable(roadscan.psd_area)
    assert callable(friction.mu_isothermal) and callable(friction.mu_flash)
    assert "psd_area" in roadscan.__all__


def test_gallery_examples_draw_figures_and_parse():
    examples = sorted((DOCS / "examples").glob("plot_*.py"))
    assert len(examples) >= 3
    for path in examples:
        src = path.read_text()
        tree = ast.parse(src)
        assert ast.get_docstring(tree), path.name  # the title block of the page
        assert "plt.subplots" in src or "plt.figure" in src, path.name


def test_ci_builds_the_site_after_the_tests():
    lines = [
        row
        for row in (ROOT / ".ci" / "run").read_text().splitlines()
        if row.strip() and not row.startswith("#")
    ]
    test_line = next(i for i, row in enumerate(lines) if "pytest" in row)
    build_line = next(i for i, row in enumerate(lines) if "sphinx-build -W" in row)
    assert build_line > test_line and ".[docs]" in lines[build_line]


def _rst_blocks(text, language):
    """The ``.. code-block:: language`` blocks of a reST page, dedented."""
    blocks, lines = [], text.splitlines()
    for i, line in enumerate(lines):
        if line.strip() == f".. code-block:: {language}":
            body = []
            for nxt in lines[i + 2 :]:
                if nxt.strip() and not nxt.startswith("   "):
                    break
                body.append(nxt[3:])
            blocks.append("\n".join(body).strip() + "\n")
    return blocks


def test_guide_python_examples_run(monkeypatch):
    """Every Python block of the guide and the getting-started page runs as written from the
    repository root (the pipelines.analyse examples write into a temporary folder)."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(ROOT)
    pages = [DOCS / "getting_started.rst", DOCS / "index.rst", *sorted((DOCS / "guide").glob("*.rst"))]
    ran = 0
    for page in pages:
        for block in _rst_blocks(page.read_text(), "python"):
            block = block.replace('"out/asphalt"', 'str(__import__("tempfile").mkdtemp())')
            exec(compile(block, str(page.relative_to(ROOT)), "exec"), {})
            ran += 1
    assert ran >= 5


def _rst_problems(rst):
    """docutils' warnings and errors on a reST text (Sphinx's code-block read as docutils' code)."""
    import docutils.core
    import docutils.nodes
    from docutils.parsers.rst import directives
    from docutils.parsers.rst.directives.body import CodeBlock

    directives.register_directive("code-block", CodeBlock)
    doc = docutils.core.publish_doctree(rst, settings_overrides={"report_level": 5, "halt_level": 5})
    return [m.astext()[:200] for m in doc.findall(docutils.nodes.system_message) if m["level"] >= 2]


def test_markdown_pages_convert_to_clean_rest():
    """The Markdown pages the site renders (FORMATS.md, RUBBER_TOML.md, docs/md/*.md...) give
    reST without a warning, and keep their tables, code blocks and inline code."""
    import sys

    sys.path.insert(0, str(DOCS / "_ext"))
    import md_pages

    sources = [ROOT / src for src, _ in md_pages.PAGES] + sorted((DOCS / "md").glob("*.md"))
    for src in sources:
        assert _rst_problems(md_pages.md_to_rst(src.read_text(encoding="utf-8"))) == [], src.name
    sample = (
        "# T\n\nText with `a|b` and **bold** [`FORMATS.md`](FORMATS.md) x_1 *y\n\n"
        "| a | b |\n|---|---|\n| `x \\| y` | 2 |\n\n```bash\nroadscan x\n```\n"
    )
    rst = md_pages.md_to_rst(sample)
    assert ".. list-table::" in rst and ".. code-block:: bash" in rst and "``a|b``" in rst
    assert "``x | y``" in rst and _rst_problems(rst) == []


def test_docstring_examples_run(monkeypatch):
    """The Examples sections of the entry points run and print what they say (doctest)."""
    import doctest

    import friction
    import roadscan
    from roadscan import fit, io, rain

    monkeypatch.chdir(ROOT)
    objects = [
        io.read,
        fit.fit_self_affine,
        rain.rain_fill,
        roadscan.psd_area,
        friction.mu_isothermal,
        friction.mu_flash,
        friction.SelfAffinePSD,
    ]
    finder, runner = doctest.DocTestFinder(recurse=False), doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    tried = 0
    for obj in objects:
        for test in finder.find(obj, name=obj.__qualname__, globs={}):
            result = runner.run(test)
            assert result.failed == 0, obj.__qualname__
            tried += result.attempted
    assert tried >= 20


# hosts that serve MathJax or KaTeX (and other scripts) to pages that do not ship their own
_CDNS = (
    "cdn.jsdelivr.net",
    "cdnjs.cloudflare.com",
    "unpkg.com",
    "polyfill.io",
    "mathjax.org",
    "katex.org",
    "googleapis.com",
)
_LOADED = re.compile(r'<(?:script|link)\b[^>]*\b(?:src|href)="([^"]+)"')


def test_math_is_configured_to_come_from_the_site(monkeypatch):
    """conf.py renders equations without network: the MathJax shipped by sphinx-mathjax-offline
    (copied into the site's _static) is the one the pages load, and the docs extra installs it."""
    import sys

    monkeypatch.setattr(sys, "path", list(sys.path))  # conf.py adds its folders
    monkeypatch.setenv("MPLBACKEND", os.environ.get("MPLBACKEND", "Agg"))
    conf = runpy.run_path(str(DOCS / "conf.py"))
    assert "sphinx-mathjax-offline" in conf["extensions"]
    path = conf["mathjax_path"]
    assert not re.match(r"(https?:)?//", path) and not any(cdn in path for cdn in _CDNS), path
    tomllib = pytest.importorskip("tomllib")  # Python >= 3.11

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert any(req.startswith("sphinx-mathjax-offline") for req in extras["docs"])


@pytest.mark.skipif(
    not os.environ.get("ROADSCAN_DOCS_SITE"),
    reason="needs a built site: ROADSCAN_DOCS_SITE=OUT after sphinx-build (CI sets it)",
)
def test_built_site_loads_no_script_from_the_network():
    """The built site: every page with an equation loads MathJax from a file of the site that
    exists (with its fonts), and no page loads a script or style sheet from another host."""
    site = Path(os.environ["ROADSCAN_DOCS_SITE"])
    pages = sorted(site.rglob("*.html"))
    math_pages = 0
    for page in pages:
        text = page.read_text(encoding="utf-8")
        loaded = _LOADED.findall(text)
        scripts = re.findall(r'<script\b[^>]*\bsrc="([^"]+)"', text)
        assert not [u for u in scripts if re.match(r"(https?:)?//", u)], page
        assert not [u for u in loaded if any(cdn in u for cdn in _CDNS)], page
        if 'class="math' in text:
            math_pages += 1
            mathjax = [u for u in scripts if "mathjax" in u.lower()]
            assert mathjax, page
            for u in mathjax:
                assert (page.parent / u.split("?")[0]).resolve().is_file(), (page, u)
    assert math_pages >= 10  # the theory page, the API pages, the gallery...
    fonts = site / "_static" / "mathjax" / "output" / "chtml" / "fonts"
    assert any(fonts.rglob("*.woff")), fonts


@pytest.mark.skipif(
    not os.environ.get("ROADSCAN_DOCS_SITE"),
    reason="needs a built site: ROADSCAN_DOCS_SITE=OUT after sphinx-build (CI sets it)",
)
def test_built_api_page_lists_every_parameter_of_every_job():
    """The pipelines API page documents each public job with every parameter of its real
    signature (names taken from inspect.signature, looked up in the rendered entry)."""
    import inspect

    import pipelines

    page = (Path(os.environ["ROADSCAN_DOCS_SITE"]) / "api" / "pipelines.html").read_text(encoding="utf-8")
    jobs = ["analyse", "compare", "dry_vs_wet", "rain_fill", "friction", "combine", "diagnose", "batch"]
    for name in jobs:
        start = page.find(f'id="pipelines.{name}"')
        assert start >= 0, name
        end = page.find('<dt class="sig', start + 1)
        entry = page[start : end if end > 0 else None]
        params = list(inspect.signature(getattr(pipelines, name)).parameters)
        assert len(params) >= 2, name
        missing = [p for p in params if f"<strong>{p}</strong>" not in entry]
        assert missing == [], (name, missing)
    assert "AnalysisResult" in page and "q_per_m" in page and ":attr:" not in page
