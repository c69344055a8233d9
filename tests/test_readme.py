"""The README's Python example runs as written (from the repository root); the example commands of
the README and of the Markdown documentation pages write only into out/."""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_readme_python_example_runs(monkeypatch):
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README has a Python example"
    monkeypatch.chdir(ROOT)
    ns = {}
    exec(compile(blocks[0], "README.md", "exec"), ns)
    assert 0.7 < ns["fit"].hurst < 1.0
    assert ns["result"].mu.shape == (41,) and (ns["result"].mu > 0).all()
    assert (ns["hot"].T_q_C >= 60 - 1e-9).all()
    import matplotlib.pyplot as plt

    plt.close("all")


def test_readme_quick_start_has_exactly_two_commands():
    text = (ROOT / "README.md").read_text()
    quick = text.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    block = re.findall(r"```bash\n(.*?)```", quick, flags=re.S)[0]
    cmds = [line for line in block.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    assert len(cmds) == 2
    ci = (ROOT / ".ci" / "run").read_text()
    assert cmds[1].strip() in ci
    assert "sample_scans/" in cmds[0] and "roadscan analyse" in cmds[0]


# ---------------------------------------------------------------- examples write only into out/ (issue 22)


def example_pages():
    """The README and the documentation pages written in Markdown (``docs/md/*.md``, where the
    README's long sections live), whose examples must run as written."""
    return [ROOT / "README.md", *sorted((ROOT / "docs" / "md").glob("*.md"))]


def readme_commands(text=None, tables=True):
    """Every example command of the README and of the Markdown documentation pages: the lines
    of their ```bash blocks (continuations joined, comments dropped, ``&&`` chains split) and
    the ``roadscan ...`` commands of their tables (backquoted)."""
    text = text if text is not None else "\n".join(p.read_text() for p in example_pages())
    cmds = []
    for block in re.findall(r"```bash\n(.*?)```", text, flags=re.S):
        for line in re.sub(r"\s*\\\n\s*", " ", block).splitlines():
            line = line.split(" #", 1)[0].strip()
            if line and not line.startswith("#"):
                cmds += [c.strip() for c in line.split("&&") if c.strip()]
    if tables:
        cmds += re.findall(r"^\|\s*`(roadscan [^`]*)`", text, flags=re.M)
    return cmds


def written_paths(cmd):
    """Paths a README command writes (None when it writes where the command decides, i.e. a
    ``roadscan`` command without an explicit output, which writes into the current folder)."""
    words = shlex.split(cmd)
    out = []
    for i, w in enumerate(words):
        if w in (">", ">>") and i + 1 < len(words):
            out.append(words[i + 1])
        elif w.startswith(">") and len(w) > 1:
            out.append(w.lstrip(">"))
    out += re.findall(r"numpy\.save\('([^']+)'", cmd)
    if words[0] == "mkdir":
        out += [w for w in words[1:] if not w.startswith("-")]
    if words[0] in ("python", "python3") and words[1].endswith(".py"):
        out += words[2:3]  # the example scripts take the file they write
    if words[0].endswith("roadscan") and len(words) > 1:
        if "--out" in words:
            out.append(words[words.index("--out") + 1])
        elif words[1] == "convert":
            out.append([w for w in words[2:] if not w.startswith("-")][1])
        elif (
            words[1]
            in (
                "friction",
                "synth",
                "stitch",
                "analyse",
                "batch",
                "rain-fill",
                "compare",
                "dry-vs-wet",
                "diagnose",
                "combine",
                "rubber",
            )
            and "-h" not in words
        ):
            out.append(None)  # the default output (friction: mu.csv here)
    return out


def _placeholder(path):
    """A synopsis placeholder of the README's command table (``DIR``, ``OUT``, ``RAW.csv``)."""
    stem = Path(path).stem.rstrip(".")
    return bool(stem) and stem.isupper()


def test_every_readme_example_writes_only_into_out():
    cmds = readme_commands()
    assert len(cmds) > 20
    bad = []
    for cmd in cmds:
        if "pip install" in cmd or cmd.startswith("python3 -m venv"):
            continue  # the quick start's set-up: .venv
        for path in written_paths(cmd):
            if path is None or not (path == "out" or path.startswith("out/") or _placeholder(path)):
                bad.append((cmd, path))
    assert not bad, bad


def test_written_paths_catches_what_leaves_out():
    """The checker itself: outputs outside out/ and commands without an output are seen."""
    assert written_paths("roadscan friction --psd p.csv --out mu.csv") == ["mu.csv"]
    assert written_paths("roadscan friction --psd p.csv") == [None]
    assert written_paths("roadscan convert a.plu b.x3p") == ["b.x3p"]
    assert written_paths("printf 'a' > x.csv") == ["x.csv"]
    assert written_paths("python -c \"import numpy; numpy.save('f.npy', 1)\"") == ["f.npy"]
    cmds = readme_commands(
        "```bash\nroadscan synth \\\n  --out s.x3p   # c\n```\n| `roadscan x --out y` | z |\n"
    )
    assert cmds == ["roadscan synth --out s.x3p", "roadscan x --out y"]
    assert written_paths(".venv/bin/roadscan analyse a.x3p --out here") == ["here"]
    assert _placeholder("DIR") and _placeholder("RAW.csv") and not _placeholder("mu.csv")


def test_readme_bare_roadscan_examples_say_activate_the_venv():
    text = (ROOT / "README.md").read_text()
    blocks = [
        m
        for m in re.finditer(r"```bash\n(.*?)```", text, flags=re.S)
        if re.search(r"^roadscan ", m.group(1), flags=re.M)
    ]
    assert blocks and ". .venv/bin/activate" in text[: blocks[0].start()]


def _fresh_copy(dest):
    files = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.splitlines()
    for f in files:
        src = ROOT / f
        if src.is_file():
            (dest / f).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / f)
    return sorted(files)


def _tree(root):
    return {
        str(p.relative_to(root)): p.stat().st_mtime_ns
        for p in root.rglob("*")
        if p.is_file() and not str(p.relative_to(root)).startswith("out/")
    }


def test_readme_examples_run_in_a_fresh_copy_into_out_only(tmp_path):
    """The quick README examples (synth, friction, rubber master, stitch, the example script)
    run as written in a copy of the repository, the venv on PATH, and change nothing outside
    out/."""
    repo = tmp_path / "clone"
    _fresh_copy(repo)
    before = _tree(repo)
    keys = (
        "roadscan synth",
        "roadscan friction --psd sample_scans/asphalt_psd.csv \\",
        "roadscan rubber master",
        "roadscan stitch",
        "make_pyvisco_measured.py",
    )
    cmds = [
        c for c in readme_commands(tables=False) if any(c.startswith(k.rstrip(" \\")) or k in c for k in keys)
    ]
    cmds = [c for c in cmds if "--scheduler" not in c]
    assert len(cmds) >= 5, cmds
    env = dict(
        os.environ,
        PATH=os.pathsep.join([str(Path(sys.executable).parent), os.environ["PATH"]]),
        ROADSCAN_FIGURE_PROCESS="0",
    )
    for cmd in cmds:
        r = subprocess.run(
            ["bash", "-c", cmd], cwd=repo, env=env, capture_output=True, text=True, timeout=300
        )
        assert r.returncode == 0, (cmd, r.stderr[-500:])
        assert "Traceback" not in r.stderr
    assert _tree(repo) == before
    assert (repo / "out").is_dir()
