"""The figures and ``report.html`` of ``roadscan dry-vs-wet`` (:mod:`pipelines.jobs.dry_vs_wet`).

Both wet models get mu_dry(v) and mu_wet(v), their ratio, the key figures and what the model
covers. The persson model (the default) adds what road engineers and the issue ask for: each
mechanism's part of ``mu_dry - mu_wet`` (sealing, squeeze-out film, adhesion lost) by speed,
the film left and the separation against the texture height (contact lost above it), the
model's wet speed constant beside the surface's IFI speed constant (ASTM E1960: Sp = 14.2 +
89.7 MPD, MPD in mm), the friction model of both curves and why, and every parameter with its
default and source. HTML only through :mod:`pipelines.output.templates` (escaped).
"""

from __future__ import annotations

import numpy as np

from pipelines.output import report
from pipelines.output.units import length, sig3, speed_kmh

__all__ = ["dry_wet_figures", "write_dry_wet_report", "FRICTION_MODEL_WHY"]

# the report's paragraph on what the wet model covers, and what it leaves out
_WET_MODEL_SCOPE = (
    "Sealing: at low speed the water the contact holds is what it seals in the pools closed at the "
    "magnification where the contact percolates (Persson, Tartaglino, Albohr, Tosatti, Phys. Rev. B "
    "71, 035428 (2005)); the rubber feels those pools filled. Squeeze-out: under a tread block the "
    "film thins during the dwell time footprint / v by averaged Reynolds flow with Persson's contact "
    "pressure (Phys. Rev. Lett. 99, 125502 (2007); Lorenz & Persson, Eur. Phys. J. E 32, 281 "
    "(2010)); the film carries part of the load, so the rubber reaches less of the roughness. "
    "Inertia: at the footprint's front, until the film has thinned to the texture's height, the "
    "water's dynamic pressure carries (v / v_p)² of the load there (Horne & Dreher, NASA TN D-2056 "
    "(1963): v_p = 6.35 √(p/kPa) km/h); counted in the squeeze-out share. Adhesion: Persson's "
    "τ_f A/A0, lost where water separates the surfaces. Contact lost: where the film left exceeds "
    "the texture or the water's inertia carries the whole load, μ_wet is the film's viscous drag. "
    "Left out: the viscous film on the asperity tops (the microtexture's thin-film lubrication), "
    "the tread's grooves as water storage, and the water's effect on rubber temperature."
)

#: why both curves use the run's friction model, and what each choice means for the shares
FRICTION_MODEL_WHY = {
    "isothermal": (
        "isothermal (the default, as roadscan analyse): the dry curve is the one analyse reports "
        "for this scan, and the wet one is comparable with it. The rubber's flash heating is "
        "left out of both, so all the fall of μ_wet with speed beyond the dry curve's own "
        "(viscoelastic) shape is the water's. --flash includes the heating (Persson, J. Phys.: "
        "Condens. Matter 18, 7789 (2006), doi:10.1088/0953-8984/18/32/025)"
    ),
    "flash temperature": (
        "flash temperature (--flash): both curves include the rubber's heating "
        "(Persson 2006, doi:10.1088/0953-8984/18/32/025); the fall of the dry curve "
        "is the heating's and the viscoelastic shape's, the extra fall of the wet one "
        "the water's (the split below)"
    ),
}


def _finite(x):
    return x is not None and np.isfinite(x)


def dry_wet_figures(out_dir, name, r, v, mu_dry, mu_wet, wf=None):
    """The PNG figures of the friction part: mu(v) dry and wet, their ratio, and with the persson
    model (``wf``, a :class:`friction.wet.WetFriction`) the loss by mechanism and the water film.

    Parameters
    ----------
    out_dir : Path
        Output folder.
    name : str
        Scan name (titles).
    r : dict
        ``comparison.json`` so far (its ``rubber``).
    v, mu_dry, mu_wet : ndarray
        Speeds [m/s] and the curves.
    wf : friction.wet.WetFriction, optional
        The persson model's result (None: the fill model).

    Returns
    -------
    list of Path
    """
    label = "wet (rain-filled)" if wf is None else "wet (sealing, squeeze-out, adhesion)"
    figs = [
        report.plot_mu(
            [("dry", v, mu_dry), (label, v, mu_wet)],
            out_dir / "mu_dry_wet.png",
            title=f"{name}: μ(v) dry and wet, {r['rubber']}",
        )
    ]
    ratio = np.divide(mu_wet, mu_dry, out=np.full_like(mu_wet, np.nan), where=mu_dry > 0)
    figs.append(
        report.plot_mu(
            [("μ_wet / μ_dry", v, ratio)],
            out_dir / "mu_ratio.png",
            title=f"{name}: wet-to-dry friction ratio",
            ylabel="μ_wet / μ_dry [-]",
        )
    )
    if wf is None:
        return figs
    parts = wf.parts
    figs.append(
        report.plot_mu(
            [
                ("lost to sealing", v, parts["sealing"]),
                ("lost to the squeeze-out film", v, parts["squeeze_out"]),
                ("adhesion lost", v, parts["adhesion"]),
                ("μ_dry - μ_wet", v, mu_dry - mu_wet, "--"),
            ],
            out_dir / "mu_mechanisms.png",
            title=f"{name}: what water takes from μ, by mechanism",
            ylabel="part of μ_dry - μ_wet [-]",
        )
    )
    tex = wf.meta["texture_height_m"]
    film = np.where(wf.film_m >= 1e-9, wf.film_m, np.nan) * 1e3
    figs.append(
        report.plot_mu(
            [
                ("film left after the dwell time (≥ 1 nm shown)", v, film, "o-"),
                ("mean separation u after the dwell time", v, wf.separation_m * 1e3),
                ("separation of the dry contact", v, wf.separation_dry_m * 1e3, "--"),
                (
                    "texture height 3 h_rms: contact lost once the film left rises above it",
                    v,
                    np.full(v.shape, tex * 1e3),
                    ":",
                ),
            ],
            out_dir / "film_left.png",
            title=f"{name}: water film under a tread block",
            ylabel="thickness [mm]",
            logy=True,
        )
    )
    return figs


def _film_text(x):
    """A film thickness for the table: below 1 nm (the squeeze quadrature's floor) it is none."""
    if x is None:
        return "—"
    return "< 1 nm" if x < 1e-9 else length(x)


def _share(x):
    return "—" if x is None else f"{100 * x:.0f} %"


def _friction_rows(r):
    vs = list(r["mu_dry"])
    v = np.array([float(s) for s in vs])
    lv = np.log10(v)
    kmh = v * 3.6
    ifi = (kmh * (1 + 1e-9) >= 20) & (kmh <= 100 * (1 + 1e-9))  # the speed constant's range
    show = [i for i in range(v.size) if abs(lv[i] - round(lv[i])) < 1e-6 or ifi[i]]
    if v.size <= 25:
        show = list(range(v.size))
    mech = r.get("mechanisms") or {}
    film = r.get("film_m") or {}
    rows = []
    for i in show:
        s = vs[i]
        d, w = r["mu_dry"][s], r["mu_wet"][s]
        row = [s, sig3(kmh[i]), sig3(d), sig3(w), sig3(w / d) if d else "—"]
        if film:
            row += [
                _film_text(film.get(s)),
                *(_share(mech.get(k, {}).get(s)) for k in ("sealing", "squeeze_out", "adhesion")),
            ]
        rows.append(row)
    head = ["v [m/s]", "v [km/h]", "μ dry", "μ wet", "wet / dry"]
    if film:
        head += ["film left", "sealing", "squeeze-out", "adhesion lost"]
    return rows, head


def _speed_constant_rows(r):
    sp = r.get("speed_constant_model_kmh")
    ifi = r.get("ifi_speed_constant_kmh")
    mpd = r.get("mpd_m")
    model = (
        speed_kmh(sp)
        if sp is not None
        else "none: μ_wet does not fall over 20-100 km/h (or the speeds do not reach there)"
    )
    surface = (
        f"{speed_kmh(ifi)} (MPD {length(mpd)}, ISO 13473-1)"
        if ifi is not None
        else f"none: {r.get('mpd_note') or 'no valid MPD'}"
    )
    rows = {
        "model: Sp of μ_wet = F exp(-S / Sp) fitted over 20-100 km/h": model,
        "surface: IFI Sp = 14.2 + 89.7 MPD [mm] (ASTM E1960)": surface,
    }
    if sp is not None and ifi is not None:
        rows["model / IFI"] = f"{sp / ifi:.2f}"
    fall = r.get("fall_20_100_kmh")
    if fall:
        rows["fall of μ_wet from 20 to 100 km/h"] = (
            f"{sig3(fall['mu_wet'])} = {sig3(fall['dry_curve'])} from the dry curve ({r.get('model')}) "
            f"+ {sig3(fall['water'])} from the water"
        )
    return rows


def _contact_lost(r):
    v = r.get("contact_lost_v_m_per_s")
    if v is not None:
        return f"{sig3(v)} m/s ({speed_kmh(v * 3.6)}): the film left exceeds the texture height"
    film = [x for x in (r.get("film_m") or {}).values() if x is not None]
    top = max(film) if film else None
    if top is None:
        return "not within the speeds computed"
    return (
        f"not within the speeds computed (largest film left {_film_text(top)}, texture height "
        f"{length(r.get('texture_height_m'))})"
    )


def _lift_text(r):
    lift = {k: x for k, x in (r.get("dynamic_lift_share") or {}).items() if x is not None}
    vp = r.get("horne_dreher_v_m_per_s")
    tail = f"; a tyre in undrained water is lifted at {speed_kmh(vp * 3.6)}" if vp else ""
    if not lift:
        return "—"
    s, x = max(lift.items(), key=lambda kv: kv[1])
    if x <= 0:
        return (
            "none: no film stands above the texture at the footprint's front (the texture holds "
            f"or drains the water){tail}"
        )
    return f"at most {sig3(100 * x)} % of the load (at v = {s} m/s){tail}"


def _parameter_rows(r, sigma0_text):
    wm = r.get("wet_model") or {}
    params = wm.get("parameters") or {}
    if wm.get("name") != "persson":
        return [
            ["connectivity", params.get("connectivity"), "default 4", "as Matlab's imfill"],
            [
                "depth cap (--max-depth)",
                length(params.get("max_depth_m")) if params.get("max_depth_m") else "none",
                "default none",
                "every basin full to its spill level (the thesis)",
            ],
            [
                "water per area (--water-film)",
                length(params.get("water_film_m")) if params.get("water_film_m") else "none",
                "default none",
                "as much water as the basins hold",
            ],
            ["nominal pressure σ0", sigma0_text, "", "--sigma0 (default 0.2 MPa)"],
        ]
    given = set(wm.get("given") or [])
    src = wm.get("sources") or {}
    show = {
        "water_depth_m": ("water on the road (--water-depth)", length),
        "water_temperature_C": ("water temperature (--water-temperature)", lambda x: f"{sig3(x)} °C"),
        "footprint_m": ("contact length (--footprint)", length),
        "block_size_m": ("tread block (--block-size)", length),
        "shear_stress_Pa": (
            "frictional shear stress τ_f (--shear-stress)",
            lambda x: "none: adhesion left out" if x is None else f"{sig3(x)} Pa",
        ),
        "percolation_contact_fraction": ("contact fraction where the pools close", sig3),
    }
    rows = [
        [label, fmt(params.get(k)), "given" if k in given else "default", src.get(k, "")]
        for k, (label, fmt) in show.items()
    ]
    rows.append(
        [
            "water viscosity",
            f"{sig3(1e3 * params['water_viscosity_Pa_s'])} mPa s",
            "from the temperature",
            "Vogel's equation, within 1 % of IAPWS 2008 (Huber et al., "
            "J. Phys. Chem. Ref. Data 38, 101 (2009))",
        ]
    )
    rows.append(
        [
            "nominal pressure σ0 (the chain's)",
            sigma0_text,
            "",
            "--sigma0 (default 0.2 MPa, about a car tyre's inflation pressure)",
        ]
    )
    return rows


def write_dry_wet_report(out_dir, r, figs):
    """Write ``report.html`` of a dry-vs-wet run from its ``comparison.json`` dict ``r``.

    Parameters
    ----------
    out_dir : Path
        Output folder.
    r : dict
        ``comparison.json``.
    figs : list of Path
        The figures, in order.

    Returns
    -------
    Path
    """
    from pipelines.output.headline import hurst_pair_text, wet_model_html

    wm = r.get("wet_model") or {}
    persson = wm.get("name") == "persson"
    key = {
        "wet model": (
            "persson: the pools the contact seals, the squeeze-out film and the water's inertia "
            "at its front, the adhesion water removes (Persson et al. 2005; Lorenz & Persson "
            "2010; Horne & Dreher 1963)"
            if persson
            else "fill: every basin filled, the rubber on the filled surface (the thesis)"
        ),
        "rms height dry / wet (rain-filled)": (
            f"{length(r['rms_height_dry_m'])} / {length(r['rms_height_wet_m'])}"
        ),
        "Hurst exponent dry / wet": hurst_pair_text(r),
        "median PSD ratio wet / dry": r["psd_ratio_wet_to_dry_median"],
        "wetted area fraction": (
            f"{sig3(100 * r['wetted_fraction'])} %" if r["wetted_fraction"] is not None else None
        ),
        "water per area (volume / area, as a depth)": length(r["water_volume_m3_per_m2"]),
        "connectivity of the fill": r["connectivity"],
        **({"water depth cap (--max-depth)": length(r["max_depth_m"])} if r.get("max_depth_m") else {}),
        **(
            {"water film per area (--water-film)": length(r["water_film_m"])} if r.get("water_film_m") else {}
        ),
        "MPD (ISO 13473-1)": length(r["mpd_m"]) if r.get("mpd_m") is not None else (r.get("mpd_note") or "—"),
        "3D view drawn with": r.get("renderer_3d") or "not drawn",
        "rubber (friction)": r.get("rubber") or "—",
    }
    if r.get("mu_dry"):
        first = next(iter(r["mu_dry"]))
        d, w = r["mu_dry"][first], r["mu_wet"][first]
        key["μ_wet / μ_dry at the lowest speed"] = f"{sig3(w / d)} (v = {first} m/s)" if d else "—"
        if persson:
            seal = r.get("sealing") or {}
            key["sealed pools"] = (
                f"{seal.get('pool_count', 0)} pools, "
                f"{sig3(100 * seal.get('sealed_fraction', 0))} % of the area, closed at "
                f"q = {sig3(seal.get('q_seal_per_m') or 0)} 1/m"
            )
            key["contact lost (hydroplaning)"] = _contact_lost(r)
            key["load carried by the water's inertia (Horne & Dreher)"] = _lift_text(r)
    sections = [("Key figures", report.table_html(key, ["quantity", "value"]))]
    notes = list(r.get("warnings") or []) + ([r["render_note"]] if r.get("render_note") else [])
    if notes:
        sections.append(("Warnings and notes", report.list_html(notes)))
    if r.get("mu_dry"):
        rows, head = _friction_rows(r)
        sections.append(
            (
                f"Friction ({r['model']}); largest difference at v = {r['max_difference_v_m_per_s']:.3g} m/s",
                report.table_html(rows, head),
            )
        )
        if persson:
            sections.append(
                ("Which friction model, and why", report.paragraph_html(FRICTION_MODEL_WHY[r["model"]] + "."))
            )
        sections.append(
            (
                "Wet speed constant: the model and the surface's IFI",
                report.table_html(_speed_constant_rows(r), ["quantity", "value"]),
            )
        )
    elif r.get("friction_refused"):
        sections.append(("Friction refused", report.paragraph_html(r["friction_refused"])))
    sections.append(
        (
            "Parameters, defaults and sources",
            report.table_html(
                _parameter_rows(r, _sigma0_text(r)), ["parameter", "value", "given or default", "source"]
            ),
        )
    )
    if persson:
        sections.append(("What the wet model covers", report.paragraph_html(_WET_MODEL_SCOPE, note=True)))
    elif r.get("wet_model"):
        sections.append(("What the wet model covers", wet_model_html()))
    if figs:
        sections.append(("Figures", [list(figs)]))
    if persson:
        intro = (
            "The wet curve follows Persson's picture of a tyre on a wet road: the water sealed in the "
            "pools the contact closes, the film squeezed out under a tread block during the time it "
            "takes to pass, and the adhesion water removes; "
            + ("the maps below also show" if figs else "the PSD comparison uses")
            + " the thesis's rain-filled surface (every basin full)"
            + (", which is what the PSD comparison uses." if figs else ".")
        )
    else:
        intro = (
            "Water fills every depression not connected to the border up to its spill level "
            "(grayscale imfill / morphological reconstruction)"
            + (f", at most {length(r['max_depth_m'])} deep" if r.get("max_depth_m") else "")
            + (f", with {length(r['water_film_m'])} of water per area" if r.get("water_film_m") else "")
            + "; the rubber slides over the filled surface."
        )
    return report.write_html(
        out_dir / "report.html",
        f"roadscan dry-vs-wet: {r['name']}",
        sections,
        intro=report.paragraph_html(intro),
    )


def _sigma0_text(r):
    p = ((r.get("wet_model") or {}).get("parameters") or {}).get("sigma0_Pa")
    return "—" if p is None else f"{sig3(p / 1e6)} MPa"
