"""Closed-form pinion moments of a double pinion planetary (singh2007 Tables 4 and 5).

Triangle of the sun centre, the sun pinion (SP) centre and the ring pinion (RP) centre:
psi at the sun centre, theta at the SP centre, phi at the RP centre. Its sides are the
centre distances sun-SP, SP-RP and sun-RP; the ring is coaxial with the sun, so sun-RP is
the RP-ring centre distance. Angles by the law of cosines::

    cos(psi)   = (d_sun_sp^2 + d_sun_rp^2 - d_sp_rp^2) / (2 d_sun_sp d_sun_rp)
    cos(theta) = (d_sun_sp^2 + d_sp_rp^2 - d_sun_rp^2) / (2 d_sun_sp d_sp_rp)
    cos(phi)   = (d_sp_rp^2 + d_sun_rp^2 - d_sun_sp^2) / (2 d_sp_rp d_sun_rp)

Concentrated loads at mid face width: only the axial mesh forces give tilting moments
(Table 4)::

    Mx-SP = -FzRP R_SP-RP sin(theta)        My-SP = FzSUN R_SP-SUN + FzRP R_SP-RP cos(theta)
    Mx-RP =  FzSP R_RP-SP sin(phi)          My-RP = FzSP R_RP-SP cos(phi) - FzRING R_RP-RING
    M_SP-SUN LOA  =  Mx-SP cos(a1) + My-SP sin(a1)
    M_SP-RP  LOA  = -Mx-SP cos(theta - a2) - My-SP sin(theta - a2)
    M_RP-SP  LOA  = -Mx-RP cos(phi + a2)   + My-RP sin(phi + a2)
    M_RP-RING LOA = -Mx-RP cos(a3) - My-RP sin(a3)

FzSUN, FzRP act on the SP (from the sun and the RP), FzSP, FzRING on the RP. Case 2-A is
the collinear limit theta = 180 deg, phi = 0 (Table 5 rows 2-A), case 2-B the real triangle.

Units: lengths mm, angles rad, forces N, moments N m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

MM_TO_M = 1e-3


@dataclass(frozen=True)
class TriangleAngles:
    """Interior angles (rad) of the sun / SP / RP centre triangle."""

    psi: float  # at the sun centre
    theta: float  # at the SP centre
    phi: float  # at the RP centre


def _angle_opposite(opposite: float, side1: float, side2: float) -> float:
    c = (side1**2 + side2**2 - opposite**2) / (2.0 * side1 * side2)
    if not -1.0 <= c <= 1.0:
        raise ValueError(f"centre distances {opposite}, {side1}, {side2} mm do not form a triangle")
    return math.acos(c)


def triangle_angles(d_sun_sp: float, d_sp_rp: float, d_sun_rp: float) -> TriangleAngles:
    """psi, theta, phi (rad) from the three centre distances (mm) by the law of cosines."""
    return TriangleAngles(
        psi=_angle_opposite(d_sp_rp, d_sun_sp, d_sun_rp),
        theta=_angle_opposite(d_sun_rp, d_sun_sp, d_sp_rp),
        phi=_angle_opposite(d_sun_sp, d_sp_rp, d_sun_rp),
    )


@dataclass(frozen=True)
class DoublePinionGeometry:
    """Operating geometry of one sun-SP-RP-ring branch. Radii mm, angles rad."""

    r_sp_sun: float  # R_SP-SUN: SP operating pitch radius at the sun mesh
    r_sp_rp: float  # R_SP-RP: SP operating pitch radius at the RP mesh
    r_rp_sp: float  # R_RP-SP: RP operating pitch radius at the SP mesh
    r_rp_ring: float  # R_RP-RING: RP operating pitch radius at the ring mesh
    a1: float  # operating transverse pressure angle sun-SP
    a2: float  # operating transverse pressure angle SP-RP
    a3: float  # operating transverse pressure angle RP-ring
    theta: float  # triangle angle at the SP centre
    phi: float  # triangle angle at the RP centre


@dataclass(frozen=True)
class AxialForces:
    """Axial mesh forces, N: FzSUN, FzRP on the SP; FzSP, FzRING on the RP."""

    FzSUN: float
    FzRP: float
    FzSP: float
    FzRING: float

    @classmethod
    def uniform(cls, fa: float) -> AxialForces:
        """singh2007 case 2 signs: FzSUN = -FzRP = FzSP = -FzRING = FA."""
        return cls(FzSUN=fa, FzRP=-fa, FzSP=fa, FzRING=-fa)


def axial_forces(
    torque_per_branch: float,
    r_sun: float,
    g: DoublePinionGeometry,
    beta_sp_sun: float,
    beta_sp_rp: float,
    beta_rp_ring: float,
) -> AxialForces:
    """Axial forces from the sun torque of one branch (N m) along the power path.

    Tangential forces: Ft1 = T / R_SUN at sun-SP; the SP spins freely, so
    Ft2 = Ft1 R_SP-SUN / R_SP-RP at SP-RP; likewise Ft3 = Ft2 R_RP-SP / R_RP-RING at RP-ring.
    Axial force = tangential force x tan(operating helix angle of the pinion at that mesh).
    Signs as in singh2007 case 2 (hands sun R, SP L, RP R, ring R): FzSUN > 0, FzRP < 0,
    FzSP = -FzRP (action and reaction), FzRING < 0. With one lead per pinion the three
    magnitudes are equal (tan(beta_w) / r_w is constant along a helix): FA.
    """
    ft1 = torque_per_branch / (r_sun * MM_TO_M)
    ft2 = ft1 * g.r_sp_sun / g.r_sp_rp
    ft3 = ft2 * g.r_rp_sp / g.r_rp_ring
    fz2 = ft2 * math.tan(beta_sp_rp)
    return AxialForces(
        FzSUN=ft1 * math.tan(beta_sp_sun),
        FzRP=-fz2,
        FzSP=fz2,
        FzRING=-ft3 * math.tan(beta_rp_ring),
    )


def per_force_moments(fz: AxialForces, g: DoublePinionGeometry) -> dict[str, dict]:
    """(Mx, My) in N m of each axial force on its pinion: the per-force rows of Table 5."""
    return {
        "SP": {
            "FzSUN": (0.0, fz.FzSUN * g.r_sp_sun * MM_TO_M),
            "FzRP": (
                -fz.FzRP * g.r_sp_rp * math.sin(g.theta) * MM_TO_M,
                fz.FzRP * g.r_sp_rp * math.cos(g.theta) * MM_TO_M,
            ),
        },
        "RP": {
            "FzSP": (
                fz.FzSP * g.r_rp_sp * math.sin(g.phi) * MM_TO_M,
                fz.FzSP * g.r_rp_sp * math.cos(g.phi) * MM_TO_M,
            ),
            "FzRING": (0.0, -fz.FzRING * g.r_rp_ring * MM_TO_M),
        },
    }


def double_pinion_moments(fz: AxialForces, g: DoublePinionGeometry) -> dict[str, float]:
    """Table 5: Mx, My, total of SP and RP and the four LOA moments, N m."""
    parts = per_force_moments(fz, g)
    mx_sp, my_sp = (sum(p[i] for p in parts["SP"].values()) for i in (0, 1))
    mx_rp, my_rp = (sum(p[i] for p in parts["RP"].values()) for i in (0, 1))
    return {
        "Mx_SP": mx_sp,
        "My_SP": my_sp,
        "M_SP": math.hypot(mx_sp, my_sp),
        "Mx_RP": mx_rp,
        "My_RP": my_rp,
        "M_RP": math.hypot(mx_rp, my_rp),
        **loa_moments(mx_sp, my_sp, mx_rp, my_rp, g),
    }


def loa_moments(mx_sp, my_sp, mx_rp, my_rp, g: DoublePinionGeometry) -> dict[str, float]:
    """The four LOA moments (section 5) from the pinion moments, N m; linear, so it also
    applies to FE-measured moments::

        M_SP-SUN  =  Mx_SP cos(a1) + My_SP sin(a1)
        M_SP-RP   = -Mx_SP cos(theta - a2) - My_SP sin(theta - a2)
        M_RP-SP   = -Mx_RP cos(phi + a2) + My_RP sin(phi + a2)
        M_RP-RING = -Mx_RP cos(a3) - My_RP sin(a3)
    """
    th, ph = g.theta, g.phi
    return {
        "M_LOA_SP_SUN": mx_sp * math.cos(g.a1) + my_sp * math.sin(g.a1),
        "M_LOA_SP_RP": -mx_sp * math.cos(th - g.a2) - my_sp * math.sin(th - g.a2),
        "M_LOA_RP_SP": -mx_rp * math.cos(ph + g.a2) + my_rp * math.sin(ph + g.a2),
        "M_LOA_RP_RING": -mx_rp * math.cos(g.a3) - my_rp * math.sin(g.a3),
    }
