"""Documentation a package user can follow: numpydoc sections on the exported names, and no
citation of files or trackers a user does not have (DESIGN.md, issue numbers)."""

import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("roadscan", "friction", "pipelines")


def exported(package):
    """(module, name, object) for every function and class listed in an ``__all__`` of the
    package or of one of its modules (constants carry no docstring of their own)."""
    top = importlib.import_module(package)
    mods = [top] + [
        importlib.import_module(m.name) for m in pkgutil.walk_packages(top.__path__, package + ".")
    ]
    out = []
    for mod in mods:
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            if inspect.isfunction(obj) or inspect.isclass(obj):
                out.append((mod.__name__, name, obj))
    return out


def has_numpydoc(obj):
    """Functions: Parameters and Returns (or Yields); classes: Parameters or Attributes."""
    from numpydoc.docscrape import NumpyDocString

    doc = NumpyDocString(inspect.getdoc(obj) or "")
    if inspect.isclass(obj):
        return bool(doc["Parameters"] or doc["Attributes"])
    return bool(doc["Parameters"]) and bool(doc["Returns"] or doc["Yields"])


def coverage(packages):
    names = [x for p in packages for x in exported(p)]
    missing = [f"{m}.{n}" for m, n, obj in names if not has_numpydoc(obj)]
    return 1 - len(missing) / len(names), missing, len(names)


def test_coverage_counter_tells_documented_from_undocumented():
    def documented(x):
        """Square.

        Parameters
        ----------
        x : float
            A number.

        Returns
        -------
        float
            x squared.
        """
        return x * x

    def prose(x):
        """Square of x (returns a float)."""
        return x * x

    assert has_numpydoc(documented) and not has_numpydoc(prose)


@pytest.mark.parametrize(
    "packages,floor", [(("friction",), 0.95), (("roadscan",), 0.95), (("pipelines",), 0.95), (PACKAGES, 0.95)]
)
def test_exported_names_carry_numpydoc_sections(packages, floor):
    pytest.importorskip("numpydoc")
    share, missing, n = coverage(packages)
    assert share >= floor, f"{share:.1%} of {n} names documented; missing: {missing}"


def test_physics_entry_points_cite_papers_with_doi():
    import friction

    for f in (friction.mu_isothermal, friction.mu_flash):
        assert re.search(r"doi:10\.\d{4,}/", inspect.getdoc(f)), f.__name__


CITATION = re.compile(r"DESIGN\.md|\b[Ii]ssues?[- ]?#?\d+")


def test_no_design_or_issue_citations_in_the_packages():
    hits = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*")):
            if path.suffix in (".py", ".md", ".html", ".j2", ".toml", ".txt") and path.is_file():
                for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                    if CITATION.search(line):
                        hits.append(f"{path.relative_to(ROOT)}:{i}: {line.strip()}")
    assert not hits, "\n".join(hits)
