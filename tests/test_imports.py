"""Imports on demand (issue 13): the CLI's parser, ``import roadscan`` and ``import friction``
must not load matplotlib, scipy.optimize or scipy.signal (each costs 0.1 to 1 s of start-up on
a busy 2-core machine). Checked in a fresh interpreter through ``sys.modules``; the start-up
time itself is measured by ``benchmarks/bench_startup.py``, not here."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("matplotlib", "scipy.optimize", "scipy.signal")


def _loaded_after(code):
    """Top modules of interest present in sys.modules after running ``code`` afresh."""
    probe = (code + "\nimport sys, json\n"
             "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
             "('numpy', 'scipy', 'matplotlib', 'skimage', 'cv2', 'numba'))))")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env,
                         cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def _heavy(mods):
    return sorted(m for m in mods if any(m == h or m.startswith(h + ".") for h in HEAVY))


def test_cli_parser_loads_no_numpy_nor_scipy():
    # every subcommand's parser is built for `roadscan --help`; heavy imports belong in run()
    mods = _loaded_after("import pipelines.cli as c\nc.build_parser()")
    assert not mods, f"building the CLI parser imported {sorted(mods)[:8]}"


@pytest.mark.parametrize("code", [
    "import roadscan",
    "import friction",
    "import roadscan.spectrum, roadscan.level, roadscan.inpaint, roadscan.roughness, roadscan.fit",
    "import roadscan.io",
    "from friction import mu_isothermal, mu_flash, thesis_rubber, TabulatedPSD, SelfAffinePSD",
])
def test_package_imports_stay_light(code):
    mods = _loaded_after(code)
    assert not _heavy(mods), f"{code!r} imported {_heavy(mods)}"


def test_lazy_names_resolve():
    import friction
    import roadscan

    for name in roadscan.__all__:
        assert getattr(roadscan, name) is not None
    for name in friction.__all__:
        assert callable(getattr(friction, name))
    with pytest.raises(AttributeError):
        roadscan.no_such_name  # noqa: B018


def test_help_runs_without_heavy_imports():
    code = ("import sys\nfrom pipelines.cli import main\n"
            "try:\n    main(['analyse', '--help'])\nexcept SystemExit:\n    pass\n")
    mods = _loaded_after(code)
    assert not mods, sorted(mods)[:8]
