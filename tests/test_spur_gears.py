"""Spur gear sets (helix angle 0): the contact lines of the flank grid are the k -> 0 limit
of the helical ones (solvers/flank_grid.py eq. 1a), and a spur case file runs through the
study driver (level 0, one position)."""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import copy
import json
import math

import numpy as np
import pytest
from mpi4py import MPI

from cases.gearset import load_gearset, parse_gearset
from meshing import scenes
from solvers.flank_grid import flank_contact_pairs
from studies import run as study_run

PARKER = load_gearset("parker2000")


def _helix(gs, beta_deg: float):
    src = copy.deepcopy(gs.source)
    src["common"]["helix_angle"] = beta_deg
    return parse_gearset(src, f"{gs.name} (helix {beta_deg} deg)")


def test_spur_contact_lines_are_axial_over_the_whole_face():
    sc = scenes.build_scene("one_branch", PARKER, 0.0)
    grids, _ = flank_contact_pairs(sc, 1.0, None, None)
    assert set(grids) == {"sun-planet", "planet-ring", "sun-planet/coast", "planet-ring/coast"}
    for name, (grid, info) in grids.items():
        zn = next(z for z in sc.zones if name.startswith(f"{z.driver}-{z.driven}"))
        assert info.lines, name
        for ln in info.lines:
            # the whole common face width, the line parallel to the axis
            assert ln["z_range"] == pytest.approx((-10.0, 10.0), abs=1e-12)
            assert ln["length"] == pytest.approx(20.0, abs=1e-12)
            x = grid.x_a[slice(*ln["rows"])]
            assert np.ptp(x[:, 0]) < 1e-12 and np.ptp(x[:, 1]) < 1e-12
        # the normal lies in the transverse plane: n = d (drive) or the mirrored d (coast)
        assert np.abs(grid.normals[:, 2]).max() == 0.0
        if not name.endswith("/coast"):
            assert np.allclose(grid.normals[:, :2], zn.direction, atol=1e-15)
        # perfect involutes: the drive flanks touch on every line, the coast flanks stand
        # the mesh's normal backlash apart
        jn = PARKER.meshes[0 if name.startswith("sun") else 1].normal_backlash
        want = jn if name.endswith("/coast") else 0.0
        assert np.abs(grid.gap0 - want).max() < 1e-9


def test_spur_lines_are_the_limit_of_helical_ones():
    """A 1e-4 deg helix turns the flanks by 20 tan(1e-4 deg) = 35 nm across the face: the
    lines must lie where the spur lines are to that order (1e-4 mm), each tooth pair alike."""
    spur = scenes.build_scene("one_branch", PARKER, 0.0)
    near = scenes.build_scene("one_branch", _helix(PARKER, 1e-4), 0.0)
    g_spur, _ = flank_contact_pairs(spur, 1.0, None, None, coast=False)
    g_near, _ = flank_contact_pairs(near, 1.0, None, None, coast=False)
    for name in g_spur:
        (a, ia), (b, ib) = g_spur[name], g_near[name]
        assert [ln["driver_tooth"] for ln in ia.lines] == [ln["driver_tooth"] for ln in ib.lines]
        assert a.n == b.n
        assert np.abs(a.x_a - b.x_a).max() < 1e-4
        assert np.abs(a.normals - b.normals).max() < 1e-5
        assert math.isclose(a.weights.sum(), b.weights.sum(), rel_tol=1e-6)


# --------------------------------------------------------------------------------------
# finite elements: a user's spur gear set through the study driver
# --------------------------------------------------------------------------------------

SPUR_SET = """\
name = "spur-user"
kind = "single_pinion"
input_torque = 120.0
planets = 3                   # (21 + 87) / 3 = 36: equally spaced
power_path = ["sun", "planet", "ring"]

[common]
normal_module = 2.0
normal_pressure_angle = 20.0
helix_angle = 0.0

[gears.sun]
teeth = 21
hand = "right"
face_width = 14.0

[gears.planet]
teeth = 33
hand = "left"
face_width = 14.0

[gears.ring]
teeth = 87
internal = true
hand = "left"
face_width = 14.0

[[meshes]]                    # 54.0 standard; 54.8: planet x = +0.42, ring x = +0.84 (the
gears = ["sun", "planet"]     # standard internal mesh interferes); default (ISO) backlash
centre_distance = 54.8

[[meshes]]
gears = ["planet", "ring"]
centre_distance = 54.8
"""

SPUR_CASE = """\
name = "spur-user"
gearset = "spur-user.toml"
description = "a user's spur planetary, default backlash"

[bearing]
radial_stiffness = 1.0e6
tilting_stiffness = 1.0e8

[material]
youngs_modulus = 206000.0
poisson_ratio = 0.3
gear_modulus_factor = 1.0

[model]
scene = "one_branch"
level = 0
positions = 1
"""


@pytest.fixture(scope="module")
def spur_run(tmp_path_factory):
    d = tmp_path_factory.mktemp("spur")
    (d / "spur-user.toml").write_text(SPUR_SET)
    (d / "case.toml").write_text(SPUR_CASE)
    out = d / "out"
    code = study_run.main(
        [str(d / "case.toml"), "--level", "0", "--positions", "1", "--out", str(out)],
        comm=MPI.COMM_SELF,
    )
    summary = json.loads((out / "spur-user" / "summary.json").read_text())
    pos = json.loads((out / "spur-user" / "positions" / "0.json").read_text())
    return code, summary, pos


@pytest.mark.slow
def test_spur_case_file_runs_with_backlash(spur_run):
    code, summary, pos = spur_run
    assert code == 0 and summary["failed_positions"] == [] and summary["warnings"] == []
    t_branch = 120.0 / 3
    # statics of the frictionless, carrier-fixed spur branch: the sun torque balances, the
    # ring carries Zr / Zs of it, both meshes carry the same normal force, and that force is
    # the sun torque over the sun's base radius (spur: the normal lies in the transverse
    # plane). Round-off (1e-9) for the balances; the ratio as in test_gear_branch (0.5 %:
    # linearized kinematics, ~theta r / r_b).
    assert pos["sun_contact_torque_Nm"] == pytest.approx(-pos["sun_torque_applied_Nm"], rel=1e-9)
    assert pos["sun_torque_applied_Nm"] == pytest.approx(t_branch, rel=1e-12)
    assert pos["ring_support_torque_Nm"] / t_branch == pytest.approx(87 / 21, rel=5e-3)
    rb_sun = 0.5 * 2.0 * 21 * math.cos(math.radians(20.0))
    for key in ("mesh_normal_force_S_N", "mesh_normal_force_R_N"):
        assert pos[key] == pytest.approx(t_branch * 1e3 / rb_sun, rel=5e-3)
    assert pos["resultant_mismatch_rel"] < 1e-6  # round-off of two resultants (measured 5e-10)
    # compressive contact only, on every loaded point of both drive meshes; coast flanks open
    for mesh in pos["meshes"].values():
        f = np.asarray(mesh["points"]["force_N"])
        assert f.min() >= 0.0 and mesh["active_points"] >= 4 and mesh["normal_force_N"] > 0
    assert summary["coast"]["loaded"] is False and summary["coast"]["min_gap_mm"] > 0.0
    # a spur mesh has no axial force: the pinion moments about the radial axis and the
    # load centroids stay near mid face (rigid-ish bearing, uniform lines); 1 mm of 14
    assert abs(summary["ZS"]) < 1.0 and abs(summary["ZR"]) < 1.0
