"""Reports speak the reader's units (issue 21): every HTML report and console line written by
``analyse`` (area, profile, several scans), ``batch`` (sections of a profile), ``compare``,
``dry-vs-wet``, ``combine`` and ``diagnose`` (friction level) is scanned for raw SI
("0.0003974", "1.849e-05 um", "2.53e+03 um"), the ASCII "um" and heights of a thousand
micrometres and more.

The checker itself is tested first on the strings the issue quotes, so that it can fail.
"""

import html
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import fourier_surface

from pipelines.cli.app import main

SAMPLES = Path(__file__).resolve().parents[1] / "sample_scans"
DX = 5e-5  # area scans: 50 µm
DXP = 5e-4  # profiles: 0.5 mm, a texture laser's interval

_NUMBER = re.compile(r"(?<![\w.:/+-])-?(\d*\.\d+)(?![\w.])")
_PATTERNS = {
    "exponent next to a length unit": re.compile(r"\d[eE][+-]?\d+\s*(?:m|mm|um|µm|nm)\b"),
    "ASCII um as a unit": re.compile(r"\d\s*um\b|\[um\]|\(um\)"),
    "a thousand µm or more (say mm)": re.compile(r"(?<![\w.])\d{4,}(?:\.\d+)?\s*µm"),
    "a length in plain metres below 1 m": re.compile(r"(?<![\w.@])0\.\d+\s*m(?![\w/])"),
}


def visible_text(page):
    """What a reader sees of an HTML page: no style, script, tags or embedded images."""
    page = re.sub(r"<(style|script)\b.*?</\1>", " ", page, flags=re.S)
    page = re.sub(r"<[^>]+>", " ", page)
    return html.unescape(page)


def raw_si(text):
    """Snippets of ``text`` that a road engineer should not have to read."""
    bad = []
    for m in _NUMBER.finditer(text):
        digits = m.group(1).replace(".", "").lstrip("0")
        if len(digits) > 4 or (len(digits) == 4 and abs(float(m.group(1))) < 0.01):
            bad.append(("more than 4 significant digits", text[max(0, m.start() - 30) : m.end() + 10]))
    for what, rx in _PATTERNS.items():
        bad += [(what, text[max(0, m.start() - 30) : m.end() + 10]) for m in rx.finditer(text)]
    return bad


@pytest.mark.parametrize(
    "text",
    [
        "rms height [m] 0.0003974",
        "MPD 0.0032755905236328256",
        "rms height = 2.53e+03 um",
        "rms mismatch [um] 1.849e-05",
        "rms mismatch 1.849e-05 um",
        "Sq 2530 µm",
        "rms mismatch 1.849e-05 m",
        "MPD 0.00328 m",
    ],
)
def test_checker_flags_the_quoted_raw_si(text):
    assert raw_si(text)


@pytest.mark.parametrize(
    "text",
    [
        "MPD 3.28 mm",
        "Sq 397 µm",
        "q range 104 1/m (λ = 60.3 mm)",
        "45.3 dB",
        "2.72 %",
        "H = 0.863 ± 0.005",
        "v 0.000100 m/s",
        "read by: x3pio 2.0.0",
        "1.81 m",
        "μ 4.89e-06",
        "station_10@0.25m",
    ],
)
def test_checker_passes_reader_units(text):
    assert raw_si(text) == []


def _measured(d):
    """Eight speeds of the shipped measured curve (a friction-level diagnosis in seconds)."""
    rows = (SAMPLES / "measured_mu_example.csv").read_text().splitlines()
    (d / "mu.csv").write_text("\n".join([rows[0], *rows[1::4]][:9]) + "\n")
    return ["diagnose", "--measured", str(d / "mu.csv"), "--psd", str(SAMPLES / "asphalt_psd.csv")]


def _profile(n, seed):
    """mm-scale texture: running-mean white noise plus a slow wave, heights about 2.3 mm rms."""
    rng = np.random.default_rng(seed)
    z = np.convolve(rng.normal(size=n + 24), np.ones(24) / 24, mode="valid")[:n] * 8e-3
    x = np.arange(n) * DXP
    return x, z + 2.5e-3 * np.sin(2 * np.pi * x / 0.9)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Run every report-writing command once; -> {name: (report path, console text)}."""
    d = tmp_path_factory.mktemp("units")
    fine = fourier_surface(160, DX, 0.8, 4e-4, seed=1)
    fine[10:13, 20:25] = np.nan
    np.save(d / "fine.npy", fine)
    np.save(d / "coarse.npy", fourier_surface(160, DX, 0.8, 9e-4, seed=2, q_roll=2 * np.pi / 2e-3))
    for k in (1, 2):
        x, z = _profile(3000, k)
        np.savetxt(
            d / f"line{k}.txt",
            np.column_stack([x * 1e3, z * 1e3]),
            fmt="%.4f",
            delimiter=", ",
            header="distance (mm), height (mm)",
            comments="",
        )
    (d / "instruments.csv").write_text(
        f"file,spacing_m,resolution_m,label\nfine.npy,{DX},{2 * DX},fine\ncoarse.npy,{DX},{2 * DX},coarse\n"
    )
    a, b = str(d / "fine.npy"), str(d / "coarse.npy")
    v = ["--velocities", "1e-4:1e2:7"]
    commands = {
        "analyse area": (["analyse", a, "--spacing", str(DX), "--no-figures"] + v, "area"),
        "analyse profile": (["analyse", str(d / "line1.txt"), "--no-figures"] + v, "profile"),
        "analyse several": (["analyse", a, b, "--spacing", str(DX), "--no-figures"] + v, "several"),
        "batch sections": (
            [
                "batch",
                str(d / "line1.txt"),
                str(d / "line2.txt"),
                "--section-length",
                "0.5",
                "--workers",
                "1",
                "--no-friction",
            ],
            "batch",
        ),
        "compare": (["compare", a, b, "--spacing", str(DX)] + v, "compare"),
        "dry-vs-wet": (["dry-vs-wet", a, "--spacing", str(DX)] + v, "wet"),
        "combine": (["combine", str(d / "instruments.csv"), "--no-figures"], "combine"),
        "diagnose": (_measured(d), "diag"),
    }
    out = {}
    for name, (argv, sub) in commands.items():
        import contextlib
        import io

        buf = io.StringIO()
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
            rc = main(argv + ["--out", str(d / sub)])
        assert rc == 0, (name, buf.getvalue())
        out[name] = (d / sub / "report.html", buf.getvalue())
    return out


NAMES = [
    "analyse area",
    "analyse profile",
    "analyse several",
    "batch sections",
    "compare",
    "dry-vs-wet",
    "combine",
    "diagnose",
]


@pytest.mark.parametrize("name", NAMES)
def test_html_report_has_no_raw_si(runs, name):
    path, _ = runs[name]
    pages = [path] + sorted(p for p in path.parent.rglob("report.html") if p != path)
    for p in pages:
        bad = raw_si(visible_text(p.read_text(encoding="utf-8")))
        assert bad == [], f"{name}: {p.relative_to(path.parent)}: {bad[:5]}"


@pytest.mark.parametrize("name", NAMES)
def test_console_has_no_raw_si(runs, name):
    text = runs[name][1]
    text = "\n".join(line for line in text.splitlines() if not line.startswith("["))  # progress
    bad = raw_si(re.sub(r"(?:/[\w.@-]+)+", "PATH", text))  # file paths are not numbers
    assert bad == [], f"{name}: {bad[:5]}"


def test_campaign_heights_in_mm_when_they_are_millimetres(runs):
    """Profiles of about 2.5 mm rms: the campaign's Sq column in mm ("2.53"), not µm ("2530")."""
    page = visible_text(runs["batch sections"][0].read_text(encoding="utf-8"))
    assert "Sq, rms height [mm]" in page and "Sq, rms height [µm]" not in page
    head = page.index("Sq, rms height [mm]")
    cells = re.findall(r"(?<![\w.])\d+\.\d+(?![\w.])", page[head : head + 4000])
    assert cells and max(float(c) for c in cells) < 1000


def test_profile_report_speaks_mm(runs):
    page = visible_text(runs["analyse profile"][0].read_text(encoding="utf-8"))
    assert re.search(r"rms height \(Sq[^)]*\)\s+\d\.\d\d mm", page), page[:2000]
    assert re.search(r"mean profile depth MPD \(ISO 13473-1\)\s+\d\.\d\d mm", page)


@pytest.fixture(scope="module")
def spectrum_figures(tmp_path_factory):
    """Every figure ``analyse`` (area and profile), ``compare``, ``dry-vs-wet``, ``combine`` and
    ``diagnose`` (friction level) save, drawn in this process -> [(command, figure file name, axes)]."""
    import pipelines.output.report as report

    d = tmp_path_factory.mktemp("figs")
    np.save(d / "a.npy", fourier_surface(128, DX, 0.8, 4e-4, seed=3))
    np.save(d / "b.npy", fourier_surface(128, DX, 0.7, 8e-4, seed=4))
    x, z = _profile(3000, 3)
    np.savetxt(
        d / "line.txt",
        np.column_stack([x * 1e3, z * 1e3]),
        fmt="%.4f",
        delimiter=", ",
        header="distance (mm), height (mm)",
        comments="",
    )
    (d / "two.csv").write_text(f"file,spacing_m,resolution_m,label\na.npy,{DX},,a\nb.npy,{DX},,b\n")
    a, b, v = str(d / "a.npy"), str(d / "b.npy"), ["--velocities", "1e-4:1e2:5"]
    seen = []
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("ROADSCAN_FIGURE_PROCESS", "0")
        save = report.save_figure

        def recording(fig, path, *args, **kwargs):
            seen.extend((command, Path(path).name, ax) for ax in fig.axes)
            return save(fig, path, *args, **kwargs)

        mp.setattr(report, "save_figure", recording)
        for command, argv in (
            ("analyse", ["analyse", a, "--spacing", str(DX)] + v),
            ("analyse profile", ["analyse", str(d / "line.txt")] + v),
            ("compare", ["compare", a, b, "--spacing", str(DX)] + v),
            ("dry-vs-wet", ["dry-vs-wet", a, "--spacing", str(DX)] + v),
            ("combine", ["combine", str(d / "two.csv")]),
            ("diagnose", _measured(d)),
        ):
            assert main(argv + ["--out", str(d / command.replace(" ", "_"))]) == 0, command
    return seen


def test_every_spectrum_plot_has_a_wavelength_axis_in_mm(spectrum_figures):
    """A log q axis [1/m] always comes with lambda = 2 pi / q in mm on top (issue 21)."""
    spectra = [
        (c, f, ax)
        for c, f, ax in spectrum_figures
        if ax.get_xlabel().startswith("wave vector q") and ax.get_xscale() == "log"
    ]
    drawn = {c for c, _, _ in spectra}
    assert drawn == {"analyse", "analyse profile", "compare", "dry-vs-wet", "combine", "diagnose"}, drawn
    for command, name, ax in spectra:
        tops = [c for c in ax.child_axes if "wavelength" in c.get_xlabel()]
        assert tops, f"{command}: {name} has no wavelength axis"
        assert "[mm]" in tops[0].get_xlabel()
        # lambda = 2 pi / q: the top axis at q = 2 pi / 1 mm reads 1 mm
        forward = tops[0]._functions[0]
        assert float(forward(np.array([2e3 * np.pi]))[0]) == pytest.approx(1.0)


def test_every_axis_names_its_unit(spectrum_figures):
    """Axis labels of every figure carry a unit in brackets ("[mm]", "[1/m]", "[-]")."""
    for command, name, ax in spectrum_figures:
        if not ax.get_visible() or not ax.axison:
            continue
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label:
                assert re.search(r"\[[^\]]+\]", label), f"{command}: {name}: {label!r}"


def test_stitch_console_has_no_raw_si(tmp_path, capsys):
    """stitch's overlap table: "rms mismatch [um] 1.849e-05" was the issue's example."""
    z = fourier_surface(224, DX, 0.8, 4e-4, seed=5)
    rng = np.random.default_rng(5)
    for k, c in enumerate((0, 96)):
        np.save(tmp_path / f"t{k}.npy", z[:120, c : c + 120] + rng.normal(0, 1e-6, (120, 120)))
    rc = main(
        [
            "stitch",
            str(tmp_path / "t0.npy"),
            str(tmp_path / "t1.npy"),
            "--grid",
            "1x2",
            "--overlap",
            "0.2",
            "--spacing",
            str(DX),
            "--out",
            str(tmp_path / "m.npz"),
        ]
    )
    text = capsys.readouterr().out
    assert rc == 0 and "µm" in text
    assert raw_si(re.sub(r"(?:/[\w.@-]+)+", "PATH", text)) == [], text
