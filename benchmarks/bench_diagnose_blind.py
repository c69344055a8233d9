"""Blind check of ``roadscan diagnose`` (issue 5, "Proof on withheld effects").

The cases are made here, independently of ``pipelines/diagnose`` (which is treated as a black box:
only its command line and its ``diagnosis.json`` contract are used). Each effect is implemented
in its own way from the issue text and DESIGN.md, on top of the friction engine's public API:

=====================  =====================================================================
hidden effect           how the "real" mu(v) is made here
=====================  =====================================================================
flash_temperature       ``friction.mu_flash`` with zeta_m ~ U(2, 5), conductivity ~ U(0.15, 0.5)
                        W/(m K), rho ~ U(1000, 1400) kg/m^3, c_v ~ U(1200, 2000) J/(kg K)
relaxation_spectrum     a Prony series of 6-10 terms whose weights follow a log-normal
                        distribution of relaxation times (width 0.4-1.5 decades, centre within
                        +-0.3 decades of the SLS's Prony time tau/(1+a1)), same rubbery and glassy
                        moduli as the SLS, same WLF
temperature_offset      the run's background temperature T0 = T_ref + dT, |dT| ~ U(5, 25) C
fine_roughness          the true surface continues its self-affine law beyond the Nyquist wave
                        vector of the scan / psd.csv up to q1 = f q_Nyquist, f ~ logU(3, 30)
water                   (scans only) the rain-filled scan (roadscan.rain.rain_fill, 4-connected)
                        with a water film of 20-100 % of the depressions' capacity
adhesion                mu_adh = tau_f / sigma0 * P(q1, v) * s(v), tau_f ~ logU(0.5, 10) MPa,
                        P(q1, v) the engine's relative contact area at the finest scale, s a
                        bell in log10 v (centre 1e-6..1e-3 m/s, width 0.7-1.5 decades) or a
                        decreasing 1 / (1 + v / v_c) (v_c 1e-6..1e-3 m/s)
load                    the true sigma0 differs from the nominal by a factor logU in
                        [0.2, 0.6] or [1.7, 5]
contact_correction      ``contact_gamma`` = gamma ~ U(0.25, 0.6) in the engine
null                    the model itself
=====================  =====================================================================

All with multiplicative log-normal noise of 2-5 % and 20-40 log-spaced speeds (jittered) spanning
3-5 decades within 1e-6..30 m/s. Surfaces are a ``psd.csv`` (Persson's normalisation, header
``q_per_m,C_m4``) tabulated from an analytic self-affine spectrum with a roll-off, or a scan made by
``roadscan.synth.self_affine_surface`` written as ``.npy`` (+ ``--spacing``) or ``.x3p``.

Identifiability (issue 5): a case *counts* when (a) its clean effect moves mu by
rms log10(mu_eff / mu_model) > ``K_SIGNAL`` x the noise rms (log10), and (b) none of the other
effects, fitted here with simple one- or two-parameter versions of this file's own effect models
(temperature_offset, load, contact_correction, fine_roughness, flash zeta_m, adhesion amplitude and
v_c, relaxation spread with its centre fixed; water is not refitted), explains the noisy data to within
``K_ALT`` x the noise rms. Accuracy is printed unfiltered, with (a) only, and with (a)+(b).

Surface level (issue 11, ``--surface N``: N cases of each kind per seed set): area scans
made here from ``roadscan.synth.self_affine_surface`` (cropped from a map twice as large, so not
periodic; 256 x 256, spacing 40-80 um, H 0.7-0.9), written as ``.npy`` with ``--spacing``:

=====================  =====================================================================
hidden surface effect   how the scan is made here
=====================  =====================================================================
anisotropy              a self-affine map stretched along x by 2-4 (cubic resampling); a third
                        of the cases: stretched, then turned by 15-75 degrees
height_skew             heights rank-mapped onto a gamma law of skewness +-(0.8-1.8); a third:
                        an exponential map (log-normal law) of skewness +-(0.8-1.8)
seams                   stitching: tiles of 3 or 4 per side with random height offsets of
                        0.2-0.5 rms, or 2-4 straight steps along x or y at random positions; a
                        third: 3 x 3 or 4 x 4 tiles each with its own offset and tilt residue
rolloff                 the synthesis' own roll-off at q_r = (3-6) 2 pi / L (periodic map); a
                        third: a map twice as large with the roll-off, cropped
noise_floor             white measurement noise of 2-6 % rms, or optical smoothing (Gaussian
                        blur of 1.5-3 points)
null                    the cropped self-affine map itself
=====================  =====================================================================

The variants draw from their own random stream, so a seed's main recipe does not change.
Several seed sets (``--seeds``, default 1000,2000,3000) give the per-kind table over all of them
at the end; ``--quick`` runs one seed set small (2 surface cases per kind, 8 friction cases and 3
nulls). The generator imports ``friction``, ``roadscan`` and ``pipelines.chain.surface`` (the
metrology chain, for the scan surfaces' PSD), never ``pipelines.diagnosis``.

Worlds with unknown input offsets (issue 19, ``--level offsets``): see
``bench_diagnose_blind_offsets.py``; they run with ``--uncertain`` ranges containing the truth.
``--few`` (issue 27) gives the same worlds 5 to 10 measured speeds (a real friction test's
count) instead of 20 to 40; the goals are then >= 90 % of named verdicts right, <= 10 % of null
worlds named and >= 30 % of effect worlds named right.

The file is split by concept: ``bench_diagnose_blind_cases.py`` (surfaces, effects, own
alternative fits, cases), ``_run.py`` (running and scoring the friction level),
``_surface.py`` (surface level), ``_offsets.py`` (offset worlds).

Usage::

    .venv/bin/python benchmarks/bench_diagnose_blind.py [--seeds 1000,2000,3000] [--surface 5]
        [--cases 40] [--nulls 10] [--level both|surface|friction] [--quick] [--jobs 2]
        [--keep DIR] [--json FILE] [--level both|surface|friction|offsets|all] [--offsets 20]
        [--offset-nulls 10] [--few]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

# the parts (each < 450 lines); their names are re-exported here for tests/test_diagnose_blind.py
from bench_diagnose_blind_cases import (
    EFFECTS,
    K_ALT,
    K_SIGNAL,
    LN10,
    ROOT,
    SIGMA0_PA,
    Case,
    Surface,
    _psd_surface,
    _rms,
    _scan_surface,
    adhesion_shape,
    alternative_fits,
    draw_params,
    draw_speeds,
    lognormal_prony,
    make_case,
    true_mu,
    write_mu_csv,
)
from bench_diagnose_blind_offsets import offset_report, run_offset_level
from bench_diagnose_blind_run import (
    _fmt_params,
    _label,
    named,
    report,
    run_diagnose,
    run_friction_level,
    score,
    summary_tables,
    verdict_names,
)
from bench_diagnose_blind_surface import (
    SURFACE_KINDS,
    make_surface_heights,
    run_surface_case,
    run_surface_level,
    surface_report,
)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "--cases", type=int, default=40, help="friction-level effect cases per seed set (default 40)"
    )
    ap.add_argument(
        "--nulls", type=int, default=10, help="friction-level null cases per seed set (default 10)"
    )
    ap.add_argument("--seed", type=int, default=None, help="one seed set (same as --seeds N)")
    ap.add_argument(
        "--seeds", default="1000,2000,3000", help="comma-separated seed sets (default 1000,2000,3000)"
    )
    ap.add_argument("--jobs", type=int, default=2, help="diagnoses run in parallel")
    ap.add_argument("--keep", default=None, help="keep case files here")
    ap.add_argument("--json", default=None, help="write per-case results (both levels) here")
    ap.add_argument(
        "--surface",
        type=int,
        default=5,
        help="surface-level cases per kind and seed set (default 5; 0: none)",
    )
    ap.add_argument(
        "--level",
        choices=("both", "surface", "friction", "offsets", "all"),
        default="both",
        help="both: surface and friction (no offsets); offsets: worlds with unknown input offsets "
        "run with --uncertain (issue 19); all: the three",
    )
    ap.add_argument(
        "--offsets", type=int, default=20, help="offset worlds with an effect per seed set (default 20)"
    )
    ap.add_argument(
        "--offset-nulls",
        type=int,
        default=10,
        help="offset worlds without an effect per seed set (default 10)",
    )
    ap.add_argument(
        "--few",
        action="store_true",
        help="offset worlds with 5 to 10 measured speeds instead of 20 to 40 (issue 27)",
    )
    ap.add_argument(
        "--quick",
        action="store_true",
        help="one seed set, 2 surface cases per kind, 8 friction cases and 3 nulls (about 5 min on 2 cores)",
    )
    a = ap.parse_args(argv)
    seeds = [a.seed] if a.seed is not None else [int(x) for x in a.seeds.split(",") if x.strip()]
    if a.quick:
        seeds, a.surface, a.cases, a.nulls, a.offsets, a.offset_nulls = seeds[:1], 2, 8, 3, 5, 3
    t_all = time.perf_counter()
    surf, fric, offs = [], [], []
    for s in seeds:
        keep = None if a.keep is None else str(Path(a.keep) / f"seed_{s}")
        if a.level in ("both", "surface", "all") and a.surface:
            rows = run_surface_level(s, a.surface, a.jobs, keep and keep + "_surface")
            print(f"\n#### seed set {s}")
            surface_report(rows)
            surf += rows
        if a.level in ("both", "friction", "all") and (a.cases or a.nulls):
            rows, t_gen = run_friction_level(s, a.cases, a.nulls, a.jobs, keep and keep + "_friction")
            print(f"\n#### seed set {s}")
            report(rows, t_gen)
            fric += rows
        if a.level in ("offsets", "all") and (a.offsets or a.offset_nulls):
            rows = run_offset_level(
                s, a.offsets, a.offset_nulls, a.jobs, keep and keep + "_offsets", few=a.few
            )
            print(f"\n#### seed set {s}")
            print(offset_report(rows, few=a.few), flush=True)
            offs += rows
    print(summary_tables(surf, fric))
    if offs:
        print("\n== all seed sets ==" + offset_report(offs, few=a.few))
    print(f"\ntotal wall time {time.perf_counter() - t_all:.0f} s ({a.jobs} jobs)")
    if a.json:
        Path(a.json).write_text(
            json.dumps(dict(surface=surf, friction=fric, offsets=offs), indent=1, default=str)
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
