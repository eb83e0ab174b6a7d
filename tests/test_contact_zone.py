"""The zone contact model (issue 11 items 2-3): the numerics switch, the grid over the whole
potential contact zone (solvers.flank_grid.zone_grid) and its FE link. Geometry only (no FE)."""

import math

import numpy as np
import pytest

from cases.gearset import CaseError
from cases.study_case import (
    DEFAULTS,
    Numerics,
    inputs_hash,
    load_study_case,
    parse_study_case,
    read_toml,
)
from gears.material import STEEL
from gears.microgeometry import FlankModifications
from gears.profile import involute_deviation
from meshing import mesh_zones, scenes
from solvers.flank_grid import (
    CORNER_A,
    CORNER_B,
    DESIGN_CONTACT_STRESS,
    flank_contact_pairs,
    flank_grid,
    pair_contact_modulus,
    zone_grid,
)

UM = 1e-3
STUDY = load_study_case("1-GA")
#: the study's plane-strain modulus E / (1 - nu^2) and the pair's contact modulus (two gears)
E_PLANE = STUDY.material.gear_youngs_modulus / (1 - STUDY.material.poisson_ratio**2)
ES = E_PLANE / 2


@pytest.fixture(scope="module")
def scene():
    return scenes.build_scene("one_branch", STUDY.gearset, 0.0)


# ------------------------------------------------------------------ numerics switch
def test_contact_model_defaults_and_validation():
    assert (DEFAULTS.contact_model, DEFAULTS.zone_gap_limit_um) == ("zone", 40.0)
    assert Numerics(contact_model="zone", zone_gap_limit_um=25).zone_gap_limit_um == 25.0
    with pytest.raises(
        CaseError,
        match=r"numerics\.contact_model = 'hertz': must be one of "
        r"'line', 'zone'",
    ):
        Numerics(contact_model="hertz")
    for bad in (0.5, 501, math.nan, "40", True):
        with pytest.raises(
            CaseError,
            match=r"numerics\.zone_gap_limit_um = .*: must be a "
            r"number in \[1, 500\] um",
        ):
            Numerics(zone_gap_limit_um=bad)


def test_contact_model_is_read_and_hashed():
    raw = read_toml(STUDY.path)
    assert raw["numerics"]["contact_model"] == "zone"  # the shipped case spells it out
    raw["numerics"] = {**raw["numerics"], "contact_model": "line"}
    line = parse_study_case(raw, "1-GA.toml", STUDY.path)
    assert line.numerics.contact_model == "line" and STUDY.numerics.contact_model == "zone"
    assert inputs_hash(line) != inputs_hash(STUDY)
    raw["numerics"]["contact_model"] = "patch"
    with pytest.raises(CaseError, match=r"1-GA\.toml: numerics\.contact_model = 'patch'"):
        parse_study_case(raw, "1-GA.toml", STUDY.path)


# ------------------------------------------------------------------ the zone grid
@pytest.mark.parametrize("zi", [0, 1])
def test_zone_grid_lies_on_the_driver_flank_within_the_gap_limit(scene, zi):
    zn = scene.zones[zi]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    grid, info, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=40 * UM, e_star=ES)
    # every point on the driver's exact flank (the turned plane-of-action construction)
    dev = involute_deviation(drv.gear, drv.placement.inverse(grid.x_a), zn.driver_side)
    assert np.abs(dev).max() < 1e-9
    # x_b on the driven flank
    dev_b = involute_deviation(dvn.gear, dvn.placement.inverse(grid.x_b), zn.driven_side)
    assert np.abs(dev_b).max() < 1e-9
    assert np.all(grid.gap0 < 40 * UM) and np.all(grid.gap0 > -1e-9)
    # far more points than the contact-line grid, every one within a tooth pair's rows
    line, linfo = flank_grid(zn, drv, dvn, 0.7)
    assert grid.n > 5 * line.n
    rows = np.concatenate([np.arange(*ln["rows"]) for ln in info.lines])
    assert np.array_equal(rows, np.arange(grid.n))
    # the tooth pairs in the path are there, and contact beyond the path (tip and corner
    # contact of the pairs entering and leaving) is covered where g0 < the limit
    in_path = {ln["driver_tooth"] for ln in linfo.lines}
    zone_teeth = {ln["driver_tooth"] for ln in info.lines}
    assert in_path <= zone_teeth
    assert sum(ln["length"] for ln in info.lines) > 1.1 * sum(ln["length"] for ln in linfo.lines)


def _flank_normal(pg, side, x, e=1e-3):
    """The exact flank normal at points x on it: the gradient of the exact normal distance
    (involute_deviation, |grad| = 1), by the fourth-order central difference
    (8 (f(e) - f(-e)) - (f(2e) - f(-2e))) / (12 e). Its error: e^4 f^(5) / 30 with
    f^(5) ~ 1 / rho^4 (rho >= 2 mm here) is below 1e-14, the round-off of f (~1e-14 mm)
    times 18 / (12 e) about 1e-11; measured 2e-12 .. 6e-12 against the grids' normals."""

    def f(y):
        return involute_deviation(pg.gear, pg.placement.inverse(y), side)

    out = np.zeros_like(x)
    for c in range(3):
        d = np.zeros(3)
        d[c] = e
        out[:, c] = (8 * (f(x + d) - f(x - d)) - (f(x + 2 * d) - f(x - 2 * d))) / (12 * e)
    return out


def _on_cone_bisector(n_a, n_b):
    """The half turn about the axis from n_a to n_b (equal axial parts): the rule's bisector."""
    u = n_a[:, :2] + n_b[:, :2]
    u *= (np.hypot(n_a[:, 0], n_a[:, 1]) / np.hypot(u[:, 0], u[:, 1]))[:, None]
    return np.c_[u, n_a[:, 2]]


def test_involute_normal_is_the_gradient_of_the_exact_distance(scene):
    """gears.profile.involute_normal (analytic gradient) against the difference stencil of
    involute_deviation, on every flank of a zone (external sun/pinion and the internal
    ring), at points on and 0.05 mm off the flank: 1e-9 (the stencil's error ~1e-11)."""
    from gears.profile import involute_normal

    for zn in scene.zones:
        for name, side in ((zn.driver, zn.driver_side), (zn.driven, zn.driven_side)):
            pg = scene.gear(name)
            line, _ = flank_grid(zn, scene.gear(zn.driver), scene.gear(zn.driven), 0.7)
            for off in (0.0, 0.05):
                x = line.x_a + off * line.normals
                loc = involute_normal(pg.gear, pg.placement.inverse(x), side)
                c, s = math.cos(pg.placement.angle), math.sin(pg.placement.angle)
                glob = np.c_[
                    c * loc[:, 0] - s * loc[:, 1], s * loc[:, 0] + c * loc[:, 1], loc[:, 2]
                ]
                assert np.abs(glob - _flank_normal(pg, side, x)).max() < 1e-9


@pytest.mark.parametrize("zi", [0, 1])
@pytest.mark.parametrize("flanks", ["drive", "coast"])
def test_zone_grid_normals_follow_the_corner_rule(scene, zi, flanks):
    """The contact normal of every zone cell (solvers.flank_grid.contact_normals): where the
    cell reaches the driver's tip circle the driven flank's exact normal (a tip corner on a
    smooth flank), where it reaches the driven tip the driver's, elsewhere the bisector of
    the two on their common cone; each flank normal is the gradient of its exact normal
    distance (involute_deviation), so the rule holds to 1e-9 (the stencil's error ~1e-11,
    see _flank_normal). The coarse points keep the driver's normal. Off the contact line
    the two flank normals differ by several degrees (a grid with one normal throughout,
    or with the wrong flank's at a corner, would fail)."""
    zn = scene.zones[zi]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    view = zn if flanks == "drive" else mesh_zones.coast_zone(zn, drv, dvn)
    grid, info, link = zone_grid(view, drv, dvn, 0.7, gap_limit=40 * UM, e_star=ES)
    line, _ = flank_grid(view, drv, dvn, 0.7)
    n_a = _flank_normal(drv, view.driver_side, grid.x_a)
    n_b = -_flank_normal(dvn, view.driven_side, grid.x_a)  # out of the driven flank, negated
    tip_a, tip_b = info.corner == CORNER_A, info.corner == CORNER_B
    assert tip_a.any() and tip_b.any() and (info.corner == 0).sum() > 0.8 * grid.n
    assert np.abs(grid.normals[tip_a] - n_b[tip_a]).max() < 1e-9
    assert np.abs(grid.normals[tip_b] - n_a[tip_b]).max() < 1e-9
    mid = ~(tip_a | tip_b)
    assert np.abs(grid.normals[mid] - _on_cone_bisector(n_a, n_b)[mid]).max() < 1e-9
    c = link.coarse
    assert np.abs(_flank_normal(drv, view.driver_side, c.x_a) - c.normals).max() < 1e-9
    for g in (grid, c):
        # the gap is measured along it: x_b = x_a + dev_B n_k on the driven flank, g0 =
        # dev_A + dev_B (no modifications here), dev_A ~1e-14 mm (x_a on the driver flank)
        assert np.allclose(g.x_b - g.x_a, g.gap0[:, None] * g.normals, rtol=0, atol=1e-12)
        dev_b = involute_deviation(dvn.gear, dvn.placement.inverse(g.x_b), view.driven_side)
        assert np.abs(dev_b).max() < 1e-9
        # the nominal normal: the plane of action's, the line grid's (one normal, exact n)
        assert np.allclose(line.normals, line.nominal_normal, rtol=0, atol=1e-15)
        assert np.array_equal(g.nominal_normal, line.nominal_normal)
    # off the line the flank normals are turned about the axis by several degrees, by
    # different amounts (the same n_z); at a driver tip corner the driven normal is used
    turn = np.degrees(np.arccos(np.clip(n_a @ grid.nominal_normal, -1.0, 1.0)))
    assert turn.max() > 3.0
    apart = np.degrees(np.arccos(np.clip(np.sum(n_a * n_b, axis=1), -1.0, 1.0)))
    assert apart.max() > 1.0
    assert np.abs(grid.normals[:, 2] - grid.nominal_normal[2]).max() < 1e-12
    # on the line (the coarse points of the pairs in the path, g0 at its smallest) n_q = n
    # up to the vertex refinement of the centre (measured < 3e-6 rad)
    on = np.abs(c.gap0 - c.gap0.min()) < 1e-9
    assert on.sum() >= line.n - 4
    assert np.abs(c.normals[on] - c.nominal_normal).max() < 1e-5


def test_zone_grid_is_centred_and_graded_on_the_contact_line(scene):
    zn = scene.zones[0]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    grid, _, link = zone_grid(zn, drv, dvn, 0.7, e_star=ES)
    line, _ = flank_grid(zn, drv, dvn, 0.7)
    # on a pair in the path the section's centre (coarse point) is on the theoretical line:
    # g0 = 0 there (perfect involutes), and the cell there is the narrowest of its section
    c = link.coarse
    on_line = np.abs(c.gap0) < 1e-9
    assert on_line.sum() >= line.n - 4  # the line grid's segments, ends aside
    # the finest cell: half the Hertz semi-width at the design stress, R the relative radius
    e_star = STEEL.youngs_modulus / (2 * (1 - STEEL.poisson_ratio**2))
    assert ES == pytest.approx(e_star, rel=1e-15)  # 1-GA is steel
    dv = 2 * link.half[:, 1]
    fin = dv[np.abs(link.plane[:, 1] - link.plane_coarse[link.parent, 1]) < 1e-9]
    a_h_max = 2 * 60.0 * DESIGN_CONTACT_STRESS / e_star  # R < 60 mm for these gears
    assert fin.max() <= 0.5 * a_h_max
    assert dv.max() <= 0.35 + 1e-12  # at most half the coarse spacing
    # the separation grows away from the line (parabola s^2 / (2R))
    for sec in np.flatnonzero(on_line)[:5]:
        k = np.flatnonzero(link.parent == sec)
        v = link.plane[k, 1] - link.plane_coarse[sec, 1]
        g = grid.gap0[k]
        assert np.all(np.diff(g[v >= 0]) > 0) and np.all(np.diff(g[v <= 0]) < 0)


def test_zone_grid_gap_limit_and_modifications(scene):
    zn = scene.zones[0]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    narrow, _, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=10 * UM, e_star=ES)
    wide, _, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=40 * UM, e_star=ES)
    # sqrt(2 R g): about half the profile extent at a quarter of the limit
    assert 0.3 < narrow.n / wide.n < 0.7
    mods = {drv.gear_name: FlankModifications(lead_crown_um=20.0)}
    crowned, cinfo, _ = zone_grid(
        zn, drv, dvn, 0.7, modifications=mods, gap_limit=40 * UM, e_star=ES
    )
    # a lead crown lifts every section's separation by the same amount across the section,
    # and the band is measured from each section's smallest: the same cells as without it
    # (a band measured from zero would lose the face ends); the modification enters g0
    assert crowned.n == wide.n
    assert np.abs(crowned.x_a - wide.x_a).max() < 1e-9
    assert np.all(crowned.gap0 - cinfo.reference < 40 * UM)
    assert np.all(crowned.gap0 >= cinfo.mod_a - 1e-12)
    z = crowned.x_a[:, 2]
    b = drv.gear.face_width
    assert cinfo.mod_a == pytest.approx(20 * UM * (2 * z / b) ** 2, abs=1e-12)


def _e_plane(scene, e=E_PLANE):
    return {g.name: e for g in scene.gears}


def test_pairs_switch_between_line_and_zone(scene):
    _, line_pairs = flank_contact_pairs(scene, 0.7, None, None)
    grids, zone_pairs = flank_contact_pairs(
        scene, 0.7, None, None, contact_model="zone", e_plane=_e_plane(scene)
    )
    assert all(p.link is None for p in line_pairs)
    # drive and coast flanks zoned; the coast pairs standby (open by the backlash) as before
    assert all(p.link is not None for p in zone_pairs)
    assert [p.standby for p in zone_pairs] == [p.standby for p in line_pairs]
    assert [p.standby for p in zone_pairs] == [False, False, True, True]
    assert all(info.fallback is None for _, info in grids.values())
    with pytest.raises(ValueError, match="contact_model = 'x': must be 'line' or 'zone'"):
        flank_contact_pairs(scene, 0.7, None, None, contact_model="x")
    # no silent steel: the zone model needs the bodies' moduli
    with pytest.raises(ValueError, match=r"contact_model = 'zone' needs e_plane"):
        flank_contact_pairs(scene, 0.7, None, None, contact_model="zone")
    with pytest.raises(ValueError, match=r"e_star = -1\.0 must be a finite number > 0"):
        zone_grid(scene.zones[0], *(scene.gear(n) for n in ("sun", "pinion")), 0.7, e_star=-1.0)


def test_pair_contact_modulus_is_the_penalty_one():
    # 1/E* = sum 1/E' over the pair's bodies (solvers.contact forms it so for the penalty)
    assert pair_contact_modulus({"a": 2.0e5, "b": 1.0e5}, "a", "b") == pytest.approx(
        1 / (1 / 2.0e5 + 1 / 1.0e5), rel=1e-15
    )
    # a rigid obstacle adds no compliance (1 / (1 / E') to round-off)
    assert pair_contact_modulus({"a": 2.0e5}, "a", "wall") == pytest.approx(2.0e5, rel=1e-15)
    with pytest.raises(ValueError, match="pair a-b: no finite plane-strain modulus"):
        pair_contact_modulus({"a": 0.0}, "a", "b")


# ------------------------------------------------------------------ coast flanks (zone)
def _coast(scene, zi):
    zn = scene.zones[zi]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    return zn, mesh_zones.coast_zone(zn, drv, dvn), drv, dvn


@pytest.mark.parametrize("zi", [0, 1])
def test_coast_zone_grid_on_the_coast_flanks(scene, zi):
    zn, cz, drv, dvn = _coast(scene, zi)
    grid, info, link = zone_grid(cz, drv, dvn, 0.7, gap_limit=40 * UM, e_star=ES)
    line, linfo = flank_grid(cz, drv, dvn, 0.7)
    j_n = STUDY.gearset.meshes[zi].normal_backlash
    assert grid.name == cz.name and info.flanks == "coast" and link.coarse.n > 0
    # on the driver's exact coast flank; x_b on the driven coast flank
    for pg, x, side in ((drv, grid.x_a, cz.driver_side), (dvn, grid.x_b, cz.driven_side)):
        assert np.abs(involute_deviation(pg.gear, pg.placement.inverse(x), side)).max() < 1e-9
    # its smallest g0 is the line grid's, the normal backlash: on perfect involutes the coast
    # separation along the contact line is j_n, and the central cell sits on that line up to
    # the vertex refinement of the sampled separation (dv ~ 1e-5 mm, dv^2 / 2R ~ 1e-11 mm);
    # 1e-9 mm as for the drive grid's coarse points (measured ~1e-14 mm). Nothing is closer
    # (the ray along the plane of action's normal is no shorter than the normal distance).
    assert np.abs(line.gap0 - j_n).max() < 1e-12
    assert abs(grid.gap0.min() - line.gap0.min()) < 1e-9
    assert grid.gap0.min() > j_n - 1e-12
    # the band: within the limit of the section's smallest separation (j_n here)
    assert grid.gap0.max() < j_n + 40 * UM
    assert grid.gap0.max() > j_n + 30 * UM  # the band does reach out to about the limit
    # the coast contact lines' tooth pairs are all there, with the line grid's driven teeth
    pairs = {(ln["driver_tooth"], ln["driven_tooth"]) for ln in info.lines}
    assert {(ln["driver_tooth"], ln["driven_tooth"]) for ln in linfo.lines} <= pairs
    # every section of the face has cells, both face ends included (where a tilt closes the
    # backlash first): the outermost section centres lie half a section inside the face
    b = min(drv.gear.face_width, dvn.gear.face_width)
    z = grid.x_a[:, 2]
    n_sec = len(np.unique(np.round(z, 9)))
    dz = b / n_sec
    assert z.min() == pytest.approx(-b / 2 + dz / 2, abs=1e-9)
    assert z.max() == pytest.approx(b / 2 - dz / 2, abs=1e-9)
    # as many points as the drive zone grid, to within a few cells: the mirror image
    drive, _, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=40 * UM, e_star=ES)
    assert abs(grid.n - drive.n) < 0.05 * drive.n


def test_zone_grids_keep_the_face_ends_under_a_crown(scene):
    """A lead crown larger than the gap limit (60 um against 40): both zone grids, drive and
    coast, hold the cells of every section within the limit of that section's smallest
    separation, so the face ends, which the crown opens and a tilt closes again, stay on
    the grid (a limit measured from zero on the drive flanks drops every section beyond
    |z| = 0.82 bs/2, where the crown passes 40 um, and the test fails there). Each
    section's smallest g0 is the crown there (drive) or the backlash plus it (coast), and
    FlankGridInfo.reference holds it per cell."""
    zn, cz, drv, dvn = _coast(scene, 0)
    crown = 60.0
    mods = {drv.gear_name: FlankModifications(lead_crown_um=crown)}
    kw = dict(modifications=mods, gap_limit=40 * UM, e_star=ES)
    b = min(drv.gear.face_width, dvn.gear.face_width)  # the crown is over the sun's face
    bs = drv.gear.face_width
    j_n = STUDY.gearset.meshes[0].normal_backlash
    for view, g_min in ((zn, 0.0), (cz, j_n)):
        grid, info, _ = zone_grid(view, drv, dvn, 0.7, **kw)
        z = grid.x_a[:, 2]
        assert z.max() > 0.95 * b / 2 and z.min() < -0.95 * b / 2, view.flanks
        assert info.gap_limit == pytest.approx(40 * UM, rel=1e-15)
        assert np.all(grid.gap0 - info.reference < 40 * UM + 1e-9)
        for zs in np.unique(np.round(z, 9))[[0, -1]]:
            k = np.abs(z - zs) < 1e-9
            expect = g_min + crown * UM * (2 * zs / bs) ** 2
            assert grid.gap0[k].min() == pytest.approx(expect, abs=1e-9), view.flanks
            # the reference is the section's sampled minimum (ZONE_SAMPLES over the profile,
            # ~0.015 mm apart): above the true one by at most (0.0075 mm)^2 / (2 R) with
            # R > 3 mm, i.e. < 1e-5 mm (measured 2e-7 mm)
            assert np.all(info.reference[k] >= expect - 1e-12), view.flanks
            assert info.reference[k] == pytest.approx(expect, abs=1e-5), view.flanks


def test_coast_zone_falls_back_to_its_line_grid(scene, monkeypatch):
    """No coast cell within reach (here forced: zone_grid refuses the coast views): the coast
    flanks keep their contact-line grid (standby, penalty), and the info says why."""
    import solvers.flank_grid as fg

    real = fg.zone_grid

    def refuse_coast(zone, *a, **kw):
        if zone.flanks == "coast":
            raise ValueError(f"zone {zone.name}: no flank point within 40 um")
        return real(zone, *a, **kw)

    monkeypatch.setattr(fg, "zone_grid", refuse_coast)
    with pytest.warns(UserWarning, match="coast flanks keep their contact-line grid"):
        grids, pairs = fg.flank_contact_pairs(
            scene, 0.7, None, None, contact_model="zone", e_plane=_e_plane(scene)
        )
    coast = [p for p in pairs if p.standby]
    assert len(coast) == 2 and all(p.link is None for p in coast)
    for p in coast:
        line, _ = flank_grid(
            _coast(scene, 0 if "sun" in p.grid.name else 1)[1],
            scene.gear(p.body_a),
            scene.gear(p.body_b),
            0.7,
        )
        assert np.array_equal(p.grid.x_a, line.x_a)
        assert "no flank point within 40 um" in grids[p.grid.name][1].fallback
    assert all(p.link is not None for p in pairs if not p.standby)  # no fallback on drive


def test_zone_cells_follow_the_contact_modulus(scene):
    """The central cell is d0 = R p_d / E* (eq. (2)): half the contact modulus (an E half
    the study's) doubles it wherever the clip [0.01, h / 2] leaves it free, and the band
    holds fewer, wider cells."""
    zn = scene.zones[0]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    out = {}
    for name, es in (("steel", ES), ("soft", ES / 2)):
        grid, _, link = zone_grid(zn, drv, dvn, 0.7, gap_limit=40 * UM, e_star=es)
        centre = np.abs(link.plane[:, 1] - link.plane_coarse[link.parent, 1]) < 1e-12
        d0 = np.full(link.coarse.n, np.nan)
        d0[link.parent[centre]] = 2 * link.half[centre, 1]
        out[name] = (grid, link, d0)
    (g1, l1, d1), (g2, l2, d2) = out["steel"], out["soft"]
    # the same sections (the limit, not the cells, decides which sections are kept)
    assert np.array_equal(l1.plane_coarse, l2.plane_coarse)
    # free of the clip: d0 within [0.01, 0.35 / 2] mm for steel, so <= 0.35 mm when soft;
    # there the ratio is E*_steel / E*_soft = 2 to round-off (the edges are sums of cells)
    # (and a centre cell in both: a wider centre cell cut by the tip circle is not centred)
    free = (d1 > 0.0101) & (d1 < 0.17) & np.isfinite(d2)
    assert free.sum() > 0.5 * l1.coarse.n
    assert d2[free] / d1[free] == pytest.approx(np.full(free.sum(), 2.0), rel=1e-9)
    assert g2.n < g1.n
