"""Closed-form inputs of a planetary set: the gears along the power path with their centre
distances and torque (:class:`PlanetaryInput`), and the operating geometry the models of
:mod:`gears.analytic.single_pinion` (singh2007 section 2-3) and
:mod:`gears.analytic.double_pinion` (section 5) take from it. Nothing derived is typed in.
"""

from __future__ import annotations

from dataclasses import dataclass

from gears.analytic import double_pinion as dp
from gears.analytic import single_pinion as sp
from gears.pair import GearPair, assign_chain_shifts
from gears.spec import GearSpec


@dataclass(frozen=True)
class PlanetaryInput:
    """One planetary set: gears along the power path (sun, pinion(s), ring), one centre
    distance per mesh along that path (mm), input torque on the sun (N m), planets (or
    pinion pairs) sharing it."""

    name: str
    gears: tuple[GearSpec, ...]
    centre_distances: tuple[float, ...]
    input_torque: float
    planets: int

    @property
    def torque_per_branch(self) -> float:
        """Sun torque of one branch, N m (equal load sharing)."""
        return self.input_torque / self.planets

    def pairs(self) -> list[GearPair]:
        """The meshes along the power path, profile shifts resolved from the centre distances."""
        gears = assign_chain_shifts(list(self.gears), list(self.centre_distances))
        return [
            GearPair(g1, g2, a)
            for g1, g2, a in zip(gears[:-1], gears[1:], self.centre_distances, strict=True)
        ]


# --------------------------------------------------------------------------- geometry


def single_pinion_geometry(inp: PlanetaryInput) -> sp.SinglePinionGeometry:
    """Operating geometry of the sun-pinion-ring branch (singh2007 section 2)."""
    sun_pin, pin_ring = inp.pairs()
    return sp.SinglePinionGeometry(
        r_sun=sun_pin.operating_pitch_radius(1),
        r_pin_sun=sun_pin.operating_pitch_radius(2),
        r_pin_ring=pin_ring.operating_pitch_radius(1),
        alpha1=sun_pin.operating_pressure_angle,
        alpha2=pin_ring.operating_pressure_angle,
        beta1=sun_pin.operating_helix_angle(2),
        beta2=pin_ring.operating_helix_angle(1),
    )


def double_pinion_triangle(inp: PlanetaryInput) -> dp.TriangleAngles:
    """psi, theta, phi of the sun-SP-RP triangle (singh2007 section 5, case B): the sun-RP
    distance is the RP-ring centre distance (RP and ring share... the RP axis lies on the
    RP-ring centre distance from the sun axis)."""
    d_sun_sp, d_sp_rp, d_rp_ring = inp.centre_distances
    return dp.triangle_angles(d_sun_sp, d_sp_rp, d_rp_ring)


def double_pinion_geometry(
    inp: PlanetaryInput, theta: float | None = None, phi: float | None = None
) -> dp.DoublePinionGeometry:
    """Operating geometry of the sun-SP-RP-ring branch; theta, phi (rad) default to the
    real triangle (case 2-B); theta = pi, phi = 0 gives case 2-A."""
    sun_sp, sp_rp, rp_ring = inp.pairs()
    tri = double_pinion_triangle(inp)
    return dp.DoublePinionGeometry(
        r_sp_sun=sun_sp.operating_pitch_radius(2),
        r_sp_rp=sp_rp.operating_pitch_radius(1),
        r_rp_sp=sp_rp.operating_pitch_radius(2),
        r_rp_ring=rp_ring.operating_pitch_radius(1),
        a1=sun_sp.operating_pressure_angle,
        a2=sp_rp.operating_pressure_angle,
        a3=rp_ring.operating_pressure_angle,
        theta=tri.theta if theta is None else theta,
        phi=tri.phi if phi is None else phi,
    )


def double_pinion_axial_forces(inp: PlanetaryInput) -> dp.AxialForces:
    """Axial mesh forces of one double-pinion branch from the sun torque (N)."""
    sun_sp, sp_rp, rp_ring = inp.pairs()
    return dp.axial_forces(
        inp.torque_per_branch,
        sun_sp.operating_pitch_radius(1),
        double_pinion_geometry(inp),
        beta_sp_sun=sun_sp.operating_helix_angle(2),
        beta_sp_rp=sp_rp.operating_helix_angle(1),
        beta_rp_ring=rp_ring.operating_helix_angle(1),
    )
