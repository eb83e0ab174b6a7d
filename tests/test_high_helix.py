"""A helix angle the validator allows solves: the zone grid's FE far field is matched below
each coarse point along the flank's inward normal, whose axial part (sin beta_b) carried a
face-end point out of the pinion at 30-35 deg (issue 57: every position ended in
``GapOperatorError: ... not inside the mesh``). The matching depth is now halved until the
point is inside the face as well as inside the tooth (solvers.flank_grid._matching_depth).
Pure geometry: no mesh, no solve."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from cases.study_case import load_study_case
from solvers.gear_train import contact_grids
from studies.position import study_scene, train_inputs
from studies.settings import RunSettings

ROOT = Path(__file__).resolve().parents[1]


def helix_case(tmp_path: Path, beta: float) -> Path:
    """Case 1-GB's data with helix angle ``beta`` and the centre distance of its standard
    sun-pinion pair (a = m_n (z_s + z_p) / (2 cos beta), rounded up), so the sun keeps no
    shift and the shifts stay valid."""
    text = (ROOT / "cases" / "gearsets" / "case1.toml").read_text()
    a = math.ceil(100 * 1.59 * 61 / (2 * math.cos(math.radians(beta)))) / 100 + 0.05
    text = re.sub(r"(?m)^helix_angle = [0-9.]+", f"helix_angle = {beta:.1f}", text)
    text = re.sub(r"(?m)^centre_distance = [0-9.]+", f"centre_distance = {a:.2f}", text)
    (tmp_path / "helix.toml").write_text(text)
    case = (ROOT / "cases" / "1-GB.toml").read_text()
    case = case.replace('gearset = "case1"', 'gearset = "helix.toml"')
    case = case.replace('name = "1-GB"', f'name = "helix{beta:g}"')
    (tmp_path / "case.toml").write_text(case)
    return tmp_path / "case.toml"


def depth_points_beyond_the_face(study, level: int) -> int:
    """How many matching points of the zone pairs lie beyond their body's face width."""
    settings = RunSettings(level=level).resolved(study)
    scene = study_scene(study, 0.0)
    _, pairs = contact_grids(scene, train_inputs(study), settings.spacing)
    placed = {g.name: g for g in scene.gears}
    beyond = 0
    for p in pairs:
        lk = p.link
        if lk is None:
            continue
        n = np.asarray(lk.coarse.normals)
        for body, pts in (
            (p.body_a, np.asarray(lk.coarse.x_a) - lk.depth_a[:, None] * n),
            (p.body_b, np.asarray(lk.coarse.x_b) + lk.depth_b[:, None] * n),
        ):
            if body in placed:
                z = placed[body].placement.inverse(pts)[:, 2]
                beyond += int(np.sum(np.abs(z) > 0.5 * placed[body].gear.face_width))
    return beyond


@pytest.mark.parametrize("beta", [21.0, 30.0, 35.0, 45.0])
def test_every_matching_point_lies_inside_its_body(beta, tmp_path):
    study = load_study_case(helix_case(tmp_path, beta))
    assert depth_points_beyond_the_face(study, 0) == 0


def spread_points_beyond_a_tip(study, spacing: float | None = None) -> float:
    """The largest distance (mm) a spreading point of any zone grid (fine or coarse) lies
    outside its body's tip circle, or beyond its face width, over two mesh positions."""
    settings = RunSettings(level=0, grid_spacing=spacing).resolved(study)
    worst = 0.0
    for roll in (0.0, 0.05):
        scene = study_scene(study, roll)
        _, pairs = contact_grids(scene, train_inputs(study), settings.spacing)
        placed = {g.name: g for g in scene.gears}
        for p in pairs:
            for grid in (p.grid, p.link.coarse if p.link else None):
                for side, body in (("a", p.body_a), ("b", p.body_b)):
                    if grid is None or body not in placed:
                        continue
                    g = placed[body].gear
                    y = placed[body].placement.inverse(grid.spread_points(side)[0])
                    r = np.hypot(y[:, 0], y[:, 1])
                    out = g.tip_radius - r if g.internal else r - g.tip_radius
                    beyond = np.maximum(out, np.abs(y[:, 2]) - 0.5 * g.face_width)
                    worst = max(worst, float(beyond.max()))
    return worst


@pytest.mark.parametrize("beta, spacing", [(0.0, None), (45.0, None), (45.0, 5.0), (0.0, 5.0)])
def test_every_spreading_point_lies_on_its_tooth(beta, spacing, tmp_path):
    """The patch a grid point is spread over stays on both flanks along the contact line as
    well as across it, corners included (solvers.flank_grid._patch_halves): at 45 deg,
    along the line it reached 0.1 mm past the pinion's tip, beyond the gap operator's
    bounding-box padding (1e-3 of the body mesh's diagonal, 0.09 mm for this pinion), and
    every position failed. Every spreading point now lies inside its tip circle and face."""
    study = load_study_case(helix_case(tmp_path, beta))
    assert spread_points_beyond_a_tip(study, spacing) == 0.0
