"""The ISO 13473-4 texture spectrum's outputs: ``texture_spectrum.csv`` (header
``centre_wavelength_m,band_lo_m,band_hi_m,level_dB``), the third-octave bar chart
``texture_spectrum.png`` and the report's band table (mm and dB re 1 µm).
"""

from __future__ import annotations

__all__ = [
    "TEXTURE_HEADER",
    "html_escape",
    "write_texture_csv",
    "texture_picture",
    "draw_texture_spectrum",
    "texture_table_html",
]

TEXTURE_HEADER = ["centre_wavelength_m", "band_lo_m", "band_hi_m", "level_dB"]


def html_escape(text):
    """``str(text)`` escaped for HTML.

    Parameters
    ----------
    text : object
        Any value.

    Returns
    -------
    str
    """
    import html

    return html.escape(str(text))


def write_texture_csv(path, ts):
    """``texture_spectrum.csv``: one row per resolved band, SI.

    Parameters
    ----------
    path : str or Path
        Output CSV.
    ts : TextureSpectrum
        The spectrum.

    Returns
    -------
    Path
    """
    from pipelines.output.report import write_csv

    return write_csv(path, TEXTURE_HEADER, [ts.centre_m, ts.lo_m, ts.hi_m, ts.level_dB])


def texture_picture(ts):
    """What :func:`draw_texture_spectrum` needs (small, picklable).

    Parameters
    ----------
    ts : TextureSpectrum
        The spectrum.

    Returns
    -------
    dict
    """
    import numpy as np

    return {"nominal_mm": np.asarray(ts.nominal_mm), "level_dB": np.asarray(ts.level_dB)}


def draw_texture_spectrum(picture, path, title):
    """Third-octave bar chart as in ISO 13473-4: wavelength bands [mm] descending from left
    to right, texture level [dB re 1 µm] as bars.

    Parameters
    ----------
    picture : dict
        From :func:`texture_picture`.
    path : str or Path
        Output PNG.
    title : str
        Title.

    Returns
    -------
    Path
    """
    import numpy as np

    from pipelines.output import report
    from pipelines.output.units import sig3

    plt = report.pyplot()
    nom = picture["nominal_mm"][::-1]
    lvl = picture["level_dB"][::-1]
    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    x = np.arange(nom.size)
    ok = np.isfinite(lvl)
    base = np.floor(np.nanmin(lvl[ok]) / 10) * 10 - 10 if ok.any() else 0.0
    ax.bar(x[ok], lvl[ok] - base, bottom=base, width=0.8, color="C0", edgecolor="0.2", lw=0.5)
    ax.set_xticks(x)
    ax.set_xticklabels([f"{v:g}" for v in nom], rotation=90, fontsize=8)
    ax.set_xlim(-0.6, nom.size - 0.4)
    ax.set_xlabel("texture wavelength, third-octave band centre [mm]")
    ax.set_ylabel("texture level L [dB re 1 µm]")
    if ok.any():
        ax.set_ylim(base, np.nanmax(lvl[ok]) + 5)
        k = int(np.nanargmax(np.where(ok, lvl, -np.inf)))
        ax.annotate(
            f"{sig3(lvl[k])} dB",
            (x[k], lvl[k]),
            textcoords="offset points",
            xytext=(0, 3),
            ha="center",
            fontsize=7,
        )
    ax.grid(axis="y", alpha=0.3)
    report.set_title(ax, title, y=1.0)
    return report.save_figure(fig, path, report.fixed_margins(ax, bottom=0.95))


def texture_table_html(ts):
    """The band table of the report (mm and dB).

    Parameters
    ----------
    ts : TextureSpectrum
        The spectrum.

    Returns
    -------
    str
    """
    from pipelines.output.report import table_html
    from pipelines.output.units import decibel, sig3

    rows = [
        (f"{n:g}", sig3(c * 1e3), f"{sig3(lo * 1e3)} – {sig3(hi * 1e3)}", decibel(v))
        for n, c, lo, hi, v in zip(
            ts.nominal_mm[::-1], ts.centre_m[::-1], ts.lo_m[::-1], ts.hi_m[::-1], ts.level_dB[::-1]
        )
    ]
    return table_html(rows, ["band [mm]", "exact centre [mm]", "band edges [mm]", "level [dB re 1 µm]"])
