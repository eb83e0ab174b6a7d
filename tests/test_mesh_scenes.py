"""Scenes: placement and phase on exact geometry, scene meshes, pictures, bad scenes.

The assembly checks use the exact involute helicoids (``involute_deviation``), not the
mesh: on the theoretical contact lines the mating drive flanks must touch, elsewhere be
apart, and the coast flanks must be the pair's backlash apart.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cases.gearset import load_gearset
from gears.pair import default_normal_backlash
from gears.profile import involute_deviation
from meshing import gmsh_util, mesh_zones, scenes
from meshing import tags as T
from meshing.build import scene_mesh_file
from meshing.sizing import MeshingError

CONTACT_TOL = 1e-4  # mm = 0.1 um (issue); measured ~1e-13 mm (closed-form phase)
NODE_TOL = 0.5e-3  # mm: mesh nodes on the exact helicoid (same bound as the body tests)

CASE1, CASE2 = load_gearset("case1"), load_gearset("case2")
SCENE_MAKERS = {
    "case1-branch": lambda: scenes.build_scene("one_branch", CASE1, 0.0),
    "case1-branch-roll": lambda: scenes.build_scene("one_branch", CASE1, 0.05),
    "case1-all": lambda: scenes.build_scene("all_planets", CASE1, 0.0),
    "case2-branch": lambda: scenes.build_scene("one_branch", CASE2, 0.0),
}


@pytest.fixture(scope="module")
def all_scenes():
    return {k: f() for k, f in SCENE_MAKERS.items()}


def _zones(all_scenes):
    for key, sc in all_scenes.items():
        for zn in sc.zones:
            yield key, sc, zn


@pytest.mark.parametrize("coast", [False, True], ids=["drive", "coast"])
def test_flanks_touch_on_contact_lines(all_scenes, coast):
    n_zones = 0
    for key, sc, zn in _zones(all_scenes):
        drv, dvn = sc.gear(zn.driver), sc.gear(zn.driven)
        side_a, side_b = zn.coast_sides if coast else (zn.driver_side, zn.driven_side)
        lines = mesh_zones.contact_lines(zn, drv, dvn, coast=coast)
        # transverse contact ratio ~1.5-1.9 plus overlap ratio ~1.1: 3-4 teeth in contact
        assert 2 <= len(lines) <= 5, f"{key} {zn.driver}/{zn.driven}: {len(lines)} lines"
        gap = mesh_zones.normal_backlash(zn, drv) if coast else 0.0
        for _, _, pts in lines:
            on_a = involute_deviation(drv.gear, drv.placement.inverse(pts), side_a)
            on_b = involute_deviation(dvn.gear, dvn.placement.inverse(pts), side_b)
            assert np.abs(on_a).max() < CONTACT_TOL  # the points are on the driver flank
            # ... and the mate is the backlash away (0 on the drive side), within 0.1 um
            assert np.abs(on_b - gap).max() < CONTACT_TOL, f"{key} {zn.driver}/{zn.driven}"
        n_zones += 1
    assert n_zones == 2 + 2 + 6 + 3


def test_drive_flanks_apart_elsewhere_and_no_interpenetration(all_scenes):
    for key, sc, zn in _zones(all_scenes):
        drv, dvn = sc.gear(zn.driver), sc.gear(zn.driven)
        sep = scenes.flank_separation(zn, drv, dvn, n_r=21, n_z=21)
        # Grid points off the contact lines: strictly positive separation (the exact
        # formula is accurate to ~1e-13 mm, so -1e-9 mm only allows round-off) ...
        assert sep["min_drive"] > -1e-9, f"{key} {zn.driver}/{zn.driven}: {sep}"
        assert sep["min_coast"] > -1e-9, f"{key} {zn.driver}/{zn.driven}: {sep}"
        # ... and the closest grid point is within a grid cell of touching (< 5 um).
        assert sep["min_drive"] < 5e-3


def test_backlash_is_the_specified_one(all_scenes):
    """The shifts close the centre distances; the thickness allowances leave the gear set's
    normal backlash (default: ISO/TR 10064-2, gears.pair.default_normal_backlash), which the
    coast flanks show on exact geometry (0.1 um: the sampling of flank_separation)."""
    for _, sc, zn in _zones(all_scenes):
        drv, dvn = sc.gear(zn.driver), sc.gear(zn.driven)
        j_n = mesh_zones.normal_backlash(zn, drv)
        expected = default_normal_backlash(zn.centre_distance, drv.gear.normal_module)
        assert j_n == pytest.approx(expected, abs=1e-7)
        sep = mesh_zones.flank_separation(zn, drv, dvn)
        assert sep["min_coast"] == pytest.approx(j_n, abs=1e-4)
        assert zn.driver_side in ("pos", "neg") and zn.driven_side in ("pos", "neg")


def test_drive_flank_convention(all_scenes):
    sc = all_scenes["case1-branch"]
    (z1, z2) = sc.zones
    # sun turns CCW: its +theta flank drives the pinion's +theta flank (same unwinding);
    # the pinion's -theta flank drives the ring's +theta flank (internal mesh)
    assert (z1.driver, z1.driver_side, z1.driven_side) == ("sun", "pos", "pos")
    assert (z2.driver, z2.driver_side, z2.driven_side) == ("pinion", "neg", "pos")
    assert sc.gear("pinion").omega == -1
    rep = sc.report()
    assert rep["left_out"] and rep["mesh_zones"][0]["drive_flanks"] == {
        "sun": "pos",
        "pinion": "pos",
    }


def test_case2_triangle(all_scenes):
    sc = all_scenes["case2-branch"]
    c_sp = np.array(sc.gear("SP").placement.centre)
    c_rp = np.array(sc.gear("RP").placement.centre)
    # centre distances of the case file to 1e-9 mm (pure trigonometry)
    assert math.isclose(np.linalg.norm(c_sp), 51.945, abs_tol=1e-9)
    assert math.isclose(np.linalg.norm(c_rp - c_sp), 42.750, abs_tol=1e-9)
    assert math.isclose(np.linalg.norm(c_rp), 58.600, abs_tol=1e-9)
    psi = math.degrees(math.atan2(c_rp[1], c_rp[0]))
    assert math.isclose(psi, 45.002, abs_tol=5e-4)  # paper prints 45.002 deg (3 decimals)


def test_all_branches_planet_angles(all_scenes):
    sc = all_scenes["case1-all"]
    angles = [
        math.degrees(math.atan2(*np.array(g.placement.centre)[::-1])) % 360
        for g in sc.gears
        if g.name.startswith("pinion")
    ]
    step = 360.0 / 121  # assembly condition: multiples of 360 / (z_sun + z_ring)
    for a in angles:
        assert abs(a / step - round(a / step)) < 1e-9
    assert max(abs(a - e) for a, e in zip(sorted(angles), (0, 120, 240), strict=True)) < step


STUDY_SCENES = [
    ("1-GB", "one_branch"),
    ("1-GA", "all_planets"),
    ("1-GA", "system"),
    ("2B-GA", "one_branch"),
    ("2B-GA", "all_planets"),
]


@pytest.mark.parametrize("case, kind", STUDY_SCENES, ids=[f"{c}-{k}" for c, k in STUDY_SCENES])
def test_positions_of_a_study_share_the_body_meshes(case, kind):
    """Every position of a study (the case's positions and 12, over one base pitch) gives
    the same body mesh cache keys (so one factorization serves them all,
    solvers.body_store): the refined teeth, sectors and fine fillets are the union over the
    mesh cycle, not the teeth in contact at the position. (With the cycle sampled at five
    angles the all-planet scenes of 1-GA and 2B-GA changed a pinion or the ring from one
    position to the next.) The fine fillets are the tension fillets (drive side) of every
    tooth in contact at every position, on refined teeth."""
    from cases.study_case import load_study_case
    from meshing import cache
    from meshing.body_cache import body_params
    from studies.position import roll_angles

    study = load_study_case(case)
    for n in sorted({study.model.positions, 12}):
        keys, fine_here = set(), {}
        for roll in roll_angles(study, n):
            sc = scenes.build_scene(kind, study.gearset, roll, fine_fillets=True)
            keys.add(
                tuple(cache.key("body", body_params(g.body, 1, g.active_teeth)) for g in sc.gears)
            )
            for zn in sc.zones:
                for k, j, _ in zn.contact_lines:
                    fine_here.setdefault(zn.driver, set()).add((k, zn.driver_side))
                    fine_here.setdefault(zn.driven, set()).add((j, zn.driven_side))
        assert len(keys) == 1, f"{case} {kind}, {n} positions: the body meshes change"
        for g in sc.gears:
            fine = set(g.body.fine_fillets)
            assert fine_here[g.name] <= fine
            assert {k for k, _ in fine} <= set(g.active_teeth)
            sides = {zn.driver_side for zn in sc.zones if zn.driver == g.name}
            sides |= {zn.driven_side for zn in sc.zones if zn.driven == g.name}
            assert {s for _, s in fine} <= sides  # drive-side (tension) fillets only


def test_planets_in_phase_get_the_same_bodies_up_to_labels():
    """parker2000-3: three planets in phase (Z_sun + Z_ring = 126, 3 | 27) see the same
    contact over the mesh cycle, so they get as many refined teeth and fine fillets each.
    (With the placements wrapped into one pitch the wrap fell at another sun angle for each
    planet and the union held both labels of a tooth for some: 5, 5 and 4 fine fillets.)"""
    from cases.study_case import load_study_case

    sc = scenes.build_scene(
        "all_planets", load_study_case("parker2000-3").gearset, 0.0, fine_fillets=True
    )
    planets = [sc.gear(n) for n in sc.pinion_names]
    assert len({len(g.body.fine_fillets) for g in planets}) == 1
    assert len({len(g.active_teeth) for g in planets}) == 1


@pytest.mark.parametrize(
    "kind, option, refined",
    [
        ("one_branch", None, True),
        ("all_planets", None, False),
        ("system", None, False),
        ("one_branch", False, False),
        ("all_planets", True, True),
    ],
)
def test_scenes_refine_the_root_fillets_of_the_global_model(kind, option, refined):
    """One branch names the cycle's tension fillets; the all-planet and system scenes name
    none by default (every fillet at fillet_far: the root stress read on submodels only;
    numerics.root_fillets), and say so in their notes. Same teeth refined either way: only
    the fillets differ."""
    sc = scenes.build_scene(kind, CASE1, 0.0, fine_fillets=option)
    assert scenes.refines_root_fillets(sc) is refined
    fine = [g.body.fine_fillets for g in sc.gears]
    assert all(f == () for f in fine) is (not refined)
    assert any("root stress only on submodels" in n for n in sc.notes) is (not refined)
    other = scenes.build_scene(kind, CASE1, 0.0, fine_fillets=not refined)
    assert [g.active_teeth for g in other.gears] == [g.active_teeth for g in sc.gears]


def test_teeth_in_mesh_are_refined(all_scenes):
    for sc in all_scenes.values():
        for g in sc.gears:
            assert set(g.contact_teeth) <= set(g.active_teeth) <= set(g.body.teeth)
            if not g.body.full:  # sector: a buffer tooth beyond the refined ones
                assert len(g.body.teeth) >= len(g.active_teeth) + 2


@pytest.mark.parametrize(
    "kwargs, match",
    [
        # beyond the 89 um normal backlash of case 1 (ISO/TR 10064-2 default)
        ({"pinion_radial_offset": -0.15}, "interpenetrate"),
        ({"pinion_radial_offset": 0.2}, "interpenetrate"),
        ({"phase_offsets": {"pinion": 2e-4}}, "interpenetrate"),
        ({"phase_offsets": {"pinion": -5e-3}}, "interpenetrate"),
        ({"phase_offsets": {"planet": 0.1}}, "unknown bodies"),
        ({"roll": float("nan")}, "roll"),
    ],
)
def test_bad_scene_fails_before_gmsh(monkeypatch, kwargs, match):
    import gmsh

    monkeypatch.setattr(gmsh, "initialize", lambda *a, **k: pytest.fail("gmsh was called"))
    with pytest.raises(MeshingError, match=match):
        sc = scenes.branch_scene(CASE1, **kwargs)
        scene_mesh_file(sc, 0)


def test_unknown_scene_is_refused():
    with pytest.raises(MeshingError, match="must be one of one_branch, all_planets"):
        scenes.build_scene("three_branches", CASE1, 0.0)


@pytest.fixture(scope="module")
def case1_mesh(all_scenes):
    sc = all_scenes["case1-branch"]
    path, meta = scene_mesh_file(sc, 0)
    return sc, path, meta, gmsh_util.group_nodes(path)


def test_scene_mesh_groups_and_volume(case1_mesh):
    sc, _path, meta, nodes = case1_mesh
    for g in sc.gears:
        assert T.volume(g.name) in nodes
        for k in g.body.teeth:
            for kind in T.TOOTH_KINDS:
                assert len(nodes[T.tooth(g.name, k, kind)]) > 0
    assert not [n for n in nodes if T.parse(n).kind == T.OTHER]
    assert meta["min_sicn"] >= 0.15  # level 0 minimum (see test_mesh_bodies.MIN_SICN)
    vols = [b["volume"] for b in meta["bodies"].values()]
    assert math.isclose(meta["volume"], sum(vols), rel_tol=1e-12)


def test_scene_mesh_placed_flanks(case1_mesh):
    """Scene-frame nodes of the drive flanks in contact, taken back to each body frame, lie
    on that body's exact helicoid; and no driver drive-flank node is inside the mate."""
    sc, _, _, nodes = case1_mesh
    for zn in sc.zones:
        drv, dvn = sc.gear(zn.driver), sc.gear(zn.driven)
        for g, side in ((drv, zn.driver_side), (dvn, zn.driven_side)):
            for k in g.contact_teeth:
                xyz = g.placement.inverse(nodes[T.flank(g.name, k, side)])
                assert np.abs(involute_deviation(g.gear, xyz, side)).max() < NODE_TOL
        for k in drv.contact_teeth:
            xyz = dvn.placement.inverse(nodes[T.flank(drv.name, k, zn.driver_side)])
            r = np.hypot(xyz[:, 0], xyz[:, 1])
            lo, hi = sorted((dvn.gear.form_radius, dvn.gear.tip_radius))
            keep = (r > lo) & (r < hi)
            if keep.any():
                sep = involute_deviation(dvn.gear, xyz[keep], zn.driven_side)
                # nodes sit on the exact surface to < 0.5 um, so none may be further inside
                assert sep.min() > -NODE_TOL


def test_scene_picture(case1_mesh, tmp_path):
    from meshing.pictures import scene_picture

    _, path, _, _ = case1_mesh
    png = scene_picture(path, tmp_path / "scene.png", "case1-branch level 0")
    assert png.stat().st_size > 20_000  # a real two-view image, not an empty canvas


def test_scene_cache_reused(case1_mesh, all_scenes):
    sc, path, _, _ = case1_mesh
    path2, meta2 = scene_mesh_file(sc, 0)
    assert path2 == path and meta2["cached"]


def test_case2_scene_mesh(all_scenes):
    sc = all_scenes["case2-branch"]
    path, meta = scene_mesh_file(sc, 0)
    names = set(gmsh_util.group_nodes(path))
    assert {"sun", "SP", "RP", "ring"} <= names
    for zn in sc.zones:
        for g, side in ((sc.gear(zn.driver), zn.driver_side), (sc.gear(zn.driven), zn.driven_side)):
            assert {T.flank(g.name, k, side) for k in g.contact_teeth} <= names
    assert meta["min_sicn"] >= 0.15  # level 0 minimum


def test_sun_bore_follows_a_small_sun():
    """A sun smaller than the case suns gets a bore that leaves SUN_RIM_MODULES modules of
    rim under its root circle (before: a fixed 15 mm bore, refused for a small sun); the
    case suns keep the 15 mm bore (their meshes are unchanged)."""
    import copy

    from cases.gearset import load_gearset, parse_gearset
    from meshing.gear_body import GearBody

    case1 = load_gearset("case1")
    assert scenes.sun_bore_radius(case1.gears["sun"]) == scenes.SUN_BORE_RADIUS
    src = copy.deepcopy(case1.source)
    src["common"]["normal_module"] = 0.8
    for m in src["meshes"]:  # the centre distances scale with the module
        m["centre_distance"] *= 0.8 / 1.59
    small = parse_gearset(src, "case1 at module 0.8")
    sun = small.gears["sun"]
    r = scenes.sun_bore_radius(sun)
    assert r == pytest.approx(sun.root_radius - scenes.SUN_RIM_MODULES * 0.8)
    assert r < scenes.SUN_BORE_RADIUS
    GearBody(sun, inner_radius=r)  # valid: no MeshingError
