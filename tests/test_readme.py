"""The README's Python example runs as written (from the repository root)."""
import re
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
    cmds = [l for l in block.splitlines() if l.strip() and not l.lstrip().startswith("#")]
    assert len(cmds) == 2
    ci = (ROOT / ".ci" / "run").read_text()
    assert cmds[1].strip() in ci
    assert "sample_scans/" in cmds[0] and "roadscan analyse" in cmds[0]
