"""Nominal tooth root stress by ISO 6336-3:2019 method B for external involute gears cut by a
rack (hob), and the exact 30 deg tangent point of a generated fillet for cross-checking.

    sigma_F0 = F_t / (b m_n) Y_F Y_S Y_beta Y_B Y_DT     (MPa)

F_t = 2 T1 / d1 the nominal tangential load at the reference circle (the same for both gears
of a pair), b the face width of the gear considered (ISO 6336-3: the wider gear counts at
most the narrower face width plus one module on each side), m_n the normal module.
Y_B (rim thickness) = Y_DT (deep tooth) = 1 here; K_A, K_v, K_Fbeta, K_Falpha = 1 (nominal).

Tooth form factor Y_F (load at the outer point of single pair tooth contact of the virtual
spur gear; symbols as ISO 6336-3, 6.2), basic rack of the tool: dedendum h_fP =
``dedendum_coef`` m_n, tip radius rho_fP = ``hob_tip_radius_coef`` m_n, no protuberance
(s_pr = 0), shift x:

    z_n = z / (cos(beta_b)^2 cos(beta))                           virtual spur gear
    E = pi m_n / 4 - h_fP tan(alpha_n) + s_pr / cos(alpha_n) - (1 - sin(alpha_n)) rho_fP
        / cos(alpha_n)
    G = rho_fP / m_n - h_fP / m_n + x,    H = 2 / z_n (pi / 2 - E / m_n) - pi / 3
    theta = 2 G / z_n tan(theta) - H      (fixed point from theta = pi / 6)
    s_Fn / m_n = z_n sin(pi / 3 - theta) + sqrt(3) (G / cos(theta) - rho_fP / m_n)
    rho_F / m_n = rho_fP / m_n + 2 G^2 / (cos(theta) (z_n cos(theta)^2 - 2 G))
    d_n = m_n z_n, d_bn = d_n cos(alpha_n), d_an = d_n + d_a - d,
    eps_alpha_n = eps_alpha / cos(beta_b)^2,
    d_en = 2 sqrt((sqrt((d_an/2)^2 - (d_bn/2)^2) - pi m_n cos(alpha_n) (eps_alpha_n - 1))^2
                  + (d_bn/2)^2)
    alpha_en = acos(d_bn / d_en),
    gamma_e = (pi / 2 + 2 x tan(alpha_n)) / z_n + inv(alpha_n) - inv(alpha_en),
    alpha_Fen = alpha_en - gamma_e
    h_Fe / m_n = ((cos(gamma_e) - sin(gamma_e) tan(alpha_Fen)) d_en / m_n
                  - z_n cos(pi / 3 - theta) - G / cos(theta) + rho_fP / m_n) / 2
    Y_F = 6 (h_Fe / m_n) cos(alpha_Fen) / ((s_Fn / m_n)^2 cos(alpha_n))

Stress correction factor Y_S = (1.2 + 0.13 L) q_s^(1 / (1.21 + 2.3 / L)), L = s_Fn / h_Fe,
q_s = s_Fn / (2 rho_F) (ISO validity 1 <= q_s < 8, not enforced; reported).
Helix angle factor Y_beta = 1 - eps_beta beta / 120 deg with eps_beta taken as 1 where it
exceeds 1 and beta as 30 deg where it exceeds 30 deg (so Y_beta >= 0.75). This is the
ISO 6336-3:2006 form; the 2019 edition is understood to divide it by cos(beta)^3 (1.014
instead of 0.825 at 21 deg), which we could not confirm from the text available here: any
comparison with an FE root stress must state which Y_beta it used.

``load_at = "tip"`` puts the load at the tip (d_en = d_an, eps_alpha_n - 1 -> 0), which gives
the tip-load factors Y_Fa, Y_Sa of the familiar Y_FS = Y_Fa Y_Sa charts.

Internal gears (ISO: 60 deg tangent, substitute rack) are not implemented
(NotImplementedError).
"""

from __future__ import annotations

import math

import numpy as np

from gears.involute import involute
from gears.pair import GearPair
from gears.profile import tooth_profile
from gears.spec import GearSpec


def _check_external(gear: GearSpec):
    if gear.internal:
        raise NotImplementedError(
            f"{gear.name}: ISO 6336-3 root stress of internal gears (60 deg tangent, substitute "
            "rack, shaper-cut fillet) is not implemented; only external, hob-cut gears"
        )


def virtual_teeth(gear: GearSpec) -> float:
    """z_n = z / (cos(beta_b)^2 cos(beta)) of the virtual spur gear."""
    return gear.teeth / (
        math.cos(gear.base_helix_angle) ** 2 * math.cos(math.radians(gear.helix_angle))
    )


def form_factors(gear: GearSpec, eps_alpha: float | None = None, load_at: str = "hpstc") -> dict:
    """ISO 6336-3 method B tooth form and stress correction factors of an external gear (see
    the module docstring for the equations). eps_alpha: the pair's transverse contact ratio
    (needed for ``load_at = "hpstc"``, the outer point of single pair contact);
    ``load_at = "tip"``: load at the tip circle (Y_Fa, Y_Sa).

    Returns a dict (lengths in mm, angles in rad): z_n, E, G, H, theta, s_Fn, rho_F, h_Fe,
    d_en, alpha_en, gamma_e, alpha_Fen, L, q_s, Y_F, Y_S, iterations.
    """
    _check_external(gear)
    m = gear.normal_module
    a_n = math.radians(gear.normal_pressure_angle)
    x = gear.profile_shift
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
    d_n = m * z_n
    d_bn = d_n * math.cos(a_n)
    d_an = d_n + 2.0 * (gear.tip_radius - gear.reference_radius)
    if load_at == "tip":
        d_en = d_an
    elif load_at == "hpstc":
        if eps_alpha is None:
            raise ValueError("load_at = 'hpstc' needs the pair's transverse contact ratio")
        eps_an = eps_alpha / math.cos(gear.base_helix_angle) ** 2
        roll = math.sqrt((0.5 * d_an) ** 2 - (0.5 * d_bn) ** 2)
        roll -= math.pi * m * math.cos(a_n) * (eps_an - 1.0)
        d_en = 2.0 * math.sqrt(roll * roll + (0.5 * d_bn) ** 2)
    else:
        raise ValueError(f"load_at = {load_at!r}: must be 'hpstc' or 'tip'")
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
    ell = s_fn / h_fe
    q_s = s_fn / (2.0 * rho_f)
    y_s = (1.2 + 0.13 * ell) * q_s ** (1.0 / (1.21 + 2.3 / ell))
    return dict(
        z_n=z_n, E=e, G=g, H=h, theta=theta, s_Fn=s_fn, rho_F=rho_f, h_Fe=h_fe, d_en=d_en,
        alpha_en=alpha_en, gamma_e=float(gamma_e), alpha_Fen=float(alpha_fen), L=ell, q_s=q_s,
        Y_F=float(y_f), Y_S=y_s, iterations=its,
    )  # fmt: skip


def helix_factor(eps_beta: float, helix_angle_deg: float) -> float:
    """Y_beta = 1 - eps_beta beta / 120 deg; eps_beta > 1 taken as 1, beta > 30 deg as 30."""
    return 1.0 - min(eps_beta, 1.0) * min(helix_angle_deg, 30.0) / 120.0


def nominal_root_stress(pair: GearPair, i: int, torque1: float, load_at: str = "hpstc") -> dict:
    """ISO 6336-3:2019 method B nominal root stress sigma_F0 (MPa) of gear i (1 or 2,
    external) of the pair for the torque torque1 (N mm) on gear1:

        sigma_F0 = F_t / (b m_n) Y_F Y_S Y_beta Y_B Y_DT,  F_t = 2 T1 / d1,
        b = min(b_i, b_mate + 2 m_n),  Y_B = Y_DT = 1,  all K factors 1.

    eps_alpha and eps_beta are the pair's (``transverse_contact_ratio``, ``overlap_ratio``).
    Returns the ``form_factors`` dict plus F_t, b, Y_beta, Y_B, Y_DT, sigma_F0.
    """
    gear, mate = pair.gear(i), pair.gear(3 - i)
    _check_external(gear)
    f = form_factors(gear, pair.transverse_contact_ratio, load_at=load_at)
    m = gear.normal_module
    f_t = torque1 / pair.gear1.reference_radius
    b = min(gear.face_width, mate.face_width + 2.0 * m)
    y_beta = helix_factor(pair.overlap_ratio, gear.helix_angle)
    sigma = f_t / (b * m) * f["Y_F"] * f["Y_S"] * y_beta
    return f | dict(F_t=f_t, b=b, Y_beta=y_beta, Y_B=1.0, Y_DT=1.0, sigma_F0=sigma)


def fillet_tangent_point(gear: GearSpec, angle_deg: float = 30.0, n_fillet: int = 4001) -> dict:
    """Exact counterpart of ISO's s_Fn and rho_F on the generated transverse fillet of
    ``gears.profile.tooth_profile`` (for a spur gear the virtual gear is the gear).

    Finds the point of the +theta fillet of tooth 0 (symmetric about +x) whose tangent makes
    ``angle_deg`` with the tooth centre line, and the fillet's radius of curvature there. The
    fillet samples are evenly spaced in the tool's rounding parameter t, so second-order
    central differences in the sample index give x', y', x'', y'' (O(h^2)); the point and the
    curvature |r'|^3 / |x' y'' - y' x''| are interpolated linearly in the tangent angle.
    Returns s_Fn = 2 y (chord between the two tangent points, mm), rho_F (mm), the point
    (x, y) and its radius.
    """
    _check_external(gear)
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
