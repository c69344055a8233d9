"""The harness of the fuzz suite (issue 14): run one command line in-process or as a subprocess
and judge the outcome; count the cases. Used by ``tests/test_fuzz.py`` and
``benchmarks/fuzz_long.py``.

A case passes when it ends in one of two ways:

- **exit 0**: no NaN or infinity in any CSV/JSON/TOML it wrote, none turned into JSON ``null``
  by ``pipelines.output.report.write_json`` either, no hidden temporary files, files and folders with
  the permissions the umask gives;
- **exit 2**: the last stderr line is the one-line ``roadscan CMD: error: ...``, no other error
  line, and the working folder is exactly as before (no partial output, no temporary files).
  (``roadscan batch`` reports a per-input failure list: one error line per failed input, the
  campaign folder stays; see README.)

Anything else fails the case: a traceback anywhere, an exception escaping ``main``, exit 1 (an
internal error) or any other code, a case over its time limit, a MemoryError outside the CLI.

Environment: ``ROADSCAN_FUZZ_SCALE`` (examples x scale; 1 = CI, derandomised),
``ROADSCAN_FUZZ_COLLECT=1`` (record failures and go on instead of failing at the first),
``ROADSCAN_FUZZ_FIGURES=1`` (draw every figure; by default the figures of most cases are
stubbed, a few tests draw them), ``ROADSCAN_FUZZ_REPORT=FILE`` (write the counts as JSON).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

SCALE = float(os.environ.get("ROADSCAN_FUZZ_SCALE", "1") or 1)
COLLECT = os.environ.get("ROADSCAN_FUZZ_COLLECT") == "1"
FIGURES = os.environ.get("ROADSCAN_FUZZ_FIGURES") == "1"
REPORT = os.environ.get("ROADSCAN_FUZZ_REPORT")

#: counts per group: cases, exit0, exit2, numpy_warning, failures
STATS = defaultdict(Counter)
#: (group, argv or description, problems) of every failed case
FAILURES = []
#: the error lines of refused cases per group, paths and numbers masked (what got refused)
MESSAGES = defaultdict(Counter)

#: size limit given to the readers during the fuzz [points] (declared sizes above it are refused)
FUZZ_MAX_PIXELS = 1 << 22
#: address space the process may grow by during one case [bytes] (a missed size check shows
#: up as a one-line "out of memory" or a MemoryError instead of swapping the machine)
MEMORY_HEADROOM = 3 << 30

_ERROR_LINE = re.compile(r"^roadscan(?: [\w-]+)*: error: \S")
_ANY_ERROR = re.compile(r"^roadscan(?: [\w-]+)*: (?:error|internal error)")
_TRACEBACK = re.compile(r"Traceback \(most recent call last\)|^\s+File \".*\", line \d+", re.M)
_NONFINITE = {"nan", "+nan", "-nan", "inf", "+inf", "-inf", "infinity", "+infinity", "-infinity"}


class FuzzTimeout(BaseException):
    """A case ran over its time limit (BaseException: the CLI's handler must not catch it)."""


class FuzzFailure(AssertionError):
    pass


def scaled(n, lo=1):
    """``max_examples`` for a test: ``n`` in CI times ``ROADSCAN_FUZZ_SCALE``."""
    return max(lo, int(round(n * SCALE)))


def fuzz_settings(n, **kw):
    from hypothesis import HealthCheck, Phase, settings

    phases = [Phase.explicit, Phase.reuse, Phase.generate, Phase.target]
    if not COLLECT:
        phases.append(Phase.shrink)
    return settings(
        max_examples=scaled(n),
        deadline=None,
        derandomize=SCALE == 1,
        database=None,
        phases=phases,
        print_blob=False,
        suppress_health_check=list(HealthCheck),
        **kw,
    )


# ------------------------------------------------------------------------------ environment
@contextlib.contextmanager
def chdir(path):
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


#: imported once before the first time limit: an alarm that lands inside a first import leaves a
#: half-initialised module behind, and every later case in the process then fails on it
#: (AttributeError in matplotlib after one slow vendor read), which is the harness's fault
_WARM_IMPORTS = (
    "matplotlib.pyplot",
    "scipy.fft",
    "scipy.interpolate",
    "scipy.ndimage",
    "scipy.optimize",
    "scipy.special",
    "scipy.stats",
    "skimage.morphology",
    "skimage.restoration",
    "SurfaceTopography",
)
_warmed = False


def _warm_imports():
    global _warmed
    if _warmed:
        return
    import importlib

    for name in _WARM_IMPORTS:
        try:
            importlib.import_module(name)
        except ImportError:  # an optional extra not installed: its cases say so themselves
            pass
    _warmed = True


@contextlib.contextmanager
def time_limit(seconds):
    _warm_imports()

    def handler(signum, frame):
        raise FuzzTimeout(f"over {seconds:g} s")

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _vm_data():
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmData:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


@contextlib.contextmanager
def memory_cap(headroom=MEMORY_HEADROOM):
    """Cap the data segment (RLIMIT_DATA: heap and private mappings) at the current size plus
    ``headroom`` for the duration of a case."""
    used = _vm_data()
    try:
        old = resource.getrlimit(resource.RLIMIT_DATA)
    except (ValueError, OSError):
        old = None
    if used is None or old is None:
        yield
        return
    soft = used + headroom
    if old[1] != resource.RLIM_INFINITY:
        soft = min(soft, old[1])
    try:
        resource.setrlimit(resource.RLIMIT_DATA, (soft, old[1]))
    except (ValueError, OSError):
        yield
        return
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_DATA, old)


@contextlib.contextmanager
def reader_limit(n=FUZZ_MAX_PIXELS):
    from roadscan.io import _common

    old = _common.get_max_pixels()
    _common.set_max_pixels(n)
    try:
        yield
    finally:
        _common.set_max_pixels(old)


@contextlib.contextmanager
def stub_figures():
    """Replace ``pipelines.output.report.save_figure`` by a stub that writes a tiny placeholder file
    atomically (same names, same atomic path) without drawing: drawing is 95 % of a small run."""
    import matplotlib.pyplot as plt

    from pipelines.output import report
    from roadscan.io.atomic import atomic_write_bytes

    orig = report.save_figure

    def fast(fig, path, *args, **kw):
        atomic_write_bytes(path, b"\x89PNG fuzz stub")
        plt.close(fig)
        return Path(path)

    report.save_figure = fast
    try:
        yield
    finally:
        report.save_figure = orig
        plt.close("all")


def _nonfinite_paths(obj, where=""):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _nonfinite_paths(v, f"{where}.{k}")
    elif isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            yield from _nonfinite_paths(v, f"{where}[{i}]")
    elif isinstance(obj, np.ndarray):
        yield from _nonfinite_paths(obj.tolist(), where)
    elif isinstance(obj, (float, np.floating)) and not np.isfinite(obj):
        yield f"{where} = {float(obj)}"


@contextlib.contextmanager
def watch_json(sink):
    """Record the non-finite floats ``pipelines.output.report.write_json`` would turn into null."""
    from pipelines.output import report

    orig = report.write_json

    def write_json(path, data):
        for p in _nonfinite_paths(data):
            sink.append(f"{Path(path).name}{p} (written as null)")
        return orig(path, data)

    report.write_json = write_json
    try:
        yield
    finally:
        report.write_json = orig


# ------------------------------------------------------------------------------ judging
def snapshot(root):
    """{relative path: (size, mtime_ns) or 'dir'} of everything below ``root``."""
    snap = {}
    root = str(root)
    for dirpath, dirnames, filenames in os.walk(root):
        for n in dirnames:
            snap[os.path.relpath(os.path.join(dirpath, n), root) + "/"] = "dir"
        for n in filenames:
            p = os.path.join(dirpath, n)
            try:
                st = os.lstat(p)
            except OSError:
                continue
            snap[os.path.relpath(p, root)] = (st.st_size, st.st_mtime_ns)
    return snap


def _modes():
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask, 0o777 & ~mask


def nonfinite_in_file(path):
    """Non-finite numbers in a CSV/JSON/TOML/TXT output (first few), as strings."""
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        return [f"unreadable ({exc})"]
    found = []
    if path.suffix == ".json":

        def const(c):
            found.append(c)
            return None

        try:
            json.loads(text, parse_constant=const)
        except ValueError as exc:
            return [f"invalid JSON ({exc})"]
        return found[:5]
    for lineno, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("#"):
            continue
        for tok in re.split(r"[,;\s=\[\]]+", line):
            if tok.strip("'\"").lower() in _NONFINITE:
                found.append(f"line {lineno}: {line[:120]}")
                break
        if len(found) >= 5:
            break
    return found


def judge(rc, out, err, before, after, root, nonfinite_json=(), batch=False):
    """The problems of one case (empty list: it passed)."""
    problems = []
    if rc not in (0, 2):
        problems.append(f"exit code {rc!r}")
    for name, text in (("stderr", err), ("stdout", out)):
        if _TRACEBACK.search(text or ""):
            problems.append(f"traceback on {name}")
    lines = [ln for ln in (err or "").splitlines() if ln.strip()]
    errors = [ln for ln in lines if _ANY_ERROR.match(ln)]
    if rc == 2:
        if not lines or not _ERROR_LINE.match(lines[-1]):
            if not (batch and errors and all(_ERROR_LINE.match(e) for e in errors)):
                problems.append("exit 2 but the last stderr line is not 'roadscan CMD: error: ...'")
        if len(errors) > 1 and not batch:
            problems.append(f"{len(errors)} error lines")
    if rc == 0 and errors:
        problems.append("an error line with exit 0")
    if any("warning: numpy:" in ln for ln in lines):
        # the CLI's net for numpy floating-point warnings: the edge case was not prevented
        problems.append("a numpy warning line (a floating-point edge case not prevented)")
    if rc == 2 and lines and "cannot process this input (" in lines[-1]:
        # the CLI's last resort for arithmetic errors: one line, but the input was not checked
        problems.append("unanticipated error (the CLI's last-resort handler, not a check naming the input)")
    changed = sorted(k for k, v in after.items() if before.get(k) != v)
    from pipelines.campaign.folder import SIDECAR  # batch's resume record: hidden by design

    hidden = [
        k
        for k in changed
        if any(part.startswith(".") and part != SIDECAR for part in Path(k.rstrip("/")).parts)
    ]
    if hidden:
        problems.append(f"hidden temporary files left: {hidden[:3]}")
    if rc == 0:
        fmode, dmode = _modes()
        for k in changed:
            p = Path(root) / k
            try:
                mode = p.stat().st_mode & 0o777
            except OSError:
                continue
            want = dmode if k.endswith("/") else fmode
            if mode != want:
                problems.append(f"{k} has mode {mode:o}, the umask gives {want:o}")
                break
        for k in changed:
            p = Path(root) / k
            if p.suffix in (".csv", ".json", ".toml", ".txt") and p.is_file():
                bad = nonfinite_in_file(p)
                if bad:
                    problems.append(f"exit 0 with non-finite numbers in {k}: {bad[:2]}")
        if nonfinite_json:
            problems.append(f"exit 0 with non-finite numbers in JSON: {list(nonfinite_json)[:3]}")
    elif rc != 0 and changed:
        campaign = batch and any(k.endswith("campaign.csv") for k in changed)
        gone = [k for k in before if k not in after]
        if not campaign or gone:
            problems.append(
                f"leftovers after a failed run: {changed[:4]}{' removed ' + str(gone[:3]) if gone else ''}"
            )
    return problems


def record(group, desc, rc, problems, err=""):
    s = STATS[group]
    s["cases"] += 1
    s[f"exit{rc}" if rc in (0, 1, 2) else "exit_other"] += 1
    if "warning: numpy:" in (err or ""):
        s["numpy_warning"] += 1
    lines = (err or "").strip().splitlines()
    if rc == 2 and lines:
        msg = re.sub(r"/\S+/", "", lines[-1])
        MESSAGES[group][re.sub(r"[-+]?\d[\d.e+-]*", "#", msg)[:110]] += 1
    if problems:
        s["failures"] += 1
        tail = " | ".join((err or "").strip().splitlines()[-3:])[-600:]
        FAILURES.append({"group": group, "case": desc, "problems": problems, "stderr_tail": tail})
        if not COLLECT:
            raise FuzzFailure(f"{group}: {'; '.join(problems)}\n  case: {desc}\n  stderr: {tail}")


# ------------------------------------------------------------------------------ running
def run_cli(group, argv, workdir, timeout=60.0, figures=None, watch=(), desc=None):
    """Run ``roadscan ARGV`` in-process in ``workdir`` and judge it; returns (rc, stdout, stderr).

    ``watch``: further folders (e.g. the inputs) that must not change either.
    """
    from pipelines.cli.app import main

    argv = [str(a) for a in argv]
    figures = FIGURES if figures is None else figures
    roots = [Path(workdir), *map(Path, watch)]
    before = [snapshot(r) for r in roots]
    json_bad = []
    out, err = io.StringIO(), io.StringIO()
    rc = None
    with contextlib.ExitStack() as stack:
        stack.enter_context(chdir(workdir))
        if not figures:
            stack.enter_context(stub_figures())
        stack.enter_context(watch_json(json_bad))
        stack.enter_context(reader_limit())
        stack.enter_context(contextlib.redirect_stdout(out))
        stack.enter_context(contextlib.redirect_stderr(err))
        stack.enter_context(memory_cap())
        try:
            with time_limit(timeout * (3 if FIGURES else 1)):
                rc = main(argv)
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) or exc.code is None else f"SystemExit({exc.code!r})"
            rc = 0 if rc is None else rc
        except FuzzTimeout as exc:
            rc = f"timeout ({exc})"
        except BaseException as exc:  # noqa: BLE001 - judged below
            rc = f"exception {type(exc).__name__}"
            err.write(traceback.format_exc())
    after = [snapshot(r) for r in roots]
    problems = judge(
        rc,
        out.getvalue(),
        err.getvalue(),
        before[0],
        after[0],
        workdir,
        json_bad,
        batch=argv and argv[0] == "batch",
    )
    for r, b, a in zip(roots[1:], before[1:], after[1:]):
        if a != b:
            problems.append(f"the inputs folder {r.name} changed")
    record(group, (f"[{desc}] " if desc else "") + " ".join(argv), rc, problems, err.getvalue())
    return rc, out.getvalue(), err.getvalue()


def run_subprocess(group, argv, workdir, timeout=120.0, desc=None):
    """Run ``python -m pipelines.cli.app ARGV`` in ``workdir`` and judge it."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "PYTHONWARNINGS": "default"}
    argv = [str(a) for a in argv]
    before = snapshot(workdir)

    def limit():
        used = 0
        resource.setrlimit(resource.RLIMIT_DATA, (used + (6 << 30), resource.RLIM_INFINITY))

    try:
        p = subprocess.run(
            [sys.executable, "-m", "pipelines.cli", *argv],
            cwd=workdir,
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
            preexec_fn=limit,
        )
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as exc:
        rc, out, err = f"timeout (over {timeout:g} s)", "", str(exc.stderr or "")
    after = snapshot(workdir)
    problems = judge(rc, out, err, before, after, workdir, batch=argv and argv[0] == "batch")
    record(group, (f"[{desc}] " if desc else "") + "subprocess: " + " ".join(argv), rc, problems, err)
    return rc, out, err


@contextlib.contextmanager
def workdir(base):
    d = Path(tempfile.mkdtemp(prefix="case", dir=base))
    try:
        yield d
    finally:
        shutil.rmtree(d, ignore_errors=True)


def counts_line():
    tot = Counter()
    for s in STATS.values():
        tot.update(s)
    per = ", ".join(f"{g} {s['cases']}" for g, s in sorted(STATS.items()))
    return (
        f"fuzz: {tot['cases']} cases ({tot['exit0']} exit 0, {tot['exit2']} exit 2, "
        f"{tot['numpy_warning']} with a numpy warning line), {tot['failures']} failed; {per}"
    )


def write_report(path=REPORT):
    if not path:
        return
    data = {
        "stats": {g: dict(s) for g, s in STATS.items()},
        "failures": FAILURES,
        "refusals": {g: dict(c.most_common()) for g, c in MESSAGES.items()},
        "scale": SCALE,
        "time": time.time(),
    }
    Path(path).write_text(json.dumps(data, indent=1, default=str))
