"""The figure helper on concurrent.futures: a script that calls the command without an
``if __name__ == "__main__"`` guard runs once (the spawned worker does not import it again)."""

import os
import subprocess
import sys

import pytest
from conftest import ROOT

SCRIPT = """
import sys
print("SCRIPT RUN", flush=True)
from pipelines.cli.app import main
rc = main(["analyse", {sample!r}, "--out", {out!r}])
print("matplotlib in parent:", "matplotlib" in sys.modules, "rc:", rc, flush=True)
"""


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="the helper runs only with two cores or more")
def test_unguarded_script_runs_once_and_the_helper_draws(tmp_path):
    script = tmp_path / "unguarded.py"
    script.write_text(
        SCRIPT.format(sample=str(ROOT / "sample_scans" / "asphalt.x3p"), out=str(tmp_path / "out"))
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT), ROADSCAN_FIGURE_PROCESS="1")
    r = subprocess.run(
        [sys.executable, str(script)], env=env, cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert r.returncode == 0, r.stderr
    assert r.stdout.count("SCRIPT RUN") == 1, r.stdout
    assert "matplotlib in parent: False rc: 0" in r.stdout  # the helper drew the figures
    assert sorted(p.name for p in (tmp_path / "out").glob("*.png"))[:4] == [
        "heightmap.png",
        "mu.png",
        "psd.png",
        "psd2d.png",
    ]
    assert "Traceback" not in r.stderr
