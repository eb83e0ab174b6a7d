"""singh2007 Fig. 6 and Table 6: the parametric double pinion misalignment study.

Table 6 uses the paper's stated FA R = 133 N m exactly, so the only tolerance is the
printed rounding: half a unit (1 N m, 0.01 for ratios, 1 deg for angles).
"""

import math

import numpy as np
import pytest
from paper_sets import paper_inputs

from gears.analytic import double_pinion as dp
from gears.analytic import parametric, planetary, printed
from gears.analytic import single_pinion as sp

ANGLES = parametric.TABLE6_PRESSURE_ANGLES_DEG


@pytest.fixture(scope="module")
def rows():
    return {row["pressure_angle"]: row for row in parametric.table6(parametric.FA_R_PAPER)}


@pytest.fixture(scope="module")
def cases():
    return paper_inputs()


@pytest.fixture(scope="module")
def my_case1(cases):
    g = planetary.single_pinion_geometry(cases[0])
    return sp.concentrated_load(cases[0].torque_per_branch, g)["My_pin"]


@pytest.mark.parametrize("paper", printed.SINGH_TABLE6, ids=lambda p: f"{p['pressure_angle']}")
def test_table6_worst_moment_and_angles(rows, paper):
    row = rows[paper["pressure_angle"]]
    # Worst moment printed to 1 N m: half a unit (30 deg gives 133 x 1.5 = 199.5 exactly, on
    # the rounding boundary, printed 199).
    assert abs(row["worst_moment"] - paper["worst_moment"]) <= 0.5 + 1e-9
    # Angles are exact closed forms (90 + a, 2a, 90 - a), printed as integers: round-off.
    for key in ("worst_theta", "equiv_theta", "worst_phi"):
        assert row[key] == pytest.approx(paper[key], abs=1e-9)


def test_table6_single_column_follows_my_case1_not_133(rows, my_case1):
    # The stated single equivalent 2 FA R sin(a) with FA R = 133 gives 68.85, 90.98, 112.42,
    # 133.00; printed 68, 90, 112, 132: 15, 20 and 30 deg are off by 0.85-1.0, beyond the 0.5
    # rounding. The printed column is My-PIN(case 1) sin(a) = 2 (FA R_mean) sin(a) with
    # FA R_mean = 132.14 N m (68.40, 90.39, 111.69, 132.14): all within 0.5 + torque rounding.
    expected = {15.0: 68.85, 20.0: 90.98, 25.0: 112.42, 30.0: 133.00}
    off = []
    for paper in printed.SINGH_TABLE6:
        a = paper["pressure_angle"]
        assert rows[a]["single_moment"] == pytest.approx(expected[a], abs=0.005)
        if abs(rows[a]["single_moment"] - paper["single_moment"]) > 0.5:
            off.append(a)
        alt = my_case1 * math.sin(math.radians(a))
        assert abs(alt - paper["single_moment"]) <= 0.5 + 0.05 / 1378.7 * alt
    assert off == [15.0, 20.0, 30.0]


def test_table6_ratio_column(rows):
    # (1 + sin a) / (2 sin a) = 2.4319, 1.9619, 1.6831, 1.5000; printed 2.44, 1.97, 1.69,
    # 1.50. The formula is the paper's own and independent of FA R; the 15-25 deg entries
    # exceed it by 0.007-0.008 (beyond the 0.005 rounding), 30 deg agrees. See report note 5.
    expected = {15.0: 2.4319, 20.0: 1.9619, 25.0: 1.6831, 30.0: 1.5000}
    for paper in printed.SINGH_TABLE6:
        a = paper["pressure_angle"]
        assert rows[a]["ratio"] == pytest.approx(expected[a], abs=5e-5)
        assert rows[a]["ratio"] == pytest.approx(
            rows[a]["worst_moment"] / rows[a]["single_moment"], rel=1e-12
        )
        agrees = abs(rows[a]["ratio"] - paper["ratio"]) <= 0.005
        assert agrees == (a == 30.0)


def test_fa_r_from_case2_geometry(cases):
    # FA R = 133 is stated, not derived: FA times the case-2 radii gives 131.05 (SP-SUN),
    # 131.58 (SP-RP), 121.46 (RP-SP), 122.42 (RP-RING); only FA times the case-1 R_pR
    # (22.51 mm) rounds to 133 (133.23). Printed FA R to 1 N m: half a unit.
    fa = planetary.double_pinion_axial_forces(cases[1]).FzSUN
    g = planetary.double_pinion_geometry(cases[1])
    radii = (g.r_sp_sun, g.r_sp_rp, g.r_rp_sp, g.r_rp_ring)
    assert all(abs(fa * r * 1e-3 - parametric.FA_R_PAPER) > 0.5 for r in radii)
    r_pr = planetary.single_pinion_geometry(cases[0]).r_pin_ring
    assert fa * r_pr * 1e-3 == pytest.approx(parametric.FA_R_PAPER, abs=0.5)


@pytest.mark.parametrize("alpha_deg", ANGLES)
def test_closed_forms_match_table4_model(alpha_deg):
    # The reduced curves are Table 4 with equal radii and pressure angles: round-off only.
    a, r, fa = math.radians(alpha_deg), 22.0, 6000.0
    fz = dp.AxialForces.uniform(fa)
    for ang in np.radians([0.0, 30.0, 75.0, 110.0, 180.0]):
        g = dp.DoublePinionGeometry(r, r, r, r, a, a, a, ang, ang)
        m = dp.double_pinion_moments(fz, g)
        fa_r = fa * r * 1e-3
        assert m["M_LOA_SP_SUN"] == pytest.approx(parametric.m_sp_sun_loa(ang, a, fa_r), abs=1e-9)
        assert -m["M_LOA_RP_RING"] == pytest.approx(
            parametric.m_rp_ring_loa(ang, a, fa_r), abs=1e-9
        )


@pytest.mark.parametrize("alpha_deg", ANGLES)
def test_worst_and_equivalent_angles(alpha_deg):
    # Maxima on a 0.01 deg grid agree with 90 +- a to the grid step; the curve meets the
    # single pinion value at 2a and at 180 deg (theta) / 0 (phi): round-off only.
    a = math.radians(alpha_deg)
    grid = np.radians(np.arange(0.0, 180.0 + 1e-9, 0.01))
    th = grid[np.argmax(parametric.m_sp_sun_loa(grid, a, 1.0))]
    ph = grid[np.argmax(parametric.m_rp_ring_loa(grid, a, 1.0))]
    assert math.degrees(th) == pytest.approx(math.degrees(parametric.worst_theta(a)), abs=0.01)
    assert math.degrees(ph) == pytest.approx(math.degrees(parametric.worst_phi(a)), abs=0.01)
    single = parametric.single_equivalent(a, 1.0)
    for theta in (parametric.equivalent_theta(a), math.pi):
        assert parametric.m_sp_sun_loa(theta, a, 1.0) == pytest.approx(single, abs=1e-12)
    assert parametric.m_rp_ring_loa(0.0, a, 1.0) == pytest.approx(single, abs=1e-12)


def test_case2_worst_points(cases):
    # Section 6 text: worst / single about 1.88 at theta = 111 deg (sun-SP, a1 = 21.30 deg)
    # and about 1.78 at phi = 67 deg (RP-ring, a3 = 22.98 deg). Printed to 0.01 and 1 deg:
    # half a unit.
    g = planetary.double_pinion_geometry(cases[1])
    paper = printed.SINGH_CASE2_WORST
    assert parametric.worst_ratio(g.a1) == pytest.approx(paper["sun_SP"]["ratio"], abs=0.005)
    assert math.degrees(parametric.worst_theta(g.a1)) == pytest.approx(
        paper["sun_SP"]["angle"], abs=0.5
    )
    assert parametric.worst_ratio(g.a3) == pytest.approx(paper["RP_ring"]["ratio"], abs=0.005)
    assert math.degrees(parametric.worst_phi(g.a3)) == pytest.approx(
        paper["RP_ring"]["angle"], abs=0.5
    )
