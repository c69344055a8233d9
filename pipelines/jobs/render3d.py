"""Off-screen 3D views of a surface and its water: pyvista (VTK) when installed (the ``[3d]``
extra), else matplotlib's mplot3d (Agg) on a downsampled map; :func:`render_3d_view` picks one
and says which (``dry-vs-wet`` writes it into ``comparison.json`` and its report)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from roadscan.io.atomic import atomic_path

__all__ = [
    "render_surface_with_water",
    "render_surface_with_water_mpl",
    "render_3d_view",
    "View3D",
    "NEEDS_PYVISTA",
]

#: the one warning line when no 3D view could be drawn
NEEDS_PYVISTA = "3D view needs pyvista: pip install 'roadscan[3d]'"


@dataclass
class View3D:
    """Outcome of :func:`render_3d_view`: the PNG (None when not drawn), the renderer used
    (``"pyvista"``, ``"matplotlib"`` or None), a note on why it was not drawn, and the warning
    line to print and record (None when there is none).

    Attributes
    ----------
    path : Path or None
        The PNG.
    renderer : str or None
        ``"pyvista"`` or ``"matplotlib"``.
    note : str or None
        Why it was not drawn.
    warning : str or None
        Warning line.
    """

    path: object = None
    renderer: str | None = None
    note: str | None = None
    warning: str | None = None


def _have_pyvista():
    try:
        import pyvista  # noqa: F401
    except ImportError:
        return False
    return True


def render_3d_view(dry_hm, depth_m, path, title="surface and water"):
    """The 3D view of ``dry_hm`` with its water ``depth_m`` [m] as PNG at ``path``.

    pyvista when importable (its failure to render, e.g. without OpenGL, gives a note, as
    before); without pyvista, matplotlib (:func:`render_surface_with_water_mpl`); when that
    fails too, no view and the warning :data:`NEEDS_PYVISTA`. Returns a :class:`View3D`.

    Parameters
    ----------
    dry_hm : HeightMap
        The dry surface [m].
    depth_m : ndarray
        Water depth [m].
    path : str or Path
        Output PNG.
    title : str, optional
        Title.

    Returns
    -------
    View3D
    """
    if _have_pyvista():
        try:
            return View3D(render_surface_with_water(dry_hm, depth_m, path, title=title), "pyvista")
        except Exception as exc:  # noqa: BLE001 - rendering needs an OpenGL context; the numbers do not
            return View3D(note=f"3D view not rendered: {type(exc).__name__}: {exc}")
    try:
        return View3D(
            render_surface_with_water_mpl(dry_hm, depth_m, path, title=title),
            "matplotlib",
            note="3D view drawn with matplotlib (pyvista not installed: pip install 'roadscan[3d]')",
        )
    except Exception as exc:  # noqa: BLE001 - matplotlib fails in many ways: the view is a note, the run goes on
        return View3D(note=f"3D view not rendered: {type(exc).__name__}: {exc}", warning=NEEDS_PYVISTA)


def _grid(dry_hm, depth_m, max_points, exaggeration):
    """Downsampled plotting grid shared by both renderers: x, y [mm] (meshgrid), the measured
    mask, heights with holes filled by the median [m], water depth [m], the displayed
    exaggerated height Z [mm] and the exaggeration (about 0.15 x span / relief, at least 1)."""
    h = np.array(dry_hm.heights_m, dtype=float)
    step = max(1, int(np.ceil(max(h.shape) / max_points)))
    h = h[::step, ::step]
    d = np.asarray(depth_m, dtype=float)[::step, ::step]
    fill = np.nanmedian(h)
    h_plot = np.where(np.isfinite(h), h, fill)
    ny, nx = h.shape
    x = np.arange(nx) * dry_hm.dx_m * step * 1e3  # mm
    y = np.arange(ny) * dry_hm.dy_m * step * 1e3
    X, Y = np.meshgrid(x, y)
    span = max(x[-1], y[-1])
    relief = np.ptp(h_plot) * 1e3 or 1.0
    if exaggeration is None:
        exaggeration = max(1.0, 0.15 * span / relief)
    Z = (h_plot - fill) * 1e3 * exaggeration
    return X, Y, h, h_plot, d, Z, exaggeration


def _quiet_vtk():
    try:
        import vtk

        vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_ERROR)
        vtk.vtkObject.GlobalWarningDisplayOff()
    except (ImportError, AttributeError):
        pass


def render_surface_with_water(
    dry_hm, depth_m, path, max_points=220, exaggeration=None, title="surface and water"
):
    """Render the dry surface (coloured by height) with the water (blue) on top, off-screen.

    Heights are vertically exaggerated so that texture is visible (the factor is printed in
    the image). Grids larger than ``max_points`` per side are subsampled for speed.

    Parameters
    ----------
    dry_hm : HeightMap
        The dry surface [m].
    depth_m : ndarray
        Water depth [m].
    path : str or Path
        Output PNG.
    max_points : int, optional
        Points per side at most.
    exaggeration : float, optional
        Vertical exaggeration.
    title : str, optional
        Title.

    Returns
    -------
    Path
    """
    import pyvista as pv

    _quiet_vtk()
    X, Y, h, h_plot, d, Z, exaggeration = _grid(dry_hm, depth_m, max_points, exaggeration)
    ground = pv.StructuredGrid(X, Y, Z)
    f, name = _height_unit(h_plot)
    ground[name] = (h_plot * f).ravel(order="F")
    ground["measured"] = np.isfinite(h).ravel(order="F").astype(float)
    if not np.isfinite(h).all():  # unmeasured points are holes, not invented ground
        ground = ground.threshold(0.5, scalars="measured", all_scalars=True)
    pl = pv.Plotter(off_screen=True, window_size=(900, 650))
    pl.set_background("white")
    pl.add_mesh(
        ground,
        scalars=name,
        cmap="copper",
        show_scalar_bar=True,
        scalar_bar_args={
            "title": name,
            "color": "black",
            "vertical": True,
            "position_x": 0.89,
            "position_y": 0.2,
            "width": 0.05,
            "fmt": "%#.3g" if f == 1e3 else "%.0f",
            "n_labels": 5,
        },
    )  # not "918."
    wet = np.isfinite(d) & (d > 0)
    if wet.any():
        Zw = np.where(wet, Z + np.nan_to_num(d) * 1e3 * exaggeration + 1e-6, np.nan)
        water = pv.StructuredGrid(X, Y, np.nan_to_num(Zw, nan=0.0))
        water["wet"] = wet.ravel(order="F").astype(float)
        water = water.threshold(0.5, scalars="wet")
        if water.n_cells:
            pl.add_mesh(water, color="#1f77ff", opacity=0.75, show_scalar_bar=False)
    pl.add_text(f"{title}\nx, y in mm; heights exaggerated x{exaggeration:.0f}", font_size=10, color="black")
    pl.camera_position = "iso"
    pl.camera.elevation = -10
    pl.camera.zoom(1.1)  # the colour bar right of the surface, not over it
    with atomic_path(path) as tmp:
        pl.screenshot(str(tmp))
    pl.close()
    return path


def _height_unit(h_m):
    """(factor, colour-bar title) for heights [m]: µm, or mm once they reach 1 mm."""
    big = float(np.nanmax(np.abs(h_m))) if np.isfinite(h_m).any() else 0.0
    return (1e3, "height [mm]") if big >= 1e-3 else (1e6, "height [µm]")


def render_surface_with_water_mpl(
    dry_hm, depth_m, path, max_points=100, exaggeration=None, title="surface and water"
):
    """The view of :func:`render_surface_with_water` drawn with matplotlib's mplot3d
    (``plot_surface``, Agg, off-screen) on a map downsampled to ``max_points`` per side:
    ground coloured by height [um] (copper), water blue on top, unmeasured points left out,
    heights exaggerated as said in the title.

    Parameters
    ----------
    dry_hm : HeightMap
        The dry surface [m].
    depth_m : ndarray
        Water depth [m].
    path : str or Path
        Output PNG.
    max_points : int, optional
        Points per side at most.
    exaggeration : float, optional
        Vertical exaggeration.
    title : str, optional
        Title.

    Returns
    -------
    Path
    """
    from matplotlib import cm, colors

    from pipelines.output.report import DPI, pyplot

    plt = pyplot()

    X, Y, h, h_plot, d, Z, exaggeration = _grid(dry_hm, depth_m, max_points, exaggeration)
    f, name = _height_unit(h_plot)
    um = h_plot * f
    norm = colors.Normalize(vmin=float(um.min()), vmax=float(max(um.max(), um.min() + 1e-9)))
    face = cm.copper(norm(um))
    face[..., 3] = np.where(np.isfinite(h), 1.0, 0.0)  # unmeasured points are holes
    fig = plt.figure(figsize=(9.0, 6.5))
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(
        X, Y, Z, facecolors=face, rstride=1, cstride=1, linewidth=0, antialiased=False, shade=False
    )
    wet = np.isfinite(d) & (d > 0)
    if wet.any():
        Zw = np.where(wet, Z + np.nan_to_num(d) * 1e3 * exaggeration + 1e-6, Z)
        blue = np.zeros(Z.shape + (4,))
        blue[...] = colors.to_rgba("#1f77ff")
        blue[..., 3] = np.where(wet, 0.75, 0.0)
        ax.plot_surface(
            X, Y, Zw, facecolors=blue, rstride=1, cstride=1, linewidth=0, antialiased=False, shade=False
        )
    mappable = cm.ScalarMappable(norm=norm, cmap=cm.copper)
    fig.colorbar(mappable, ax=ax, shrink=0.6, pad=0.08, label=name)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zticks([])
    ax.set_box_aspect((float(np.ptp(X)) or 1.0, float(np.ptp(Y)) or 1.0, max(float(np.ptp(Z)), 1e-9)))
    ax.view_init(elev=35, azim=-60)
    ax.set_title(f"{title}\nx, y in mm; heights exaggerated x{exaggeration:.0f}", fontsize=10)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=DPI, format="png", bbox_inches="tight")
    plt.close(fig)
    return path
