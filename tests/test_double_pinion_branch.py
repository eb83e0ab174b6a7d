"""One branch of the case-2 double pinion planetary (sun, SP, RP, ring) on the FE contact model.

P1 at mesh level 0 (about 188k DOFs, ~13 s per case serially). Each case is solved once per
module (fixtures) and shared by the tests; no test here reads the root stress, so it is read
on the global model (studies/case_variants.py: the submodels would be most of the time).
"""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split

from dataclasses import replace

import numpy as np
import pytest
from mpi4py import MPI
from statics import chain_bound, gear_torque, off_line_share, sun_force

from cases.study_case import load_study_case
from studies.case_variants import global_root_stress
from studies.position import solve_position
from studies.settings import RunSettings

T_BRANCH = 1378.7 / 3  # N m per branch (singh2007 section 1)
Z_SUN, Z_RING = 35, 92
FACE_PINION = 29.0  # mm, SP and RP face width


@pytest.fixture(scope="module")
def ga():
    return solve_position(
        global_root_stress(load_study_case("2B-GA")), 0.0, MPI.COMM_WORLD, RunSettings(level=0)
    )


@pytest.fixture(scope="module")
def gb():
    return solve_position(
        global_root_stress(load_study_case("2B-GB")), 0.0, MPI.COMM_WORLD, RunSettings(level=0)
    )


@pytest.fixture(scope="module")
def ga_line():
    """2B-GA on the line contact model (every force on a plane of action)."""
    case = global_root_stress(load_study_case("2B-GA"))
    case = replace(case, numerics=replace(case.numerics, contact_model="line"))
    return solve_position(case, 0.0, MPI.COMM_WORLD, RunSettings(level=0))


GEARS = ["sun", "SP", "RP", "ring"]  # the power path of the branch scene's bodies


def carrier_torque_Nm(r: dict) -> float:
    """Torque about the scene axis the carrier exerts on SP and RP through their bearings
    (N m): minus the moment of the contact force on each pinion (``<p>_force_N`` in its frame,
    turned to the scene frame) at its centre."""
    total = 0.0
    for pn in ("SP", "RP"):
        c = np.asarray(r["centres_mm"][pn])
        f = np.asarray(r["frames"][pn]).T @ np.asarray(r[f"{pn}_force_N"])
        total -= float(c[0] * f[1] - c[1] * f[0]) / 1e3
    return total


@pytest.mark.parametrize("name", ["ga_line", "ga", "gb"])
def test_torque_balance_and_ratio(name, request):
    """Pinions free to spin; ring / sun = Z_ring / Z_sun (carrier held, frictionless
    involutes on the line grid: exact up to the small-rotation linearization; on the zone
    grid, the default, within the off-line share, tests/statics.py); the carrier carries
    T_sun (Z_ring / Z_sun - 1). The exact statics for any normals: the sun's moment equation
    (a rigid unknown), the pinions' spin equations, the ring's support, and the balance of
    the branch (carrier from the reported bearing forces, frames and centres), each from
    the point forces F_k n_k at x_k, to round-off (1e-9; measured ~1e-15)."""
    r = request.getfixturevalue(name)
    for pn in ("SP", "RP"):
        # spin moment: rigid-unknown equation solved exactly; round-off of N mm sums
        assert abs(r[f"{pn}_spin_moment_Nm"]) < 1e-6 * T_BRANCH
        assert abs(r[f"Mz_{pn}"]) < 1e-6 * T_BRANCH
        assert abs(gear_torque(r, pn) - r[f"{pn}_spin_moment_Nm"]) < 1e-9 * T_BRANCH
    assert gear_torque(r, "sun") == pytest.approx(-T_BRANCH, rel=1e-9)
    assert gear_torque(r, "sun") == pytest.approx(r["sun_contact_torque_Nm"], rel=1e-9)
    assert gear_torque(r, "ring") == pytest.approx(r["ring_contact_torque_Nm"], rel=1e-9)
    assert r["ring_support_torque_Nm"] == pytest.approx(-r["ring_contact_torque_Nm"], rel=1e-9)
    assert r["resultant_mismatch_rel"] < 1e-9
    # T_sun + T_ring + T_c = 0: the carrier from the reported bearing forces, frames and
    # centres (the model imposes none of it)
    assert carrier_torque_Nm(r) == pytest.approx(
        -(T_BRANCH + r["ring_support_torque_Nm"]), rel=1e-9
    )
    # the closed forms (the ring turns with the sun, so T_c = T_sun (Z_ring / Z_sun - 1), on
    # the sun's side): on the line grid 0.5 % (linearization; measured round-off), on the
    # zone grid within the off-line share (a bound, attained where every mesh shifts the
    # same way: 2B-GA measured 5.0e-3 against a ratio 5.0e-3 low)
    off = off_line_share(r)
    if name == "ga_line":
        assert off < 1e-12
        tol = 5e-3
    else:
        assert 1e-4 < off < 2e-2
        tol = off + 1e-9
    ratio = r["ring_contact_torque_Nm"] / -r["sun_contact_torque_Nm"]
    assert abs(ratio / (Z_RING / Z_SUN) - 1) <= tol
    # T_c = T_ring - T_sun moves by the ratio's departure times Z_ring / (Z_ring - Z_sun)
    closed = T_BRANCH * (Z_RING / Z_SUN - 1)
    assert abs(carrier_torque_Nm(r) / closed - 1) <= tol * Z_RING / (Z_RING - Z_SUN)


@pytest.mark.parametrize("name", ["ga_line", "ga", "gb"])
def test_axial_force_signs_match_closed_form(name, request):
    """In the pinion frames (Z = -z) the FE axial mesh forces have the section-5 signs and
    magnitudes: FzSUN = -FzRP = FzSP = -FzRING = FA. Every point force of a mesh has the
    same axial part n_z F_k (zone cells too: their normals are turned about the axis), so
    Fz = n_z sum F_k: on the line grid sum F_k = F_0 at every mesh (a force balance, to
    round-off: 1e-6), on the zone grid within the chain of the point arms' departures
    (tests/statics.py chain_bound; 2B-GA measured 0.09-0.45 %)."""
    r = request.getfixturevalue(name)
    a = r["analytic"]
    f0 = sun_force(r)
    mesh = {"FzSUN": 0, "FzSP": 1, "FzRP": 1, "FzRING": 2}  # the mesh of each force
    for key in ("FzSUN", "FzRP", "FzSP", "FzRING"):
        tol = 1e-6 + chain_bound(r, GEARS, mesh[key]) / f0
        if name == "ga_line":
            assert chain_bound(r, GEARS, mesh[key]) < 1e-9 * f0
        assert r[f"{key}_fe"] == pytest.approx(a[key], rel=tol)
    assert a["FzSUN"] > 0 and a["FzSP"] > 0 and a["FzRP"] < 0 and a["FzRING"] < 0


def test_bearing_moments_vs_table5(ga):
    """2B-GA (rigid bearing): SP and RP (Mx, My) and the four LOA moments near Table 5 2-B.

    Tolerances. Against the closed form with the forces moved to the FE's own centroid
    offsets Z (pitch point + Z e_Z): My within 2 % (the case-1 experience); Mx within 5 %,
    because the FE centroid also sits off the pitch point along the transverse line of action
    (``loa_offset_*``: 0.09-0.18 mm, RP-ring 0.64 mm) and the axial force there adds to Mx
    (measured: SP 0.9 %, RP 3.5 %). Against Table 5 itself (concentrated load at the pitch
    points, Z = 0) the FE is a few % off (measured 3-6 %); 8 % bounds it, signs must agree.
    """
    t5 = ga["analytic"]["table5"]
    sh = ga["analytic"]["at_fe_centroids"]
    for pn in ("SP", "RP"):
        assert ga[f"My_{pn}"] == pytest.approx(sh[f"My_{pn}"], rel=0.02)
        assert ga[f"Mx_{pn}"] == pytest.approx(sh[f"Mx_{pn}"], rel=0.05)
        for c in ("Mx", "My"):
            assert ga[f"{c}_{pn}"] == pytest.approx(t5[f"{c}_{pn}"], rel=0.08)
    for key in ("M_LOA_SP_SUN", "M_LOA_SP_RP", "M_LOA_RP_SP", "M_LOA_RP_RING"):
        assert ga[key] == pytest.approx(t5[key], rel=0.08)
    # the paper's printed values (rounded to 1 N m; 2 N m covers the rounding of FA)
    assert t5["Mx_SP"] == pytest.approx(128, abs=2) and t5["My_SP"] == pytest.approx(99, abs=2)
    assert t5["Mx_RP"] == pytest.approx(104, abs=2) and t5["My_RP"] == pytest.approx(185, abs=2)


def test_sp_rp_mesh_near_centred(ga, gb):
    """singh2007: the SP-RP mesh sees only a small LOA-moment differential and stays nearly
    centred. 2B-GA (rigid bearing): every offset is small; |Z_SP-RP| < 2 % of the pinion face
    width. 2B-GB: the sun mesh load moves to -Z and the ring mesh load to +Z (as in case 1,
    bearing tilt is self-correcting) by ~4 mm, and the SP-RP centroid moves < 0.3 of the
    smaller of the two (measured 0.19): its LOA moments nearly cancel (the SP-RP differential
    at the default level, 5 positions, is 19.3 N m for 2B-GA and 23.8 N m for 2B-GB against
    146-166 N m LOA moments, results/case2/report.md; the paper's closed form: 11 N m)."""
    assert abs(ga["Z_SPRP"]) < 0.02 * FACE_PINION
    assert gb["ZS"] < 0 < gb["ZR"]
    assert abs(gb["Z_SPRP"]) < 0.3 * min(abs(gb["ZS"]), abs(gb["ZR"]))
    # rigid bearings: the sun and ring meshes stay centred too (< 2 % of the face width)
    assert abs(ga["ZS"]) < 0.02 * FACE_PINION and abs(ga["ZR"]) < 0.02 * FACE_PINION
