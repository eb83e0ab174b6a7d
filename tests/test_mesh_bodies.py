"""Gear body meshes: exact flanks and fillets, volume, named groups, quality, cache, errors.

Bodies are the case 1 gears (shifts from the case file) at level 0 (CI), sectors of 3
teeth, plus the full pinion and one level-1 sector; each is built once per session (and
cached on disk across sessions, keyed by its parameters and the meshing sources).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cases.gearset import load_gearset
from gears.profile import fillet_deviation, gear_outline, involute_deviation, tooth_profile
from meshing import body_geometry as gbm
from meshing import gmsh_util, sizing
from meshing import tags as T
from meshing.body_cache import body_mesh_file
from meshing.carrier import carrier_mesh_file, carrier_spec
from meshing.gear_body import GearBody
from meshing.sizing import MeshingError

# Stated bounds.
FLANK_TOL = 0.5e-3  # mm: the aim for mesh nodes on the exact helicoid / trochoid
# Minimum SICN per level (the stated floor, sizing.MIN_SICN = 0.15 at every level): HXT
# gives 0.19-0.35 on these bodies (levels 0-2, measured); below the floor the builder runs
# the Netgen optimiser, so a body under it is a meshing failure.
MIN_SICN = dict.fromkeys(range(len(sizing.LEVELS)), sizing.MIN_SICN)


def _case1():
    from cases.gearset import load_gearset

    return load_gearset("case1").gears


def _body(name: str, n_teeth: int | None, first: int = 0) -> GearBody:
    g = _case1()[name]
    if g.internal:
        return GearBody(g, first_tooth=first, n_teeth=n_teeth, outer_radius=g.root_radius + 5.0)
    bore = 11.0 if name == "pinion" else 15.0
    return GearBody(g, first_tooth=first, n_teeth=n_teeth, inner_radius=bore)


BODIES = {
    # key: (gear, n_teeth, first tooth, level, active teeth)
    "pinion-sector-L0": ("pinion", 3, 0, 0, None),
    "pinion-sector-L1": ("pinion", 3, 0, 1, None),
    "sun-sector-L0": ("sun", 3, 34, 0, None),
    "ring-sector-L0": ("ring", 3, 85, 0, None),
    "pinion-full-L0": ("pinion", None, 0, 0, [0, 1, 25]),
    "ring-full-L0": ("ring", None, 0, 0, []),
    "pinion-sector-L2": ("pinion", 2, 5, 2, None),
}


@pytest.fixture(scope="module")
def built():
    """key -> (GearBody, level, msh path, meta, group nodes)."""
    out = {}
    for key, (name, n, first, level, active) in BODIES.items():
        gb = _body(name, n, first)
        path, meta = body_mesh_file(gb, level, active)
        out[key] = (gb, level, path, meta, gmsh_util.group_nodes(path))
    return out


@pytest.mark.parametrize("key", list(BODIES))
def test_flank_nodes_on_exact_helicoid(built, key):
    gb, _, _, _meta, nodes = built[key]
    worst = 0.0
    n_groups = 0
    for name, xyz in nodes.items():
        p = T.parse(name)
        if p.kind in (T.FLANK_POS, T.FLANK_NEG):
            side = p.kind.split("_")[1]
            worst = max(worst, float(np.abs(involute_deviation(gb.gear, xyz, side)).max()))
            n_groups += 1
    assert n_groups == 2 * len(gb.teeth)
    # Bound: the 0.5 um aim; measured 0.01 um (9 loft sections, 20 involute points
    # with exact end tangents), so 0.5 um also catches a wrong helix sense or amount (a
    # mirrored twist is off by ~mm at the ends).
    assert worst < FLANK_TOL, f"{key}: flank node deviation {worst * 1e3:.4f} um"


@pytest.mark.parametrize("key", list(BODIES))
def test_fillet_nodes_on_trochoid(built, key):
    gb, _, _, _, nodes = built[key]
    worst = 0.0
    for name, xyz in nodes.items():
        p = T.parse(name)
        if p.kind in (T.FILLET_POS, T.FILLET_NEG):
            side = p.kind.split("_")[1]
            worst = max(worst, float(np.abs(fillet_deviation(gb.gear, xyz, side)).max()))
    # Same bound as the flanks (issue); measured below 0.01 um (fillet + half root land).
    assert worst < FLANK_TOL, f"{key}: fillet node deviation {worst * 1e3:.4f} um"


@pytest.mark.parametrize("name", ["pinion", "ring"])
def test_fillet_meets_flank_tangentially(name):
    """Along the edge shared by each fillet and its flank, the CAD surface normals agree."""
    gb = _body(name, 2)
    worst = 0.0
    with gmsh_util.session("tangency") as gm:
        vol = gbm.build_geometry(gm, gb)
        groups = gbm.classify_surfaces(gm, gb, vol)
        for k in gb.teeth:
            for side in ("pos", "neg"):
                (fl,) = groups[T.flank(gb.body, k, side)]
                (fi,) = groups[T.fillet(gb.body, k, side)]
                edges = [
                    {abs(c) for _, c in gm.model.getBoundary([(2, f)], oriented=False)}
                    for f in (fl, fi)
                ]
                (c,) = edges[0] & edges[1]
                lo, hi = gm.model.getParametrizationBounds(1, c)
                xyz = np.asarray(gm.model.getValue(1, c, np.linspace(lo[0], hi[0], 15)))
                normals = []
                for f in (fl, fi):
                    uv = gm.model.getParametrization(2, f, xyz)
                    normals.append(np.asarray(gm.model.getNormal(f, uv)).reshape(-1, 3))
                cos = np.abs(np.sum(normals[0] * normals[1], axis=1))
                worst = max(worst, float(np.arccos(np.clip(cos.min(), -1.0, 1.0))))
    # Both splines end with the exact involute tangent; measured 3e-8 rad. 1e-5 rad is a
    # kink 100x below anything a linear mesh could show (element edge turns ~0.1 rad).
    assert worst < 1e-5, f"{name}: fillet/flank normals differ by {worst:.2e} rad"


def _polygon_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _section_area(gb: GearBody) -> float:
    """Independent transverse area from the dense numpy profile (not from gmsh)."""
    g = gb.gear
    prof = tooth_profile(g, 400, 400)
    if gb.full:
        r_in = gb.outer_radius if g.internal else gb.inner_radius
        teeth = _polygon_area(gear_outline(prof, 256))
        return abs(math.pi * r_in**2 - teeth)
    one = prof.outline(256)
    pitch = 2 * math.pi / g.teeth
    pts = []
    for k in gb.teeth:
        c, s = math.cos(k * pitch), math.sin(k * pitch)
        pts.append(one @ np.array([[c, s], [-s, c]]))
    a_neg, a_pos = gb.cut_angles
    r_in = gb.outer_radius if g.internal else gb.inner_radius
    arc = np.linspace(a_pos, a_neg, 2001)
    pts.append(r_in * np.c_[np.cos(arc), np.sin(arc)])
    return _polygon_area(np.vstack(pts))


@pytest.mark.parametrize(
    "key", ["pinion-full-L0", "ring-full-L0", "ring-sector-L0", "sun-sector-L0"]
)
def test_volume_against_section_area(built, key):
    gb, _, _, meta, _ = built[key]
    expected = _section_area(gb) * gb.gear.face_width
    rel = meta["volume"] / expected - 1.0
    # Issue bound 0.5 %; the helix does not change the volume of a prism twisted about
    # its axis, so area x face width is exact. Measured -0.02 % (full pinion, level 0):
    # chords of the convex flanks and tips against concave fillets and bore.
    assert abs(rel) < 5e-3, f"{key}: mesh volume {meta['volume']:.2f} vs {expected:.2f}"


def _expected_names(gb: GearBody) -> set[str]:
    names = {T.volume(gb.body), T.surface(gb.body, T.END_ZPOS), T.surface(gb.body, T.END_ZNEG)}
    names.add(T.surface(gb.body, T.RIM if gb.gear.internal else T.BORE))
    if not gb.full:
        names |= {T.surface(gb.body, T.CUT_POS), T.surface(gb.body, T.CUT_NEG)}
    for k in gb.teeth:
        names |= {T.tooth(gb.body, k, kind) for kind in T.TOOTH_KINDS}
    return names


@pytest.mark.parametrize("key", list(BODIES))
def test_named_groups_complete_and_nonempty(built, key):
    gb, _, _, _meta, nodes = built[key]
    assert set(nodes) == _expected_names(gb)  # exactly the table's names, no "other"
    empty = [n for n, xyz in nodes.items() if len(xyz) == 0]
    assert not empty


@pytest.mark.parametrize("key", list(BODIES))
def test_quality(built, key):
    _, level, _path, meta, _ = built[key]
    # minSICN > 0 excludes inverted and degenerate tets; the level's stated minimum above.
    assert meta["min_sicn"] >= MIN_SICN[level], f"{key}: min SICN {meta['min_sicn']:.3f}"
    assert meta["element_types"] == [4]  # linear tets only


def test_dolfinx_tags_match_gmsh(built):
    """Serial conversion keeps every group: facet counts equal the gmsh triangle counts."""
    from mpi4py import MPI

    from meshing.to_dolfinx import global_facet_counts, global_volume, load_msh

    gb, _, path, meta, nodes = built["pinion-sector-L0"]
    bundle = load_msh(path, MPI.COMM_SELF, meta=meta)
    assert set(bundle.names) == set(nodes)
    counts = global_facet_counts(bundle)
    assert all(c > 0 for c in counts.values())
    # Same tets, so the volumes agree to round-off (1e-10 relative).
    assert math.isclose(global_volume(bundle, gb.body), meta["volume"], rel_tol=1e-10)


def test_cache_reuses_the_mesh(built):
    gb, level, path, _, _ = built["pinion-sector-L0"]
    path2, meta2 = body_mesh_file(gb, level)
    assert path2 == path and meta2["cached"]


def test_fillet_refinement_changes_the_cache_key(built, monkeypatch):
    """A fillet-only refinement (sizing.with_fillet) is a different mesh: another cache key
    (the key holds the Level's sizes), so a changed size never returns the cached mesh of
    another size; the same refinement asked twice is the same key."""
    from meshing import cache

    gb, level, path, meta, _ = built["pinion-sector-L0"]
    fine = sizing.with_fillet(level, 0.3)
    path2, meta2 = body_mesh_file(gb, fine)
    assert path2 != path and meta2["params"]["level"]["fillet"] == 0.3
    # a finer fillet strip: more elements (the base level's fillet is 0.6 mm)
    assert meta2["elements"] > meta["elements"]
    seen = []

    def key_only(kind, params, *args, **kwargs):
        seen.append(cache.key(kind, params))

    monkeypatch.setattr(cache, "get_or_build", key_only)
    for lv in (level, fine, sizing.with_fillet(level, 0.2), sizing.with_fillet(level, 0.3)):
        body_mesh_file(gb, lv)
    assert len(set(seen[:3])) == 3 and seen[3] == seen[1]


def test_fine_fillets_refine_only_the_named_fillets(built):
    """GearBody.fine_fillets: only the named fillet of an active tooth gets the level's
    fillet size, its neighbour on the same tooth keeps fillet_far; the field enters the
    cache key, and a body without it keeps the key it had (no "fine_fillets" parameter)."""
    gb, _, _, _, _ = built["pinion-sector-L0"]
    one = GearBody(gb.gear, first_tooth=0, n_teeth=3, inner_radius=11.0, fine_fillets=((1, "pos"),))
    assert "fine_fillets" not in gb.params() and one.params()["fine_fillets"] == ((1, "pos"),)
    lv = sizing.with_fillet(0, 0.3)
    path, _ = body_mesh_file(one, lv)
    assert path != body_mesh_file(gb, lv)[0]
    nodes = gmsh_util.group_nodes(path)
    pos, neg = (len(nodes[T.fillet(one.body, 1, s)]) for s in ("pos", "neg"))
    # 0.3 mm across against fillet_far = 1.0 mm: about 3x the nodes (2x is a safe floor)
    assert pos > 2 * neg, (pos, neg)


@pytest.mark.parametrize("entry", [(5, "pos"), (1, "up"), (True, "pos"), "1pos"])
def test_bad_fine_fillets_fail_before_gmsh(no_gmsh, entry):
    g = _case1()["pinion"]
    gb = GearBody(g, inner_radius=11.0, n_teeth=3, fine_fillets=(entry,))
    with pytest.raises(MeshingError, match="fine_fillets entry"):
        body_mesh_file(gb, 0)


@pytest.mark.parametrize(
    "change, match",
    [
        ({"fillet": 0.0}, "level.fillet = 0.0"),
        ({"fillet": float("nan")}, "level.fillet = nan"),
        ({"coarse": -1.0}, "level.coarse"),
        ({"per_circle": 4}, "level.per_circle = 4"),
        ({"per_circle": 64.0}, "level.per_circle = 64.0"),
    ],
)
def test_bad_level_sizes_fail_before_gmsh(no_gmsh, change, match):
    from dataclasses import replace

    g = _case1()["pinion"]
    lv = replace(sizing.LEVELS[0], **change)
    with pytest.raises(MeshingError, match=match):
        body_mesh_file(GearBody(g, inner_radius=11.0, n_teeth=3), lv)


@pytest.fixture
def no_gmsh(monkeypatch):
    """Make any use of gmsh fail loudly: errors must come before gmsh runs."""
    import gmsh

    def boom(*a, **k):
        raise AssertionError("gmsh was called")

    monkeypatch.setattr(gmsh, "initialize", boom)
    monkeypatch.setattr(gmsh.model, "add", boom)


@pytest.mark.parametrize(
    "kwargs, level, match",
    [
        ({"n_teeth": 0}, 0, "n_teeth = 0"),
        ({"n_teeth": 14}, 0, "n_teeth = 14"),
        ({"first_tooth": 26}, 0, "first_tooth"),
        ({"n_sections": 3}, 0, "n_sections"),
        ({"inner_radius": 19.9}, 0, "inner_radius"),
        ({}, 5, "level = 5"),
        ({}, -1, "level = -1"),
        ({}, 1.0, "level = 1.0"),
    ],
)
def test_bad_input_fails_before_gmsh(no_gmsh, kwargs, level, match):
    g = _case1()["pinion"]
    args = {"inner_radius": 11.0, "n_teeth": 3, **kwargs}
    with pytest.raises(MeshingError, match=match):
        body_mesh_file(GearBody(g, **args), level)


def test_ring_needs_rim_radius(no_gmsh):
    g = _case1()["ring"]
    with pytest.raises(MeshingError, match="outer_radius"):
        body_mesh_file(GearBody(g, n_teeth=3), 0)


def test_tag_names():
    assert T.flank("pinion", 7, "pos") == "pinion/tooth07/flank_pos"
    assert T.fillet("ring", 85, "neg") == "ring/tooth85/fillet_neg"
    assert T.surface("sun", T.CUT_POS) == "sun/cut_pos"
    p = T.parse("SP/tooth12/flank_neg")
    assert (p.body, p.tooth, p.kind) == ("SP", 12, T.FLANK_NEG)
    assert T.parse("ring/rim").kind == T.RIM and T.parse("sun").kind is None
    with pytest.raises(ValueError):
        T.tooth("sun", 1, "flank")
    with pytest.raises(ValueError):
        T.volume("2sun")
    assert len(sizing.LEVELS) >= 4  # levels 0 to 3 at least (issue)


# --------------------------------------------------------------------------------------
# carrier
# --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def carrier():

    spec = carrier_spec(load_gearset("case1"))
    path, meta = carrier_mesh_file(spec, 0)
    return spec, path, meta, gmsh_util.group_nodes(path)


def test_carrier_groups_volume_quality(carrier):
    spec, _, meta, nodes = carrier
    n_pins = len(spec.pin_angles)
    expected = {T.CARRIER} | {T.carrier_surface(k) for k in T.CARRIER_KINDS}
    expected |= {T.pin(k) for k in range(n_pins)}
    assert set(nodes) == expected and all(len(v) for v in nodes.values())
    z_in, _ = spec.plate_z
    r_o, r_i, t = spec.plate_outer_radius, spec.plate_inner_radius, spec.plate_thickness
    exact = 2 * math.pi * (r_o**2 - r_i**2) * t  # two annular plates
    exact += n_pins * math.pi * (0.5 * spec.pin_diameter) ** 2 * 2 * z_in  # pins between
    exact += len(spec.post_angles()) * math.pi * spec.post_radius**2 * 2 * z_in  # posts
    # cylinders faceted by linear tets: 48+ segments a turn lose < 0.3 %; bound 0.5 %
    assert abs(meta["volume"] / exact - 1) < 5e-3
    assert meta["min_sicn"] >= MIN_SICN[0]  # stated level-0 minimum


def test_carrier_pin_surface_is_the_pin(carrier):
    spec, _, _, nodes = carrier
    for k, a in enumerate(spec.pin_angles):
        xyz = nodes[T.pin(k)]
        c = spec.pin_circle_radius * np.array([math.cos(a), math.sin(a)])
        r = np.hypot(xyz[:, 0] - c[0], xyz[:, 1] - c[1])
        # nodes on the exact cylinder (CAD) to round-off; between the plates only
        assert np.abs(r - 0.5 * spec.pin_diameter).max() < 1e-9
        assert np.abs(xyz[:, 2]).max() <= spec.plate_z[0] + 1e-9


@pytest.mark.parametrize(
    "field, value, match",
    [("pin_length", 10.0, "pin_length"), ("pin_diameter", 60.0, "pin_diameter")],
)
def test_carrier_bad_input(no_gmsh, field, value, match):
    from dataclasses import replace

    with pytest.raises(MeshingError, match=match):
        carrier_mesh_file(replace(carrier_spec(load_gearset("case1")), **{field: value}), 0)


def test_carrier_clears_the_gears(carrier):
    """No carrier node inside the space a case 1 gear occupies (tip cylinders over face
    widths) except the pins inside the pinion bores, which leave room for the needles."""
    from meshing import scenes

    spec, _, _, nodes = carrier
    xyz = nodes[T.CARRIER]
    gears = _case1()
    r = np.hypot(xyz[:, 0], xyz[:, 1])
    sun, ring = gears["sun"], gears["ring"]
    in_sun = (np.abs(xyz[:, 2]) < 0.5 * sun.face_width) & (r < sun.tip_radius)
    in_ring = (np.abs(xyz[:, 2]) < 0.5 * ring.face_width) & (r > ring.tip_radius)
    assert not in_sun.any() and not in_ring.any()
    bore = scenes.pinion_bore_radius(spec.pin_diameter)
    for a in spec.pin_angles:
        c = spec.pin_circle_radius * np.array([math.cos(a), math.sin(a)])
        d = np.hypot(xyz[:, 0] - c[0], xyz[:, 1] - c[1])
        in_pinion = (np.abs(xyz[:, 2]) < 0.5 * spec.pinion_face_width) & (
            d < gears["pinion"].tip_radius
        )
        # inside the pinion's tip cylinder only the pin, which is a needle diameter
        # (3 mm) clear of the bore
        assert (d[in_pinion] <= 0.5 * spec.pin_diameter + 1e-9).all()
        assert 0.5 * spec.pin_diameter < bore


def test_flank_check_sees_a_wrong_helix(built):
    """The flank test is sensitive to the helix: the same nodes measured against the
    opposite hand, or half the helix angle, are far off the helicoid."""
    from dataclasses import replace

    gb, _, _, _, nodes = built["pinion-sector-L0"]
    xyz = nodes[T.flank(gb.body, 0, "pos")]
    other_hand = replace(gb.gear, hand="right" if gb.gear.hand == "left" else "left")
    half_angle = replace(gb.gear, helix_angle=0.5 * gb.gear.helix_angle)
    for wrong in (other_hand, half_angle):
        # a wrong twist moves the end sections by ~0.1-0.2 rad x 20 mm: millimetres, so
        # 0.1 mm is a conservative floor
        assert np.abs(involute_deviation(wrong, xyz, "pos")).max() > 0.1


def test_a_mesh_does_not_depend_on_what_was_meshed_before():
    """gmsh's options are global to its session, which solvers.simple_meshes starts and leaves
    open: every mesher starts from the defaults, so a mesh is the same whatever ran before in
    the process. Before the fix a body-mesh session left the HXT mesher set and the roller
    of the contact tests came out with 4083 cells instead of 4809, and the Hertz test's peak
    pressure read +3.2 % on Hertz instead of +1.5 % (its bound 3 %): pass or fail by the order
    the tests ran in."""
    from mpi4py import MPI

    from solvers import simple_meshes as sm

    def roller_cells() -> int:
        r = sm.roller(
            MPI.COMM_SELF, 20.0, 10.0, 20.0 / 3, h_min=1.0, h_max=4.0, grade=0.3, plateau=2.0
        )
        return r.mesh.topology.index_map(3).size_local

    first = roller_cells()  # leaves gmsh initialized: the sessions below do not own it
    with gmsh_util.session("body-options") as g:
        gmsh_util.mesh_options(g)  # what a body mesh sets (HXT, optimise, one thread)
        g.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    assert roller_cells() == first
    with gmsh_util.session("next-body") as g:
        assert g.option.getNumber("Mesh.Algorithm3D") == 1  # gmsh's default (Delaunay)
        assert g.option.getNumber("Mesh.MeshSizeFromPoints") == 1


def test_a_curved_sector_has_its_edge_nodes_on_the_exact_surfaces(built):
    """geometry_order 2 (the root-stress sectors' option, meshing/submodel.py): 10-node tets,
    none inverted, whose edge nodes lie on the exact helicoid and trochoid like the vertices
    (within the same 0.5 um); an edge node on the straight chord instead would be off by the
    chord's sag, about h^2 / (8 R) = 50 um on a 0.45 mm fillet element of radius 0.5 mm."""
    from dataclasses import replace

    straight = built["pinion-sector-L0"]
    gb = replace(straight[0], geometry_order=2)
    path, meta = body_mesh_file(gb, 0)
    assert meta["element_types"] == [11] and meta["min_scaled_jacobian"] > 0.0
    nodes = gmsh_util.group_nodes(path)
    worst = {"flank": 0.0, "fillet": 0.0}
    counts = [0, 0]  # fillet nodes: curved, straight
    for name, xyz in nodes.items():
        p = T.parse(name)
        if p.kind in (T.FLANK_POS, T.FLANK_NEG):
            dev = involute_deviation(gb.gear, xyz, p.kind.split("_")[1])
            worst["flank"] = max(worst["flank"], float(np.abs(dev).max()))
        if p.kind in (T.FILLET_POS, T.FILLET_NEG):
            dev = fillet_deviation(gb.gear, xyz, p.kind.split("_")[1])
            worst["fillet"] = max(worst["fillet"], float(np.abs(dev).max()))
            counts[0] += len(xyz)
            counts[1] += len(straight[4][name])
    assert max(worst.values()) < FLANK_TOL, worst
    assert counts[0] > 3 * counts[1]  # the edge nodes are there (a triangle mesh: ~4x)
    with pytest.raises(MeshingError, match="geometry_order = 3: must be 1"):
        replace(gb, geometry_order=3).validate()
