"""One text per option of the public jobs, shared by every job that takes it.

Each public job (:func:`pipelines.analyse`, :func:`pipelines.compare`, ...) writes ``{options}``
in its docstring where its Parameters section lists its options; :func:`document_options` puts
there one numpydoc entry per keyword-only parameter: its name, its annotation and default read
from the signature itself (so the docs cannot drift from the code), and its text from
:data:`OPTION_TEXT` (the command's help for the same flag, with the flag named).
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from typing import Any, TypeVar

from pipelines.settings.keywords import job_parameters

__all__ = ["OPTION_TEXT", "document_options"]

F = TypeVar("F", bound=Callable[..., Any])

#: option name -> what it is, its unit and what its default means (the flag named first)
OPTION_TEXT: dict[str, str] = {
    # roadscan batch's own
    "figures": "``--figures``: also write each scan's PNG figures.",
    "workers": (
        "``--workers``: a local Dask cluster of this many worker processes, one thread each "
        "(default: one per core)."
    ),
    "scheduler": (
        "``--scheduler``: address ``tcp://HOST:PORT`` of an existing dask.distributed cluster "
        "(files must be readable, and ``out`` writable, under the same paths on every worker)."
    ),
    "resume": ("``--resume``: skip inputs whose outputs exist and whose input and options are unchanged."),
    "section_length": (
        "``--section-length``: cut long line profiles into sections of this length [m] along "
        "chainage, one row each (MPD per ISO 13473-1, PSD, H, rms per section)."
    ),
    "columns": (
        "``--columns``: the columns of campaign.csv after ``file,label,chainage_m,status,error``, "
        "names or patterns, comma separated (e.g. ``mpd_m,mpd_valid,roughness.S*``; default all)."
    ),
    "no_figures": "``--no-figures``: no PNG figures (and none in report.html) when written.",
    "spacing": (
        "``--spacing``: grid spacing in metres for formats that do not carry it (e.g. 5.54e-5 or 5e-5,6e-5)."
    ),
    "units": (
        "``--units``: units of the heights in files that carry no units, and of the x (and y) columns "
        "of text files without unit titles (default m)."
    ),
    "x_units": (
        "``--x-units``: units of the x (and y) columns of an x,z or x,y,z text file without unit "
        "titles, when they differ from --units (e.g. x in m, heights in mm)."
    ),
    "override_calibration": (
        "``--override-calibration``: let --spacing/--units replace the spacing/units a file carries "
        "(X3P, vendor, .npz with dx/dy.; refused otherwise); recorded as calibration_override in "
        "summary.json."
    ),
    "channel": (
        "``--channel``: page of a multi-page TIFF, colour channel of an RGB/stack TIFF, or channel of "
        "an instrument file with several (index from 0 or name); recorded in summary.json."
    ),
    "window_alpha": "``--window-alpha``: Tukey window alpha (default 0.25).",
    "fit_band": "``--fit-band``: self-affine fit band [1/m] (default: detected).",
    "despike": "``--despike``: mark spikes as unmeasured before levelling.",
    "mpd_spike_alpha": (
        "``--mpd-spike-alpha``: MPD spike criterion |dh| >= ALPHA x sampling interval (ISO 13473-1 "
        "default 3; CAPTIF uses 6 on chip seals, whose stone edges are steep)."
    ),
    "resolution": (
        "``--resolution``: the instrument's lateral resolution [m] (wavelength passed at 50 % "
        "amplitude; default: the file's metadata): the reliable band ends where it still passes 80 %."
    ),
    "direction": (
        "``--direction``: driving direction of an area scan for the ISO 13473-4 texture spectrum "
        "(lines along it are analysed; default x)."
    ),
    "friction_measurement": (
        "``--friction-measurement``: friction F measured at slip speed SPEED km/h (e.g. 0.45@30): "
        "with --ifi-constants gives the IFI F60 of ASTM E1960."
    ),
    "ifi_constants": (
        "``--ifi-constants``: the friction device's IFI calibration constants (ASTM E1960; C "
        "multiplies MPD in mm, default 0)."
    ),
    "form": (
        "``--form``: form removed before the roughness figures: least-squares plane (default), or "
        "polynomial of degree 2 or 3 (ISO 25178-2 F-operator)."
    ),
    "s_filter": (
        "``--s-filter``: S-filter nesting index [m]: Gaussian low-pass removing scales below it (ISO "
        "16610-61 / -21, 50 % transmission at M) before the roughness figures."
    ),
    "l_filter": (
        "``--l-filter``: L-filter nesting index [m]: Gaussian high-pass removing scales above it "
        "(waviness), e.g. 0.008; the spectrum and friction stay unfiltered."
    ),
    "rubber": (
        "``--rubber``: rubber model, friction/RUBBER_TOML.md (default: the thesis's standard linear "
        "solid, T_ref = 60 C)."
    ),
    "sigma0": (
        "``--sigma0``: nominal contact pressure sigma0 = load / nominal area, with a unit: 0.3MPa, "
        "300kPa, 3e5Pa; a bare number is Pa (>= 1 kPa). The engine uses (1 - nu^2) sigma0 in P(q) "
        "(default 0.2MPa)."
    ),
    "temperature": (
        "``--temperature``: background temperature T0 [C] (default: the rubber's reference temperature)."
    ),
    "flash": "``--flash``: flash-temperature model (Persson 2006).",
    "velocities": (
        "``--velocities``: N log-spaced sliding speeds [m/s] from LO to HI, or a list V1,V2,. (e.g. "
        "another program's table; default 1e-4:1e2:61, where tyres slide)."
    ),
    "q0": (
        "``--q0``: lower end of the friction integrals [1/m], inside the spectrum (default: its "
        "lowest wave vector)."
    ),
    "q1": (
        "``--q1``: upper end of the friction integrals [1/m]; beyond the Nyquist wave vector the "
        "spectrum is extended by its self-affine fit."
    ),
    "contact_gamma": (
        "``--contact-gamma``: Persson's S(q) = G + (1 - G) P(q)^2 in the dissipation integrand (mu = "
        "1/2 int q^3 C S P M dq); 0 <= G <= 1, e.g. 0.5 (default: off, S = 1)."
    ),
    "nu": "``--nu``: Poisson ratio of the rubber, 0 <= nu <= 0.5 (default 0.5).",
    "extrapolate": (
        "``--extrapolate``: master curve beyond its measured frequencies: powerlaw (E' held, E'' "
        "continues as the power law of its last decade; default) or hold (both held)."
    ),
    "no_friction": "``--no-friction``: skip mu(v).",
    "connectivity": "``--connectivity``: connectivity of the fill (default 4, as Matlab's imfill).",
    "max_depth": "``--max-depth``: water at most this deep above each depression's lowest point [m].",
    "water_film": (
        "``--water-film``: water available per area [m^3/m^2 = m]; fills to the smallest depth cap "
        "holding it."
    ),
    "wet_model": (
        "``--wet-model``: persson (default): sealing, squeeze-out, adhesion lost (Persson 2005, "
        "Lorenz & Persson 2010); fill: every basin filled (the thesis)."
    ),
    "water_depth": "``--water-depth``: water on the road per area [m] (default 5e-4, ASTM E274's film).",
    "water_temperature": "``--water-temperature``: water temperature [C], sets its viscosity (default 20).",
    "footprint": "``--footprint``: tyre contact length along the sliding [m] (default 0.12).",
    "block_size": "``--block-size``: tread block size, the squeeze-out length [m] (default 0.025).",
    "shear_stress": (
        "``--shear-stress``: frictional shear stress of the adhesive term [Pa] (default: none, "
        "adhesion left out)."
    ),
    "no_level": "``--no-level``: fill the heights as read (default: remove the least-squares plane first).",
    "psd": "``--psd``: psd.csv with header q_per_m,C_m4 [1/m, m^4].",
    "self_affine": (
        "``--self-affine``: self-affine model (thesis appendix A): Hurst H, h0 [m], q0, q1 [1/m], "
        "optional qroll [1/m]."
    ),
    "master_curve": (
        "``--master-curve``: master curve CSV: f [Hz], E_stor, E_loss (units line 'Hz, MPa, MPa' or "
        "header E_stor_MPa; default Pa) at --reference-temperature."
    ),
    "shift_table": (
        "``--shift-table``: with --master-curve: shift factors, columns T_C and aT (linear) or "
        "log10_aT; or one row of WLF constants C1,C2_K,T_s_C."
    ),
    "reference_temperature": (
        "``--reference-temperature``: with --master-curve: the temperature of the master curve T_ref "
        "[C] (default: where the shift table has aT = 1)."
    ),
    "magnifications": (
        "``--magnifications``: with --flash: also report T at these magnifications zeta = q/q0."
    ),
    "tol": "``--tol``: relative accuracy target for mu (1e-3).",
    "measured": (
        "``--measured``: measured mu(v): CSV v_m_per_s,mu[,T0_C,sigma0_Pa,condition] (friction "
        "level); without it the scan itself is diagnosed (surface level)."
    ),
    "scan": "``--scan``: height file (area scan or line profile).",
    "noise": "``--noise``: measurement noise as rms of log10 (default: estimated from the data).",
    "validate": "``--validate``: a separate measurement predicted by the corrected model without refitting.",
    "uncertain": (
        "``--uncertain``: inputs known only within a range, calibrated on the training points: "
        "q1=LO:HI [1/m] (q1=known: q1 fixed), sigma0=LO:HI (units as --sigma0), psd_scale=LO:HI "
        "(factor on C(q)), temperature=LO:HI [C]; any subset."
    ),
    "measurements": (
        "``--measurements``: several measurements at once: CSV "
        "measured,rubber,label[,temperature_C,sigma0_Pa] (paths relative to M.csv); q1, psd_scale and "
        "sigma0 shared."
    ),
}


def _entry(name: str, annotation: Any, default: Any, text: str) -> str:
    kind = annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation))
    head = f"    {name} : {kind.replace(' | ', ' or ')}, default {default!r}"
    body = textwrap.fill(text, 96, initial_indent=" " * 8, subsequent_indent=" " * 8)
    return f"{head}\n{body}"


def document_options(overrides: dict[str, str] | None = None) -> Callable[[F], F]:
    """Decorator: replace the ``{options}`` line of the job's docstring by one numpydoc entry
    per keyword-only parameter (annotation and default from the signature, text from
    :data:`OPTION_TEXT` or ``overrides``, for an option whose meaning the job narrows).

    Parameters
    ----------
    overrides : dict of str to str, optional
        Option name -> the text this job gives it instead of the shared one.

    Returns
    -------
    callable
        The decorator; the job itself is returned unchanged but for its ``__doc__``.
    """

    def decorate(job: F) -> F:
        entries = []
        for name, p in job_parameters(job).items():
            text = (overrides or {}).get(name) or OPTION_TEXT.get(name)
            if text is None:
                raise KeyError(f"{job.__name__}: option {name!r} has no text in OPTION_TEXT")
            entries.append(_entry(name, p.annotation, p.default, text))
        doc = job.__doc__ or ""
        if "    {options}\n" not in doc:
            raise ValueError(f"{job.__name__}: its docstring has no '    {{options}}' line")
        job.__doc__ = doc.replace("    {options}\n", "\n".join(entries) + "\n")
        return job

    return decorate
