"""Off-screen 3D views of a surface and its water, rendered with pyvista (VTK)."""
from __future__ import annotations

import numpy as np

from roadscan.io.atomic import atomic_path

__all__ = ["render_surface_with_water"]


def _quiet_vtk():
    try:
        import vtk

        vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_ERROR)
        vtk.vtkObject.GlobalWarningDisplayOff()
    except (ImportError, AttributeError):
        pass


def render_surface_with_water(dry_hm, depth_m, path, max_points=220, exaggeration=None,
                              title="surface and water"):
    """Render the dry surface (coloured by height) with the water (blue) on top, off-screen.

    Heights are vertically exaggerated so that texture is visible (the factor is printed in
    the image). Grids larger than ``max_points`` per side are subsampled for speed.
    """
    import pyvista as pv

    _quiet_vtk()
    h = np.array(dry_hm.heights_m, dtype=float)
    step = max(1, int(np.ceil(max(h.shape) / max_points)))
    h = h[::step, ::step]
    d = np.asarray(depth_m, dtype=float)[::step, ::step]
    fill = np.nanmedian(h)
    h_plot = np.where(np.isfinite(h), h, fill)
    ny, nx = h.shape
    x = np.arange(nx) * dry_hm.dx_m * step * 1e3   # mm
    y = np.arange(ny) * dry_hm.dy_m * step * 1e3
    X, Y = np.meshgrid(x, y)
    span = max(x[-1], y[-1])
    relief = np.ptp(h_plot) * 1e3 or 1.0
    if exaggeration is None:
        exaggeration = max(1.0, 0.15 * span / relief)
    Z = (h_plot - fill) * 1e3 * exaggeration
    ground = pv.StructuredGrid(X, Y, Z)
    ground["height [µm]"] = (h_plot * 1e6).ravel(order="F")
    ground["measured"] = np.isfinite(h).ravel(order="F").astype(float)
    if not np.isfinite(h).all():   # unmeasured points are holes, not invented ground
        ground = ground.threshold(0.5, scalars="measured", all_scalars=True)
    pl = pv.Plotter(off_screen=True, window_size=(900, 650))
    pl.set_background("white")
    pl.add_mesh(ground, scalars="height [µm]", cmap="copper", show_scalar_bar=True,
                scalar_bar_args={"title": "height [µm]", "color": "black", "vertical": True,
                                 "position_x": 0.86, "position_y": 0.2})
    wet = np.isfinite(d) & (d > 0)
    if wet.any():
        Zw = np.where(wet, Z + np.nan_to_num(d) * 1e3 * exaggeration + 1e-6, np.nan)
        water = pv.StructuredGrid(X, Y, np.nan_to_num(Zw, nan=0.0))
        water["wet"] = wet.ravel(order="F").astype(float)
        water = water.threshold(0.5, scalars="wet")
        if water.n_cells:
            pl.add_mesh(water, color="#1f77ff", opacity=0.75, show_scalar_bar=False)
    pl.add_text(f"{title}\nx, y in mm; heights exaggerated x{exaggeration:.0f}", font_size=10,
                color="black")
    pl.camera_position = "iso"
    pl.camera.elevation = -10
    pl.camera.zoom(1.35)
    with atomic_path(path) as tmp:
        pl.screenshot(str(tmp))
    pl.close()
    return path
