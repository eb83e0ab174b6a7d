"""Pure-numpy gear geometry: the paper's derived values, a seeded sweep of invariants, the
exact-surface deviations, gear pairs and shift assignment, and one test per bad input.

Every numeric assertion says why its tolerance is what it is."""

import math
from dataclasses import replace

import numpy as np
import pytest

from gears.involute import inverse_involute, involute
from gears.pair import GearPair, assign_chain_shifts, with_required_shift
from gears.profile import (
    fillet_deviation,
    gear_outline,
    involute_deviation,
    polyline_foot,
    tooth_profile,
)
from gears.spec import GearSpec, GeometryError

COMMON = dict(normal_module=1.59, normal_pressure_angle=20.0, helix_angle=21.0)
SPUR = dict(normal_module=1.0, normal_pressure_angle=20.0, helix_angle=0.0, face_width=10.0)


def case1():
    """Sun, pinion and ring of the paper's case 1 (singh2007.md section 1), unshifted."""
    return [
        GearSpec("sun", 35, hand="R", face_width=32.35, **COMMON),
        GearSpec("pinion", 26, hand="L", face_width=29.00, **COMMON),
        GearSpec("ring", 86, hand="L", face_width=32.00, internal=True, **COMMON),
    ]


def case2():
    """Sun, SP, RP and ring of the paper's case 2, unshifted."""
    return [
        GearSpec("sun", 35, hand="R", face_width=32.35, **COMMON),
        GearSpec("SP", 26, hand="L", face_width=29.00, **COMMON),
        GearSpec("RP", 24, hand="R", face_width=29.00, **COMMON),
        GearSpec("ring", 92, hand="R", face_width=32.00, internal=True, **COMMON),
    ]


def assert_printed(value, printed: str):
    """value rounds to the printed figure: within half a unit of its last digit (plus 1e-12
    so that exact ties such as 22.5095 -> 22.510 survive float rounding)."""
    decimals = len(printed.split(".")[1])
    assert abs(value - float(printed)) <= 0.5 * 10.0**-decimals + 1e-12, (value, printed)


def _angle(u, v):
    """Angles (rad) between the vectors in the last axis of u and v."""
    cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    return np.abs(np.arctan2(cross, np.einsum("...i,...i", u, v)))


def _screw(g, points, z):
    """Transverse points (N, 2) carried along the helix to the axial positions z (broadcast
    against N, e.g. (N,) or (M, 1)): (..., N, 3)."""
    q = g.helix_rotation(z)
    x, y = points[:, 0], points[:, 1]
    return np.stack(
        np.broadcast_arrays(np.cos(q) * x - np.sin(q) * y, np.sin(q) * x + np.cos(q) * y, z),
        axis=-1,
    )


# --------------------------------------------------------------------------------------
# the paper's derived operating geometry
# --------------------------------------------------------------------------------------


def test_case1_printed_operating_geometry():
    sun, pinion, ring = case1()
    # The sun mesh is standard: the printed 51.945 mm is a0 = 51.94518 mm rounded, and the
    # printed radii are the reference radii (at 51.945 itself R_pS = 22.14049 would print
    # as 22.140), so the sun mesh is evaluated at a0.
    a0 = GearPair(sun, pinion, 51.945).standard_centre_distance
    assert_printed(a0, "51.945")
    sun_mesh = GearPair(sun, pinion, a0)
    ring_mesh = with_required_shift(GearPair(pinion, ring, 51.945))
    deg = math.degrees
    assert_printed(sun_mesh.operating_pitch_radius(1), "29.805")  # R_SUN
    assert_printed(sun_mesh.operating_pitch_radius(2), "22.141")  # R_pS
    assert_printed(ring_mesh.operating_pitch_radius(1), "22.510")  # R_pR
    assert_printed(deg(sun_mesh.operating_pressure_angle), "21.30")  # alpha1
    assert_printed(deg(ring_mesh.operating_pressure_angle), "23.59")  # alpha2
    assert_printed(deg(sun_mesh.operating_helix_angle(2)), "21.00")  # beta1
    assert_printed(deg(ring_mesh.operating_helix_angle(1)), "21.32")  # beta2
    # Both gears of a mesh share the operating helix angle: float rounding only.
    assert ring_mesh.operating_helix_angle(2) == pytest.approx(
        ring_mesh.operating_helix_angle(1), rel=1e-14
    )


def test_case2_printed_radii():
    distances = [51.945, 42.750, 58.600]
    gears = assign_chain_shifts(case2(), distances)
    sun_sp, sp_rp, rp_ring = (
        GearPair(g1, g2, a) for g1, g2, a in zip(gears, gears[1:], distances, strict=False)
    )
    assert_printed(sun_sp.operating_pitch_radius(2), "22.14")  # R_SP-SUN
    assert_printed(sp_rp.operating_pitch_radius(1), "22.23")  # R_SP-RP
    assert_printed(sp_rp.operating_pitch_radius(2), "20.52")  # R_RP-SP
    assert_printed(rp_ring.operating_pitch_radius(1), "20.68")  # R_RP-RING


# --------------------------------------------------------------------------------------
# involute function
# --------------------------------------------------------------------------------------


def test_inverse_involute():
    alpha = np.linspace(0.05, 1.5, 1001)
    # Newton to the last bit: what is left is the float error of tan(a) - a divided by
    # tan(a)^2, 4e-15 rad at a = 0.05 and less above.
    assert np.max(np.abs(inverse_involute(involute(alpha)) - alpha)) <= 1e-14
    assert inverse_involute(0.0) == 0.0  # inv(0) = 0 is exact
    assert inverse_involute(-involute(0.3)) == pytest.approx(-0.3, abs=1e-15)  # odd, rounding
    assert isinstance(inverse_involute(0.01), float)  # scalars in, scalars out


# --------------------------------------------------------------------------------------
# seeded sweep of single gears
# --------------------------------------------------------------------------------------


def _rho_max(alpha_n_deg: float, h_f: float = 1.25) -> float:
    """Largest rack tip rounding (/ m_n) that fits a rack tooth of addendum h_f."""
    a = math.radians(alpha_n_deg)
    return (math.pi / 4 - h_f * math.tan(a)) * math.cos(a) / (1 - math.sin(a))


def random_gear(rng, internal: bool) -> GearSpec:
    """A random valid gear. External: z 12..120, pressure angle 14..28 deg, shift from 0.15
    below to 0.6 above the no-undercut shift (some mildly undercut). Internal: z 40..150,
    17..28 deg (lower angles need bigger shapers), x 0.3..1, a 24..30-tooth shaper."""
    z = int(rng.integers(40, 151) if internal else rng.integers(12, 121))
    alpha_n = float(rng.uniform(17.0 if internal else 14.0, 28.0))
    beta = 0.0 if rng.random() < 0.25 else float(rng.uniform(5.0, 40.0))
    rho = float(rng.uniform(0.15, 0.95) * _rho_max(alpha_n))
    m_n = float(np.exp(rng.uniform(math.log(0.5), math.log(8.0))))
    extra = {}
    if internal:
        x = float(rng.uniform(0.3, 1.0))
        extra["shaper_teeth"] = int(rng.integers(24, 31))
    else:
        an, b = math.radians(alpha_n), math.radians(beta)
        alpha_t = math.atan(math.tan(an) / math.cos(b))
        x_free = 1.25 - rho * (1 - math.sin(an)) - z / (2 * math.cos(b)) * math.sin(alpha_t) ** 2
        x = max(x_free, -0.6) + float(rng.uniform(-0.15, 0.6))
    hand = "right" if rng.random() < 0.5 else "left"
    while True:  # redraw the rare pointed tooth (small z, high shift): tested on its own
        try:
            return GearSpec(
                name="g",
                teeth=z,
                normal_module=m_n,
                normal_pressure_angle=alpha_n,
                helix_angle=beta,
                hand=hand,
                face_width=10.0 * m_n,
                internal=internal,
                profile_shift=x,
                hob_tip_radius_coef=rho,
                **extra,
            )
        except GeometryError as exc:
            if "pointed" not in str(exc):
                raise
            x -= 0.1


def _check_circles_and_thickness(g):
    sigma = -1 if g.internal else 1
    beta, an = math.radians(g.helix_angle), math.radians(g.normal_pressure_angle)
    m_t, alpha_t = g.normal_module / math.cos(beta), math.atan(math.tan(an) / math.cos(beta))
    r_b, r_a, r_f, r_form = g.base_radius, g.tip_radius, g.root_radius, g.form_radius
    # Base circle r cos(alpha_t) from the inputs alone: the same product, rounding only.
    assert r_b == pytest.approx(g.teeth * m_t / 2 * math.cos(alpha_t), rel=1e-14)
    # Circles in order; only external gears undercut, and even then r_b <= r_F.
    if g.internal:
        assert r_b < r_a < r_form < r_f and not g.is_undercut
    else:
        assert r_f < r_form < r_a and r_b <= r_form
    # Reference thickness m_t (pi/2 + sigma 2 x tan(alpha_n)): float rounding only.
    s_ref = m_t * (math.pi / 2 + sigma * 2 * g.profile_shift * math.tan(an))
    assert g.tooth_thickness(g.reference_radius) == pytest.approx(s_ref, rel=1e-12)
    # Positive over the whole involute: thinnest at the tip, which keeps the 0.2 m_n limit
    # (1e-12: rounding where the minimum is the tip itself).
    assert np.all(g.tooth_thickness(np.linspace(r_form, r_a, 50)) >= g.tip_thickness * (1 - 1e-12))
    assert g.tip_thickness >= 0.2 * g.normal_module
    # The helix turns counter-clockwise with z for a right hand (same formula, rounding).
    turn = math.tan(beta) / g.reference_radius * (1 if g.hand == "right" else -1)
    assert g.helix_rotation(2.0) == pytest.approx(2.0 * turn, rel=1e-14, abs=0.0)


def _check_flanks(g, prof):
    sigma = -1 if g.internal else 1
    an, r_b = math.radians(g.normal_pressure_angle), g.base_radius
    cusp = math.pi / (2 * g.teeth) + sigma * (
        2 * g.profile_shift * math.tan(an) / g.teeth + involute(g.transverse_pressure_angle)
    )
    for s, flank in ((1, prof.flank_pos), (-1, prof.flank_neg)):
        rho = np.hypot(flank[:, 0], flank[:, 1])
        assert rho[0] == pytest.approx(g.form_radius, rel=1e-14)  # set exactly, rounding
        assert rho[-1] == pytest.approx(g.tip_radius, rel=1e-14)  # set exactly, rounding
        # The involute as an unwound string, without inv(): P = r_b e(t) + s sigma L e(t + 90),
        # tangent point t = s (theta_cusp - sigma L / r_b), roll length L = sqrt(rho^2 - r_b^2);
        # rounding only (1e-12 of the radius).
        roll = np.sqrt(rho**2 - r_b**2)
        t = s * (cusp - sigma * roll / r_b)
        e_t = np.c_[np.cos(t), np.sin(t)]
        string = r_b * e_t + (s * sigma * roll)[:, None] * np.c_[-e_t[:, 1], e_t[:, 0]]
        assert np.max(np.linalg.norm(flank - string, axis=1)) <= 1e-12 * rho.max()
    # Thickness at the tip = the arc between the flank ends (rounding only).
    tip_arc = g.tip_radius * _angle(prof.flank_pos[-1], prof.flank_neg[-1])
    assert tip_arc == pytest.approx(g.tip_thickness, rel=1e-12)


def _check_fillet(g, prof):
    fil, flank = prof.fillet_neg, prof.flank_neg
    assert np.array_equal(fil[-1], flank[0])  # one shared point
    # ... which is where the generated fillet really ends: its exact trochoid, sampled
    # independently by fillet_deviation (chord error < 1e-7 m_n).
    junction = np.r_[flank[0], 0.0]
    assert abs(fillet_deviation(g, junction, "neg")) <= 1e-7 * g.normal_module
    assert np.hypot(*fil[0]) == pytest.approx(g.root_radius, rel=1e-12)  # on the root circle
    # Tangent joints: a chord differs from the tangent by about half the turn over it, so at
    # a C1 joint the chord-to-chord angle stays below the turns of the neighbouring chords;
    # a corner would not shrink with the sampling.
    chords, inv_chords = np.diff(fil, axis=0), np.diff(flank, axis=0)
    root_tangent = np.array([-fil[0, 1], fil[0, 0]])
    assert _angle(chords[0], root_tangent) <= _angle(chords[0], chords[1])
    if g.is_undercut:
        assert 0.0 < g.undercut_fraction <= 0.1  # flagged, within the stated limit
        return
    turns = _angle(chords[-2], chords[-1]) + _angle(inv_chords[0], inv_chords[1])
    assert _angle(chords[-1], inv_chords[0]) <= turns
    # The fillet stays in the tooth space (theta <= -psi(rho) on the neg side) wherever the
    # involute exists; 1e-12 rad of rounding.
    rho = np.hypot(fil[:, 0], fil[:, 1])
    above = rho >= g.base_radius
    psi = g.tooth_thickness(rho[above]) / (2 * rho[above])
    assert np.all(np.arctan2(fil[above, 1], fil[above, 0]) <= -psi + 1e-12)


def _check_surfaces_and_outline(g, prof):
    # The profile screwed to any z lies on the exact surfaces: involute (exact formula,
    # rounding 1e-12 m_n) and fillet (2000-point reference trochoid, chord error 1e-7 m_n).
    z = np.linspace(-g.face_width / 2, g.face_width / 2, 3)[:, None]
    for side in ("pos", "neg"):
        flank, fillet = getattr(prof, f"flank_{side}"), getattr(prof, f"fillet_{side}")
        dev = involute_deviation(g, _screw(g, flank, z), side)
        assert np.max(np.abs(dev)) <= 1e-12 * g.normal_module
        dev = fillet_deviation(g, _screw(g, fillet[::40], z), side)
        assert np.max(np.abs(dev)) <= 1e-7 * g.normal_module
    # Whole outline: z copies of one pitch, counter-clockwise, between root and tip circles
    # (1e-12: rounding of rotated points).
    coarse = tooth_profile(g)  # default sampling, as the mesher uses it
    outline = gear_outline(coarse, n_arc=4)
    assert len(outline) == g.teeth * (len(coarse.outline(n_arc=4)) - 1)
    rr = np.hypot(outline[:, 0], outline[:, 1])
    lo, hi = sorted((g.tip_radius, g.root_radius))
    assert rr.min() >= lo * (1 - 1e-12) and rr.max() <= hi * (1 + 1e-12)
    x, y = outline[:, 0], outline[:, 1]
    assert np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) > 0.0  # shoelace: CCW


def check_gear(g):
    _check_circles_and_thickness(g)
    prof = tooth_profile(g, n_involute=200, n_fillet=200)
    _check_flanks(g, prof)
    _check_fillet(g, prof)
    _check_surfaces_and_outline(g, prof)


@pytest.mark.parametrize(("internal", "seed"), [(False, 20240601), (True, 20240602)])
def test_seeded_sweep(internal, seed):
    rng = np.random.default_rng(seed)
    gears = [random_gear(rng, internal) for _ in range(100)]
    for g in gears:
        check_gear(g)
    if not internal:  # the shift draw reaches 0.15 below the no-undercut shift
        assert any(g.is_undercut for g in gears)


def test_undercut_gears():
    """Small spur pinions below the no-undercut shift: flagged, cut where the tip trochoid
    crosses the involute above the base circle, within the stated limit."""
    for z in (12, 14, 16, 17):
        g = GearSpec("p", z, hand="R", **SPUR)
        assert g.is_undercut and g.form_radius > g.base_radius
        check_gear(g)
        if z < 17:  # at z = 17 the undercut is marginal and the crossing almost tangential
            prof = tooth_profile(g, 200, 200)
            fil, inv = np.diff(prof.fillet_neg, axis=0), np.diff(prof.flank_neg, axis=0)
            # A corner, unlike the C1 joint above: twice what the chords' turns explain.
            turns = _angle(fil[-2], fil[-1]) + _angle(inv[0], inv[1])
            assert _angle(fil[-1], inv[0]) > 2 * turns
    # One more tooth clears the undercut (z sin(alpha)^2 / 2 reaches the tool's h_F).
    assert not GearSpec("p", 18, hand="R", **SPUR).is_undercut


# --------------------------------------------------------------------------------------
# deviations from the exact surfaces
# --------------------------------------------------------------------------------------


def _helicoid(g, rho, z, side, tooth):
    """Points on the flank helicoid of one side and tooth, with outward unit normals from
    the surface partials (psi' by central differences: 1e-10 relative error)."""
    s = 1 if side == "pos" else -1

    def psi(r):
        return g.tooth_thickness(r) / (2 * r)

    theta = s * psi(rho) + g.helix_rotation(z) + tooth * 2 * math.pi / g.teeth
    h = 1e-5 * rho
    d_theta = s * (psi(rho + h) - psi(rho - h)) / (2 * h)
    k = g.helix_rotation(1.0)
    c, sn, zero = np.cos(theta), np.sin(theta), np.zeros_like(rho)
    d_rho = np.c_[c - rho * sn * d_theta, sn + rho * c * d_theta, zero]
    d_z = np.c_[-rho * sn * k, rho * c * k, zero + 1.0]
    n = np.cross(d_rho, d_z)
    n *= (s * np.sign(n[:, 1] * c - n[:, 0] * sn) / np.linalg.norm(n, axis=1))[:, None]
    return np.c_[rho * c, rho * sn, z], n  # outward: towards +theta on "pos", -theta on "neg"


@pytest.mark.parametrize("which", [0, 1, 2])
@pytest.mark.parametrize("side", ["pos", "neg"])
def test_involute_deviation(which, side):
    g = case1()[which]
    rng = np.random.default_rng(7)
    rho = np.linspace(g.form_radius, g.tip_radius, 30)
    z = rng.uniform(-g.face_width / 2, g.face_width / 2, rho.size)
    p, n = _helicoid(g, rho, z, side, tooth=rng.integers(0, g.teeth, rho.size))
    # On the helicoid: zero up to the rounding of angles times radii (~1e-13 mm).
    assert np.max(np.abs(involute_deviation(g, p, side))) <= 1e-9
    # Moved along the normal by d: exactly d (involute helicoids of one base cylinder are
    # parallel surfaces), up to the finite-difference normal (1e-10 relative) and rounding.
    for d in (0.02, -0.02):
        assert np.allclose(involute_deviation(g, p + d * n, side), d, rtol=0.0, atol=1e-9)


@pytest.mark.parametrize("which", [1, 2])
@pytest.mark.parametrize("side", ["pos", "neg"])
def test_fillet_deviation(which, side):
    g = assign_chain_shifts(case1(), [51.945, 51.945])[which]  # pinion, shifted ring
    fil = getattr(tooth_profile(g, n_fillet=401), f"fillet_{side}")
    i = np.arange(1, 400, 8)
    c, tangent = fil[i], fil[i + 1] - fil[i - 1]  # central differences: tangent error ~h^2
    z = np.linspace(-g.face_width / 2, g.face_width / 2, i.size)
    p = _screw(g, c, z)  # point i at height z_i
    # On the surface: the chord error of the 2000-point reference curve, < 1e-7 mm for this
    # 0.6 mm fillet with radii of curvature above 0.1 mm.
    assert np.max(np.abs(fillet_deviation(g, p, side))) <= 1e-7
    # Moved along the 3D normal (n_t, -k c x n_t) by d: d to first order; the rest, ~d / R
    # (curvature) plus the tangent error, is below 1e-3 d for d = 2 um.
    s = 1 if side == "pos" else -1
    n_t = np.c_[tangent[:, 1], -tangent[:, 0]] / np.linalg.norm(tangent, axis=1)[:, None]
    n_t *= -s * (-1 if g.internal else 1)  # outward: away from the body at the root
    n_axial = -g.helix_rotation(1.0) * (c[:, 0] * n_t[:, 1] - c[:, 1] * n_t[:, 0])
    n = np.c_[_screw(g, n_t, z)[:, :2], n_axial]  # n_t turned with its point
    n /= np.linalg.norm(n, axis=1)[:, None]
    for d in (2e-3, -2e-3):
        assert np.allclose(fillet_deviation(g, p + d * n, side), d, rtol=1e-3, atol=1e-9)
    # Sign, independently of the curve: 0.01 mm off the root circle into the tooth space
    # next to the mid-space is 0.01 mm outside (the land is a cylinder; chord error 1e-7).
    r_air = g.root_radius + (-0.01 if g.internal else 0.01)
    theta = s * (math.pi / g.teeth - 1e-4)
    air = np.array([r_air * math.cos(theta), r_air * math.sin(theta), 0.0])
    assert fillet_deviation(g, air, side) == pytest.approx(0.01, abs=1e-7)


# --------------------------------------------------------------------------------------
# pairs and shift assignment
# --------------------------------------------------------------------------------------


def test_polyline_foot():
    # The foot on a polyline with a repeated vertex against a brute force over 5001 samples
    # per segment (spacing at most 1.12 / 5000 = 2.2e-4, so the nearest sample is within
    # half of it, 1.2e-4, of the exact foot's distance).
    rng = np.random.default_rng(3)
    curve = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.5, 1.0], [1.0, 2.0], [0.0, 2.5]])
    q = rng.uniform([-0.5, -0.5], [2.0, 3.0], (200, 2))
    j, w = polyline_foot(curve, q)
    assert np.all((w >= 0.0) & (w <= 1.0)) and not np.any(j == 1)  # the zero-length one
    foot = curve[j] + w[:, None] * (curve[j + 1] - curve[j])
    t = np.linspace(0.0, 1.0, 5001)[:, None]
    dense = curve[:-1, None, :] + t[None] * np.diff(curve, axis=0)[:, None, :]
    dense = dense.reshape(-1, 2)
    brute = np.min(np.linalg.norm(q[:, None, :] - dense[None], axis=2), axis=1)
    assert np.allclose(np.linalg.norm(q - foot, axis=1), brute, atol=1.2e-4)
    # a point on a segment is its own foot
    jj, ww = polyline_foot(curve, np.array([[1.25, 0.5]]))
    assert jj[0] == 2 and ww[0] == pytest.approx(0.5)


def test_required_shift_and_backlash():
    sun, pinion, ring = case1()
    a0 = GearPair(sun, pinion, 51.945).standard_centre_distance
    assert abs(GearPair(sun, pinion, a0).required_shift) <= 1e-6  # standard: zero, rounding
    # The printed 51.945 is a0 rounded to 0.0005 mm; the shift that difference needs is
    # below dx/da * 0.0005 mm, dx/da = (z1 + z2) tan(alpha_wt) / (2 a tan(alpha_n)).
    pair = GearPair(sun, pinion, 51.945)
    dx_da = 61 * math.tan(pair.operating_pressure_angle) / (2 * 51.945 * math.tan(math.radians(20)))
    assert abs(pair.required_shift) <= dx_da * 5e-4
    ring_pair = GearPair(pinion, ring, 51.945)
    assert ring_pair.required_shift > 0.5  # the ring mesh runs 0.85 mm above a0 = 51.094 mm
    # Backlash from the actual shifts, j = 2 K tan(alpha_n) (x_sum - x_required) with
    # K = m_t cos(alpha_t) / cos(alpha_wt): the unshifted ring overlaps (rounding only).
    k = pinion.transverse_module * math.cos(pinion.transverse_pressure_angle)
    k /= math.cos(ring_pair.operating_pressure_angle)
    expected = 2 * k * math.tan(math.radians(20)) * (0.0 - ring_pair.required_shift)
    assert ring_pair.backlash == pytest.approx(expected, rel=1e-12)
    assert ring_pair.backlash < 0
    for p in (pair, ring_pair):
        meshed = with_required_shift(p)
        assert meshed.gear1 == p.gear1
        assert abs(meshed.backlash) <= 1e-9  # zero by construction, rounding only


def test_contact_ratios_case1():
    sun, pinion, ring = assign_chain_shifts(case1(), [51.945, 51.945])
    eps_beta = 29.0 * math.sin(math.radians(21.0)) / (math.pi * 1.59)  # b: the pinion's 29 mm
    for p in (GearPair(sun, pinion, 51.945), GearPair(pinion, ring, 51.945)):
        assert 1.2 < p.transverse_contact_ratio < 2.0  # plausible for 20 deg and h_a* = 1
        assert p.overlap_ratio == pytest.approx(eps_beta, rel=1e-14)  # same formula, rounding
        assert p.total_contact_ratio == pytest.approx(p.transverse_contact_ratio + eps_beta)


def test_assign_chain_shifts_case2():
    raw, distances = case2(), [51.945, 42.750, 58.600]
    sun, sp, rp, ring = assign_chain_shifts(raw, distances)
    assert sun == raw[0]
    # Each mesh's shift lands on its downstream gear (the same arithmetic, rounding only).
    x_sp_rp = GearPair(sp, raw[2], 42.750).required_shift
    x_rp_ring = GearPair(rp, raw[3], 58.600).required_shift
    assert rp.profile_shift == pytest.approx(x_sp_rp - sp.profile_shift, abs=1e-14)
    assert ring.profile_shift == pytest.approx(rp.profile_shift + x_rp_ring, abs=1e-14)
    for g in (sun, sp, rp, ring):
        assert g.tip_thickness >= 0.2 * g.normal_module and not g.is_undercut
    for g1, g2, a in zip((sun, sp, rp), (sp, rp, ring), distances, strict=True):
        assert abs(GearPair(g1, g2, a).backlash) <= 1e-9  # zero by construction, rounding
    with pytest.raises(GeometryError, match="centre_distances: 2 given, must be one per mesh"):
        assign_chain_shifts(raw, distances[:2])


def _tip_corner_depth(pinion, ring, a):
    """Deepest reach (mm, > 0: inside) of the pinion's tip corners into the ring's teeth over
    a full turn, by plain kinematics at zero backlash: pinion tooth 0 centred in the ring's
    space on +x at phi = 0, the ring turning by phi z1 / z2."""
    phi = np.linspace(-math.pi, math.pi, 400_001)
    r_a1, pitch = pinion.tip_radius, 2 * math.pi / ring.teeth
    deepest = -math.inf
    for s in (1, -1):
        corner = phi + s * pinion.tooth_thickness(r_a1) / (2 * r_a1)
        x, y = a + r_a1 * np.cos(corner), r_a1 * np.sin(corner)
        rho = np.hypot(x, y)
        theta = np.arctan2(y, x) - phi * pinion.teeth / ring.teeth - pitch / 2
        theta -= pitch * np.round(theta / pitch)
        m = (rho >= ring.tip_radius) & (rho <= ring.form_radius)
        depth = ring.tooth_thickness(rho[m]) / 2 - rho[m] * np.abs(theta[m])
        deepest = max(deepest, depth.max())
    return deepest


def _zero_backlash_distance(pinion, ring):
    """Centre distance of an internal spur pair at zero backlash for its actual shifts."""
    at, dz = pinion.transverse_pressure_angle, ring.teeth - pinion.teeth
    shift = ring.profile_shift - pinion.profile_shift
    tan_an = math.tan(math.radians(pinion.normal_pressure_angle))
    aw = inverse_involute(involute(at) + 2 * tan_an * shift / dz)
    return dz * pinion.transverse_module / 2 * math.cos(at) / math.cos(aw)


def test_tip_interference_matches_kinematics():
    """The closed-form tip (trochoid) interference check of internal pairs agrees with a
    brute-force sweep of the pinion's tip corners through the ring."""
    pinion = GearSpec("pinion", 26, hand="R", addendum_coef=0.8, **SPUR)
    ring = replace(pinion, name="ring", teeth=29, internal=True, profile_shift=0.2, shaper_teeth=20)
    a = _zero_backlash_distance(pinion, ring)
    with pytest.raises(GeometryError, match=r"tip interference .* ring\.teeth - pinion\.teeth"):
        GearPair(pinion, ring, a)
    assert _tip_corner_depth(pinion, ring, a) > 1e-4  # a real overlap, 1e5 x the clear case
    pinion = GearSpec("pinion", 26, hand="R", **SPUR)
    ring = GearSpec("ring", 86, hand="R", internal=True, profile_shift=0.56, **SPUR)
    a = _zero_backlash_distance(pinion, ring)
    GearPair(pinion, ring, a)  # valid
    # The corners touch the ring only at the end of contact: zero up to rounding (1e-9 mm).
    assert _tip_corner_depth(pinion, ring, a) <= 1e-9


# --------------------------------------------------------------------------------------
# bad input: one test each, the message names the field
# --------------------------------------------------------------------------------------


SUN = dict(name="sun", teeth=35, hand="R", face_width=32.35, **COMMON)
PINION = dict(name="pinion", teeth=26, hand="L", face_width=29.0, **COMMON)


def _sun(**change):
    return GearSpec(**(SUN | change))


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"teeth": 0}, r"sun\.teeth = 0: must be an integer >= 5"),
        ({"teeth": 20.5}, r"sun\.teeth = 20\.5: must be an integer"),
        ({"normal_module": 0.0}, r"sun\.normal_module = 0\.0: must be a number > 0"),
        ({"face_width": -3.0}, r"sun\.face_width = -3\.0: must be a number > 0"),
        ({"normal_pressure_angle": 5.0}, r"sun\.normal_pressure_angle = 5\.0: .*\[10, 35\]"),
        ({"normal_pressure_angle": 40.0}, r"sun\.normal_pressure_angle = 40\.0"),
        ({"helix_angle": 50.0}, r"sun\.helix_angle = 50\.0: must be a number in \[0, 45\]"),
        ({"helix_angle": -21.0}, r"sun\.helix_angle = -21\.0"),
        ({"hand": "up"}, r"sun\.hand = 'up': must be 'right' or 'left'"),
        ({"hob_tip_radius_coef": 0.6}, r"sun\.hob_tip_radius_coef = 0\.6: must be a number in"),
        ({"internal": "yes"}, r"sun\.internal = 'yes': must be true or false"),
        ({"teeth": 12, "profile_shift": 1.2}, r"sun\.profile_shift = 1\.2: tip thickness.*pointed"),
        ({"teeth": 10, "helix_angle": 0.0}, r"sun\.profile_shift = 0\.0: undercut .* at most 10%"),
        ({"internal": True, "shaper_teeth": 35}, r"sun\.shaper_teeth = 35: must be < teeth"),
    ],
)
def test_bad_gear_fields(change, match):
    with pytest.raises(GeometryError, match=match):
        _sun(**change)


def test_hand_normalised():
    assert _sun(hand="r").hand == "right" and _sun(hand="LEFT").hand == "left"
    # Spur gears mesh whatever their hands.
    GearPair(GearSpec("a", 30, hand="R", **SPUR), GearSpec("b", 40, hand="R", **SPUR), 35.0)


def test_thickness_and_deviation_domains():
    sun = _sun()
    with pytest.raises(GeometryError, match=r"sun: radius r = .* must be >= the base radius"):
        sun.tooth_thickness(sun.base_radius * 0.99)
    with pytest.raises(GeometryError, match=r"side = 'left': must be 'pos' or 'neg'"):
        involute_deviation(sun, np.full((1, 3), sun.tip_radius), "left")


@pytest.mark.parametrize(
    ("gear2", "a", "match"),
    [
        ({"normal_module": 1.5}, 51.0, r"pinion\.normal_module = 1\.5: must equal sun\."),
        ({"normal_pressure_angle": 22.0}, 52.0, r"pinion\.normal_pressure_angle = 22\.0: must"),
        ({"hand": "R"}, 51.945, r"pinion\.hand = 'right': an external .* opposite hand"),
        ({}, 48.0, r"centre_distance = 48\.0: must be > a0 cos\(alpha_t\) = 48\.397"),
        ({}, 55.0, r"centre_distance = 55\.0: needs pinion\.profile_shift = .*pointed"),
    ],
)
def test_bad_external_pairs(gear2, a, match):
    with pytest.raises(GeometryError, match=match):
        GearPair(_sun(), GearSpec(**(PINION | gear2)), a)


def test_bad_internal_pairs():
    _, pinion, ring = case1()
    with pytest.raises(GeometryError, match=r"ring\.hand = 'right': an internal .* same hand"):
        GearPair(pinion, replace(ring, hand="R"), 51.945)
    with pytest.raises(GeometryError, match=r"ring\.internal = True: gear1 must be external"):
        GearPair(ring, pinion, 51.945)
    small = replace(ring, teeth=26, shaper_teeth=12, profile_shift=1.0)
    with pytest.raises(GeometryError, match=r"ring\.teeth = 26: an internal gear needs more"):
        GearPair(pinion, small, 10.0)
    # Unshifted at its standard centre distance, the ring's tip meets the pinion below the
    # pinion's form circle (why rings carry positive shift).
    a0 = GearPair(pinion, ring, 51.945).standard_centre_distance
    with pytest.raises(GeometryError, match=r"centre_distance = .*ring tip meets pinion"):
        GearPair(pinion, ring, a0)
