"""Contact patterns on the exact flanks (postprocess.flank_pattern, postprocess.flank_pictures)
from a synthetic position: the case-1 scene's theoretical contact lines with a known line load
on part of one line, no FE solve."""

import math

import numpy as np
import pytest
from matplotlib import colors
from matplotlib import pyplot as plt

from cases.study_case import load_study_case
from gears.contact_stress import mesh_contact
from meshing.scenes import build_scene
from postprocess.flank_pattern import (
    contact_phase,
    cycle_maximum,
    flank_grid,
    mesh_flank_patterns,
    split_lines,
    to_flank,
)
from postprocess.flank_pictures import (
    CMAP,
    UNLOADED,
    draw_flank_patterns,
    pressure_colours,
    render_flank,
)

W_LOAD = 400.0  # N/mm on the loaded points


def synthetic_position(study, scene, loaded) -> dict:
    """A position dict like studies.position.solve_position's at the scene's roll: every
    mesh's grid = the theoretical contact lines of its zone; line load W_LOAD where
    ``loaded(mesh, line index, points)`` is True, else 0."""
    pinion = scene.pinion_names[0]
    centre = [*scene.gear(pinion).placement.centre, 0.0]
    meshes, grid_lines = {}, {}
    for zn in scene.zones:
        name = f"{zn.driver}-{zn.driven}"
        xs, ws, rows = [], [], []
        for i, (_k, _j, pts) in enumerate(zn.contact_lines):
            rows.append(
                {
                    "rows": [sum(len(x) for x in xs), sum(len(x) for x in xs) + len(pts)],
                    "spacing": float(np.linalg.norm(pts[1] - pts[0])) if len(pts) > 1 else 0.5,
                }
            )
            xs.append(pts)
            ws.append(np.where(loaded(name, i, pts), W_LOAD, 0.0))
        x, w = np.vstack(xs), np.concatenate(ws)
        f = w * 0.7  # the force of a point: its line load times its length (any constant)
        meshes[name] = {
            "driver": zn.driver,
            "driven": zn.driven,
            "gears": [scene.gear(zn.driver).gear_name, scene.gear(zn.driven).gear_name],
            "active_points": int(np.count_nonzero(w)),
            "points": {"x_mm": x.tolist(), "force_N": f.tolist(), "line_load_N_per_mm": w.tolist()},
            "on": {pinion: {"Z_mm": -float((f * x[:, 2]).sum() / max(f.sum(), 1e-30))}},
        }
        grid_lines[name] = rows
    return {
        "roll": scene.roll,
        "meshes": meshes,
        "grid_lines": grid_lines,
        "pinions": {
            pinion: {
                "centre_mm": centre,
                "frame": [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
            }
        },
    }


@pytest.fixture(scope="module")
def case():
    """1-GA at roll 0 with load on the z > 0 half of the sun-pinion mesh's longest line."""
    study = load_study_case("1-GA")
    scene = build_scene(study.model.scene, study.gearset, 0.0)
    zone = scene.zones[0]
    longest = int(np.argmax([len(p) for _, _, p in zone.contact_lines]))

    def loaded(mesh, i, pts):
        return (mesh == "sun-pinion") & (i == longest) & (pts[:, 2] > 0.0)

    pos = synthetic_position(study, scene, loaded)
    return study, scene, pos, zone.contact_lines[longest][2]


def test_contact_lines_map_onto_tooth_zero_at_one_phase(case):
    # Every theoretical contact line lies on the exact flank of the tooth the zone names
    # (its own construction) and at one contact phase; turning onto tooth 0 keeps the radius.
    # 1e-9 mm is round-off on 10-80 mm coordinates.
    _, scene, _, _ = case
    for zn in scene.zones:
        for body, side, col in ((zn.driver, zn.driver_side, 0), (zn.driven, zn.driven_side, 1)):
            g = scene.gear(body)
            for line in zn.contact_lines:
                local = g.placement.inverse(line[2])
                q = to_flank(g.gear, side, local)
                assert np.abs(q["deviation"]).max() < 1e-9
                assert np.all(q["tooth"] == line[col])
                assert np.ptp(contact_phase(g.gear, side, q["u"], q["z"])) < 1e-9
                assert np.allclose(np.hypot(*q["xyz"][:, :2].T), np.hypot(*local[:, :2].T))


def test_cycle_maximum_interpolates_in_phase_and_takes_the_max():
    # Two lines of one phase (p = 100 and 300 MPa) and one line a step above (p = 500): at
    # the shared phase the max (300), half a step above the mean of 300 and 500.
    study = load_study_case("1-GA")
    gear = study.gearset.gears["pinion"]
    flank = flank_grid(gear, "pos", n_u=101, n_z=41)
    step = 1.0
    z = np.linspace(-10.0, 10.0, 21)
    u0 = 6.0
    c0 = float(contact_phase(gear, "pos", u0, 0.0))
    lines = []
    for c, p in ((c0, 100.0), (c0, 300.0), (c0 + step, 500.0)):
        u = c - contact_phase(gear, "pos", 0.0, z)  # u of the line at phase c
        lines += split_lines(gear, "pos", u, z, np.full_like(z, p), 0.25)
    assert len(lines) == 3
    c = flank.phase
    p = cycle_maximum(lines, step, c, flank.z[None, :])
    inner = np.abs(flank.z) < 9.0
    at0 = np.abs(c - c0) < 0.02
    half = np.abs(c - c0 - 0.5 * step) < 0.02
    assert np.allclose(p[at0 & inner[None, :]], 300.0, atol=0.02 / step * 200.0 + 1e-9)
    assert np.allclose(p[half & inner[None, :]], 400.0, atol=0.02 / step * 200.0 + 1e-9)
    assert np.all(np.isnan(p[(c < c0 - 0.6 * step) | (c > c0 + 1.6 * step)]))


def test_pattern_is_where_the_load_is(case):
    study, scene, pos, line = case
    pats = mesh_flank_patterns(study, [pos])
    assert [(p.mesh, p.body) for p in pats] == [
        ("sun-pinion", "pinion"),
        ("sun-pinion", "sun"),
        ("pinion-ring", "pinion"),
        ("pinion-ring", "ring"),
    ]
    pair = study.gearset.pair("sun", "pinion")
    r1 = np.hypot(line[:, 0], line[:, 1])  # radius on the sun (at the origin)
    s = np.sqrt(r1**2 - pair.gear1.base_radius**2) - pair.gear1.base_radius * math.tan(
        pair.operating_pressure_angle
    )
    p_expected = mesh_contact(pair, s, W_LOAD).p_max  # Hertz at the loaded line's points
    for pat in pats[:2]:
        g = scene.gear(pat.body)
        q = to_flank(g.gear, pat.flank.side, g.placement.inverse(line))
        assert pat.max_deviation < 1e-9
        # At the loaded line's points the pattern is Hertz p of their line load (the
        # loaded half) or 0 (the other half), to round-off.
        at = pat.samples.pressure(q["u"], q["z"])
        assert np.allclose(at[q["z"] > 0], p_expected[q["z"] > 0], rtol=1e-12)
        assert np.all(at[q["z"] < 0] == 0.0)
        # The field on the flank samples nearest each point: a sample lies a little off the
        # line in phase (dc) and z; the field falls from the line value p(z) at most
        # linearly in phase towards the unloaded lines a base pitch p_bt away (one position).
        iu = np.abs(pat.flank.u[:, None] - q["u"][None, :]).argmin(axis=0)
        iz = np.abs(pat.flank.z[:, None] - q["z"][None, :]).argmin(axis=0)
        got = pat.pressure[iu, iz]
        gear = pat.gear
        p_bt = 2 * math.pi * gear.base_radius / gear.teeth
        dc = pat.flank.phase[iu, iz] - contact_phase(gear, pat.flank.side, q["u"], q["z"])
        order = np.argsort(q["z"])
        p_line = np.interp(pat.flank.z[iz], q["z"][order], p_expected[order])
        on = q["z"] > 0.5  # clear of the load's end at z = 0 by a grid spacing
        # a line end on the path of contact may have its nearest sample just outside the
        # active profile (no value there: it lies off the flank); at most one point a line
        on &= np.isfinite(got)
        assert on.sum() >= (q["z"] > 0.5).sum() - 1
        assert np.all(got[on] <= p_line[on] * (1 + 1e-12))
        assert np.all(got[on] >= (p_line * (1 - np.abs(dc) / p_bt))[on] * (1 - 1e-12))
        # The unloaded half: 0, or no value where the nearest sample lies just outside the
        # active profile (a line end on the path of contact).
        assert np.all(np.nan_to_num(got[q["z"] < -0.5]) == 0.0)
        # The load centroid is the mean z of the loaded points (equal forces).
        assert pat.centroid_z == pytest.approx(line[line[:, 2] > 0, 2].mean(), abs=1e-9)
    # No load on the ring mesh: reached, zero everywhere.
    assert np.nanmax(pats[3].pressure) == 0.0


def test_rendered_pattern_shows_the_load(case, tmp_path):
    study, scene, pos, line = case
    pat = mesh_flank_patterns(study, [pos])[0]  # the pinion's flank in the sun mesh
    norm = colors.Normalize(0.0, 2000.0)
    cmap = plt.get_cmap(CMAP)
    img = render_flank(pat, norm, cmap)
    im = img.image.astype(float)
    assert im.std() > 20.0  # not blank
    g = scene.gear(pat.body)
    q = to_flank(g.gear, pat.flank.side, g.placement.inverse(line))
    px = img.pixel(q["xyz"]).round().astype(int)
    iu = np.abs(pat.flank.u[:, None] - q["u"][None, :]).argmin(axis=0)
    iz = np.abs(pat.flank.z[:, None] - q["z"][None, :]).argmin(axis=0)
    want = pressure_colours(pat.pressure[iu, iz], norm, cmap).astype(float)
    got = im[px[:, 1], px[:, 0]]
    # Away from the drawn lines (mid face at z = 0, the centroid at about +7 mm) and the
    # face ends, the pixel under each point has the colour of its pressure: the loaded half
    # the colour map's colour at p (about 1600-1700 MPa: yellow-orange), the unloaded half
    # white. 25 levels of 255 allow for Gouraud shading between samples and anti-aliasing.
    zc = pat.centroid_z
    clear = (np.abs(q["z"]) > 1.5) & (np.abs(q["z"] - zc) > 1.5) & (np.abs(q["z"]) < 12.0)
    clear &= np.isfinite(pat.pressure[iu, iz])  # a line end just off the active profile
    assert clear.sum() >= 10
    assert np.abs(got[clear] - want[clear]).max() < 25.0
    white = np.array(colors.to_rgb(UNLOADED)) * 255
    loaded = clear & (q["z"] > 0)
    assert np.all(np.abs(got[loaded] - white).max(axis=1) > 60.0)
    assert np.all(np.abs(got[clear & (q["z"] < 0)] - white).max(axis=1) < 25.0)
    paths = draw_flank_patterns(study, [pos], tmp_path)
    assert paths[0].is_file() and paths[0].stat().st_size > 20_000
