"""Contact-pattern pictures on the 3D flanks (off-screen pyvista), laid out like singh2007's
contact pattern figures: per mesh the pinion's drive flank and its mate's, each seen face on,
coloured by the contact pressure over the mesh cycle (:mod:`postprocess.flank_pattern`).

Each flank is rendered alone with a parallel camera looking along its normal at the middle
of the profile and mid face width, the profile (form -> tip) vertical and the pinion's +Z to
the right, so every panel reads like the 2D (Z, s) chart of :mod:`postprocess.
contact_pattern`. Lines on the flank mark the face ends (black), mid face width (dark grey)
and the load centroid (magenta, the mean over the positions of sum F z / sum F). The
rendered images are laid out with matplotlib, which draws the titles, the Z axis (mm in the
pinion frame), the legend and one colour bar (MPa) that all panels share.

Colours: the pressure on a colour map; flank regions a sampled contact line reaches but
carries no load (p < ``P_FLOOR``) are white, regions no contact line reaches (outside the
path of contact, beyond the face width of the mate) light grey. Line grids show Hertz p_max
from the line loads; zone grids the solved pressure (:func:`postprocess.flank_pattern.
zone_flank_pattern`), whose colour scale tops at the largest interior pressure: the corner
contact of the sharp tips and the face-end cells (edge cells,
:func:`postprocess.mesh_stress.edge_points`), often several times higher, are drawn in the
top colour (the colour bar's arrow) and their maximum is written above each panel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import Normalize
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from meshing.pictures import vtk_warnings_off
from postprocess.flank_pattern import FlankPattern, flank_point, mesh_flank_patterns

CMAP = "turbo"
P_FLOOR = 1.0  # MPa: below this a reached flank point counts as unloaded
UNREACHED = "#c8c8c8"
UNLOADED = "#ffffff"
FACE_END = "#000000"
MID_FACE = "#555555"
CENTROID = "#e0119d"
PROFILE_SCALE = 2.0  # the profile (about 3 mm of a 30 mm face) drawn twice its length
PX_PER_MM = 26.0  # about the pixel density of the saved figure (DPI)
DPI = 120
MARGIN_PX = 40
LINE_LIFT = 0.05  # mm: lines drawn this far in front of the flank (towards the camera)


@dataclass(frozen=True, eq=False)
class FlankImage:
    """A rendered flank: the RGB ``image`` and the parallel camera that made it (world
    point -> pixel: :meth:`pixel`)."""

    image: np.ndarray  # (H, W, 3) uint8
    focal: np.ndarray
    right: np.ndarray  # screen right, gear frame (unit)
    up: np.ndarray  # screen up
    px_per_mm: float
    tip_up: bool  # True if the tip edge is at the top of the image
    profile_scale: float  # the screen's up direction is drawn this many times longer

    def pixel(self, xyz) -> np.ndarray:
        """(column, row) pixel coordinates (..., 2) of gear-frame points ``xyz`` (..., 3)."""
        d = np.asarray(xyz, float) - self.focal
        h, w = self.image.shape[:2]
        col = 0.5 * w + (d @ self.right) * self.px_per_mm
        row = 0.5 * h - (d @ self.up) * self.px_per_mm * self.profile_scale
        return np.stack([col, row], axis=-1)


def pressure_colours(p: np.ndarray, norm: Normalize, cmap) -> np.ndarray:
    """RGB (..., 3) uint8: the colour map where p >= P_FLOOR, white where reached but
    unloaded, grey where NaN (no contact line reaches)."""
    rgba = np.asarray(cmap(norm(np.nan_to_num(p, nan=0.0))))
    grey = np.asarray(matplotlib.colors.to_rgba(UNREACHED))
    white = np.asarray(matplotlib.colors.to_rgba(UNLOADED))
    rgba = np.where(np.isnan(p)[..., None], grey, rgba)
    rgba = np.where((~np.isnan(p) & (p < P_FLOOR))[..., None], white, rgba)
    return (255 * rgba[..., :3]).round().astype(np.uint8)


def _camera(pattern: FlankPattern):
    """Direction of projection, screen up and right of the face-on view: the view looks
    along -n (n out of the material) at the middle of the flank; right runs along the chord
    of the mid-profile helix between the face ends, towards the pinion's +Z; up completes
    the frame (towards the tip or the root, ``tip_up`` says which)."""
    fl = pattern.flank
    iu, iz = len(fl.u) // 2, len(fl.z) // 2
    d = -fl.outward_normal(iu, iz)
    right = (fl.xyz[iu, -1] - fl.xyz[iu, 0]) * pattern.z_sign
    right -= (right @ d) * d
    right /= np.linalg.norm(right)
    up = np.cross(right, d)
    tip_up = bool(up @ (fl.xyz[-1, iz] - fl.xyz[0, iz]) > 0.0)
    return d, up, right, tip_up


def flank_lines(pattern: FlankPattern, n: int = 60) -> dict[str, list[np.ndarray]]:
    """Polylines (gear frame, on the flank) of the marks: face ends, mid face width, load
    centroid (constant z from the form to the tip circle) and the flank outline (form and
    tip edges)."""
    fl = pattern.flank
    g, side = fl.gear, fl.side
    u = np.linspace(fl.u_form, fl.u_tip, n)
    zs = np.linspace(fl.z[0], fl.z[-1], 4 * n)

    def const_z(z0):  # a transverse involute of the flank
        return flank_point(g, side, u, np.full_like(u, z0))

    out = {
        "face ends": [const_z(fl.z[0]), const_z(fl.z[-1])],
        "mid face width": [const_z(0.0)],
        "outline": [flank_point(g, side, np.full_like(zs, u0), zs) for u0 in (u[0], u[-1])],
    }
    if math.isfinite(pattern.centroid_z):
        out["load centroid"] = [const_z(pattern.centroid_z)]
    return out


def render_flank(
    pattern: FlankPattern,
    norm: Normalize,
    cmap,
    px_per_mm: float = PX_PER_MM,
    profile_scale: float = PROFILE_SCALE,
) -> FlankImage:
    """Render one flank pattern face on (off-screen pyvista) with its marks; the screen's
    up direction (the profile) is stretched ``profile_scale`` times about the focal point
    (a face-on view drawn with an exaggerated profile, like a contact pattern chart)."""
    with vtk_warnings_off():
        return _render(pattern, norm, cmap, px_per_mm, profile_scale)


def _render(pattern, norm, cmap, px_per_mm, profile_scale) -> FlankImage:
    import pyvista as pv  # heavy: only when a picture is drawn

    pv.OFF_SCREEN = True
    fl = pattern.flank
    d, up, right, tip_up = _camera(pattern)
    pts = fl.xyz.reshape(-1, 3)
    centre = fl.xyz[len(fl.u) // 2, len(fl.z) // 2]
    pr, pu = (pts - centre) @ right, (pts - centre) @ up
    focal = centre + right * 0.5 * (pr.min() + pr.max()) + up * 0.5 * (pu.min() + pu.max())
    width = math.ceil(float(np.ptp(pr)) * px_per_mm) + 2 * MARGIN_PX
    height = math.ceil(float(np.ptp(pu)) * px_per_mm * profile_scale) + 2 * MARGIN_PX

    def stretch(x):  # the profile (screen up) drawn profile_scale times longer
        return x + (profile_scale - 1.0) * ((x - focal) @ up)[..., None] * up

    n_u, n_z = len(fl.u), len(fl.z)
    idx = np.arange(n_u * n_z).reshape(n_u, n_z)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1)
    faces = np.hstack([np.full((quads.size // 4, 1), 4), quads.reshape(-1, 4)]).ravel()
    surf = pv.PolyData(stretch(pts), faces)
    surf.point_data["rgb"] = pressure_colours(pattern.pressure.ravel(), norm, cmap)
    pl = pv.Plotter(off_screen=True, window_size=(width, height), lighting="none")
    pl.set_background("white")
    pl.add_mesh(surf, scalars="rgb", rgb=True, show_scalar_bar=False)
    lift = -d * LINE_LIFT  # towards the camera
    styles = {
        "outline": ("#303030", 1.5),
        "mid face width": (MID_FACE, 2.5),
        "face ends": (FACE_END, 4),
        "load centroid": (CENTROID, 4),
    }
    for name, polylines in flank_lines(pattern).items():
        colour, width_px = styles[name]
        for line in polylines:
            poly = pv.lines_from_points(stretch(line) + lift)
            pl.add_mesh(poly, color=colour, line_width=width_px)
    pl.enable_parallel_projection()
    pl.camera.focal_point = tuple(focal)
    pl.camera.position = tuple(focal - 100.0 * d)
    pl.camera.up = tuple(up)
    pl.camera.parallel_scale = 0.5 * height / px_per_mm
    pl.enable_anti_aliasing("ssaa")
    image = np.asarray(pl.screenshot(None, return_img=True))[..., :3].copy()
    pl.close()
    return FlankImage(image, focal, right, up, px_per_mm, tip_up, profile_scale)


def _z_ticks(pattern: FlankPattern) -> np.ndarray:
    """Z values (mm, pinion frame) for the axis: the face ends and every 5 mm between them
    (those at least 2 mm inside)."""
    half = 0.5 * pattern.face_width
    inner = np.arange(-5.0 * math.floor(half / 5.0), half + 1e-9, 5.0)
    return np.r_[-half, inner[np.abs(inner) <= half - 2.0], half]


def draw_flank(ax, pattern: FlankPattern, img: FlankImage, title: str) -> None:
    """One flank panel on the matplotlib axes ``ax``: the image, the Z axis (pinion frame)
    under it, tip / form labels and the centroid value."""
    ax.imshow(img.image, interpolation="antialiased")
    fl = pattern.flank
    u_low = fl.u_form if img.tip_up else fl.u_tip  # the profile edge at the bottom
    ticks = _z_ticks(pattern)
    cols = img.pixel(flank_point(fl.gear, fl.side, u_low, ticks * pattern.z_sign))[:, 0]
    ax.set_xticks(cols, [f"{t:+.3g}" if t else "0" for t in ticks])
    ax.set_yticks([])
    ax.tick_params(axis="x", labelsize=8, length=3)
    for sp in ax.spines.values():
        sp.set_visible(False)
    z_left = fl.z[0] if pattern.z_sign > 0 else fl.z[-1]
    for u0, label in ((fl.u_tip, "tip"), (fl.u_form, "form")):
        c, r = img.pixel(flank_point(fl.gear, fl.side, u0, z_left))
        ax.text(c - 6, r, label, ha="right", va="center", fontsize=8)
    if math.isfinite(pattern.centroid_z) and pattern.points_p.size:
        txt = f"centroid Z = {pattern.centroid_z * pattern.z_sign:+.2f} mm,  "
        if pattern.grid_model == "zone":
            txt += f"interior max {pattern.interior_max:.0f} MPa"
            if math.isfinite(pattern.edge_max):
                txt += f", edge max {pattern.edge_max:.0f} MPa"
        else:
            txt += f"max {pattern.points_p.max():.0f} MPa"
    else:
        txt = "no load"
    ax.set_title(title, fontsize=9.5, loc="left")
    ax.text(
        1.0,
        1.02,
        txt,
        transform=ax.transAxes,
        ha="right",
        va="bottom",
        fontsize=8.5,
        color=CENTROID if np.isfinite(pattern.centroid_z) else "k",
    )


def _flank_title(p: FlankPattern) -> str:
    return f"{p.body} flank ({p.flank.side}, {p.role})"


def _legend_handles() -> list:
    return [
        Line2D([], [], color=FACE_END, lw=2.5, label="face ends"),
        Line2D([], [], color=MID_FACE, lw=1.5, label="mid face width"),
        Line2D([], [], color=CENTROID, lw=2.5, label="load centroid (mean over positions)"),
        Patch(facecolor=UNLOADED, edgecolor="0.5", label="reached, no load"),
        Patch(facecolor=UNREACHED, edgecolor="0.5", label="no contact line reaches"),
    ]


def _nice_max(p: float) -> float:
    """Colour scale top: p rounded up to 100 MPa (at least 100)."""
    return max(100.0, 100.0 * math.ceil(p / 100.0))


def _case_patterns(study, positions, scenes=None) -> dict[str, list[FlankPattern]]:
    by_mesh: dict[str, list[FlankPattern]] = {}
    for p in mesh_flank_patterns(study, positions, scenes):
        by_mesh.setdefault(p.mesh, []).append(p)
    return by_mesh


def _zoned(by_mesh: dict[str, list[FlankPattern]]) -> bool:
    return any(p.grid_model == "zone" for ps in by_mesh.values() for p in ps)


def _peak(patterns) -> float:
    """Top of the colour scale: the largest pressure of the line-grid patterns, the largest
    interior pressure of the zone-grid ones (their edge cells above it take the top colour)."""
    vals = [
        p.interior_max if p.grid_model == "zone" else np.nanmax(p.pressure)
        for p in patterns
        if np.isfinite(p.pressure).any()
    ]
    return max(vals) if vals else 0.0


def _layout(rows: list[tuple[str, dict[str, list[FlankPattern]]]], out_png: Path, title: str):
    """Figure: per case (row label) a block of two image rows (the pinion's flank above its
    mate's) with one column per mesh; one colour bar and one legend for all. Axes are
    placed in inches so the titles, Z axes, colour bar and legend never overlap or clip."""
    all_patterns = [p for _, by_mesh in rows for ps in by_mesh.values() for p in ps]
    norm = Normalize(0.0, _nice_max(_peak(all_patterns)))
    cmap = plt.get_cmap(CMAP)
    n_cols = max(len(by_mesh) for _, by_mesh in rows)
    images = {id(p): render_flank(p, norm, cmap) for p in all_patterns}
    aspect = max(img.image.shape[0] / img.image.shape[1] for img in images.values())
    left, label_w, col_w, gap_w, cbar_w = 0.35, 0.35, 7.2, 0.35, 1.1
    img_h = col_w * aspect
    above, below, block_gap = 0.42, 0.55, 0.3  # title room; Z ticks and label room
    cell_h = above + img_h + below
    head, foot = 0.5, 0.45
    fig_w = left + label_w + n_cols * col_w + (n_cols - 1) * gap_w + cbar_w
    body_h = len(rows) * 2 * cell_h + (len(rows) - 1) * block_gap
    fig_h = head + body_h + foot
    fig = plt.figure(figsize=(fig_w, fig_h))

    def axes(x, y, w, h):  # inches from the bottom left -> figure axes
        return fig.add_axes((x / fig_w, y / fig_h, w / fig_w, h / fig_h))

    for r, (label, by_mesh) in enumerate(rows):
        y_top = fig_h - head - r * (2 * cell_h + block_gap)
        fig.text(
            (left + 0.05) / fig_w,
            (y_top - cell_h) / fig_h,
            label,
            rotation=90,
            ha="center",
            va="center",
            fontsize=11,
            weight="bold",
        )
        for c, (mesh, pats) in enumerate(by_mesh.items()):
            x = left + label_w + c * (col_w + gap_w)
            for k, p in enumerate(pats):
                y = y_top - (k + 1) * cell_h + below
                ax = axes(x, y, col_w, img_h)
                draw_flank(ax, p, images[id(p)], f"{mesh} mesh: {_flank_title(p)}")
                ax.set_xlabel(
                    f"Z from mid face width (mm, {p.pinion} frame)", fontsize=8, labelpad=1
                )
    x_cb = left + label_w + n_cols * col_w + (n_cols - 1) * gap_w + 0.25
    cax = axes(x_cb, foot + 0.1 * body_h, 0.16, 0.8 * body_h)
    over = any(
        np.nanmax(p.pressure) > norm.vmax for p in all_patterns if np.isfinite(p.pressure).any()
    )
    cb = fig.colorbar(
        plt.cm.ScalarMappable(norm=norm, cmap=cmap), cax=cax, extend="max" if over else "neither"
    )
    zone = any(p.grid_model == "zone" for p in all_patterns)
    label = "contact pressure, solved (MPa)" if zone else "contact pressure, Hertz p_max (MPa)"
    cb.set_label(label, fontsize=10)
    cb.ax.tick_params(labelsize=9)
    fig.legend(
        handles=_legend_handles(),
        loc="lower center",
        ncol=5,
        fontsize=8.5,
        frameon=False,
        bbox_to_anchor=(0.5, 0.0),
    )
    title += f"; flanks seen face on, profile drawn x{PROFILE_SCALE:g}"
    fig.text(0.5, 1.0 - 0.12 / fig_h, title, ha="center", va="top", fontsize=11.5)
    out_png = Path(out_png)
    out_png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_png, dpi=DPI)
    plt.close(fig)
    return out_png


def draw_flank_patterns(study, positions: list[dict], out_dir: Path, scenes=None) -> list[Path]:
    """``<out_dir>/flank_patterns.png``: the contact pattern of every mesh of one case on
    the pinion's and the mate's drive flank, maximum pressure over the solved ``positions``
    (a mesh cycle). ``scenes``: the scene of each position (rebuilt if None). Serial."""
    n = len(positions)
    by_mesh = _case_patterns(study, positions, scenes)
    what = "pressure" if _zoned(by_mesh) else "Hertz pressure"
    title = (
        f"{study.name}: contact pattern on the drive flanks, maximum {what} over "
        f"the mesh cycle ({n} position{'s' if n != 1 else ''})"
    )
    return [_layout([(study.name, by_mesh)], Path(out_dir) / "flank_patterns.png", title)]
