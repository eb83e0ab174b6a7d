"""Closed-form pinion loads of a single pinion planetary (singh2007 Tables 3 and 7-9).

Pinion frame (singh2007 section 3): origin at the pinion centre, X radial (from the sun
centre through the pinion centre), Y tangential, Z axial; counter-clockwise moments positive.
The sun mesh acts at (-R_pS, 0, ZS), the ring mesh at (+R_pR, 0, ZR); ZS = ZR = 0 is the
concentrated-load model (forces at the operating pitch point, mid face width), non-zero ZS, ZR
are the axial offsets of the load centroids of a distributed load (Tables 7-9).

Table 3, forces on the pinion from a torque T per mesh on the sun::

    FyS = -T / R_SUN                  FxS = -FyS tan(alpha1)    FzS = -FyS tan(beta1)
    FyR = -(T / R_SUN)(R_pS / R_pR)   FxR =  FyR tan(alpha2)    FzR =  FyR tan(beta2)

Moments about the pinion centre (Table 3 with Table 7's distributed-load terms)::

    Mx-PIN = -(FyS ZS + FyR ZR)
    My-PIN = (FzS R_pS - FzR R_pR) + (FxS ZS + FxR ZR)
    Mz-PIN = R_pR FyR - R_pS FyS  (= 0: the pinion spins freely on its pin)

Moments resolved into the planes of action (positive pushes the load towards -Z)::

    M_LOA-sun  = Mx cos(alpha1) + My sin(alpha1)
    M_LOA-ring = Mx cos(alpha2) - My sin(alpha2)

Units: lengths mm, angles rad, forces N, torques and moments N m.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

MM_TO_M = 1e-3


@dataclass(frozen=True)
class SinglePinionGeometry:
    """Operating geometry of one sun-pinion-ring branch (singh2007 section 2).

    Radii in mm, angles in radians. ``beta1``/``beta2`` are the operating helix angles of
    the pinion at the sun and ring meshes (on the operating pitch cylinders).
    """

    r_sun: float  # R_SUN: sun operating pitch radius, sun-pinion mesh
    r_pin_sun: float  # R_pS: pinion operating pitch radius at the sun mesh
    r_pin_ring: float  # R_pR: pinion operating pitch radius at the ring mesh
    alpha1: float  # operating transverse pressure angle, sun mesh
    alpha2: float  # operating transverse pressure angle, ring mesh
    beta1: float  # operating helix angle, sun mesh
    beta2: float  # operating helix angle, ring mesh


@dataclass(frozen=True)
class MeshForces:
    """Forces on the pinion at the sun (S) and ring (R) meshes, N (singh2007 Table 3)."""

    FxS: float
    FyS: float
    FzS: float
    FxR: float
    FyR: float
    FzR: float

    @property
    def resultant(self) -> tuple[float, float, float]:
        """(Fx-PIN, Fy-PIN, Fz-PIN): the force the pin bearing carries, N."""
        return (self.FxS + self.FxR, self.FyS + self.FyR, self.FzS + self.FzR)


def mesh_forces(torque_per_mesh: float, g: SinglePinionGeometry) -> MeshForces:
    """Table 3 forces on the pinion from the sun torque carried by one mesh (N m)."""
    ft = torque_per_mesh / (g.r_sun * MM_TO_M)  # tangential force at the sun mesh, N
    fys = -ft
    fyr = -ft * g.r_pin_sun / g.r_pin_ring
    return MeshForces(
        FxS=-fys * math.tan(g.alpha1),
        FyS=fys,
        FzS=-fys * math.tan(g.beta1),
        FxR=fyr * math.tan(g.alpha2),
        FyR=fyr,
        FzR=fyr * math.tan(g.beta2),
    )


def pinion_moments(
    f: MeshForces, g: SinglePinionGeometry, zs: float = 0.0, zr: float = 0.0
) -> tuple[float, float, float]:
    """(Mx-PIN, My-PIN, Mz-PIN) in N m about the pinion centre (Tables 3 and 7).

    ``zs``, ``zr``: axial offsets (mm) of the load centroids at the sun and ring meshes
    from mid face width; zero for the concentrated-load model.
    """
    mx = -(f.FyS * zs + f.FyR * zr)
    my = (f.FzS * g.r_pin_sun - f.FzR * g.r_pin_ring) + (f.FxS * zs + f.FxR * zr)
    mz = g.r_pin_ring * f.FyR - g.r_pin_sun * f.FyS
    return (mx * MM_TO_M, my * MM_TO_M, mz * MM_TO_M)


def loa_moments(mx: float, my: float, alpha1: float, alpha2: float) -> tuple[float, float]:
    """(M_LOA-sun, M_LOA-ring): pinion moments resolved into the two planes of action.

    M_LOA-sun = Mx cos(alpha1) + My sin(alpha1); M_LOA-ring = Mx cos(alpha2) - My sin(alpha2)
    (singh2007 Table 3). Linear, so it applies to the distributed-load parts alone as well.
    """
    return (
        mx * math.cos(alpha1) + my * math.sin(alpha1),
        mx * math.cos(alpha2) - my * math.sin(alpha2),
    )


def concentrated_load(torque_per_mesh: float, g: SinglePinionGeometry) -> dict[str, float]:
    """singh2007 Table 3: forces (N), pinion resultant (N), moments and LOA moments (N m)."""
    f = mesh_forces(torque_per_mesh, g)
    fx, fy, fz = f.resultant
    mx, my, mz = pinion_moments(f, g)
    m_sun, m_ring = loa_moments(mx, my, g.alpha1, g.alpha2)
    return {
        **asdict(f),
        "Fx_pin": fx,
        "Fy_pin": fy,
        "Fz_pin": fz,
        "Mx_pin": mx,
        "My_pin": my,
        "Mz_pin": mz,
        "M_LOA_sun": m_sun,
        "M_LOA_ring": m_ring,
    }


def distributed_load(
    f: MeshForces, g: SinglePinionGeometry, zs: float, zr: float
) -> dict[str, float]:
    """One row of singh2007 Tables 8 and 9 for load centroid offsets ``zs``, ``zr`` (mm).

    The ``_LD`` terms are the load-distribution parts alone (Table 7)::

        Mx_LD = -(FyS ZS + FyR ZR)       My_LD = FxS ZS + FxR ZR
        M_LOA_sun_LD = Mx_LD cos(alpha1) + My_LD sin(alpha1)
        M_LOA_ring_LD = Mx_LD cos(alpha2) - My_LD sin(alpha2)

    and ``Mx_pin``, ``My_pin``, ``M_LOA_sun``, ``M_LOA_ring`` are the totals (concentrated
    part + distributed part). Pure function of floats: FE-measured forces and centroid
    offsets can be passed in directly.
    """
    mx0, my0, _ = pinion_moments(f, g)
    mx, my, _ = pinion_moments(f, g, zs, zr)
    mx_ld, my_ld = mx - mx0, my - my0
    m_sun_ld, m_ring_ld = loa_moments(mx_ld, my_ld, g.alpha1, g.alpha2)
    m_sun, m_ring = loa_moments(mx, my, g.alpha1, g.alpha2)
    return {
        "ZS": zs,
        "ZR": zr,
        "Mx_LD": mx_ld,
        "My_LD": my_ld,
        "Mx_pin": mx,
        "My_pin": my,
        "M_LOA_sun_LD": m_sun_ld,
        "M_LOA_ring_LD": m_ring_ld,
        "M_LOA_sun": m_sun,
        "M_LOA_ring": m_ring,
    }


# singh2007 Table 8: the five centroid-offset cases, as signs of a quarter of the face width.
OFFSET_CASES: dict[str, tuple[int, int]] = {
    "A": (0, 0),
    "B": (1, 1),
    "C": (1, -1),
    "D": (-1, 1),
    "E": (-1, -1),
}


def offset_cases(
    f: MeshForces, g: SinglePinionGeometry, offset: float
) -> list[dict[str, float | str]]:
    """Rows A..E of singh2007 Tables 8-9 with ZS, ZR in {0, +-offset} (mm)."""
    return [
        {"case": name, **distributed_load(f, g, s * offset, r * offset)}
        for name, (s, r) in OFFSET_CASES.items()
    ]
