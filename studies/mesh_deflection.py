"""A load the contact grid cannot hold, refused before anything is meshed.

Each mesh's flanks approach under load by about its tooth-pair deflection, estimated with
ISO 6336-1's standard single-pair stiffness of a steel spur pair, c' = 14 N/(mm um), scaled by
the gears' Young's modulus over steel's (the stiffness is linear in E):

    delta = w_t / (c' E_gear / E_steel),   w_t = F_t / b,   F_t = T_driver / r_w1,          (1)

the nominal tangential load per face width of the mesh's driver on one branch (b: the
narrower face). Eq. (1) overstates the approach of these cases by a factor 2-4 (two pairs
share the load over much of the cycle, the helix adds length of contact): case 1's
sun-pinion mesh gives 38 um where the zone reach of a solve is 10-20 um. The zone grid holds
a reach of at most REACH_FRACTION x LIMIT_CEILING_UM (:mod:`solvers.zone_reach`), so a set
whose estimate exceeds :data:`REFUSE_FACTOR` times that cannot be solved by any band and is
refused with the fields that set it; below, the solve decides (and widens its band).
"""

from __future__ import annotations

from gears.material import STEEL
from postprocess.mesh_stress import driver_torques
from solvers.zone_reach import LIMIT_CEILING_UM, REACH_FRACTION
from studies.cli import InputError

#: ISO 6336-1's standard single-pair stiffness of steel gears, N/(mm um)
C_PRIME_STEEL = 14.0
#: how far eq. (1) may exceed what the zone grid holds before it is refused: twice its
#: largest overestimate on the shipped cases, so a set that could solve is never refused
REFUSE_FACTOR = 8.0


def mesh_deflections_um(study) -> dict[tuple[str, str], float]:
    """Eq. (1) per mesh (driver, driven), um."""
    gs = study.gearset
    scale = study.material.gear_youngs_modulus / STEEL.youngs_modulus
    out = {}
    for (g1, g2), torque in driver_torques(gs).items():
        pair = gs.pair(g1, g2)
        b = min(gs.gears[g1].face_width, gs.gears[g2].face_width)
        w_t = torque / pair.operating_pitch_radius(1) / b
        out[(g1, g2)] = w_t / (C_PRIME_STEEL * scale)
    return out


def check_mesh_deflection(study) -> None:
    """:class:`studies.cli.InputError` naming the torque and the modulus where a mesh's
    estimated deflection (1) is beyond REFUSE_FACTOR x what the zone grid holds."""
    holds = REACH_FRACTION * LIMIT_CEILING_UM
    for (g1, g2), d in mesh_deflections_um(study).items():
        if d > REFUSE_FACTOR * holds:
            e = study.material.gear_youngs_modulus
            raise InputError(
                f"{study.name}: input_torque = {study.gearset.input_torque:g} N m on gears of "
                f"E = {e:g} MPa (material.youngs_modulus x gear_modulus_factor) bends the "
                f"{g1}-{g2} teeth about {d / 1e3:.2g} mm (ISO 6336-1's single-pair stiffness "
                f"c' = {C_PRIME_STEEL:g} N/(mm um) for steel, scaled by E), far beyond the "
                f"{holds:g} um of approach the contact grid represents: the linear model does "
                "not apply; lower the torque or raise the modulus"
            )


__all__ = ["C_PRIME_STEEL", "REFUSE_FACTOR", "check_mesh_deflection", "mesh_deflections_um"]
