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
from meshing import scenes
from solvers.flank_grid import (
    DESIGN_CONTACT_STRESS,
    flank_contact_pairs,
    flank_grid,
    zone_grid,
)

UM = 1e-3
STUDY = load_study_case("1-GA")


@pytest.fixture(scope="module")
def scene():
    return scenes.build_scene("one_branch", STUDY.gearset, 0.0)


# ------------------------------------------------------------------ numerics switch
def test_contact_model_defaults_and_validation():
    assert (DEFAULTS.contact_model, DEFAULTS.zone_gap_limit_um) == ("line", 40.0)
    assert Numerics(contact_model="zone", zone_gap_limit_um=25).zone_gap_limit_um == 25.0
    with pytest.raises(CaseError, match=r"numerics\.contact_model = 'hertz': must be one of "
                                        r"'line', 'zone'"):  # fmt: skip
        Numerics(contact_model="hertz")
    for bad in (0.5, 501, math.nan, "40", True):
        with pytest.raises(CaseError, match=r"numerics\.zone_gap_limit_um = .*: must be a "
                                            r"number in \[1, 500\] um"):  # fmt: skip
            Numerics(zone_gap_limit_um=bad)


def test_contact_model_is_read_and_hashed():
    raw = read_toml(STUDY.path)
    raw["numerics"] = {**raw["numerics"], "contact_model": "zone"}
    zone = parse_study_case(raw, "1-GA.toml", STUDY.path)
    assert zone.numerics.contact_model == "zone"
    assert inputs_hash(zone) != inputs_hash(STUDY)
    raw["numerics"]["contact_model"] = "patch"
    with pytest.raises(CaseError, match=r"1-GA\.toml: numerics\.contact_model = 'patch'"):
        parse_study_case(raw, "1-GA.toml", STUDY.path)


# ------------------------------------------------------------------ the zone grid
@pytest.mark.parametrize("zi", [0, 1])
def test_zone_grid_lies_on_the_driver_flank_within_the_gap_limit(scene, zi):
    zn = scene.zones[zi]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    grid, info, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=40 * UM)
    # every point on the driver's exact flank (the turned plane-of-action construction)
    dev = involute_deviation(drv.gear, drv.placement.inverse(grid.x_a), zn.driver_side)
    assert np.abs(dev).max() < 1e-9
    # x_b on the driven flank
    dev_b = involute_deviation(dvn.gear, dvn.placement.inverse(grid.x_b), zn.driven_side)
    assert np.abs(dev_b).max() < 1e-9
    assert np.all(grid.gap0 < 40 * UM) and np.all(grid.gap0 > -1e-9)
    # the normal is the plane of action's, within 10 degrees of the flank normal at the
    # zone's edges (v / rho, v <= 1.1 mm near the form circle, rho >= 8 mm): a small step
    # along it changes the driver's deviation by cos(angle) times the step
    eps = 1e-4
    step = involute_deviation(drv.gear, drv.placement.inverse(grid.x_a + eps * grid.normals),
                              zn.driver_side)  # fmt: skip
    assert np.all(step > eps * math.cos(math.radians(10))) and np.all(step < eps * (1 + 1e-6))
    assert np.allclose(grid.normals, grid.normals[0], atol=1e-15)
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


def test_zone_grid_is_centred_and_graded_on_the_contact_line(scene):
    zn = scene.zones[0]
    drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
    grid, _, link = zone_grid(zn, drv, dvn, 0.7)
    line, _ = flank_grid(zn, drv, dvn, 0.7)
    # on a pair in the path the section's centre (coarse point) is on the theoretical line:
    # g0 = 0 there (perfect involutes), and the cell there is the narrowest of its section
    c = link.coarse
    on_line = np.abs(c.gap0) < 1e-9
    assert on_line.sum() >= line.n - 4  # the line grid's segments, ends aside
    # the finest cell: half the Hertz semi-width at the design stress, R the relative radius
    e_star = STEEL.youngs_modulus / (2 * (1 - STEEL.poisson_ratio**2))
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
    narrow, _, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=10 * UM)
    wide, _, _ = zone_grid(zn, drv, dvn, 0.7, gap_limit=40 * UM)
    # sqrt(2 R g): about half the profile extent at a quarter of the limit
    assert 0.3 < narrow.n / wide.n < 0.7
    mods = {drv.gear_name: FlankModifications(lead_crown_um=20.0)}
    crowned, cinfo, _ = zone_grid(zn, drv, dvn, 0.7, modifications=mods, gap_limit=40 * UM)
    # the crown opens the face ends: fewer points there, and the modification enters g0
    assert crowned.n < wide.n
    assert np.all(crowned.gap0 >= cinfo.mod_a - 1e-12)
    z = crowned.x_a[:, 2]
    b = drv.gear.face_width
    assert cinfo.mod_a == pytest.approx(20 * UM * (2 * z / b) ** 2, abs=1e-12)


def test_pairs_switch_between_line_and_zone(scene):
    _, line_pairs = flank_contact_pairs(scene, 0.7, None, None)
    _, zone_pairs = flank_contact_pairs(scene, 0.7, None, None, contact_model="zone")
    assert all(p.link is None for p in line_pairs)
    # drive flanks zoned, coast flanks (open by the backlash) on their lines
    assert [p.link is not None for p in zone_pairs] == [not p.standby for p in zone_pairs]
    with pytest.raises(ValueError, match="contact_model = 'x': must be 'line' or 'zone'"):
        flank_contact_pairs(scene, 0.7, None, None, contact_model="x")
