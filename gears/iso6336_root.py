"""Nominal tooth root stress by ISO 6336-3 method B for external involute gears cut by a rack
(hob) and for internal gears (substitute rack, 60 deg tangent), and the exact 30 / 60 deg
tangent point of a generated fillet for cross-checking.

    sigma_F0 = F_t / (b m_n) Y_F Y_S Y_beta Y_B Y_DT     (MPa)

F_t = 2 T1 / d1 the nominal tangential load at the reference circle (the same for both gears
of a pair), b the face width of the gear considered (ISO 6336-3: the wider gear counts at
most the narrower face width plus one module on each side), m_n the normal module.
Y_B (rim thickness) = Y_DT (deep tooth) = 1 here; K_A, K_v, K_Fbeta, K_Falpha = 1 (nominal).

Tooth thickness allowance: the flanks and fillets are those of the generating shift
x_E = x + sigma A_sn / (2 m_n tan(alpha_n)) (:attr:`gears.spec.GearSpec.generating_shift`,
the tool fed in by the allowance), so x_E replaces x wherever ISO's x sets the tooth
thickness (G, gamma_e); the tip circle stays that of the nominal x. For case 1
(A_sn = -47.4 um on every gear) this thins the sun and pinion critical section s_Fn by
0.022 and 0.028 mm and raises their sigma_F0 by 2.7-3.1 %; the ring's rack tooth keeps its
s_Fn, but its datum moves 0.065 mm outwards under the same tip circle and load point, which
lengthens the lever arm h_Fe (+2.2 %).

External gear: tooth form factor Y_F (load at the outer point of single pair tooth contact
of the virtual spur gear; symbols as ISO 6336-3, 6.2), basic rack of the tool: dedendum
h_fP = ``dedendum_coef`` m_n, tip radius rho_fP = ``hob_tip_radius_coef`` m_n, no
protuberance (s_pr = 0), shift x_E:

    z_n = z / (cos(beta_b)^2 cos(beta))                           virtual spur gear
    E = pi m_n / 4 - h_fP tan(alpha_n) + s_pr / cos(alpha_n) - (1 - sin(alpha_n)) rho_fP
        / cos(alpha_n)
    G = rho_fP / m_n - h_fP / m_n + x_E,    H = 2 / z_n (pi / 2 - E / m_n) - pi / 3
    theta = 2 G / z_n tan(theta) - H      (fixed point from theta = pi / 6)
    s_Fn / m_n = z_n sin(pi / 3 - theta) + sqrt(3) (G / cos(theta) - rho_fP / m_n)
    rho_F / m_n = rho_fP / m_n + 2 G^2 / (cos(theta) (z_n cos(theta)^2 - 2 G))
    d_n = m_n z_n, d_bn = d_n cos(alpha_n), d_an = d_n + d_a - d,
    eps_alpha_n = eps_alpha / cos(beta_b)^2,
    d_en = 2 sqrt((sqrt((d_an/2)^2 - (d_bn/2)^2) - pi m_n cos(alpha_n) (eps_alpha_n - 1))^2
                  + (d_bn/2)^2)
    alpha_en = acos(d_bn / d_en),
    gamma_e = (pi / 2 + 2 x_E tan(alpha_n)) / z_n + inv(alpha_n) - inv(alpha_en),
    alpha_Fen = alpha_en - gamma_e
    h_Fe / m_n = ((cos(gamma_e) - sin(gamma_e) tan(alpha_Fen)) d_en / m_n
                  - z_n cos(pi / 3 - theta) - G / cos(theta) + rho_fP / m_n) / 2
    Y_F = 6 (h_Fe / m_n) cos(alpha_Fen) / ((s_Fn / m_n)^2 cos(alpha_n))

Internal gear (ISO 6336-3: the form factor of a rack whose tooth is the internal gear's
basic rack tooth, critical section where the fillet tangent makes 60 deg with the tooth
centre line, load at the outer point of single pair contact of the virtual internal gear).
The internal gear's rack tooth has flanks at alpha_n, dedendum h_fP = ``dedendum_coef``
m_n from its datum line and a root rounding of radius rho_fP = ``hob_tip_radius_coef`` m_n
(the shaper's tip rounding); depths y (normal section) are measured from the datum line,
which lies at the radius r_n + x_E m_n of the virtual gear, towards the root (outwards). A
shift moves a rack tooth without changing it, so with s(y) = pi m_n / 4 + y tan(alpha_n) the
half thickness of the flank:

    critical point (rounding centre at depth h_fP - rho_fP, tangent at 60 deg):
    s_Fn = 2 (s(h_fP - rho_fP) + rho_fP / cos(alpha_n) - rho_fP cos(60 deg)),
    y_F = h_fP - rho_fP (1 - sin(60 deg)),    rho_F = rho_fP
    load point: d_an = d_n + d_a - d (< d_n), d_en = 2 sqrt((sqrt((d_an/2)^2 - (d_bn/2)^2)
                  + pi m_n cos(alpha_n) (eps_alpha_n - 1))^2 + (d_bn/2)^2)
                (one base pitch times (eps_alpha_n - 1) from the tip, towards the root),
    alpha_Fen = alpha_en = acos(d_bn / d_en),   y_e = d_en / 2 - d_n / 2 - x_E m_n,
    h_Fe = y_F - y_e - s(y_e) tan(alpha_Fen)
           (the load line meets the tooth centre line s(y_e) tan(alpha_Fen) deeper than the
            load point; h_Fe is its distance from the critical section)
    Y_F = 6 (h_Fe / m_n) cos(alpha_Fen) / ((s_Fn / m_n)^2 cos(alpha_n))

Stress correction factor Y_S = (1.2 + 0.13 L) q_s^(1 / (1.21 + 2.3 / L)), L = s_Fn / h_Fe,
q_s = s_Fn / (2 rho_F) (ISO validity 1 <= q_s < 8, not enforced; reported).

Helix angle factor, edition 2006 (the default, used by every nominal stress the pipeline
reports): Y_beta = 1 - eps_beta beta / 120 deg with eps_beta taken as 1 where it exceeds 1
and beta as 30 deg where it exceeds 30 deg (so Y_beta >= 0.75; 0.825 for case 1). Edition
2019 (``edition=2019``): the same divided by cos(beta)^3 (1.014 for case 1), as we
understand the 2019 text; we could not check it against the standard here. The 2006 form is
the default because the paper (2007) and the ISO-based literature it compares with use it,
and because it is the form we can quote; both are reported so a reader sees the 23 %
spread the choice makes (1 / cos(21 deg)^3 = 1.23).

``load_at = "tip"`` puts the load at the tip (d_en = d_an, eps_alpha_n - 1 -> 0), which gives
the tip-load factors Y_Fa, Y_Sa of the familiar Y_FS = Y_Fa Y_Sa charts.
"""

from __future__ import annotations

import math

import numpy as np

from gears.involute import involute
from gears.pair import GearPair
from gears.profile import tooth_profile
from gears.spec import GearSpec


def virtual_teeth(gear: GearSpec) -> float:
    """z_n = z / (cos(beta_b)^2 cos(beta)) of the virtual spur gear."""
    return gear.teeth / (
        math.cos(gear.base_helix_angle) ** 2 * math.cos(math.radians(gear.helix_angle))
    )


def _virtual_load_diameter(gear: GearSpec, z_n: float, eps_alpha, load_at: str):
    """(d_n, d_bn, d_an, d_en) of the virtual gear; the load at the outer point of single pair
    contact (``"hpstc"``) or at the tip (``"tip"``); see the module docstring."""
    m = gear.normal_module
    d_n = m * z_n
    d_bn = d_n * math.cos(math.radians(gear.normal_pressure_angle))
    d_an = d_n + 2.0 * (gear.tip_radius - gear.reference_radius)
    if load_at == "tip":
        return d_n, d_bn, d_an, d_an
    if load_at != "hpstc":
        raise ValueError(f"load_at = {load_at!r}: must be 'hpstc' or 'tip'")
    if eps_alpha is None:
        raise ValueError("load_at = 'hpstc' needs the pair's transverse contact ratio")
    eps_an = eps_alpha / math.cos(gear.base_helix_angle) ** 2
    step = math.pi * m * math.cos(math.radians(gear.normal_pressure_angle)) * (eps_an - 1.0)
    roll = math.sqrt((0.5 * d_an) ** 2 - (0.5 * d_bn) ** 2) - gear.sigma * step
    return d_n, d_bn, d_an, 2.0 * math.sqrt(roll * roll + (0.5 * d_bn) ** 2)


def _stress_correction(s_fn: float, h_fe: float, rho_f: float) -> tuple[float, float, float]:
    """(L, q_s, Y_S): Y_S = (1.2 + 0.13 L) q_s^(1 / (1.21 + 2.3 / L))."""
    ell = s_fn / h_fe
    q_s = s_fn / (2.0 * rho_f)
    return ell, q_s, (1.2 + 0.13 * ell) * q_s ** (1.0 / (1.21 + 2.3 / ell))


def form_factors(gear: GearSpec, eps_alpha: float | None = None, load_at: str = "hpstc") -> dict:
    """ISO 6336-3 method B tooth form and stress correction factors (see the module
    docstring for the equations; internal gears by the substitute rack). eps_alpha: the
    pair's transverse contact ratio (needed for ``load_at = "hpstc"``, the outer point of
    single pair contact); ``load_at = "tip"``: load at the tip circle (Y_Fa, Y_Sa).

    Returns a dict (lengths in mm, angles in rad): z_n, x_E, s_Fn, rho_F, h_Fe, d_en,
    alpha_en, alpha_Fen, L, q_s, Y_F, Y_S; external gears also E, G, H, theta, gamma_e,
    iterations; internal gears y_F, y_e (depths from the rack datum).
    """
    if gear.internal:
        return _internal_form_factors(gear, eps_alpha, load_at)
    m = gear.normal_module
    a_n = math.radians(gear.normal_pressure_angle)
    x = gear.generating_shift
    h_fp, rho_fp = gear.dedendum_coef * m, gear.hob_tip_radius_coef * m
    z_n = virtual_teeth(gear)
    e = math.pi / 4.0 * m - h_fp * math.tan(a_n) - (1.0 - math.sin(a_n)) * rho_fp / math.cos(a_n)
    g = rho_fp / m - h_fp / m + x
    h = 2.0 / z_n * (math.pi / 2.0 - e / m) - math.pi / 3.0
    theta, its = math.pi / 6.0, 0
    while True:  # contraction: |d/dtheta| = 2 |G| / (z_n cos(theta)^2) < 1
        its += 1
        new = 2.0 * g / z_n * math.tan(theta) - h
        done = abs(new - theta) <= 1e-14
        theta = new
        if done:
            break
        if its >= 200:
            raise RuntimeError(f"{gear.name}: ISO 6336-3 theta iteration did not converge")
    s_fn = m * (
        z_n * math.sin(math.pi / 3.0 - theta) + math.sqrt(3.0) * (g / math.cos(theta) - rho_fp / m)
    )
    rho_f = m * (
        rho_fp / m + 2.0 * g * g / (math.cos(theta) * (z_n * math.cos(theta) ** 2 - 2.0 * g))
    )
    _, d_bn, _, d_en = _virtual_load_diameter(gear, z_n, eps_alpha, load_at)
    alpha_en = math.acos(d_bn / d_en)
    gamma_e = (0.5 * math.pi + 2.0 * x * math.tan(a_n)) / z_n + involute(a_n) - involute(alpha_en)
    alpha_fen = alpha_en - gamma_e
    h_fe = (
        0.5
        * m
        * (
            (math.cos(gamma_e) - math.sin(gamma_e) * math.tan(alpha_fen)) * d_en / m
            - z_n * math.cos(math.pi / 3.0 - theta)
            - g / math.cos(theta)
            + rho_fp / m
        )
    )
    y_f = 6.0 * (h_fe / m) * math.cos(alpha_fen) / ((s_fn / m) ** 2 * math.cos(a_n))
    ell, q_s, y_s = _stress_correction(s_fn, h_fe, rho_f)
    return dict(
        z_n=z_n,
        x_E=x,
        E=e,
        G=g,
        H=h,
        theta=theta,
        s_Fn=s_fn,
        rho_F=rho_f,
        h_Fe=h_fe,
        d_en=d_en,
        alpha_en=alpha_en,
        gamma_e=float(gamma_e),
        alpha_Fen=float(alpha_fen),
        L=ell,
        q_s=q_s,
        Y_F=float(y_f),
        Y_S=y_s,
        iterations=its,
    )


def _internal_form_factors(gear: GearSpec, eps_alpha, load_at: str) -> dict:
    """Substitute-rack form factors of an internal gear (module docstring)."""
    m = gear.normal_module
    a_n = math.radians(gear.normal_pressure_angle)
    x = gear.generating_shift
    h_fp, rho = gear.dedendum_coef * m, gear.hob_tip_radius_coef * m
    z_n = virtual_teeth(gear)
    half = lambda y: math.pi * m / 4.0 + y * math.tan(a_n)  # noqa: E731 - rack flank s(y)
    tangent = math.radians(60.0)
    s_fn = 2.0 * (half(h_fp - rho) + rho / math.cos(a_n) - rho * math.cos(tangent))
    y_f = h_fp - rho * (1.0 - math.sin(tangent))
    d_n, d_bn, _, d_en = _virtual_load_diameter(gear, z_n, eps_alpha, load_at)
    alpha_en = math.acos(d_bn / d_en)
    y_e = 0.5 * (d_en - d_n) - x * m
    h_fe = y_f - y_e - half(y_e) * math.tan(alpha_en)
    y_form = 6.0 * (h_fe / m) * math.cos(alpha_en) / ((s_fn / m) ** 2 * math.cos(a_n))
    ell, q_s, y_s = _stress_correction(s_fn, h_fe, rho)
    return dict(
        z_n=z_n,
        x_E=x,
        s_Fn=s_fn,
        rho_F=rho,
        h_Fe=h_fe,
        y_F=y_f,
        y_e=y_e,
        d_en=d_en,
        alpha_en=alpha_en,
        alpha_Fen=alpha_en,
        L=ell,
        q_s=q_s,
        Y_F=y_form,
        Y_S=y_s,
    )


EDITIONS = (2006, 2019)


def helix_factor(eps_beta: float, helix_angle_deg: float, edition: int = 2006) -> float:
    """Y_beta of ISO 6336-3 (module docstring): 2006, 1 - eps_beta beta / 120 deg (eps_beta
    > 1 taken as 1, beta > 30 deg as 30); 2019, that divided by cos(beta)^3."""
    if edition not in EDITIONS:
        raise ValueError(f"edition = {edition!r}: must be one of {EDITIONS}")
    y = 1.0 - min(eps_beta, 1.0) * min(helix_angle_deg, 30.0) / 120.0
    if edition == 2019:
        y /= math.cos(math.radians(helix_angle_deg)) ** 3
    return y


def nominal_root_stress(
    pair: GearPair, i: int, torque1: float, load_at: str = "hpstc", edition: int = 2006
) -> dict:
    """ISO 6336-3 method B nominal root stress sigma_F0 (MPa) of gear i (1 or 2; external or
    internal) of the pair for the torque torque1 (N mm) on gear1:

        sigma_F0 = F_t / (b m_n) Y_F Y_S Y_beta Y_B Y_DT,  F_t = 2 T1 / d1,
        b = min(b_i, b_mate + 2 m_n),  Y_B = Y_DT = 1,  all K factors 1.

    eps_alpha and eps_beta are the pair's (``transverse_contact_ratio``, ``overlap_ratio``);
    Y_beta of the ``edition`` (2006 default, see the module docstring).
    Returns the ``form_factors`` dict plus F_t, b, Y_beta, edition, Y_B, Y_DT, sigma_F0.
    """
    gear, mate = pair.gear(i), pair.gear(3 - i)
    f = form_factors(gear, pair.transverse_contact_ratio, load_at=load_at)
    m = gear.normal_module
    f_t = torque1 / pair.gear1.reference_radius
    b = min(gear.face_width, mate.face_width + 2.0 * m)
    y_beta = helix_factor(pair.overlap_ratio, gear.helix_angle, edition)
    sigma = f_t / (b * m) * f["Y_F"] * f["Y_S"] * y_beta
    return f | dict(F_t=f_t, b=b, Y_beta=y_beta, edition=edition, Y_B=1.0, Y_DT=1.0, sigma_F0=sigma)


def fillet_tangent_point(
    gear: GearSpec, angle_deg: float | None = None, n_fillet: int = 4001
) -> dict:
    """Exact counterpart of ISO's s_Fn and rho_F on the generated transverse fillet of
    ``gears.profile.tooth_profile`` (for a spur gear the virtual gear is the gear; for an
    internal gear ISO's substitute rack is an approximation of this shaper-cut fillet).

    Finds the point of the +theta fillet of tooth 0 (symmetric about +x) whose tangent makes
    ``angle_deg`` (default: 30 external, 60 internal, ISO's) with the tooth centre line, and
    the fillet's radius of curvature there. The fillet samples are evenly spaced in the
    tool's rounding parameter t, so second-order central differences in the sample index
    give x', y', x'', y'' (O(h^2)); the point and the curvature |r'|^3 / |x' y'' - y' x''|
    are interpolated linearly in the tangent angle. Returns s_Fn = 2 y (chord between the two
    tangent points, mm), rho_F (mm), the point (x, y) and its radius.
    """
    if angle_deg is None:
        angle_deg = 60.0 if gear.internal else 30.0
    pts = tooth_profile(gear, n_fillet=n_fillet).fillet_pos
    d1 = np.gradient(pts, axis=0, edge_order=2)
    d2 = np.gradient(d1, axis=0, edge_order=2)
    phi = np.degrees(np.arctan2(np.abs(d1[:, 1]), np.abs(d1[:, 0])))  # 90 at the root circle
    rho = np.linalg.norm(d1, axis=1) ** 3 / np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    k = int(np.nonzero((phi[:-1] - angle_deg) * (phi[1:] - angle_deg) <= 0.0)[0][0])
    t = (angle_deg - phi[k]) / (phi[k + 1] - phi[k])
    p = (1.0 - t) * pts[k] + t * pts[k + 1]
    rho_f = (1.0 - t) * rho[k] + t * rho[k + 1]
    return dict(s_Fn=2.0 * abs(p[1]), rho_F=float(rho_f), point=p, radius=float(np.hypot(*p)))
