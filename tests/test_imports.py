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
    probe = (
        code + "\nimport sys, json\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('numpy', 'scipy', 'matplotlib', 'skimage', 'cv2', 'numba'))))"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, env=env, cwd=ROOT, timeout=120
    )
    assert out.returncode == 0, out.stderr
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def _heavy(mods):
    return sorted(m for m in mods if any(m == h or m.startswith(h + ".") for h in HEAVY))


def test_cli_parser_loads_no_numpy_nor_scipy():
    # every subcommand's parser is built for `roadscan --help`; heavy imports belong in run()
    mods = _loaded_after("import pipelines.cli.app as c\nc.build_parser()")
    assert not mods, f"building the CLI parser imported {sorted(mods)[:8]}"


@pytest.mark.parametrize(
    "code",
    [
        "import roadscan",
        "import friction",
        "import roadscan.spectrum, roadscan.level, roadscan.inpaint, roadscan.roughness, roadscan.fit",
        "import roadscan.io",
        "from friction import mu_isothermal, mu_flash, thesis_rubber, TabulatedPSD, SelfAffinePSD",
    ],
)
def test_package_imports_stay_light(code):
    mods = _loaded_after(code)
    assert not _heavy(mods), f"{code!r} imported {_heavy(mods)}"


#: modules whose purpose is what they import: friction.fitting fits Prony series and WLF
#: constants with scipy.optimize (imported only by ``roadscan rubber`` and the fitting API)
OPTIMIZE_BY_DESIGN = {"friction.fitting"}


def test_every_module_of_both_packages_stays_light():
    # all of roadscan and friction at once, submodules included (stitch, rain, io readers, ...)
    code = (
        "import importlib, pkgutil, roadscan, friction\n"
        "for pkg in (roadscan, friction):\n"
        "    for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + '.'):\n"
        f"        if m.name not in {sorted(OPTIMIZE_BY_DESIGN)!r}:\n"
        "            importlib.import_module(m.name)\n"
    )
    mods = _loaded_after(code)
    assert not _heavy(mods), f"importing every module imported {_heavy(mods)}"


def test_lazy_names_resolve():
    import friction
    import roadscan

    for name in roadscan.__all__:
        assert getattr(roadscan, name) is not None
    for name in friction.__all__:
        assert callable(getattr(friction, name))
    with pytest.raises(AttributeError):
        roadscan.no_such_name  # noqa: B018


def _command_names():
    from pipelines.cli.app import _load_commands

    return [m.NAME for m in _load_commands()]


@pytest.mark.parametrize("argv", [["--help"]] + [[name, "--help"] for name in _command_names()])
def test_help_runs_without_heavy_imports(argv):
    # every command `roadscan --help` lists (issue 13: each --help within 0.15 s, timed by
    # benchmarks/bench_startup.py): argparse only, no numpy nor scipy nor matplotlib
    code = (
        "import sys\nfrom pipelines.cli.app import main\n"
        f"try:\n    main({argv!r})\nexcept SystemExit:\n    pass\n"
    )
    mods = _loaded_after(code)
    assert not mods, f"roadscan {' '.join(argv)} imported {sorted(mods)[:8]}"


def test_every_listed_command_is_checked():
    from pipelines.cli.app import COMMAND_MODULES

    names = _command_names()
    assert len(names) >= len(COMMAND_MODULES) - 1 and "analyse" in names and "friction" in names


def test_reports_and_friction_engine_load_matplotlib_only_to_draw(tmp_path):
    # the analysis modules and a friction run pull in no plotting (figures import it on demand),
    # and the engine's phi table needs no scipy.interpolate (0.1 s of every run)
    code = (
        "import numpy as np\nimport pipelines.output.report, "
        "pipelines.jobs.analyse.call, pipelines.jobs.compare, "
        "pipelines.jobs.dry_vs_wet\nimport friction\n"
        "psd = friction.SelfAffinePSD(hurst=0.8, h0_m=5e-4, q0_per_m=2e3, q1_per_m=2e5)\n"
        "friction.mu_isothermal(psd, friction.thesis_rubber(), np.logspace(-6, 2, 9))\n"
    )
    mods = _loaded_after(code)
    assert not {m for m in mods if m.split(".")[0] == "matplotlib"}, sorted(mods)
    assert "scipy.interpolate" not in mods


def test_analyse_without_figures_never_imports_matplotlib(tmp_path):
    import numpy as np

    h = np.random.default_rng(0).normal(size=(64, 64)) * 1e-4
    np.save(tmp_path / "s.npy", h)
    code = (
        "from pipelines.cli.app import main\n"
        f"assert main(['analyse', {str(tmp_path / 's.npy')!r}, '--spacing', '1e-4', '--no-figures', "
        f"'--out', {str(tmp_path / 'out')!r}]) == 0\n"
    )
    mods = _loaded_after(code)
    assert not {m for m in mods if m.split(".")[0] == "matplotlib"}, sorted(mods)
    assert (tmp_path / "out" / "summary.json").exists() and not list((tmp_path / "out").glob("*.png"))


def test_analyse_of_the_sample_imports_no_scipy(tmp_path):
    """``roadscan analyse`` of the 1-Mpx sample (dropouts included) needs neither scipy.fft
    (numpy's FFT below 4 Mpx), nor scipy.ndimage, scipy.sparse or scikit-image (the numpy
    biharmonic fill below 4 Mpx), nor matplotlib in the main process (the figure helper):
    0.3 s of scipy imports less; nor scipy.special (the friction engine's erf of a few thousand
    values comes from the C library): 0.1 s less."""
    code = (
        "from pipelines.cli.app import main\n"
        f"assert main(['analyse', {str(ROOT / 'sample_scans' / 'asphalt.x3p')!r}, '--out', "
        f"{str(tmp_path / 'out')!r}]) == 0"
    )
    mods = _loaded_after(code)
    tops = {".".join(m.split(".")[:2]) for m in mods}
    helper = (os.cpu_count() or 1) >= 2  # the figures are drawn by a helper process
    for heavy in ("scipy.fft", "scipy.ndimage", "scipy.sparse", "scipy.special", "skimage") + (
        "matplotlib",
    ) * helper:
        assert heavy not in tops, f"analyse imported {heavy}"
    assert (tmp_path / "out" / "psd.png").is_file()
