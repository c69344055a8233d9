"""The house rules of ARCHITECTURE.md, checked from the source (issue 23).

* ``roadscan`` (metrology) and ``friction`` (the friction engine) import neither each other nor
  ``pipelines``; ``pipelines`` may import both.
* No import circle between modules of the three packages, ``benchmarks`` and ``sample_scans``
  (imports inside functions count: a circle deferred to run time is still a circle in the design).
* No module longer than 450 lines.

The graph is built from the abstract syntax tree of every module, so the check needs no import
and runs in a fraction of a second.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("roadscan", "friction", "pipelines", "benchmarks", "sample_scans")
FOUNDATIONS = ("roadscan", "friction")
MAX_LINES = 450


def _module_files(root=ROOT):
    """Map dotted module name -> path for every module of the checked packages."""
    found = {}
    for top in PACKAGES:
        for path in sorted((root / top).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            if any(p.startswith(".") or p == "__pycache__" for p in parts):
                continue
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join(parts)] = path
    return found


def _resolve(name, modules):
    """The longest known module that ``name`` (a module or an attribute of one) lies in."""
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name or None


def import_graph(modules):
    """Directed graph {module: set of modules it imports}, relative imports resolved."""
    graph = {}
    for name, path in modules.items():
        is_package = path.name == "__init__.py"
        package = name if is_package else name.rpartition(".")[0]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                wanted = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    anchor = package.split(".")
                    anchor = anchor[: len(anchor) - (node.level - 1)]
                    base = ".".join(anchor + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                # `from pkg import mod` is an edge to pkg.mod; `from mod import name` to mod
                wanted = [
                    f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base
                    for alias in node.names
                ]
            else:
                continue
            for w in wanted:
                target = _resolve(w, modules)
                # a package importing its own submodules, or a module its parent package,
                # is the package's own structure, not an edge between concepts
                if (
                    target
                    and target != name
                    and not target.startswith(name + ".")
                    and not name.startswith(target + ".")
                ):
                    targets.add(target)
        graph[name] = targets
    return graph


def strongly_connected(graph):
    """Tarjan's algorithm, iterative: components with more than one module (the circles)."""
    index, low, on_stack, stack, circles = {}, {}, set(), [], []
    counter = 0
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        circles.append(sorted(component))
    return circles


def layer_violations(graph):
    """Edges from a foundation package into the other foundation or into pipelines."""
    bad = []
    for source, targets in graph.items():
        top = source.split(".")[0]
        if top not in FOUNDATIONS:
            continue
        for target in sorted(targets):
            other = target.split(".")[0]
            if other != top and other in FOUNDATIONS + ("pipelines",):
                bad.append(f"{source} imports {target}")
    return sorted(bad)


@pytest.fixture(scope="module")
def graph():
    return import_graph(_module_files())


def test_no_import_circle(graph):
    assert strongly_connected(graph) == []


def test_foundations_import_neither_each_other_nor_pipelines(graph):
    assert layer_violations(graph) == []


def test_no_module_over_450_lines():
    long = {
        name: n
        for name, path in _module_files().items()
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_LINES
    }
    assert long == {}


def test_the_checks_catch_what_they_guard_against(tmp_path):
    # the checker itself on a small tree that breaks every rule once
    (tmp_path / "roadscan").mkdir()
    (tmp_path / "friction").mkdir()
    (tmp_path / "pipelines").mkdir()
    for pkg in ("roadscan", "friction", "pipelines"):
        (tmp_path / pkg / "__init__.py").write_text("")
    (tmp_path / "roadscan" / "a.py").write_text("from . import b\nimport friction.c\n")
    (tmp_path / "roadscan" / "b.py").write_text("def f():\n    from .a import x\n")
    (tmp_path / "friction" / "c.py").write_text("from pipelines import d\n")
    (tmp_path / "pipelines" / "d.py").write_text("import numpy\n")
    g = import_graph(_module_files(tmp_path))
    assert strongly_connected(g) == [["roadscan.a", "roadscan.b"]]
    assert layer_violations(g) == ["friction.c imports pipelines.d", "roadscan.a imports friction.c"]


# ---- the rules of ARCHITECTURE.md beyond the import graph ------------------------------------

import re  # noqa: E402

_FLAG_WORD = re.compile(r"(?<![\w-])--[a-z]")
#: heavy libraries a module imports inside the function that uses them (rule 4)
HEAVY = ("matplotlib", "scipy.optimize", "scipy.signal", "jinja2", "dask", "distributed")
#: what a command module must not import (rule: commands parse, call one job, print)
NUMERIC = ("numpy", "scipy", "friction")


def _docstrings(tree):
    """The ast.Constant nodes that are docstrings (of the module, classes and functions)."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                found.add(id(body[0].value))
    return found


def flag_names(modules, top="roadscan"):
    """``module: text`` of every string literal (docstrings aside) of package ``top`` that names
    a command-line flag (``--word``)."""
    hits = []
    for name, path in modules.items():
        if name.split(".")[0] != top:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        skip = _docstrings(tree)
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Constant)
                and isinstance(node.value, str)
                and id(node) not in skip
                and _FLAG_WORD.search(node.value)
            ):
                hits.append(f"{name}: {node.value.strip()[:60]!r}")
    return sorted(hits)


def _imported(tree, module_level_only):
    nodes = tree.body if module_level_only else list(ast.walk(tree))
    names = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            names.add(node.module)
    return names


def heavy_at_import(modules):
    """``module imports lib`` for each heavy library imported at a module's top level."""
    bad = []
    for name, path in modules.items():
        for lib in _imported(ast.parse(path.read_text(encoding="utf-8")), True):
            if any(lib == h or lib.startswith(h + ".") for h in HEAVY):
                bad.append(f"{name} imports {lib}")
    return sorted(bad)


def computing_commands(modules):
    """``{command module: sorted numeric libraries it imports}`` (anywhere in the module)."""
    out = {}
    for name, path in modules.items():
        if (
            not name.startswith(("pipelines.cli.commands.", "pipelines.cli.inputs."))
            or path.name == "__init__.py"
        ):
            continue
        hit = {lib.split(".")[0] for lib in _imported(ast.parse(path.read_text(encoding="utf-8")), False)}
        hit &= set(NUMERIC)
        if hit:
            out[name] = sorted(hit)
    return out


#: commands that still compute (their jobs are being moved into pipelines/ job modules); the list
#: may only shrink: a command that computes and is not listed fails the test
COMPUTING_COMMANDS_LEFT = set()


def test_roadscan_names_no_flags():
    # roadscan points at an option by its keyword ({spacing} in roadscan.errors.InputError);
    # the command line names the flag
    assert flag_names(_module_files()) == []


def printing(modules, tops=FOUNDATIONS):
    """``module: line`` of every ``print(...)`` call in the foundation packages."""
    hits = []
    for name, path in modules.items():
        if name.split(".")[0] not in tops:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "print":
                hits.append(f"{name}: {node.lineno}")
    return sorted(hits)


def test_foundations_do_not_print():
    # roadscan and friction return numbers and raise errors; pipelines says things
    assert printing(_module_files()) == []


def test_heavy_libraries_are_imported_where_used():
    assert heavy_at_import(_module_files()) == []


def test_commands_hold_nothing_numeric():
    found = computing_commands(_module_files())
    assert set(found) <= COMPUTING_COMMANDS_LEFT, sorted(set(found) - COMPUTING_COMMANDS_LEFT)


def test_every_command_module_is_listed():
    from pipelines.cli.app import COMMAND_MODULES

    files = {
        f"{p.parent.name}.{p.stem}"
        for folder in ("commands", "inputs")
        for p in (ROOT / "pipelines" / "cli" / folder).glob("*.py")
        if p.stem != "__init__"
    }
    assert files == set(COMMAND_MODULES)


_HTML_TAG = re.compile(r"<(?:p|ul|ol|li|table|tr|td|th|div|span|a|b|img|html|h[1-6])[ >]")

#: modules that still join HTML strings by hand (the list may only shrink; HTML comes from
#: pipelines/templates through pipelines.output.report's writers)
HAND_HTML_LEFT = set()


def hand_built_html(modules):
    """Modules of ``pipelines`` (templates aside) with a string literal holding an HTML tag."""
    found = set()
    for name, path in modules.items():
        if not name.startswith("pipelines.") or name.startswith("pipelines.output.templates"):
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        skip = _docstrings(tree)
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Constant)
                and isinstance(node.value, str)
                and id(node) not in skip
                and _HTML_TAG.search(node.value)
            ):
                found.add(name)
                break
    return found


def test_html_comes_from_templates():
    found = hand_built_html(_module_files())
    assert found <= HAND_HTML_LEFT, sorted(found - HAND_HTML_LEFT)


def test_the_rule_checks_catch_what_they_guard_against(tmp_path):
    (tmp_path / "roadscan").mkdir()
    (tmp_path / "pipelines" / "cli" / "commands").mkdir(parents=True)
    (tmp_path / "roadscan" / "a.py").write_text(
        '"""Use --spacing."""\nimport matplotlib\nX = "pass --spacing DX"\nY = "a -- b, x--y"\n'
    )
    (tmp_path / "pipelines" / "cli" / "commands" / "c.py").write_text("def run():\n    import numpy\n")
    (tmp_path / "roadscan" / "b.py").write_text("def f():\n    print('x')\n")
    (tmp_path / "pipelines" / "r.py").write_text("X = f\"<p class='note'>{1}</p>\"\n")
    mods = _module_files(tmp_path)
    assert flag_names(mods) == ["roadscan.a: 'pass --spacing DX'"]
    assert heavy_at_import(mods) == ["roadscan.a imports matplotlib"]
    assert computing_commands(mods) == {"pipelines.cli.commands.c": ["numpy"]}
    assert printing(mods) == ["roadscan.b: 2"]
    assert hand_built_html(mods) == {"pipelines.r"}


#: folders that are plug-in registries (one module per effect or per command), exempt from the
#: size rule: adding a plug-in must not force a split
PLUGIN_FOLDERS = {"pipelines/diagnosis/effects"}
MAX_MODULES_PER_FOLDER = 12


def crowded_folders(root=ROOT, top="pipelines"):
    """``{folder: number of modules}`` of the folders of ``top`` holding more than
    :data:`MAX_MODULES_PER_FOLDER` Python modules (``__init__.py`` counted)."""
    out = {}
    for d in [root / top, *sorted((root / top).rglob("*"))]:
        rel = d.relative_to(root).as_posix()
        if not d.is_dir() or "__pycache__" in rel or rel in PLUGIN_FOLDERS:
            continue
        n = len(list(d.glob("*.py")))
        if n > MAX_MODULES_PER_FOLDER:
            out[rel] = n
    return out


def test_no_folder_is_one_flat_room():
    assert crowded_folders() == {}


def test_the_folder_rule_catches_a_crowded_folder(tmp_path):
    (tmp_path / "pipelines" / "jobs").mkdir(parents=True)
    for i in range(MAX_MODULES_PER_FOLDER + 1):
        (tmp_path / "pipelines" / "jobs" / f"m{i}.py").write_text("")
    assert crowded_folders(tmp_path) == {"pipelines/jobs": MAX_MODULES_PER_FOLDER + 1}
