"""Off-screen pictures of a tagged mesh (pyvista), for a person to check the gears.

Two views side by side: the transverse view from +z (placement, phase, teeth in mesh) and
an oblique 3D view (helix sense, face widths, refinement). Bodies get one colour each; the
flanks and fillets of the active teeth are drawn in a stronger shade with their mesh edges.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np

from meshing import gmsh_util
from meshing import tags as T

# pyvista is heavy: it is imported lazily, inside the functions that draw.

BODY_COLOURS = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1"]


@contextlib.contextmanager
def vtk_warnings_off():
    """vtk's warning output off while our pictures are drawn, back as it was after.

    Without a display, vtk's X render window prints "bad X server connection. DISPLAY=" with
    raw colour codes through its output window when the first off-screen plotter is made
    (into log files too); the picture is drawn off-screen all the same. Only vtk's own
    switch is used (``vtkObject.GlobalWarningDisplayOff``), only around our drawing."""
    from vtkmodules.vtkCommonCore import vtkObject

    before = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtkObject.SetGlobalWarningDisplay(before)


def surface_polydata(msh_path: Path):
    """All named surface triangles of ``msh_path`` as one pyvista PolyData with cell
    arrays ``body`` (index into the returned body list), ``tooth`` (1 on tooth surfaces)
    and ``pin`` (1 on the carrier's pin surfaces, drawn apart from its plates and posts)."""
    import pyvista as pv

    with gmsh_util.session("picture") as gm:
        gm.merge(str(msh_path))
        node_tags, coords, _ = gm.model.mesh.getNodes()
        coords = np.asarray(coords).reshape(-1, 3)
        order = np.argsort(node_tags)
        sorted_tags = np.asarray(node_tags)[order]
        coords = coords[order]
        tris, body_idx, kinds, pins = [], [], [], []
        pin_names = {T.pin(k) for k in range(64)}
        bodies: list[str] = []
        for dim, ptag in gm.model.getPhysicalGroups(2):
            name = gm.model.getPhysicalName(dim, ptag)
            p = T.parse(name)
            if p.body not in bodies:
                bodies.append(p.body)
            for ent in gm.model.getEntitiesForPhysicalGroup(dim, ptag):
                types, _, enodes = gm.model.mesh.getElements(dim, ent)
                for t, n in zip(types, enodes, strict=True):
                    if t != 2:  # linear triangles only
                        continue
                    tri = np.searchsorted(sorted_tags, np.asarray(n)).reshape(-1, 3)
                    tris.append(tri)
                    body_idx.append(np.full(len(tri), bodies.index(p.body)))
                    kinds.append(np.full(len(tri), 1 if p.tooth is not None else 0))
                    pins.append(np.full(len(tri), 1 if name in pin_names else 0))
    tri = np.vstack(tris)
    faces = np.hstack([np.full((len(tri), 1), 3), tri]).ravel()
    poly = pv.PolyData(coords, faces)
    poly.cell_data["body"] = np.concatenate(body_idx)
    poly.cell_data["tooth"] = np.concatenate(kinds)
    poly.cell_data["pin"] = np.concatenate(pins)
    return poly, bodies


PIN_COLOUR = "#3b3b3b"  # carrier pins: dark, apart from the plates and posts


def scene_picture(
    msh_path: Path,
    png_path: Path,
    title: str = "",
    focus: tuple[tuple[float, float, float], float] | None = None,
) -> Path:
    """Write a PNG of the mesh in ``msh_path``: transverse view from +z, (if ``focus`` =
    (point, half height in mm)) a close transverse view of a mesh zone with mesh edges,
    and an oblique view. The carrier is drawn translucent so the gears stay visible."""
    with vtk_warnings_off():
        return _scene_picture(Path(msh_path), png_path, title, focus)


def _scene_picture(msh_path: Path, png_path: Path, title: str, focus) -> Path:
    import pyvista as pv

    pv.OFF_SCREEN = True
    poly, bodies = surface_polydata(msh_path)
    views = ["xy", "zoom", "iso"] if focus is not None else ["xy", "iso"]
    plotter = pv.Plotter(
        off_screen=True, shape=(1, len(views)), window_size=(900 * len(views), 900)
    )
    for col, view in enumerate(views):
        plotter.subplot(0, col)
        for i, body in enumerate(bodies):
            part = poly.extract_cells(np.flatnonzero(poly.cell_data["body"] == i))
            plotter.add_mesh(
                part,
                color=BODY_COLOURS[i % len(BODY_COLOURS)],
                opacity=0.25 if body == T.CARRIER else 1.0,
                show_edges=view != "xy",
                edge_color="#333333",
                line_width=0.3,
                label=body,
            )
        if view == "xy":
            plotter.view_xy()
            plotter.enable_parallel_projection()
            plotter.add_legend(bcolor="white", size=(0.2, 0.06 * len(bodies)))
            plotter.add_text(title or msh_path.stem, font_size=10)
        elif view == "zoom":
            point, half = focus
            plotter.view_xy()
            plotter.enable_parallel_projection()
            plotter.camera.focal_point = tuple(point)
            plotter.camera.position = (point[0], point[1], point[2] + 500.0)
            plotter.camera.parallel_scale = half
            plotter.add_text("mesh zone from +z (end face mesh)", font_size=10)
        else:
            plotter.view_isometric()
            plotter.add_text("oblique view (mesh edges)", font_size=10)
        plotter.show_axes()
    return save_screenshot(plotter, png_path)


def save_screenshot(plotter, png_path: Path) -> Path:
    """Write the plotter's picture to ``png_path`` (folders made as needed) and close it."""
    png_path = Path(png_path)
    png_path.parent.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(png_path))
    plotter.close()
    return png_path
