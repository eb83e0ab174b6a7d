"""Contact pattern pictures: the FE line load over the pinion flank of each mesh.

Every grid point of every solved mesh position is drawn at (Z, s): Z the axial position in
the paper's pinion frame (mm from mid face width, singh2007 section 3), s the roll position
along the line of action from the pitch point (mm). Over one base pitch the contact lines
sweep the active flank, so together they show the pattern an engineer reads from a marking
compound test. Mid face width and the load centroid (ZS, ZR) are drawn.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

MESHES = {"S": ("sun-pinion", "ZS"), "R": ("pinion-ring", "ZR")}


def pattern_points(case, pos: dict, key: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Z, s, w) of the grid points of mesh ``key`` ("S" or "R") at one position."""
    from postprocess.case_study import contact_stress_at_points

    x = np.asarray(pos[f"points_{key}"]["x_mm"])
    frame = np.asarray(pos["frame"])
    z = (x - np.asarray(pos["pinion_centre_mm"])) @ frame[2]
    s = contact_stress_at_points(case, pos)[key]["s_mm"]
    w = np.clip(np.asarray(pos[f"points_{key}"]["line_load_N_per_mm"]), 0.0, None)
    return z, s, w


def draw_contact_patterns(case, positions: list[dict], out_dir: Path) -> list[Path]:
    """One PNG per mesh plus a side-by-side panel; returns the paths."""
    data = {k: [pattern_points(case, p, k) for p in positions] for k in MESHES}
    w_max = max(float(w.max()) for pts in data.values() for _, _, w in pts) or 1.0
    half_face = case.gearset.gears["pinion"].face_width / 2
    paths = []

    def panel(ax, key):
        title, zkey = MESHES[key]
        for z, s, w in data[key]:
            sc = ax.scatter(z, s, c=w, s=14, cmap="inferno_r", vmin=0.0, vmax=w_max)
        centroid = float(np.mean([p[zkey] for p in positions]))
        ax.axvline(0.0, color="0.4", ls="--", lw=1, label="mid face width")
        ax.axvline(
            centroid, color="tab:blue", lw=2, label=f"load centroid {zkey} = {centroid:+.2f} mm"
        )
        ax.set_xlim(-half_face, half_face)
        ax.set_xlabel("Z, axial position from mid face width (mm, pinion frame)")
        ax.set_ylabel("s, roll position from pitch point (mm)")
        ax.set_title(f"{case.name}: {title} mesh, {len(positions)} positions")
        ax.legend(loc="upper right", fontsize=8)
        return sc

    for key, (title, _) in MESHES.items():
        fig, ax = plt.subplots(figsize=(7, 4.2))
        sc = panel(ax, key)
        fig.colorbar(sc, ax=ax, label="line load (N/mm)")
        fig.tight_layout()
        path = out_dir / f"contact_pattern_{title}.png"
        fig.savefig(path, dpi=130)
        plt.close(fig)
        paths.append(path)
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.2))
    for ax, key in zip(axes, MESHES, strict=True):
        sc = panel(ax, key)
    fig.colorbar(sc, ax=axes, label="line load (N/mm)")
    path = out_dir / "contact_patterns.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    paths.append(path)
    return paths
