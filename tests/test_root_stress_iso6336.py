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
        "g", z, m, 20.0, 0.0, "R", 10.0, profile_shift=x, dedendum_coef=1.25,
        hob_tip_radius_coef=0.38,
    )  # fmt: skip


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
TEXTBOOK_TIP = {17: (2.97, 1.52), 20: (2.80, 1.55), 25: (2.62, 1.59), 30: (2.52, 1.625),
                40: (2.40, 1.67), 50: (2.32, 1.70), 100: (2.18, 1.79)}  # fmt: skip


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
    """Scaling every length by s (module, face width, centre distance; tooth numbers, shifts
    and coefficients kept) and the torque by s^3 leaves a stress unchanged, and stress is
    linear in the torque: a check on the units and powers of every length in the formula."""
    ext, _ = case1
    big = GearPair(
        replace(ext.gear1, normal_module=s * ext.gear1.normal_module,
                face_width=s * ext.gear1.face_width),
        replace(ext.gear2, normal_module=s * ext.gear2.normal_module,
                face_width=s * ext.gear2.face_width),
        s * ext.centre_distance,
    )  # fmt: skip
    for i in (1, 2):
        ref = nominal_root_stress(ext, i, TORQUE)["sigma_F0"]
        assert nominal_root_stress(big, i, TORQUE * s**3)["sigma_F0"] == pytest.approx(
            ref, rel=1e-9
        )
        assert nominal_root_stress(ext, i, 2.0 * TORQUE)["sigma_F0"] == pytest.approx(
            2.0 * ref, rel=1e-12
        )


def test_internal_gear_not_implemented(case1):
    _, ring_mesh = case1
    with pytest.raises(NotImplementedError, match="internal"):
        nominal_root_stress(ring_mesh, 2, TORQUE * 26 / 35)


def test_case1_sun_and_pinion(case1, capsys):
    ext, ring_mesh = case1
    rows = [
        ("sun (sun mesh)", nominal_root_stress(ext, 1, TORQUE)),
        ("pinion (sun mesh)", nominal_root_stress(ext, 2, TORQUE)),
        ("pinion (ring mesh)", nominal_root_stress(ring_mesh, 1, TORQUE * 26 / 35)),
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
