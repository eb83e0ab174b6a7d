"""Contact stress over the mesh cycle (postprocess.mesh_stress.contact_stress_cycle and
edge_points) on synthetic positions with known line loads: the case-1 scene's theoretical
contact lines as the grid, no FE solve."""

import math

import numpy as np
import pytest

from cases.study_case import load_study_case
from gears.contact_stress import iso6336_pitch_contact_stress, mesh_contact
from gears.involute import roll_length
from gears.units import n_mm
from meshing.scenes import build_scene
from postprocess.mesh_stress import contact_stress_cycle, driver_torques, edge_points
from postprocess.paper_moments import MEAN_KEYS
from postprocess.summary import position_record

SPACING = 0.7  # mm, the grid spacing the synthetic grid lines state
W_BASE, W_PEAK, W_EDGE = 300.0, 600.0, 1500.0  # N/mm


def synthetic_position(study, scene, w_of) -> dict:
    """A position dict at the scene's roll whose grid is the theoretical contact lines of
    every zone; ``w_of(mesh, line index, n points)`` gives each line's line loads."""
    pinion = scene.pinion_names[0]
    meshes, grid_lines = {}, {}
    for zn in scene.zones:
        name = f"{zn.driver}-{zn.driven}"
        xs, ws, rows, n0 = [], [], [], 0
        for i, (_k, _j, pts) in enumerate(zn.contact_lines):
            rows.append({"rows": [n0, n0 + len(pts)], "spacing": SPACING})
            n0 += len(pts)
            xs.append(pts)
            ws.append(np.asarray(w_of(name, i, len(pts)), float))
        x, w = np.vstack(xs), np.concatenate(ws)
        meshes[name] = {
            "driver": zn.driver,
            "driven": zn.driven,
            "gears": [scene.gear(zn.driver).gear_name, scene.gear(zn.driven).gear_name],
            "active_points": int(np.count_nonzero(w)),
            "points": {
                "x_mm": x.tolist(),
                "force_N": (w * SPACING).tolist(),
                "line_load_N_per_mm": w.tolist(),
            },
            "on": {pinion: {"Z_mm": 0.0}},
        }
        grid_lines[name] = rows
    return {
        "roll": scene.roll,
        "meshes": meshes,
        "grid_lines": grid_lines,
        "grid_spacing_mm": SPACING,
        "pinions": {
            pinion: {
                "centre_mm": [*scene.gear(pinion).placement.centre, 0.0],
                "frame": [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
            }
        },
    }


def _s(pair, x):
    """Roll position s (mm from the pitch point) of points x on the sun (at the origin)."""
    r = np.hypot(x[..., 0], x[..., 1])
    rb = pair.gear1.base_radius
    return np.sqrt(r * r - rb * rb) - rb * math.tan(pair.operating_pressure_angle)


@pytest.fixture(scope="module")
def cycle():
    """Two positions of 1-GA: every point W_BASE, except at position 1 the middle point of
    the sun mesh's longest line (W_PEAK, the interior maximum) and at position 0 the first
    point of that line (W_EDGE, a line end)."""
    study = load_study_case("1-GA")
    rolls = (0.0, 0.5 * 2 * math.pi / 35)  # half a sun pitch apart
    scenes = [build_scene(study.model.scene, study.gearset, r) for r in rolls]
    longest = [int(np.argmax([len(p) for *_, p in sc.zones[0].contact_lines])) for sc in scenes]

    def w_of(k):
        def w(mesh, i, n):
            out = np.full(n, W_BASE)
            if mesh == "sun-pinion" and i == longest[k]:
                if k == 1:
                    out[n // 2] = W_PEAK
                else:
                    out[0] = W_EDGE
            return out

        return w

    positions = [synthetic_position(study, sc, w_of(k)) for k, sc in enumerate(scenes)]
    lines = [sc.zones[0].contact_lines[longest[k]][2] for k, sc in enumerate(scenes)]
    return study, positions, lines


def test_interior_and_edge_maxima_over_the_cycle(cycle):
    study, positions, lines = cycle
    pair = study.gearset.pair("sun", "pinion")
    steel = (study.material.gear_youngs_modulus, study.material.poisson_ratio)
    peak_x = lines[1][len(lines[1]) // 2]
    edge_x = lines[0][0]
    res = contact_stress_cycle(study.gearset, study.material, positions)
    sp = res["sun-pinion"]
    # Hertz of the known loads at the known points, to round-off.
    p_peak = float(mesh_contact(pair, _s(pair, peak_x), W_PEAK, steel, steel).p_max)
    p_edge = float(mesh_contact(pair, _s(pair, edge_x), W_EDGE, steel, steel).p_max)
    assert sp["interior_p_max_MPa"] == pytest.approx(p_peak, rel=1e-12)
    assert sp["interior_at"]["roll"] == positions[1]["roll"]
    assert sp["interior_at"]["Z_mm"] == pytest.approx(-peak_x[2], abs=1e-9)  # e_Z = -z
    assert sp["edge_p_max_MPa"] == pytest.approx(p_edge, rel=1e-12)
    assert sp["edge_at"]["roll"] == 0.0
    assert "line end" in sp["edge_kind"]
    assert sp["p_max_MPa"] == pytest.approx(p_edge, rel=1e-12)
    assert sp["edge_to_interior"] == pytest.approx(p_edge / p_peak, rel=1e-12)
    # K_Hbeta: every interior point carries W_BASE except one at W_PEAK.
    n_int = sp["interior_points"]
    w_mean = W_BASE + (W_PEAK - W_BASE) / n_int
    assert sp["w_max_N_per_mm"] == W_PEAK
    assert sp["w_mean_N_per_mm"] == pytest.approx(w_mean, rel=1e-12)
    assert sp["K_Hbeta"] == pytest.approx(W_PEAK / w_mean, rel=1e-12)
    # ISO 6336-2 at the sun torque of one branch (case 1: 1378.7 N m over 3 pinions).
    iso = iso6336_pitch_contact_stress(pair, n_mm(1378.7 / 3), steel, steel)
    assert sp["iso_driver_torque_Nm"] == pytest.approx(1378.7 / 3, rel=1e-12)
    assert sp["sigma_H0_MPa"] == pytest.approx(iso["sigma_H0"], rel=1e-12)
    assert sp["sigma_H_MPa"] == pytest.approx(iso["sigma_H0"] * math.sqrt(W_PEAK / w_mean))
    # The ring mesh: a uniform load, no peak: K_Hbeta = 1, edge = interior where the
    # curvature is the same; the pinion drives it at T_sun z_pinion / z_sun.
    pr = res["pinion-ring"]
    assert pr["K_Hbeta"] == pytest.approx(1.0, rel=1e-12)
    assert pr["iso_driver_torque_Nm"] == pytest.approx(1378.7 / 3 * 26 / 35, rel=1e-12)
    assert pr["sigma_H_MPa"] == pytest.approx(pr["sigma_H0_MPa"], rel=1e-12)


def test_hertz_at_the_pitch_point_cross_checks_iso(cycle):
    """Hertz at the pitch point under a uniform line load: under ISO's mean load per contact
    length it is sigma_H0 / Z_beta (eps_beta = 2.08 >= 1, the identity of
    gears.contact_stress.iso6336_pitch_contact_stress, to round-off); under the FE mean and
    largest interior loads it scales as sqrt(w), so their ratio is sqrt(K_Hbeta)."""
    study, positions, _ = cycle
    res = contact_stress_cycle(study.gearset, study.material, positions)
    for c in res.values():
        z_b = c["iso_factors"]["Z_beta"]
        assert c["hertz_pitch_w_nominal_mean_MPa"] * z_b == pytest.approx(
            c["sigma_H0_MPa"], rel=1e-12
        )
        assert c["hertz_pitch_w_max_MPa"] / c["hertz_pitch_w_mean_MPa"] == pytest.approx(
            math.sqrt(c["K_Hbeta"]), rel=1e-12
        )
    # the synthetic ring mesh carries W_BASE everywhere: Hertz at C under W_BASE
    pr = res["pinion-ring"]
    pair = study.gearset.pair("pinion", "ring")
    steel = (study.material.gear_youngs_modulus, study.material.poisson_ratio)
    want = float(mesh_contact(pair, 0.0, W_BASE, steel, steel).p_max)
    assert pr["hertz_pitch_w_mean_MPa"] == pytest.approx(want, rel=1e-12)


def test_line_ends_and_tip_form_points(cycle):
    study, positions, _ = cycle
    pos = positions[0]
    e = edge_points(study.gearset, pos)["sun-pinion"]
    n = len(pos["meshes"]["sun-pinion"]["points"]["x_mm"])
    ends = np.zeros(n, bool)
    for line in pos["grid_lines"]["sun-pinion"]:
        ends[[line["rows"][0], line["rows"][1] - 1]] = True
    # the line ends, and the points within one normal module (1.59 mm) of a face end of the
    # common face width (the pinion's 29 mm): the fixed face-end band
    sun, pin = study.gearset.gears["sun"], study.gearset.gears["pinion"]
    z = np.asarray(pos["meshes"]["sun-pinion"]["points"]["x_mm"], float)[:, 2]
    band = 14.5 - np.abs(z) < 1.59
    assert band.any() and (~band).any()
    assert np.array_equal(e["line_end"], ends | band)
    assert np.array_equal(e["edge"], ends | band | e["tip_form"])
    # Points placed at a chosen roll length on the sun and the pinion's reference radius
    # (far from its tip and form circles): an edge point within one spacing (along the
    # contact line: |du| / sin(beta_b)) of the sun's tip circle or within the tip band (a
    # quarter module, 0.40 mm, of profile arc (u_tip^2 - u^2) / (2 r_b): 0 / 0.06 / 0.11 /
    # 0.14 / 0.24 / 0.48 / 0.71 mm at these fractions of a spacing), interior beyond both.
    a = pos["pinions"]["pinion"]["centre_mm"][0]
    u_tip = float(roll_length(sun.tip_radius, sun.base_radius))
    sin_b = math.sin(sun.base_helix_angle)
    fractions = np.array([0.0, 0.5, 0.9, 1.1, 2.0, 4.0, 6.0])
    r_s = np.hypot(sun.base_radius, u_tip - fractions * SPACING * sin_b)
    r_p = pin.reference_radius
    x = (r_s**2 - r_p**2 + a * a) / (2 * a)
    pts = np.c_[x, np.sqrt(r_s**2 - x**2), np.zeros_like(x)]
    probe = {
        **pos,
        "grid_lines": {},
        "meshes": {"sun-pinion": {**pos["meshes"]["sun-pinion"], "points": {"x_mm": pts.tolist()}}},
    }
    tip_form = edge_points(study.gearset, probe)["sun-pinion"]["tip_form"]
    assert tip_form.tolist() == [True, True, True, True, True, False, False]


def test_summary_keeps_the_old_keys(cycle):
    # position_record keeps contact_stress (the peak, here the line end's W_EDGE at
    # position 0) and adds the interior peak (W_BASE's largest Hertz p there).
    study, positions, _ = cycle
    scalars = dict.fromkeys(MEAN_KEYS[study.gearset.kind], 0.0)
    rec = position_record(study, {**positions[0], **scalars, "timings": {"wall": 0.0}}, 0)
    res = contact_stress_cycle(study.gearset, study.material, positions[:1])
    assert rec["contact_stress"]["sun_pinion"] == pytest.approx(
        res["sun-pinion"]["edge_p_max_MPa"], rel=1e-12
    )
    assert rec["contact_stress_interior"]["sun_pinion"] == pytest.approx(
        res["sun-pinion"]["interior_p_max_MPa"], rel=1e-12
    )
    assert set(driver_torques(study.gearset)) == {("sun", "pinion"), ("pinion", "ring")}


def test_planet_meshes_reduce_to_the_gear_set_meshes():
    """The system scene's contact stresses per mesh of the gear set: the largest over the
    planets' meshes, and which mesh it was (planet bodies are the gear's name and index)."""
    from postprocess.summary import cycle_set, set_mesh

    gears = ("sun", "pinion", "ring")
    assert set_mesh("sun-pinion2", gears) == "sun_pinion"
    assert set_mesh("pinion13-ring", gears) == "pinion_ring"
    assert set_mesh("sun-pinion", gears) == "sun_pinion"
    cycle = {
        "sun-pinion1": {"interior_p_max_MPa": 2100.0, "sigma_H_MPa": 2300.0},
        "sun-pinion2": {"interior_p_max_MPa": 2200.0, "sigma_H_MPa": 2250.0},
        "pinion1-ring": {"interior_p_max_MPa": 1400.0, "sigma_H_MPa": None},
    }
    out = cycle_set(cycle, gears)
    assert out["sun_pinion"] == {
        "mesh": "sun_pinion2",
        "interior_p_max_MPa": 2200.0,
        "sigma_H_MPa": 2300.0,
    }
    assert out["pinion_ring"] == {"mesh": "pinion1_ring", "interior_p_max_MPa": 1400.0}
