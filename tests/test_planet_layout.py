"""Default planet angles (gears.analytic.phasing.assemblable_angles) and the all-planet
scene that uses them: equal spacing when it assembles, else parker2000's paired layout
(diametrically opposed pairs) when the tooth numbers allow it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cases.gearset import load_gearset
from gears.analytic import phasing as ph
from meshing.scenes import build_scene

STEP = 360.0 / 126  # deg, assemblable step of parker2000 (Zs + Zr = 126)


def test_parker_four_planets_default_to_opposed_pairs():
    # 126 / 4 = 31.5: no equal spacing; 126 even: pi = 63 steps, so pairs assemble.
    psi = ph.assemblable_angles(27, 99, 4)
    assert ph.planet_layout(27, 99, 4) == "opposed pairs"
    assert np.degrees(psi) == pytest.approx([0.0, 32 * STEP, 180.0, 95 * STEP], abs=1e-9)
    assert ph.is_diametrically_opposed(psi)
    for l in range(1, 13):  # the opposed-pairs rule holds on the default angles
        odd = l * 27 % 2 == 1
        assert not ph.is_zero(ph.net_force_amplitude(l, 27, psi), 4) == odd
        assert not ph.is_zero(ph.net_torque_amplitude(l, 27, psi), 4) == (not odd)


@pytest.mark.parametrize(
    ("zs", "zr", "n", "double", "layout", "steps"),
    [
        (27, 99, 3, False, "equally spaced", [0, 42, 84]),
        (20, 100, 4, False, "equally spaced", [0, 30, 60, 90]),
        (27, 99, 6, False, "equally spaced", [0, 21, 42, 63, 84, 105]),
        (35, 92, 3, True, "equally spaced", [0, 19, 38]),
        (21, 101, 6, False, "opposed pairs", [0, 20, 41, 61, 81, 102]),
        (35, 86, 3, False, "nearest to equal spacing", [0, 40, 81]),  # N odd
        (35, 86, 4, False, "nearest to equal spacing", [0, 30, 60, 91]),  # S = 121 odd
    ],
)
def test_default_layouts(zs, zr, n, double, layout, steps):
    s = ph.assembly_steps(zs, zr, double)
    psi = ph.assemblable_angles(zs, zr, n, double)
    assert ph.planet_layout(zs, zr, n, double) == layout
    assert psi * s / (2 * math.pi) == pytest.approx(steps, abs=1e-9)  # whole steps: assembles
    assert ph.is_diametrically_opposed(psi) == (layout != "nearest to equal spacing" and n % 2 == 0)


def test_four_planet_scene_default_is_paired_and_says_so():
    sc = build_scene("all_planets", load_gearset("parker2000-4"), 0.0)
    centres = [sc.gear(p).placement.centre for p in sc.pinion_names]
    got = np.radians([math.degrees(math.atan2(c[1], c[0])) % 360 for c in centres])
    assert ph.is_diametrically_opposed(got, tol=1e-9)
    assert np.degrees(got) == pytest.approx([0.0, 32 * STEP, 180.0, 95 * STEP], abs=1e-9)
    assert any("opposed pairs" in note for note in sc.notes)


def test_pinion_centres_keep_the_centre_distances():
    """gears.layout.pinion_centres (the scenes' branch_centres and the gear set's clearance
    check): case 2's SP on a1, its RP on a3 and a2 from the SP, on the side rp_side asks for;
    a radial offset moves the SP alone."""
    from gears.layout import pinion_centres

    a1, a2, a3 = (m.centre_distance for m in load_gearset("case2").meshes)
    for psi in (0.0, 1.0, 4.2):
        for side in (1, -1):
            sp, rp = (np.asarray(c) for c in pinion_centres([a1, a2, a3], psi, side, 0.1))
            assert np.linalg.norm(sp) == pytest.approx(a1 + 0.1, rel=1e-14)
            assert np.linalg.norm(rp) == pytest.approx(a3, rel=1e-14)
            sp0 = np.asarray(pinion_centres([a1, a2, a3], psi, side)[0])
            assert np.linalg.norm(rp - sp0) == pytest.approx(a2, rel=1e-12)
            cross = sp[0] * rp[1] - sp[1] * rp[0]  # > 0: RP counter-clockwise of SP
            assert np.sign(cross) == side


@pytest.mark.parametrize("name", ["case1", "case2"])
def test_the_shipped_sets_clear_by_their_hand_computed_gaps(name):
    """The smallest clearance of the shipped sets, by hand: case 1's nearest planets (0 and
    40 of Zs + Zr = 121 assembly steps, 119.008 deg: 121 has no thirds) are 2 a sin(40 pi /
    121) apart, less two tip radii; case 2's SP clears the ring's tip circle by r_a,ring - a1
    - r_a,SP."""
    from gears.layout import layout_clearances

    gs = load_gearset(name)
    path = [gs.gears[p] for p in gs.power_path]
    a = [m.centre_distance for m in gs.meshes]
    angles = ph.assemblable_angles(path[0].teeth, path[-1].teeth, gs.planets, len(path) == 4)
    clear = dict(layout_clearances(gs.power_path, [g.tip_radius for g in path], a, angles))
    if name == "case1":
        gap = 2 * a[0] * math.sin(40 * math.pi / 121) - 2 * path[1].tip_radius
        assert min(clear.values()) == pytest.approx(gap, rel=1e-12)
    else:
        gap = path[-1].tip_radius - a[0] - path[1].tip_radius
        assert min(clear.values()) == clear["SP and ring"] == pytest.approx(gap, rel=1e-12)
