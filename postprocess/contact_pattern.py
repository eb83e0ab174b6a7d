"""Contact pattern charts: the FE load over the pinion flank of each mesh.

Every grid point of every solved mesh position is drawn at (Z, s): Z the axial position in
the frame of the pinion in that mesh (mm from mid face width, singh2007 sections 3 and 5), s
the roll position along the line of action from the pitch point (mm). Over one base pitch
the contact lines sweep the active flank, so together they show the pattern an engineer
reads from a marking compound test. Mid face width and the load centroid are drawn.

Colour: a line grid's points by their line load (N/mm); a zone grid's cells by their
solved pressure (MPa, the cell average F / w), loaded cells over unloaded ones. The zone
colour scale tops at the largest interior cell pressure
(:func:`postprocess.mesh_stress.edge_points`): the corner contact of the sharp tips and the
face-end cells can be several times higher and are drawn in the top colour, ringed, with
their maximum in the colour bar's label.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import Normalize

from postprocess.mesh_stress import contact_stress_at_points, edge_points

CMAP = "inferno_r"


def _pinion_of(mesh: dict) -> str:
    """The pinion whose frame the mesh's pattern is drawn in (the first pinion in it)."""
    return next(iter(mesh["on"]))


def pattern_points(pos: dict, mesh: str, s_mm, values=None):
    """(Z, s, v) of the grid points of ``mesh`` at one position: v the line load (N/mm) of
    each point, or ``values`` (one per point) if given (a zone grid's pressures)."""
    m = pos["meshes"][mesh]
    pinion = pos["pinions"][_pinion_of(m)]
    x = np.asarray(m["points"]["x_mm"], float).reshape(-1, 3)
    z = (x - np.asarray(pinion["centre_mm"])) @ np.asarray(pinion["frame"])[2]
    v = m["points"]["line_load_N_per_mm"] if values is None else values
    return z, np.asarray(s_mm), np.clip(np.asarray(v, float), 0.0, None)


def _mesh_data(study, positions, mesh, hz, edges) -> dict:
    """Points of every position, the value drawn and the colour scale of one mesh."""
    zone = positions[0]["meshes"][mesh].get("grid_model", "line") == "zone"
    pts, edge = [], []
    for p, h, e in zip(positions, hz, edges, strict=True):
        pts.append(pattern_points(p, mesh, h[mesh]["s_mm"], h[mesh]["p_max"] if zone else None))
        edge.append(e[mesh]["edge"])
    z, s, v = (np.concatenate(a) for a in zip(*pts, strict=True))
    edge = np.concatenate(edge)
    if zone:
        inner = v[~edge]
        top = float(inner.max()) if inner.size and inner.max() > 0 else float(v.max())
        edge_max = float(v[edge].max()) if edge.any() else None
        label = "contact pressure, cell average (MPa)"
        if edge_max is not None and edge_max > top:
            label += f"\nring: edge cell, up to {edge_max:.0f} MPa"
    else:
        top, label = float(v.max()), "line load (N/mm)"
    return {"z": z, "s": s, "v": v, "edge": edge, "zone": zone, "top": top or 1.0, "label": label}


def draw_contact_patterns(study, positions: list[dict], out_dir: Path) -> list[Path]:
    """One PNG per mesh plus a side-by-side panel; returns the paths."""
    meshes = list(positions[0]["meshes"])
    hz = [contact_stress_at_points(study.gearset, study.material, p) for p in positions]
    edges = [edge_points(study.gearset, p) for p in positions]
    data = {m: _mesh_data(study, positions, m, hz, edges) for m in meshes}
    # one scale per kind of value: line loads of all line meshes, pressures of all zone ones
    tops = {
        k: max((d["top"] for d in data.values() if d["zone"] == k), default=1.0)
        for k in (False, True)
    }
    paths = []

    def panel(ax, mesh):
        m0 = positions[0]["meshes"][mesh]
        d = data[mesh]
        pinion = _pinion_of(m0)
        gear = dict(zip((m0["driver"], m0["driven"]), m0["gears"], strict=True))[pinion]
        half_face = study.gearset.gears[gear].face_width / 2
        norm = Normalize(0.0, tops[d["zone"]])
        if d["zone"]:
            off = d["v"] <= 0.0
            ax.scatter(d["z"][off], d["s"][off], s=2, c="0.85", lw=0)
            on = np.flatnonzero(~off)
            on = on[np.argsort(d["v"][on])]  # the highest pressures on top
            sc = ax.scatter(d["z"][on], d["s"][on], c=d["v"][on], s=7, cmap=CMAP, norm=norm, lw=0)
            ring = on[d["edge"][on] & (d["v"][on] > norm.vmax)]
            ax.scatter(
                d["z"][ring],
                d["s"][ring],
                s=40,
                facecolors="none",
                edgecolors="tab:cyan",
                lw=1.2,
                label="edge cell above the scale",
            )
        else:
            sc = ax.scatter(d["z"], d["s"], c=d["v"], s=14, cmap=CMAP, norm=norm)
        centroid = float(np.mean([p["meshes"][mesh]["on"][pinion]["Z_mm"] for p in positions]))
        ax.axvline(0.0, color="0.4", ls="--", lw=1, label="mid face width")
        ax.axvline(centroid, color="tab:blue", lw=2, label=f"load centroid {centroid:+.2f} mm")
        ax.set_xlim(-half_face, half_face)
        ax.set_xlabel(f"Z, axial position from mid face width (mm, {pinion} frame)")
        ax.set_ylabel("s, roll position from pitch point (mm)")
        grid = " (zone grid)" if d["zone"] else ""
        ax.set_title(f"{study.name}: {mesh} mesh{grid}, {len(positions)} positions")
        ax.legend(
            loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=3, fontsize=8, frameon=False
        )
        return sc

    def colorbar(fig, sc, ax, label, clipped):
        fig.colorbar(sc, ax=ax, label=label, extend="max" if clipped else "neither")

    for mesh in meshes:
        d = data[mesh]
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        sc = panel(ax, mesh)
        colorbar(fig, sc, ax, d["label"], d["zone"] and d["v"].max() > tops[True])
        fig.tight_layout()
        path = out_dir / f"contact_pattern_{mesh}.png"
        fig.savefig(path, dpi=130)
        plt.close(fig)
        paths.append(path)
    fig, axes = plt.subplots(1, len(meshes), figsize=(7.0 * len(meshes), 4.8), squeeze=False)
    for ax, mesh in zip(axes[0], meshes, strict=True):
        sc = panel(ax, mesh)
        d = data[mesh]
        colorbar(fig, sc, ax, d["label"], d["zone"] and d["v"].max() > tops[True])
    path = out_dir / "contact_patterns.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    paths.append(path)
    return paths
