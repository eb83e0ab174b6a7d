"""Tooth microgeometry per gear (issue 11, item 4): lead crown, lead slope, tip and end
relief from ``[gears.X.modifications]`` enter the contact as initial gaps (the FE meshes keep
the exact flanks).

The FE tests run one position of the case-1 branch at level 0 (P1, ~130k DOFs, ~6 s each),
the bodies shared through one BodyStore (modifications and bearings leave them unchanged).
"""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import copy
import math

import numpy as np
import pytest
from mpi4py import MPI

from cases.gearset import CaseError, load_gearset, parse_gearset
from cases.study_case import load_study_case
from gears.microgeometry import FlankModifications, flank_modification
from gears.profile import involute_deviation
from gears.spec import GeometryError
from meshing import scenes
from postprocess.mesh_stress import contact_stress_cycle
from postprocess.train_results import mesh_stations
from solvers.body_store import BodyStore
from solvers.flank_grid import flank_grid
from studies.case_variants import global_root_stress
from studies.position import solve_position
from studies.settings import RunSettings

UM = 1e-3
CASE1 = load_gearset("case1")
PINION, RING = CASE1.gears["pinion"], CASE1.gears["ring"]


def _set(mods: dict | None = None, backlash_um=None, base="case1"):
    data = copy.deepcopy(load_gearset(base).source)
    for gear, table in (mods or {}).items():
        data["gears"][gear]["modifications"] = table
    if backlash_um is not None:
        for m in data["meshes"]:
            m["normal_backlash_um"] = backlash_um
    return parse_gearset(data, f"{base}.toml")


def _flank_points(gear, side: str, r, z):
    """Points (n, 3) on the exact ``side`` flank of tooth 0 at radii r and axial z."""
    s = 1 if side == "pos" else -1
    r, z = np.broadcast_arrays(np.asarray(r, float), np.asarray(z, float))
    ang = s * gear.half_angle(r) + gear.helix_rotation(z)
    return np.c_[r * np.cos(ang), r * np.sin(ang), z]


# --------------------------------------------------------------------------------------
# the removal laws (pure functions)
# --------------------------------------------------------------------------------------


def test_no_modification_removes_nothing():
    p = _flank_points(PINION, "pos", [21.5, 22.0], [-5.0, 3.0])
    assert np.array_equal(flank_modification(PINION, None, "pos", p), np.zeros(2))
    assert np.array_equal(flank_modification(PINION, FlankModifications(), "neg", p), np.zeros(2))


def test_lead_crown_is_parabolic_across_the_face():
    b = PINION.face_width
    z = np.array([-b / 2, -b / 4, 0.0, b / 4, b / 2])
    m = FlankModifications(lead_crown_um=12.0)
    for side in ("pos", "neg"):
        got = flank_modification(PINION, m, side, _flank_points(PINION, side, 22.0, z))
        assert got == pytest.approx(np.array([12.0, 3.0, 0.0, 3.0, 12.0]) * UM, abs=1e-15)


def test_lead_slope_turns_the_helix():
    """f_Hb/2 removed at +z and added at -z on the pos flank, the reverse on the neg flank:
    the section at z turned by -f_Hb z / (b r_b cos(beta_b)), the same for both flanks."""
    b, f = PINION.face_width, 20.0
    z = np.array([-b / 2, 0.0, b / 2])
    m = FlankModifications(lead_slope_um=f)
    pos = flank_modification(PINION, m, "pos", _flank_points(PINION, "pos", 22.0, z))
    neg = flank_modification(PINION, m, "neg", _flank_points(PINION, "neg", 22.0, z))
    assert pos == pytest.approx(np.array([-10.0, 0.0, 10.0]) * UM, abs=1e-15)
    assert neg == pytest.approx(-pos, abs=1e-15)
    # the removal is how far the exact flank point lies outside the tooth turned by d(z)
    d = -f * UM * (b / 2) / (b * PINION.base_radius * math.cos(PINION.base_helix_angle))
    c, si = math.cos(-d), math.sin(-d)  # the point turned by -d against the tooth turned by d
    for side in ("pos", "neg"):
        p = _flank_points(PINION, side, [21.0, 22.0, 23.0], b / 2)
        q = np.c_[c * p[:, 0] - si * p[:, 1], si * p[:, 0] + c * p[:, 1], p[:, 2]]
        removed = involute_deviation(PINION, q, side)
        assert removed == pytest.approx(flank_modification(PINION, m, side, p), abs=1e-9)


@pytest.mark.parametrize("gear", [PINION, RING], ids=["external", "internal"])
def test_tip_relief_is_linear_in_roll_length(gear):
    rb = gear.base_radius
    r_a, r_form = gear.tip_radius, gear.form_radius
    d_start = 2.0 * (r_a + 0.4 * (r_form - r_a))  # 40 % of the way from the tip to the form
    m = FlankModifications(tip_relief_um=15.0, tip_relief_diameter=d_start)
    m.check(gear)
    roll = lambda r: math.sqrt(r * r - rb * rb)  # noqa: E731
    l_s, l_a = roll(d_start / 2), roll(r_a)
    r = np.array([r_form, 0.5 * d_start, r_a])
    mid = math.sqrt(rb**2 + (0.5 * (l_s + l_a)) ** 2)
    r = np.r_[r, mid]
    got = flank_modification(gear, m, "pos", _flank_points(gear, "pos", r, 0.0))
    assert got == pytest.approx(np.array([0.0, 0.0, 15.0, 7.5]) * UM, abs=1e-12)


def test_end_relief_is_linear_over_its_length():
    b = PINION.face_width
    m = FlankModifications(end_relief_um=8.0, end_relief_length=4.0)
    z = np.array([-b / 2, -b / 2 + 2.0, -b / 2 + 4.0, 0.0, b / 2 - 1.0, b / 2])
    got = flank_modification(PINION, m, "neg", _flank_points(PINION, "neg", 22.0, z))
    assert got == pytest.approx(np.array([8.0, 4.0, 0.0, 0.0, 6.0, 8.0]) * UM, abs=1e-12)


def test_modifications_add_up():
    b = PINION.face_width
    each = {"lead_crown_um": 5.0, "lead_slope_um": -6.0, "end_relief_um": 3.0}
    p = _flank_points(PINION, "pos", [21.0, 22.5], [b / 2 - 0.5, -3.0])
    total = flank_modification(PINION, FlankModifications(**each, end_relief_length=2.0), "pos", p)
    parts = sum(
        flank_modification(PINION, FlankModifications(**{k: v}, end_relief_length=2.0), "pos", p)
        for k, v in each.items()
    )
    assert total == pytest.approx(parts, abs=1e-15)


# --------------------------------------------------------------------------------------
# the gear-set file
# --------------------------------------------------------------------------------------


def test_modifications_from_the_gear_set_file():
    gs = _set(
        {
            "pinion": {"lead_crown_um": 10.0, "tip_relief_um": 5, "tip_relief_diameter": 47.0},
            "sun": {"lead_crown_um": 0.0},
        }
    )
    assert set(gs.modifications) == {"pinion"}  # a table of zeros is no modification
    m = gs.modifications["pinion"]
    assert (m.lead_crown_um, m.tip_relief_um, m.tip_relief_diameter) == (10.0, 5.0, 47.0)
    # the gears (and so the meshes and their cache keys) are those without modifications
    assert gs.gears == CASE1.gears
    assert CASE1.modifications == {}


@pytest.mark.parametrize(
    "table, match",
    [
        ({"crown_um": 5.0}, r"gears\.pinion\.modifications: unknown field 'crown_um'"),
        ({"lead_crown_um": -1.0}, r"gears\.pinion\.modifications\.lead_crown_um = -1\.0: must"),
        ({"lead_slope_um": "5"}, r"gears\.pinion\.modifications\.lead_slope_um = '5': must be"),
        (
            {"lead_crown_um": 600.0},
            r"gears\.pinion\.modifications\.lead_crown_um = 600\.0: must be a number in \[0, 500\]",
        ),
        (
            {"tip_relief_um": 5.0},
            r"gears\.pinion\.modifications\.tip_relief_diameter = None: "
            r"must be given \(mm\) with tip_relief_um = 5\.0",
        ),
        (
            {"end_relief_um": 5.0},
            r"gears\.pinion\.modifications\.end_relief_length = None: "
            r"must be given \(mm\) with end_relief_um = 5\.0",
        ),
        (
            {"tip_relief_um": 5.0, "tip_relief_diameter": 60.0},
            r"gears\.pinion: pinion\.modifications\.tip_relief_diameter = 60\.0: must lie between",
        ),
        (
            {"end_relief_um": 5.0, "end_relief_length": 20.0},
            r"gears\.pinion: pinion\.modifications\.end_relief_length = 20\.0: must be <= half "
            r"the face width, 14\.5 mm",
        ),
    ],
)
def test_bad_modifications_name_file_and_field(table, match):
    with pytest.raises(CaseError, match=r"^case1\.toml: " + match):
        _set({"pinion": table})


def test_modification_values_are_checked_without_a_file():
    with pytest.raises(GeometryError, match=r"modifications\.end_relief_um = nan"):
        FlankModifications(end_relief_um=float("nan"))


# --------------------------------------------------------------------------------------
# the contact grid: g0 = exact separation + driver and driven modifications
# --------------------------------------------------------------------------------------


def test_grid_gap_adds_both_gears_modifications():
    mods = _set({"sun": {"lead_slope_um": 7.0}, "pinion": {"lead_crown_um": 10.0}}).modifications
    sc = scenes.build_scene("one_branch", CASE1, 0.0)
    zn = sc.zones[0]  # sun -> pinion
    drv, dvn = sc.gear(zn.driver), sc.gear(zn.driven)
    plain, _ = flank_grid(zn, drv, dvn, 1.0)
    grid, info = flank_grid(zn, drv, dvn, 1.0, modifications=mods)
    z = grid.x_a[:, 2]
    sun_b, pin_b = drv.gear.face_width, dvn.gear.face_width
    want_a = 7.0 * UM * z / sun_b  # the sun's pos (drive) flank
    want_b = 10.0 * UM * (2 * z / pin_b) ** 2
    assert info.mod_a == pytest.approx(want_a, abs=1e-15)
    assert info.mod_b == pytest.approx(want_b, abs=1e-15)
    assert grid.gap0 - plain.gap0 == pytest.approx(want_a + want_b, abs=1e-15)
    assert np.array_equal(grid.x_a, plain.x_a) and np.array_equal(grid.x_b, plain.x_b)


# --------------------------------------------------------------------------------------
# finite elements (level 0, one position)
# --------------------------------------------------------------------------------------

# 1-GA at level 0, roll 0, P1, penalty 100, spacing 1.0, solved by studies.position.
# solve_position BEFORE issue 11 (git 38bf585: no backlash, no coast grids, no
# microgeometry). A deliberate change of the meshes or of the solver must record them anew.
# Recorded anew for the scenes' fine fillets (issue 13 item 1: level 0 refines the cycle's
# tension fillets to 0.45 mm, the other fillets 1.0 mm; the cycle sampled at 60 angles, the
# placements unwrapped over the cycle): the meshes changed, not the solver. On the meshes of
# before (5 samples, every active fillet at 0.6 mm) the code of commit 6021ebd still gave
# the 38bf585 values (My_pin 259.70054528368604, Mx_pin 10.26241916258707, ZS
# 0.010741795461686781, ZR 0.23508872693859148, force norms 2715.4561376106367 /
# 2677.0050511541717) to 1.5e-12; the values below are this code's on the new meshes, so
# the test now pins the zero-backlash results instead of comparing with the code of before
# issue 11.
GA_BEFORE = {
    "My_pin": 259.639426803604,
    "Mx_pin": 11.181354709706744,
    "ZS": 0.03791400043556325,
    "ZR": 0.26175339086678856,
    "M_LOA_sun": 104.72595454329182,
    "M_LOA_ring": -93.6615673654086,
    "ring_support_torque_Nm": 1129.220952380952,
}
GA_BEFORE_RIGID = {
    "sun_rotation": 0.0015611453627211896,
    "pinion_x": -2.6262913228439364e-06,
    "pinion_y": 0.00013127020854821424,
    "pinion_rx": 1.2706084897394184e-06,
    "pinion_ry": -2.9504480318591366e-05,
    "pinion_spin": -0.0008488411700054424,
}
GA_BEFORE_FORCE_NORM = {"sun-pinion": 2693.010820501914, "pinion-ring": 2634.427163725645}


@pytest.fixture(scope="module")
def store():
    return BodyStore()


def _solve(name: str, gearset, store, model: str | None = None, gap_limit_um=None):
    """One position of case ``name`` on ``gearset``; ``model`` a contact model other than
    the case's (the default, "zone"); ``gap_limit_um`` a zone gap limit other than the
    case's. No test here reads the root stress (studies/case_variants.py)."""
    import dataclasses

    study = global_root_stress(dataclasses.replace(load_study_case(name), gearset=gearset))
    if model is not None:
        numerics = dataclasses.replace(study.numerics, contact_model=model)
        study = dataclasses.replace(study, numerics=numerics)
    if gap_limit_um is not None:
        numerics = dataclasses.replace(study.numerics, zone_gap_limit_um=gap_limit_um)
        study = dataclasses.replace(study, numerics=numerics)
    return solve_position(study, 0.0, MPI.COMM_SELF, RunSettings(level=0, degree=1), store=store)


@pytest.fixture(scope="module")
def ga(store):
    return _solve("1-GA", CASE1, store)


@pytest.fixture(scope="module")
def ga_line(store):
    return _solve("1-GA", CASE1, store, "line")


@pytest.fixture(scope="module")
def gb(store):
    return _solve("1-GB", CASE1, store)


def test_zero_backlash_no_modification_reproduces_the_drive_flanks(store):
    """Line model (the results of before were line grids): zero backlash and no modification
    give the drive-flank results of before the coast grids and microgeometry, to 1e-10
    (measured 2e-12; the coast grids stay open, 1.4 um)."""
    pos = _solve("1-GA", _set(backlash_um=0.0), store, "line")
    for k, v in GA_BEFORE.items():
        assert pos[k] == pytest.approx(v, rel=1e-10), k
    for k, v in GA_BEFORE_RIGID.items():
        assert pos["rigid"][k] == pytest.approx(v, rel=1e-10), k
    for mesh, v in GA_BEFORE_FORCE_NORM.items():
        f = np.asarray(pos["meshes"][mesh]["points"]["force_N"])
        assert np.linalg.norm(f) == pytest.approx(v, rel=1e-10), mesh
    assert pos["coast_force_N"] == 0.0 and pos["coast_min_gap_mm"] > 0.0


def _end_points(mesh: dict, b: float) -> np.ndarray:
    """Stations (line grid: its points; zone grid: its sections) within one grid spacing
    (1 mm) of a face end of the common width."""
    z = np.asarray(mesh_stations(mesh)["x_mm"])[:, 2]
    return np.abs(z) > 0.5 * b - 1.0


def _chain_bound(pos: dict, mesh: str) -> float:
    """How far (N) the mesh's sum F_k may lie from F_0 = T_sun / (r_b,sun cos(beta_b)), the
    coast flanks open: the force-weighted departures of the point arms from r_b cos(beta_b)
    (``off_line_N``) along sun -> pinion (its spin: equal torques at its meshes) -> ring."""
    s = pos["meshes"]["sun-pinion"]["off_line_N"]
    if mesh == "sun-pinion":
        return s["sun"]
    return s["sun"] + s["pinion"] + pos["meshes"][mesh]["off_line_N"]["pinion"]


@pytest.mark.parametrize("model", ["line", "zone"])
def test_lead_crown_pulls_the_load_off_the_face_ends(ga, ga_line, store, model):
    """A 10 um lead crown on the pinion (both flanks, so both meshes) unloads the face ends of the
    aligned 1-GA: the mean line load of the end stations falls to about half at the sun mesh and a
    third at the ring mesh (line model: measured 789 -> 388 and 497 -> 143 N/mm; zone model 370 ->
    211 and 172 -> 76 N/mm: its local contact compliance already spreads the end load), the peak
    moves inside, the total is unchanged (the zone grid's sections differ with the crown: their
    cells are laid where g0, the crown included, is below the gap limit; the sections along the face
    do not)."""
    plain = ga_line if model == "line" else ga
    crowned = _solve("1-GA", _set({"pinion": {"lead_crown_um": 10.0}}), store, model)
    b = min(PINION.face_width, CASE1.gears["sun"].face_width)
    for mesh in ("sun-pinion", "pinion-ring"):
        m0, m1 = plain["meshes"][mesh], crowned["meshes"][mesh]
        w0 = np.asarray(mesh_stations(m0)["line_load_N_per_mm"])
        w1 = np.asarray(mesh_stations(m1)["line_load_N_per_mm"])
        end, end1 = _end_points(m0, b), _end_points(m1, b)
        if model == "line":
            assert np.array_equal(end, end1)  # the same grid
        assert w1[end1].mean() < 0.6 * w0[end].mean()
        assert w1[end1].max() < w1[~end1].max()  # the peak is inside the face
        # the total: the sun's torque fixes sum F_k on a line grid exactly; on a zone grid
        # up to the point arms' departure from r_b cos(beta_b) (_chain_bound, both solves)
        tol = 1e-9 * m0["normal_force_N"]
        if model == "zone":
            tol += _chain_bound(plain, mesh) + _chain_bound(crowned, mesh)
        else:
            assert _chain_bound(plain, mesh) < tol
        assert abs(m1["normal_force_N"] - m0["normal_force_N"]) <= tol
    if model == "line":
        # the largest initial gap: the crown at the outermost grid points, half a spacing in
        assert 0.85 * 10.0 * UM < crowned["g0_max_abs_mm"] <= 10.0 * UM


def test_a_crown_beyond_the_gap_limit_keeps_the_face_ends_on_the_grid(store):
    """A 100 um lead crown on the tilted 1-GB pinion, over twice the default zone gap limit
    (40 um): every section of the face, both ends included, keeps its cells (each band is
    measured from its section's smallest separation, which the crown lifts; measured from
    zero, the band would stop where the crown passes 40 um, |z| = 0.63 b/2, and the load
    would sit on its last row, the answer set by the hidden limit). The solve passes its
    reach check (solvers.zone_reach) and does not depend on the limit: doubling it moves
    the pinion moment by less than 1e-4 and the centroids by less than 0.01 mm (1-GC at
    level 0 measured 2e-6 and 1e-5 mm between 80 and 160 um); K_Hbeta to 1e-3 (its
    interior maximum may move by a station between the two grids' sections)."""
    crown = _set({"pinion": {"lead_crown_um": 100.0}})
    pos = _solve("1-GB", crown, store)
    wide = _solve("1-GB", crown, store, gap_limit_um=80.0)
    b = min(PINION.face_width, CASE1.gears["sun"].face_width)
    for mesh in ("sun-pinion", "pinion-ring"):
        z = np.asarray(mesh_stations(pos["meshes"][mesh])["x_mm"])[:, 2]
        assert z.max() > 0.5 * b - 1.0 and z.min() < -0.5 * b + 1.0, mesh
        assert pos["zone_reach_um"][mesh] <= 20.0, mesh
    assert wide["My_pin"] == pytest.approx(pos["My_pin"], rel=1e-4)
    assert wide["Mx_pin"] == pytest.approx(pos["Mx_pin"], rel=1e-4, abs=1e-4 * abs(pos["My_pin"]))
    for k in ("ZS", "ZR"):
        assert wide[k] == pytest.approx(pos[k], abs=0.01), k
    # K_Hbeta = w_max / w_mean over the stations of the whole face width, so the limit
    # leaves it too (it was taken over the grid's length: 4.93 against 7.57 for one answer)
    mat = load_study_case("1-GB").material
    k_hb = [
        {m: c["K_Hbeta"] for m, c in contact_stress_cycle(crown, mat, [p]).items()}
        for p in (pos, wide)
    ]
    for mesh, k in k_hb[0].items():
        assert k_hb[1][mesh] == pytest.approx(k, rel=1e-3), mesh


def _tilt_mismatch_um(pos: dict) -> dict[str, float]:
    """Per mesh, the change across the pinion face width of the drive-flank gap that the
    pinion's rigid tilt makes (um, + opening towards +z): n . (theta x (x - c)), theta the
    bore's tilts about scene x and y, fitted linearly in z over the stations (the points of
    a line grid, the sections' points on the contact lines of a zone grid; pinion on side B
    of the sun mesh, side A of the ring mesh)."""
    rig = pos["rigid"]
    theta = np.array([rig["pinion_rx"], rig["pinion_ry"], 0.0])
    c = np.asarray(pos["pinions"]["pinion"]["centre_mm"])
    out = {}
    for mesh, sign in (("sun-pinion", 1.0), ("pinion-ring", -1.0)):
        m = pos["meshes"][mesh]
        x = np.asarray(mesh_stations(m)["x_mm"])  # on the contact lines (zone: sections)
        dg = sign * np.cross(theta, x - c) @ np.asarray(m["normal"])
        out[mesh] = float(np.polyfit(x[:, 2], dg, 1)[0]) * PINION.face_width / UM
    return out


def test_lead_slope_against_the_tilt_recentres_the_pattern(gb, store):
    """1-GB: the pinion tilt opens the sun-mesh gap towards -z and the ring-mesh gap
    towards +z (measured -27.0 and +23.4 um across the face) and pushes the loads to the
    face ends (ZS = -3.64, ZR = +3.95 mm). A lead slope on the pinion that removes the same
    amount (pos flank at the sun mesh +27.0 um towards +z, neg flank at the ring mesh
    -23.4 um: one helix angle modification, f_Hb = +25.2 um, the mean) re-centres both: ZS
    and ZR shrink to a fifth (measured -0.69, +0.78 mm; the centred load raises My_pin and
    with it the tilt, so one step under-corrects)."""
    mis = _tilt_mismatch_um(gb)
    assert mis["sun-pinion"] < -15.0 and mis["pinion-ring"] > 15.0
    # removal slope on the pinion flank = -(gap change); pos flank (sun mesh) removes +f z/b,
    # neg flank (ring mesh) -f z/b: both estimates of f agree within 30 % (the line model
    # measured 27.0 / 23.4 um, 15 % apart; the zone model, the default, 28.2 / 22.7 um, 24 %
    # apart: its local contact compliance lets the pinion tilt a little more towards the
    # sun mesh; one slope, their mean, still re-centres both below)
    f_sun, f_ring = -mis["sun-pinion"], mis["pinion-ring"]
    assert f_sun == pytest.approx(f_ring, rel=0.3)
    f = 0.5 * (f_sun + f_ring)
    sloped = _solve("1-GB", _set({"pinion": {"lead_slope_um": f}}), store)
    assert gb["ZS"] < -3.0 and gb["ZR"] > 3.0
    assert abs(sloped["ZS"]) < 0.3 * abs(gb["ZS"])
    assert abs(sloped["ZR"]) < 0.3 * abs(gb["ZR"])
    assert sloped["My_pin"] > gb["My_pin"]  # towards the centred (rigid) value
    assert sloped["coast_force_N"] == 0.0


def test_modifications_that_eat_the_backlash_are_refused_before_meshing(tmp_path, capsys):
    """A lead slope adds half its value at one face end of each flank: 150 um on the pinion
    leaves 14 um of case 1's 89 um normal backlash on the sun mesh's coast flanks, 500 um
    would start them 152 um inside each other (a set that cannot be assembled, which used to
    solve with the coast flanks interfering from the start). Refused with the mesh, the
    overlap and the backlash, by the command line with exit 2 before anything is meshed."""
    import dataclasses

    from studies.console import main
    from studies.position import check_coast_backlash, study_scene

    gb = load_study_case("1-GB")
    for slope, bad in ((150.0, False), (500.0, True)):
        study = dataclasses.replace(gb, gearset=_set({"pinion": {"lead_slope_um": slope}}))
        if not bad:
            check_coast_backlash(study, study_scene(study, 0.0))
            continue
        with pytest.raises(CaseError, match=r"coast flanks of mesh sun-pinion start 15\d um"):
            check_coast_backlash(study, study_scene(study, 0.0))
    from cases.gearset import GEARSET_DIR

    text = (GEARSET_DIR / "case1.toml").read_text().replace('name = "case1"', 'name = "sloped"')
    (tmp_path / "sloped.toml").write_text(
        text + "\n[gears.pinion.modifications]\nlead_slope_um = 500.0\n"
    )
    case = tmp_path / "sloped_case.toml"
    own = (GEARSET_DIR.parent / "1-GB.toml").read_text()
    case.write_text(own.replace('gearset = "case1"', 'gearset = "sloped.toml"'))
    assert main(["run", str(case), "--level", "0", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "start 15" in err and "Traceback" not in err
    assert not (tmp_path / "out" / "1-GB" / "positions").exists()
