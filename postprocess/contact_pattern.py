"""Contact pattern charts: the FE line load over the pinion flank of each mesh.

Every grid point of every solved mesh position is drawn at (Z, s): Z the axial position in
the frame of the pinion in that mesh (mm from mid face width, singh2007 sections 3 and 5), s
the roll position along the line of action from the pitch point (mm). Over one base pitch
the contact lines sweep the active flank, so together they show the pattern an engineer
reads from a marking compound test. Mid face width and the load centroid are drawn.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from postprocess.mesh_stress import contact_stress_at_points


def _pinion_of(mesh: dict) -> str:
    """The pinion whose frame the mesh's pattern is drawn in (the first pinion in it)."""
    return next(iter(mesh["on"]))


def pattern_points(pos: dict, mesh: str, s_mm) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Z, s, w) of the grid points of ``mesh`` at one position."""
    m = pos["meshes"][mesh]
    pinion = pos["pinions"][_pinion_of(m)]
    x = np.asarray(m["points"]["x_mm"])
    z = (x - np.asarray(pinion["centre_mm"])) @ np.asarray(pinion["frame"])[2]
    w = np.clip(np.asarray(m["points"]["line_load_N_per_mm"]), 0.0, None)
    return z, np.asarray(s_mm), w


def draw_contact_patterns(study, positions: list[dict], out_dir: Path) -> list[Path]:
    """One PNG per mesh plus a side-by-side panel; returns the paths."""
    meshes = list(positions[0]["meshes"])
    hz = [contact_stress_at_points(study.gearset, study.material, p) for p in positions]
    data = {m: [pattern_points(p, m, h[m]["s_mm"]) for p, h in zip(positions, hz, strict=True)]
            for m in meshes}  # fmt: skip
    w_max = max(float(w.max()) for pts in data.values() for _, _, w in pts) or 1.0
    paths = []

    def panel(ax, mesh):
        m0 = positions[0]["meshes"][mesh]
        pinion = _pinion_of(m0)
        gear = dict(zip((m0["driver"], m0["driven"]), m0["gears"], strict=True))[pinion]
        half_face = study.gearset.gears[gear].face_width / 2
        for z, s, w in data[mesh]:
            sc = ax.scatter(z, s, c=w, s=14, cmap="inferno_r", vmin=0.0, vmax=w_max)
        centroid = float(np.mean([p["meshes"][mesh]["on"][pinion]["Z_mm"] for p in positions]))
        ax.axvline(0.0, color="0.4", ls="--", lw=1, label="mid face width")
        ax.axvline(centroid, color="tab:blue", lw=2, label=f"load centroid {centroid:+.2f} mm")
        ax.set_xlim(-half_face, half_face)
        ax.set_xlabel(f"Z, axial position from mid face width (mm, {pinion} frame)")
        ax.set_ylabel("s, roll position from pitch point (mm)")
        ax.set_title(f"{study.name}: {mesh} mesh, {len(positions)} positions")
        ax.legend(loc="upper right", fontsize=8)
        return sc

    for mesh in meshes:
        fig, ax = plt.subplots(figsize=(7, 4.2))
        sc = panel(ax, mesh)
        fig.colorbar(sc, ax=ax, label="line load (N/mm)")
        fig.tight_layout()
        path = out_dir / f"contact_pattern_{mesh}.png"
        fig.savefig(path, dpi=130)
        plt.close(fig)
        paths.append(path)
    fig, axes = plt.subplots(1, len(meshes), figsize=(6.5 * len(meshes), 4.2), squeeze=False)
    for ax, mesh in zip(axes[0], meshes, strict=True):
        sc = panel(ax, mesh)
    fig.colorbar(sc, ax=axes[0].tolist(), label="line load (N/mm)")
    path = out_dir / "contact_patterns.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    paths.append(path)
    return paths
