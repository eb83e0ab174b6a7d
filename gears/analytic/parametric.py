"""Parametric misalignment study of the double pinion (singh2007 Fig. 6 and Table 6).

With FzSUN = -FzRP = FA, equal operating pressure angles a and equal pinion radii R, the
Table 4 moments reduce to::

    M_SP-SUN LOA(theta) = FA R (sin(theta - a) + sin(a))     worst at theta = 90 deg + a
    M_RP-RING LOA(phi)  = FA R (sin(phi + a) + sin(a))       worst at phi   = 90 deg - a

(the RP-ring value is the magnitude; Table 4 gives it with a minus sign). Both reduce to the
single pinion value 2 FA R sin(a) at theta = 180 deg (phi = 0), which the sun-SP curve meets
again at the "equivalent" angle theta = 2a. Worst / single = (1 + sin a) / (2 sin a).

Table 6 uses the paper's stated FA R = 133 N m. Angles in radians unless a name ends in
``_deg``; moments N m.
"""

from __future__ import annotations

import math

import numpy as np

FA_R_PAPER = 133.0  # N m: singh2007 section 6, the stated FA R of Table 6
TABLE6_PRESSURE_ANGLES_DEG = (15.0, 20.0, 25.0, 30.0)


def m_sp_sun_loa(theta, alpha: float, fa_r: float):
    """M_SP-SUN LOA(theta) = FA R (sin(theta - a) + sin a), N m; theta may be an array."""
    return fa_r * (np.sin(np.asarray(theta) - alpha) + math.sin(alpha))


def m_rp_ring_loa(phi, alpha: float, fa_r: float):
    """|M_RP-RING LOA|(phi) = FA R (sin(phi + a) + sin a), N m; phi may be an array."""
    return fa_r * (np.sin(np.asarray(phi) + alpha) + math.sin(alpha))


def worst_theta(alpha: float) -> float:
    """theta maximising M_SP-SUN LOA: 90 deg + a (rad)."""
    return 0.5 * math.pi + alpha


def worst_phi(alpha: float) -> float:
    """phi maximising M_RP-RING LOA: 90 deg - a (rad)."""
    return 0.5 * math.pi - alpha


def equivalent_theta(alpha: float) -> float:
    """theta < 180 deg where M_SP-SUN LOA equals the single pinion value: 2a (rad)."""
    return 2.0 * alpha


def worst_moment(alpha: float, fa_r: float) -> float:
    """Maximum LOA moment over the triangle angle: FA R (1 + sin a), N m."""
    return fa_r * (1.0 + math.sin(alpha))


def single_equivalent(alpha: float, fa_r: float) -> float:
    """Single pinion LOA moment: 2 FA R sin a, N m (theta = 180 deg, phi = 0)."""
    return 2.0 * fa_r * math.sin(alpha)


def worst_ratio(alpha: float) -> float:
    """Worst / single = (1 + sin a) / (2 sin a), independent of FA R."""
    return (1.0 + math.sin(alpha)) / (2.0 * math.sin(alpha))


def table6_row(pressure_angle_deg: float, fa_r: float = FA_R_PAPER) -> dict[str, float]:
    """One row of singh2007 Table 6 (angles in deg, moments N m)."""
    a = math.radians(pressure_angle_deg)
    return {
        "pressure_angle": pressure_angle_deg,
        "worst_moment": worst_moment(a, fa_r),
        "single_moment": single_equivalent(a, fa_r),
        "ratio": worst_ratio(a),
        "worst_theta": math.degrees(worst_theta(a)),
        "equiv_theta": math.degrees(equivalent_theta(a)),
        "worst_phi": math.degrees(worst_phi(a)),
    }


def table6(
    fa_r: float = FA_R_PAPER, angles_deg: tuple[float, ...] = TABLE6_PRESSURE_ANGLES_DEG
) -> list[dict[str, float]]:
    """singh2007 Table 6 rows for the given pressure angles (deg)."""
    return [table6_row(a, fa_r) for a in angles_deg]
