"""Hertz line contact along the path of contact of an involute helical mesh, and the nominal
ISO 6336-2 contact stress at the pitch point for comparison.

DESIGN.md: read the load per unit length along the contact lines from the FE solution and get
the contact stress from Hertz line contact with the exact local curvatures. This module gives
those curvatures and the Hertz formulas; the line load w comes from the caller.

Position on the path of contact
-------------------------------
``s`` (mm) is the signed distance along the transverse line of action from the operating
pitch point C, positive towards gear1's tip (where gear1's involute radius of curvature grows).
With the operating transverse pressure angle alpha_wt and T_i the tangent points of the line
of action on the base circles, the transverse involute radii of curvature (roll lengths) are

    rho_t1 = r_b1 tan(alpha_wt) + s                 (= sqrt(r1^2 - r_b1^2) at radius r1)
    external: rho_t2 = r_b2 tan(alpha_wt) - s,      rho_t1 + rho_t2 = a sin(alpha_wt)
    internal: rho_t2 = r_b2 tan(alpha_wt) + s,      rho_t2 - rho_t1 = a sin(alpha_wt)

(internal: both tangent points lie on the same side of C; the ring flank is concave).

Normal-plane curvature of a helical involute flank along its (straight) contact line: the
contact line lies in the plane of action, inclined at beta_b to the axis, and the flank's
normal curvature perpendicular to it is that of the transverse involute projected into the
normal plane, rho_n = rho_t / cos(beta_b). Relative radius of curvature (mm)

    1 / R = 1 / rho_n1 + sigma / rho_n2,    sigma = +1 external, -1 internal (concave flank).

Hertz line contact (two elastic cylinders, plane strain, line load w N/mm normal to the
surfaces, along the contact line), contact modulus E* (MPa)

    1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2,
    b = sqrt(4 w R / (pi E*))   (half-width),    p_max = sqrt(w E* / (pi R)) = 2 w / (pi b).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gears import material
from gears.pair import GearPair

STEEL = (material.STEEL.youngs_modulus, material.STEEL.poisson_ratio)  # (E MPa, nu)


def contact_modulus(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """E* (MPa): 1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2."""
    return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)


def hertz_line_contact(w, radius, e_star):
    """Hertz line contact: (half-width b mm, p_max MPa), vectorised.

    w: normal load per unit length of the contact line (N/mm); radius: relative radius of
    curvature R (mm, 1/R = 1/R1 + 1/R2, R2 = inf for a plane); e_star: contact modulus (MPa).
    b = sqrt(4 w R / (pi E*)), p_max = sqrt(w E* / (pi R)); the pressure is
    p(y) = p_max sqrt(1 - y^2 / b^2) and integrates to w.
    """
    w = np.asarray(w, dtype=float)
    radius = np.asarray(radius, dtype=float)
    if np.any(w < 0.0) or np.any(radius <= 0.0) or e_star <= 0.0:
        raise ValueError("hertz_line_contact: needs w >= 0, R > 0 and E* > 0")
    b = np.sqrt(4.0 * w * radius / (math.pi * e_star))
    p_max = np.sqrt(w * e_star / (math.pi * radius))
    return b[()], p_max[()]


def pitch_roll(pair: GearPair, i: int) -> float:
    """Transverse roll length of gear i at the operating pitch point, r_bi tan(alpha_wt) (mm)."""
    return pair.gear(i).base_radius * math.tan(pair.operating_pressure_angle)


def position_from_radius(pair: GearPair, r1):
    """s (mm, vectorised) of the contact point at radius r1 on gear1:
    s = sqrt(r1^2 - r_b1^2) - r_b1 tan(alpha_wt)."""
    r_b1 = pair.gear1.base_radius
    r1 = np.asarray(r1, dtype=float)
    if np.any(r1 < r_b1):
        raise ValueError(f"r1 = {float(np.min(r1)):.6g} mm: below gear1's base radius {r_b1:.6g}")
    return (np.sqrt(r1 * r1 - r_b1 * r_b1) - pitch_roll(pair, 1))[()]


def path_of_contact(pair: GearPair) -> tuple[float, float]:
    """(s_start, s_end) (mm) of the transverse path of contact from the tip circles:
    gear1 tip at s_end = L_a1 - r_b1 tan(alpha_wt), L_ai = sqrt(r_ai^2 - r_bi^2);
    external: gear2 tip at s_start = r_b2 tan(alpha_wt) - L_a2;
    internal: ring tip (inner) circle at s_start = L_a2 - r_b2 tan(alpha_wt)."""
    g1, g2 = pair.gear1, pair.gear2
    l_a1 = math.sqrt(g1.tip_radius**2 - g1.base_radius**2)
    l_a2 = math.sqrt(g2.tip_radius**2 - g2.base_radius**2)
    start = l_a2 - pitch_roll(pair, 2) if pair.internal else pitch_roll(pair, 2) - l_a2
    return start, l_a1 - pitch_roll(pair, 1)


@dataclass(frozen=True)
class FlankContact:
    """Hertz line contact of a mesh at position(s) s (arrays broadcast like s and w)."""

    s: np.ndarray  # position on the line of action from the pitch point, mm
    rho_t1: np.ndarray  # transverse involute radius of curvature, gear1 (convex), mm
    rho_t2: np.ndarray  # gear2 (convex external, concave internal: magnitude), mm
    rho_n1: np.ndarray  # normal-plane radii rho_t / cos(beta_b), mm
    rho_n2: np.ndarray
    radius: np.ndarray  # relative radius R, 1/R = 1/rho_n1 + sigma/rho_n2, mm
    e_star: float  # contact modulus, MPa
    w: np.ndarray  # normal line load along the contact line, N/mm
    half_width: np.ndarray  # b, mm
    p_max: np.ndarray  # MPa


def flank_curvatures(pair: GearPair, s):
    """(rho_t1, rho_t2, rho_n1, rho_n2, R) at position s (mm, vectorised); see the module
    docstring. ValueError where s leaves the line of action between the base tangent points
    (a radius <= 0). The tip circles are not checked: see ``path_of_contact``."""
    s = np.asarray(s, dtype=float)
    sigma = -1.0 if pair.internal else 1.0
    rho_t1 = pitch_roll(pair, 1) + s
    rho_t2 = pitch_roll(pair, 2) - sigma * s
    if np.any(rho_t1 <= 0.0) or np.any(rho_t2 <= 0.0):
        raise ValueError("s outside the line of action between the base tangent points")
    cos_bb = math.cos(pair.gear1.base_helix_angle)
    rho_n1, rho_n2 = rho_t1 / cos_bb, rho_t2 / cos_bb
    radius = 1.0 / (1.0 / rho_n1 + sigma / rho_n2)
    return rho_t1[()], rho_t2[()], rho_n1[()], rho_n2[()], radius[()]


def mesh_contact(pair: GearPair, s, w, material1=STEEL, material2=STEEL) -> FlankContact:
    """Hertz line contact at position s (mm from the pitch point along the line of action,
    see the module docstring) under the normal line load w (N/mm along the contact line);
    material_i = (E MPa, nu). Returns the curvatures, E*, b and p_max (``FlankContact``)."""
    rho_t1, rho_t2, rho_n1, rho_n2, radius = flank_curvatures(pair, s)
    e_star = contact_modulus(*material1, *material2)
    s_arr, w_arr = np.broadcast_arrays(np.asarray(s, dtype=float), np.asarray(w, dtype=float))
    b, p_max = hertz_line_contact(w_arr, np.broadcast_to(radius, s_arr.shape), e_star)
    return FlankContact(
        s_arr[()], rho_t1, rho_t2, rho_n1, rho_n2, radius, e_star, w_arr[()], b, p_max
    )


def nominal_line_load(pair: GearPair, torque1: float, lines: str = "single") -> float:
    """Uniform normal line load (N/mm) for the torque torque1 (N mm) on gear1.

    Normal tooth force F_n = T1 / (r_b1 cos(beta_b)); the face width b is the smaller of the
    two. ``lines = "single"``: one contact line across the face, length b / cos(beta_b):
    w = F_n cos(beta_b) / b = F_t / (b cos(alpha_wt)) with F_t = T1 / r_w1 (the load the ISO
    formula without Z_eps and Z_beta carries). ``lines = "mean"``: the mean total length of
    the contact lines b eps_alpha / cos(beta_b) (eps_beta >= 1), w = F_n cos(beta_b) / (b
    eps_alpha) (the load ISO's Z_eps = sqrt(1 / eps_alpha) stands for when eps_beta >= 1).
    """
    g1 = pair.gear1
    b = min(g1.face_width, pair.gear2.face_width)
    f_n = torque1 / (g1.base_radius * math.cos(g1.base_helix_angle))
    w = f_n * math.cos(g1.base_helix_angle) / b
    if lines == "single":
        return w
    if lines == "mean":
        return w / pair.transverse_contact_ratio
    raise ValueError(f"lines = {lines!r}: must be 'single' or 'mean'")


def iso6336_pitch_contact_stress(
    pair: GearPair,
    torque1: float,
    material1=STEEL,
    material2=STEEL,
    z_eps: bool = True,
    z_beta: bool = True,
) -> dict:
    """Nominal ISO 6336-2:2019 (method B) contact stress at the pitch point, K factors = 1.

    sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t / (d1 b) (u + 1) / u)    (MPa), with
    F_t = 2 T1 / d1 (reference diameter d1 = 2 r1, torque1 in N mm), b the smaller face width,
    u = z2 / z1 (> 0 also for an internal gear; the concave flank enters as (u - 1) / u, i.e.
    the ISO form with u < 0 for internal gears),
    Z_H = sqrt(2 cos(beta_b) cos(alpha_wt) / (cos(alpha_t)^2 sin(alpha_wt))),
    Z_E = sqrt(E* / pi) (= sqrt(1 / (pi ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)))),
    Z_eps: eps_beta < 1: sqrt((4 - eps_alpha)/3 (1 - eps_beta) + eps_beta / eps_alpha),
    eps_beta >= 1: sqrt(1 / eps_alpha); Z_beta = sqrt(1 / cos(beta)).
    Not included (= 1): K_A, K_v, K_Hbeta, K_Halpha, Z_B / Z_D (single pair contact factors).
    ``z_eps`` / ``z_beta`` False set that factor to 1: with both False sigma_H0 equals the
    Hertz p_max at the pitch point under ``nominal_line_load(pair, torque1, "single")``
    exactly; with only z_beta False and eps_beta >= 1 it equals p_max under the "mean" load.
    Returns a dict of F_t, u, Z_H, Z_E, Z_eps, Z_beta and sigma_H0.
    """
    g1, g2 = pair.gear1, pair.gear2
    d1 = 2.0 * g1.reference_radius
    b = min(g1.face_width, g2.face_width)
    f_t = 2.0 * torque1 / d1
    u = g2.teeth / g1.teeth
    sigma = -1.0 if pair.internal else 1.0
    a_t, a_w = g1.transverse_pressure_angle, pair.operating_pressure_angle
    beta = math.radians(g1.helix_angle)
    z_h = math.sqrt(
        2.0 * math.cos(g1.base_helix_angle) * math.cos(a_w) / (math.cos(a_t) ** 2 * math.sin(a_w))
    )
    z_e = math.sqrt(contact_modulus(*material1, *material2) / math.pi)
    e_a, e_b = pair.transverse_contact_ratio, pair.overlap_ratio
    if not z_eps:
        z_ep = 1.0
    elif e_b < 1.0:
        z_ep = math.sqrt((4.0 - e_a) / 3.0 * (1.0 - e_b) + e_b / e_a)
    else:
        z_ep = math.sqrt(1.0 / e_a)
    z_b = math.sqrt(1.0 / math.cos(beta)) if z_beta else 1.0
    sigma_h0 = z_h * z_e * z_ep * z_b * math.sqrt(f_t / (d1 * b) * (u + sigma) / u)
    return dict(F_t=f_t, u=u, Z_H=z_h, Z_E=z_e, Z_eps=z_ep, Z_beta=z_b, sigma_H0=sigma_h0)
