"""ISO 6336-3 method B nominal tooth root stress (gears.iso6336_root)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from cases.gearset import load_gearset
from gears.contact_stress import path_of_contact, pitch_roll
from gears.iso6336_root import (
    fillet_tangent_point,
    form_factors,
    helix_factor,
    nominal_root_stress,
)
from gears.pair import GearPair
from gears.spec import GearSpec

COMMON = dict(normal_module=1.59, normal_pressure_angle=20.0, helix_angle=21.0)
TORQUE = 459.57e3  # N mm on the sun per mesh (singh2007.md section 1)


def spur(z, x=0.0, m=1.0):
    """Spur gear on the ISO 53 profile A rack (h_fP = 1.25 m, rho_fP = 0.38 m, h_a = m)."""
    return GearSpec(
        "g",
        z,
        m,
        20.0,
        0.0,
        "R",
        10.0,
        profile_shift=x,
        dedendum_coef=1.25,
        hob_tip_radius_coef=0.38,
    )


@pytest.fixture(scope="module")
def case1():
    """singh2007 case 1 meshes from cases/gearsets/case1.toml: (sun-pinion, pinion-ring)."""
    gs = load_gearset("case1")
    return gs.pair("sun", "pinion"), gs.pair("pinion", "ring")


# Tip-load form and stress correction factors Y_Fa, Y_Sa of the standard textbook table for
# alpha_n = 20 deg, h_a* = 1, c* = 0.25, rho_fP = 0.38 m_n, x = 0 (GB/T 3480 = ISO 6336-3
# based table, e.g. Pu Lianggui, "Mechanical Design", table 10-5; values read off ISO 6336-3
# style charts, two to three significant digits). Tolerance 1 %: chart-reading precision
# (the table's own steps, e.g. 2.62 -> 2.52 from z 25 -> 30, are 4 %).
TEXTBOOK_TIP = {
    17: (2.97, 1.52),
    20: (2.80, 1.55),
    25: (2.62, 1.59),
    30: (2.52, 1.625),
    40: (2.40, 1.67),
    50: (2.32, 1.70),
    100: (2.18, 1.79),
}


@pytest.mark.parametrize("z", sorted(TEXTBOOK_TIP))
def test_tip_load_factors_match_textbook_table(z):
    f = form_factors(spur(z), load_at="tip")
    y_fa, y_sa = TEXTBOOK_TIP[z]
    assert f["Y_F"] == pytest.approx(y_fa, rel=0.01)
    assert f["Y_S"] == pytest.approx(y_sa, rel=0.01)


def test_tip_load_y_fs_chart():
    # Y_FS = Y_Fa Y_Sa charts (ISO 6336-3 style, x = 0): about 4.3-4.4 at z = 20 and just
    # under 4.0 at z = 100 (the table above: 2.80 * 1.55 = 4.34, 2.18 * 1.79 = 3.90)
    y_fs = {z: form_factors(spur(z), load_at="tip") for z in (20, 100)}
    assert 4.3 <= y_fs[20]["Y_F"] * y_fs[20]["Y_S"] <= 4.4
    assert 3.88 <= y_fs[100]["Y_F"] * y_fs[100]["Y_S"] <= 4.0


def test_theta_solves_the_iso_equation():
    for z, x in ((12, 0.3), (20, 0.0), (35, -0.3), (100, 0.0)):
        f = form_factors(spur(z, x), load_at="tip")
        lhs = 2.0 * f["G"] / f["z_n"] * math.tan(f["theta"]) - f["H"]
        assert f["theta"] == pytest.approx(lhs, abs=1e-14)
        assert f["iterations"] < 50


@pytest.mark.parametrize("z, x", [(12, 0.3), (17, 0.0), (20, 0.5), (35, -0.3), (60, 0.8), (100, 0)])
def test_s_fn_and_rho_f_match_exact_fillet(z, x):
    # For a spur gear the virtual gear is the gear itself and ISO's theta / s_Fn / rho_F are
    # the exact 30 deg tangent point of the rack-generated trochoid. tooth_profile samples the
    # fillet evenly in the tool parameter; with 4001 samples the O(h^2) interpolation and
    # differencing errors measured at most 2.4e-8 (s_Fn) and 6.2e-7 (rho_F), 16x smaller than
    # with 1001 samples: tolerances 10x the measured.
    f = form_factors(spur(z, x, m=2.0), load_at="tip")
    ex = fillet_tangent_point(spur(z, x, m=2.0), n_fillet=4001)
    assert ex["s_Fn"] == pytest.approx(f["s_Fn"], rel=3e-7)
    assert ex["rho_F"] == pytest.approx(f["rho_F"], rel=7e-6)


def test_hpstc_diameter_matches_pair_geometry():
    # Spur pair: the outer point of single contact on gear i is one base pitch from the start
    # of its contact: roll = (its lowest contact roll) + p_b; ISO's d_en must agree.
    g1, g2 = spur(20, 0.2, m=2.0), spur(40, -0.2, m=2.0)
    pair = GearPair(g1, replace(g2, name="g2"), 60.0)
    p_b = 2.0 * math.pi * g1.base_radius / g1.teeth
    s0, s1 = path_of_contact(pair)
    roll1 = pitch_roll(pair, 1) + s0 + p_b  # gear1 tip end is s1, its HPSTC at s0 + p_b
    roll2 = pitch_roll(pair, 2) - (s1 - p_b)
    for i, roll in ((1, roll1), (2, roll2)):
        g = pair.gear(i)
        f = form_factors(g, pair.transverse_contact_ratio)
        assert f["d_en"] / 2.0 == pytest.approx(math.hypot(g.base_radius, roll), rel=1e-12)
    # eps_alpha = 1 puts the HPSTC at the tip
    f1 = form_factors(g1, 1.0)
    assert f1["Y_F"] == pytest.approx(form_factors(g1, load_at="tip")["Y_F"], rel=1e-14)


def test_form_factor_trends():
    eps = 1.6
    y_z = [form_factors(spur(z), eps)["Y_F"] for z in (14, 17, 20, 30, 50, 100, 200)]
    assert np.all(np.diff(y_z) < 0.0)  # Y_F falls with z
    y_x = [form_factors(spur(20, x), eps)["Y_F"] for x in (-0.3, 0.0, 0.3, 0.6)]
    assert np.all(np.diff(y_x) < 0.0)  # and with the profile shift
    y_ft = [form_factors(spur(z), load_at="tip")["Y_F"] for z in (14, 20, 50, 200)]
    assert np.all(np.diff(y_ft) < 0.0)
    # HPSTC load: smaller lever arm than at the tip
    assert form_factors(spur(20), eps)["Y_F"] < form_factors(spur(20), load_at="tip")["Y_F"]


def test_helix_factor_limits():
    assert helix_factor(0.5, 21.0) == pytest.approx(1.0 - 0.5 * 21.0 / 120.0)
    assert helix_factor(2.08, 21.0) == pytest.approx(0.825)  # eps_beta > 1 -> 1
    assert helix_factor(1.5, 40.0) == pytest.approx(0.75)  # beta > 30 deg -> 30
    assert helix_factor(0.0, 0.0) == 1.0


def test_spur_tip_load_stress_by_hand():
    """sigma_F0 against a hand calculation from independent numbers: a spur gear z = 20 on
    the ISO 53 rack (m = 1, b = 10 mm, mate z = 40 as wide) with the load at the tip, the
    textbook Y_Fa = 2.80, Y_Sa = 1.55 (TEXTBOOK_TIP), F_t = T / r = 1e4 N mm / 10 mm and
    Y_beta = 1 (spur): sigma = 1000 / (10 * 1) * 2.80 * 1.55 = 434 MPa. 2 %: the two chart
    readings at 1 % each."""
    pair = GearPair(spur(20), replace(spur(40), name="g2"), 30.0)
    r = nominal_root_stress(pair, 1, 1.0e4, load_at="tip")
    assert r["sigma_F0"] == pytest.approx(1000.0 / 10.0 * 2.80 * 1.55, rel=0.02)


@pytest.mark.parametrize("s", [0.5, 3.0])
def test_nominal_stress_is_invariant_under_similarity(s, case1):
    """Scaling every length by s (module, face width, centre distance, thickness allowance;
    tooth numbers, shifts
    and coefficients kept) and the torque by s^3 leaves a stress unchanged, and stress is
    linear in the torque: a check on the units and powers of every length in the formula."""
    ext, _ = case1
    big = GearPair(
        replace(
            ext.gear1,
            normal_module=s * ext.gear1.normal_module,
            face_width=s * ext.gear1.face_width,
            thickness_allowance=s * ext.gear1.thickness_allowance,
        ),
        replace(
            ext.gear2,
            normal_module=s * ext.gear2.normal_module,
            face_width=s * ext.gear2.face_width,
            thickness_allowance=s * ext.gear2.thickness_allowance,
        ),
        s * ext.centre_distance,
    )
    for i in (1, 2):
        ref = nominal_root_stress(ext, i, TORQUE)["sigma_F0"]
        assert nominal_root_stress(big, i, TORQUE * s**3)["sigma_F0"] == pytest.approx(
            ref, rel=1e-9
        )
        assert nominal_root_stress(ext, i, 2.0 * TORQUE)["sigma_F0"] == pytest.approx(
            2.0 * ref, rel=1e-12
        )


def test_ring_by_hand(case1):
    """ISO 6336-3 method B for the case-1 ring (internal gear, substitute rack, 60 deg
    tangent), by hand from the gear data (cases/gearsets/case1.toml and the shifts and
    allowances the gear set assigns):

    m_n = 1.59 mm, alpha_n = 20 deg, beta = 21 deg, z = 86, h_fP = 1.25 m_n = 1.9875 mm,
    rho_fP = 0.38 m_n = 0.6042 mm, x = 0.563263, A_sn = -0.047417 mm (thinner tooth, wider
    space): x_E = x - A_sn / (2 m_n tan(alpha_n)) = 0.563263 + 0.040967 = 0.604230 (sigma = -1);
    d = z m_n / cos(beta) = 146.46837 mm, d_a = d - 2 (1 - x) m_n = 145.07954 mm;
    pinion-ring mesh: eps_alpha = 1.583496, eps_beta = 2.0806; F_t = 15419.43 N
    (T_sun 459.57 N m / r_sun = T_pinion / r_pinion = 341.41e3 / 22.14057),
    b = min(32.0, 29.0 + 2 m_n) = 32.0 mm.

    alpha_t = atan(tan 20 / cos 21) = 21.2992 deg, beta_b = atan(tan 21 cos alpha_t) =
    19.7124 deg, z_n = 86 / (cos^2 beta_b cos beta) = 103.9013, d_n = m_n z_n = 165.2031,
    d_bn = d_n cos 20 = 155.2395, d_an = d_n + d_a - d = 163.8143,
    eps_alpha_n = eps_alpha / cos^2 beta_b = 1.79092;
    roll at the tip sqrt(81.9071^2 - 77.6198^2) = 26.1556, plus one normal base pitch
    pi m_n cos 20 = 4.69391 times 0.79092: 29.8680; d_en = 2 sqrt(29.8680^2 + 77.6198^2) =
    166.3174, alpha_en = acos(155.2395 / 166.3174) = 21.0293 deg.
    Rack tooth (depths y from the datum, outwards): s(y) = pi m_n / 4 + y tan 20;
    s_Fn = 2 (s(1.9875 - 0.6042) + 0.6042 / cos 20 - 0.6042 cos 60)
         = 2 (1.24879 + 0.50348 + 0.64297 - 0.30210) = 4.18628 mm;
    y_F = 1.9875 - 0.6042 (1 - sin 60) = 1.90655 mm;
    y_e = (d_en - d_n) / 2 - x_E m_n = 0.55716 - 0.96073 = -0.40358 mm;
    h_Fe = y_F - y_e - s(y_e) tan alpha_en = 1.90655 + 0.40358 - 1.10195 * 0.38446
         = 1.88651 mm;
    Y_F = 6 (1.88651 / 1.59) cos 21.0293 / ((4.18628 / 1.59)^2 cos 20) = 1.02007;
    L = 4.18628 / 1.88651 = 2.21907, q_s = 4.18628 / (2 * 0.6042) = 3.46432,
    Y_S = (1.2 + 0.13 L) q_s^(1 / (1.21 + 2.3 / L)) = 1.48848 * 3.46432^0.44413 = 2.58791;
    Y_beta (2006) = 1 - 21 / 120 = 0.825;
    sigma_F0 = 15419.43 / (32 * 1.59) * 1.02007 * 2.58791 * 0.825 = 660.0 MPa.
    Tolerance 1e-4: the hand values above carry 5-6 digits.
    """
    _, ring_mesh = case1
    r = nominal_root_stress(ring_mesh, 2, TORQUE * 26 / 35)
    hand = {
        "z_n": 103.9013,
        "d_en": 166.3174,
        "s_Fn": 4.18628,
        "y_F": 1.90655,
        "y_e": -0.40358,
        "h_Fe": 1.88651,
        "Y_F": 1.02007,
        "Y_S": 2.58791,
        "sigma_F0": 15419.43 / (32.0 * 1.59) * 1.02007 * 2.58791 * 0.825,
    }
    for k, v in hand.items():
        assert r[k] == pytest.approx(v, rel=1e-4), k
    assert math.degrees(r["alpha_en"]) == pytest.approx(21.0293, abs=1e-4)
    assert r["x_E"] == pytest.approx(0.604230, abs=1e-6)
    assert 1.0 <= r["q_s"] < 8.0


def test_ring_form_factor_from_the_arithmetic():
    """The hand steps of test_ring_by_hand, recomputed from the raw data alone (no module
    code), to 1e-9: the docstring's rounding does not hide a formula slip."""
    m, an, beta, z = 1.59, math.radians(20.0), math.radians(21.0), 86
    h_fp, rho, x, a_sn = 1.25 * m, 0.38 * m, 0.5632625531556706, -0.04741710109709536
    x_e = x - a_sn / (2.0 * m * math.tan(an))
    at = math.atan(math.tan(an) / math.cos(beta))
    bb = math.atan(math.tan(beta) * math.cos(at))
    d = z * m / math.cos(beta)
    d_a = d - 2.0 * (1.0 - x) * m
    z_n = z / (math.cos(bb) ** 2 * math.cos(beta))
    d_n, eps_an = m * z_n, 1.5834959036124143 / math.cos(bb) ** 2
    d_bn, d_an = d_n * math.cos(an), d_n + d_a - d
    roll = math.sqrt((d_an / 2) ** 2 - (d_bn / 2) ** 2) + math.pi * m * math.cos(an) * (eps_an - 1)
    d_en = 2.0 * math.hypot(roll, d_bn / 2)
    a_en = math.acos(d_bn / d_en)
    s = lambda y: math.pi * m / 4 + y * math.tan(an)  # noqa: E731
    s_fn = 2.0 * (s(h_fp - rho) + rho / math.cos(an) - rho * 0.5)
    y_e = (d_en - d_n) / 2 - x_e * m
    h_fe = h_fp - rho * (1.0 - math.sqrt(3.0) / 2.0) - y_e - s(y_e) * math.tan(a_en)
    y_f = 6.0 * h_fe / m * math.cos(a_en) / ((s_fn / m) ** 2 * math.cos(an))
    ell, q_s = s_fn / h_fe, s_fn / (2.0 * rho)
    y_s = (1.2 + 0.13 * ell) * q_s ** (1.0 / (1.21 + 2.3 / ell))
    gs = load_gearset("case1")
    r = nominal_root_stress(gs.pair("pinion", "ring"), 2, TORQUE * 26 / 35)
    for k, v in {"s_Fn": s_fn, "h_Fe": h_fe, "Y_F": y_f, "Y_S": y_s, "d_en": d_en}.items():
        assert r[k] == pytest.approx(v, rel=1e-9), k


def test_internal_rack_is_the_limit_of_an_external_gear():
    """ISO's substitute rack at a 30 deg tangent is what the external-gear formulas give for
    z -> infinity (the tooth of a rack does not change with the shift): s_Fn and rho_F of
    z = 1e6 against the rack section s_Fn = 2 (s(h_fP - rho) + rho / cos(alpha_n) -
    rho cos 30), rho_F = rho. 1e-6: the external values approach the limit as 1 / z
    (rho_F - rho = 2 G^2 / (z cos(theta)^3) m_n = 4.4e-5 mm at z = 1e6, x = -0.3)."""
    m, an = 2.0, math.radians(20.0)
    h_fp, rho = 1.25 * m, 0.38 * m
    s = math.pi * m / 4 + (h_fp - rho) * math.tan(an)
    rack = 2.0 * (s + rho / math.cos(an) - rho * math.cos(math.radians(30.0)))
    for x in (-0.3, 0.0, 0.5):
        f = form_factors(spur(100_000_000, x, m=m), load_at="tip")
        assert f["s_Fn"] == pytest.approx(rack, rel=1e-6)
        assert f["rho_F"] == pytest.approx(rho, rel=1e-6)


def test_internal_tangent_point_on_the_generated_fillet(case1):
    """The 60 deg tangent point of the shaper-cut ring fillet lies on the fillet, between
    form and root circle, where the tangent makes 60 deg with the tooth centre line; the
    substitute rack's s_Fn (normal section) is within 10 % of the generated fillet's chord
    turned into the normal section (transverse chord cos(beta)): the rack straightens the
    concave root of a z = 86 gear, and the shaper-cut fillet radius differs from the rack's
    rho_fP (measured: 4.19 against 4.49 mm, 0.604 against 0.640 mm)."""
    _, ring_mesh = case1
    ring = ring_mesh.gear2
    ex = fillet_tangent_point(ring)
    assert ring.form_radius < ex["radius"] < ring.root_radius
    f = form_factors(ring, ring_mesh.transverse_contact_ratio)
    chord_n = ex["s_Fn"] * math.cos(math.radians(ring.helix_angle))
    assert f["s_Fn"] == pytest.approx(chord_n, rel=0.1)
    assert f["rho_F"] == pytest.approx(ex["rho_F"], rel=0.1)


def test_thickness_allowance_thins_the_critical_section():
    """A tooth thickness allowance A_sn (< 0 thinner) is cut by the tool fed in by
    A_sn / (2 tan(alpha_n)): ISO's s_Fn and rho_F with the generating shift x_E must be the
    exact 30 deg chord and curvature of the generated fillet of the thinned tooth (tolerances
    as test_s_fn_and_rho_f_match_exact_fillet), and thinner than without the allowance by
    about |A_sn| (the chord sits near the reference line's thickness change)."""
    g0 = spur(20, 0.2, m=2.0)
    g1 = replace(g0, thickness_allowance=-0.1)
    f0, f1 = form_factors(g0, load_at="tip"), form_factors(g1, load_at="tip")
    ex = fillet_tangent_point(g1, n_fillet=4001)
    assert f1["x_E"] == pytest.approx(0.2 - 0.1 / (2 * 2.0 * math.tan(math.radians(20))))
    assert ex["s_Fn"] == pytest.approx(f1["s_Fn"], rel=3e-7)
    assert ex["rho_F"] == pytest.approx(f1["rho_F"], rel=7e-6)
    assert 0.05 < f0["s_Fn"] - f1["s_Fn"] < 0.15


def test_helix_factor_editions():
    # 2019: the 2006 value divided by cos(beta)^3 (1 / cos(21 deg)^3 = 1.229)
    assert helix_factor(2.08, 21.0, 2019) == pytest.approx(0.825 / math.cos(math.radians(21)) ** 3)
    assert helix_factor(2.08, 21.0, 2006) == helix_factor(2.08, 21.0)
    with pytest.raises(ValueError, match="edition"):
        helix_factor(1.0, 10.0, 2010)


def test_case1_sun_and_pinion(case1, capsys):
    ext, ring_mesh = case1
    rows = [
        ("sun (sun mesh)", nominal_root_stress(ext, 1, TORQUE)),
        ("pinion (sun mesh)", nominal_root_stress(ext, 2, TORQUE)),
        ("pinion (ring mesh)", nominal_root_stress(ring_mesh, 1, TORQUE * 26 / 35)),
        ("ring (ring mesh)", nominal_root_stress(ring_mesh, 2, TORQUE * 26 / 35)),
    ]
    for name, r in rows:
        # the tangential load is the paper's T / R_SUN = 15419 N in every mesh (Table 3)
        assert r["F_t"] == pytest.approx(15419.0, abs=0.5)
        assert 1.0 <= r["q_s"] < 8.0  # ISO's validity range of Y_S
        assert r["Y_beta"] == pytest.approx(0.825)  # eps_beta = 2.08 > 1, beta = 21 deg
        with capsys.disabled():
            print(
                f"\ncase 1 {name}: z_n = {r['z_n']:.3f}, s_Fn = {r['s_Fn']:.4f} mm, "
                f"rho_F = {r['rho_F']:.4f} mm, h_Fe = {r['h_Fe']:.4f} mm, alpha_Fen = "
                f"{math.degrees(r['alpha_Fen']):.3f} deg, Y_F = {r['Y_F']:.4f}, Y_S = "
                f"{r['Y_S']:.4f}, Y_beta = {r['Y_beta']:.3f}, b = {r['b']:.2f} mm, "
                f"sigma_F0 = {r['sigma_F0']:.1f} MPa"
            )
    assert rows[1][1]["Y_F"] > rows[0][1]["Y_F"]  # the smaller pinion has the larger Y_F
