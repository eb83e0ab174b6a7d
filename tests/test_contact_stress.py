"""Hertz line contact along an involute helical mesh (gears.contact_stress) and the
nominal ISO 6336-2 pitch-point contact stress it reduces to."""

import math

import numpy as np
import pytest

from cases.gearset import load_gearset
from gears.contact_stress import (
    contact_modulus,
    flank_curvatures,
    hertz_line_contact,
    iso6336_pitch_contact_stress,
    mesh_contact,
    nominal_line_load,
    path_of_contact,
    position_from_radius,
)
from gears.pair import GearPair
from gears.spec import GearSpec

COMMON = dict(normal_module=1.59, normal_pressure_angle=20.0, helix_angle=21.0)
TORQUE = 459.57e3  # N mm on the sun per mesh (singh2007.md section 1)


@pytest.fixture(scope="module")
def case1():
    """singh2007 case 1 meshes from cases/gearsets/case1.toml: (sun-pinion, pinion-ring)."""
    gs = load_gearset("case1")
    return gs.pair("sun", "pinion"), gs.pair("pinion", "ring")


def test_nafems_cylinder_on_plane():
    # NAFEMS-like Hertz benchmark (as in tests/test_solver_hertz.py): R = 50 mm on a plane,
    # E 210 GPa on 70 GPa, nu 0.3, 35 kN/mm -> a = 6.21 mm, p0 = 3585 MPa as printed:
    # tolerance half a unit of the last printed digit.
    e_star = contact_modulus(210e3, 0.3, 70e3, 0.3)
    b, p = hertz_line_contact(35e3, 50.0, e_star)
    assert b == pytest.approx(6.21, abs=0.005)
    assert p == pytest.approx(3585.0, abs=0.5)
    # the elliptic pressure carries the load: w = pi b p_max / 2
    assert math.pi * b * p / 2.0 == pytest.approx(35e3, rel=1e-12)


def test_steel_elasticity_factor():
    # ISO 6336-2: Z_E = 189.8 sqrt(MPa) for steel/steel, E = 206 GPa, nu = 0.3
    spur = dict(normal_module=2.0, normal_pressure_angle=20.0, helix_angle=0.0, face_width=20.0)
    pair = GearPair(GearSpec("p", 20, hand="R", **spur), GearSpec("g", 40, hand="L", **spur), 60.0)
    iso = iso6336_pitch_contact_stress(pair, 1e5, (206e3, 0.3), (206e3, 0.3))
    assert iso["Z_E"] == pytest.approx(189.8, abs=0.05)
    # Z_H = 2 / sqrt(sin(2 alpha)) = 2.495 for an unshifted 20 deg spur pair (ISO 6336-2 fig.)
    assert iso["Z_H"] == pytest.approx(2.495, abs=5e-4)
    assert iso["Z_eps"] == pytest.approx(math.sqrt((4.0 - pair.transverse_contact_ratio) / 3.0))
    assert iso["Z_beta"] == 1.0


def test_curvature_invariants(case1):
    ext, inn = case1
    for pair, sign in ((ext, 1.0), (inn, -1.0)):
        s0, s1 = path_of_contact(pair)
        s = np.linspace(s0, s1, 7)
        rho_t1, rho_t2, rho_n1, rho_n2, radius = flank_curvatures(pair, s)
        g = pair.centre_distance * math.sin(pair.operating_pressure_angle)
        # rho1 + rho2 = a sin(alpha_w) external; rho2 - rho1 = a sin(alpha_w) internal
        np.testing.assert_allclose(rho_t2 + sign * rho_t1, g, rtol=1e-13)
        cos_bb = math.cos(pair.gear1.base_helix_angle)
        np.testing.assert_allclose(rho_n1 * cos_bb, rho_t1, rtol=1e-14)
        np.testing.assert_allclose(1.0 / radius, 1.0 / rho_n1 + sign / rho_n2, rtol=1e-13)
        # the transverse radius on gear1 is the involute's roll length at its radius
        r1 = np.hypot(pair.gear1.base_radius, rho_t1)
        np.testing.assert_allclose(position_from_radius(pair, r1), s, atol=1e-12)
        # the tip-to-tip path agrees with the geometry module's path of contact
        assert s1 - s0 == pytest.approx(pair.path_of_contact_lengths[2], rel=1e-12)
        # pitch point: R = r_w1 sin(alpha_w) u / ((u + sign) cos(beta_b)), u = z2 / z1
        u = pair.gear2.teeth / pair.gear1.teeth
        r_w1 = pair.operating_pitch_radius(1)
        expect = r_w1 * math.sin(pair.operating_pressure_angle) * u / ((u + sign) * cos_bb)
        assert flank_curvatures(pair, 0.0)[4] == pytest.approx(expect, rel=1e-13)
    with pytest.raises(ValueError, match="line of action"):
        flank_curvatures(ext, -20.0)


def test_pitch_point_hertz_equals_iso(case1, capsys):
    for pair in case1:
        torque = TORQUE if pair.gear1.name == "sun" else TORQUE * 26 / 35  # pinion torque
        # one contact line across the face <-> Z_eps = Z_beta = 1
        w = nominal_line_load(pair, torque, "single")
        c = mesh_contact(pair, 0.0, w)
        iso = iso6336_pitch_contact_stress(pair, torque, z_eps=False, z_beta=False)
        assert c.p_max == pytest.approx(iso["sigma_H0"], rel=1e-9)
        # mean contact-line length b eps_alpha / cos(beta_b) <-> Z_eps = sqrt(1 / eps_alpha)
        assert pair.overlap_ratio >= 1.0
        w_mean = nominal_line_load(pair, torque, "mean")
        c_mean = mesh_contact(pair, 0.0, w_mean)
        iso_eps = iso6336_pitch_contact_stress(pair, torque, z_beta=False)
        assert c_mean.p_max == pytest.approx(iso_eps["sigma_H0"], rel=1e-9)
        full = iso6336_pitch_contact_stress(pair, torque)
        with capsys.disabled():
            print(
                f"\n{pair.gear1.name}-{pair.gear2.name} pitch point (steel 206 GPa, 0.3): "
                f"R = {c.radius:.4f} mm, w_single = {w:.1f} N/mm -> p_max = {c.p_max:.1f} MPa, "
                f"b = {c.half_width:.4f} mm; w_mean = {w_mean:.1f} N/mm -> p_max = "
                f"{c_mean.p_max:.1f} MPa; ISO sigma_H0 (Z_H {full['Z_H']:.4f}, Z_E "
                f"{full['Z_E']:.2f}, Z_eps {full['Z_eps']:.4f}, Z_beta {full['Z_beta']:.4f}) "
                f"= {full['sigma_H0']:.1f} MPa"
            )


def test_case1_forces(case1):
    ext, _ = case1
    # singh2007 Table 3: F_t = T / R_SUN = 15419 N (the sun mesh is at the standard distance)
    assert iso6336_pitch_contact_stress(ext, TORQUE)["F_t"] == pytest.approx(15419.0, abs=0.5)


def test_vectorised_positions(case1):
    ext, _ = case1
    s = np.linspace(*path_of_contact(ext), 5)
    c = mesh_contact(ext, s, 500.0)
    assert c.p_max.shape == s.shape and c.half_width.shape == s.shape
    for k in range(5):
        one = mesh_contact(ext, s[k], 500.0)
        assert one.p_max == pytest.approx(c.p_max[k], rel=1e-14)
