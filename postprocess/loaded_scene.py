"""3D picture of a loaded scene: the gear surfaces with the contact-line loads of one solved
mesh position drawn on the flanks (off-screen pyvista), for a person to see where the load
sits on the face width and which tooth pairs carry it.

The loads drawn are the stations' (:func:`postprocess.train_results.mesh_stations`): one
sphere per station at its point on the contact line, coloured by its line load. A line
grid's stations are its points; a zone grid's are its sections (one per section and tooth
pair, at the section's closest approach), so its many cells are not drawn one by one."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshing.build import scene_mesh_file
from meshing.pictures import (
    BODY_COLOURS,
    PIN_COLOUR,
    save_screenshot,
    surface_polydata,
    vtk_warnings_off,
)
from postprocess.train_results import mesh_stations


def loaded_scene_picture(scene, pos: dict, level: int, png_path: Path, title: str) -> Path:
    """PNG of ``scene`` (the scene ``pos`` was solved in, at level ``level``) with every
    station of every mesh as a sphere coloured by its line load (N/mm).
    Serial: call on one rank (the body meshes are already cached by the solve)."""
    with vtk_warnings_off():
        return _draw(scene, pos, level, Path(png_path), title)


def _draw(scene, pos: dict, level: int, png_path: Path, title: str) -> Path:
    import pyvista as pv  # heavy: only when a picture is drawn

    pv.OFF_SCREEN = True
    msh, _ = scene_mesh_file(scene, level)
    poly, bodies = surface_polydata(Path(msh))
    stations = [mesh_stations(m) for m in pos["meshes"].values()]
    x = np.vstack([np.asarray(st["x_mm"], float).reshape(-1, 3) for st in stations])
    w = np.concatenate([np.clip(st["line_load_N_per_mm"], 0.0, None) for st in stations])
    cloud = pv.PolyData(x)
    cloud["line load (N/mm)"] = w
    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1800, 900))
    for col, view in enumerate(("iso", "xy")):
        plotter.subplot(0, col)
        for i, body in enumerate(bodies):
            cells = (poly.cell_data["body"] == i) & (poly.cell_data["pin"] == 0)
            part = poly.extract_cells(np.flatnonzero(cells))
            colour = BODY_COLOURS[i % len(BODY_COLOURS)]
            plotter.add_mesh(part, color=colour, opacity=0.35, label=body)
        pins = np.flatnonzero(poly.cell_data["pin"] == 1)
        if pins.size:  # the carrier's pins, apart from its plates and posts
            plotter.add_mesh(
                poly.extract_cells(pins), color=PIN_COLOUR, opacity=0.9, label="carrier pins"
            )
        plotter.add_mesh(
            cloud,
            scalars="line load (N/mm)",
            cmap="inferno_r",
            point_size=9,
            render_points_as_spheres=True,
            clim=(0.0, max(float(w.max()), 1.0)),
            scalar_bar_args={"position_x": 0.2, "width": 0.6, "fmt": "%.0f"},
        )
        if view == "xy":
            plotter.view_xy()
            plotter.add_text("from +z (scene frame)", font_size=10)
        else:
            plotter.view_isometric()
            plotter.add_text(title, font_size=10)
            plotter.add_legend(bcolor="white", size=(0.15, 0.12))
        plotter.show_axes()
    return save_screenshot(plotter, png_path)
