"""How far a solved contact load reaches into a zone grid's band, and the error when the band
was too narrow for it.

A zone grid keeps, per transverse section, the cells whose unloaded separation g0 lies within
the gap limit L of the section's smallest, g_ref (:func:`solvers.flank_grid.zone_grid`;
``[numerics] zone_gap_limit_um``). A cell that carries load has closed: the approach of the
two flanks there (rigid and elastic) is its g0. Its reach above the section's closest point is
s_k = g0_k - g_ref,k, and the reach of a grid

    s_max = max over loaded cells (F_k > 0) of s_k.                                      (1)

A cell left off the grid has s > L. Its gap after deformation is about s - s_max, so it stays
open while s_max is well below L: within a section the rigid motion's normal approach is the
same along an involute profile, and the elastic approach falls off away from the loaded cells.
What varies across a section is the part of a rigid tilt along the normal's axial component
(it grows with the radius) and the bending of the teeth, and with tooth modifications the
loaded band sits where g0 grows fastest. Beyond s_max = REACH_FRACTION x L these may close
cells the grid does not hold, and the answer would depend on a hidden setting: the solve is
refused with the limit that would hold it (the study driver then solves the position again
on that band: :func:`studies.position.solve_position`). A larger limit costs grid cells only.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from solvers.errors import ZoneReachError

#: the largest reach (1), as a share of the gap limit, a solve is accepted with
REACH_FRACTION = 0.5
#: the largest gap limit a case may set (um), cases.study_case.ZONE_GAP_RANGE's upper end
LIMIT_CEILING_UM = 500.0


def zone_reach(grids: Iterable, result) -> dict[str, float]:
    """Per zone grid name its reach s_max of eq. (1) in um (0 where no cell carries load),
    from ``grids`` ((ContactGrid, FlankGridInfo) pairs, as :func:`solvers.flank_grid.
    flank_contact_pairs` lays them) and the solved ``result``
    (:class:`solvers.contact.ContactResult`). Grids without a reference (line grids) and
    grids not in the solve are left out."""
    rows = dict(result.pairs)
    out = {}
    for grid, info in grids:
        if info.reference is None or grid.name not in rows:
            continue
        loaded = result.forces[rows[grid.name]] > 0
        s = np.asarray(grid.gap0, float) - info.reference
        out[grid.name] = float(s[loaded].max(initial=0.0)) * 1e3
    return out


def suggested_limit_um(reach_um: float) -> float:
    """A gap limit (um) that would hold a reach of ``reach_um`` with room to spare: twice
    what REACH_FRACTION needs (the load spreads further on a wider band), rounded up to
    10 um, at most LIMIT_CEILING_UM."""
    return min(LIMIT_CEILING_UM, 10.0 * math.ceil(2.0 * reach_um / REACH_FRACTION / 10.0))


def check_zone_reach(grids: Iterable, result) -> dict[str, float]:
    """:func:`zone_reach`, and :class:`solvers.errors.ZoneReachError` naming the grid, its
    reach and the limit to set where a reach exceeds REACH_FRACTION of its grid's gap
    limit."""
    grids = list(grids)
    limits = {g.name: info.gap_limit for g, info in grids}
    reach = zone_reach(grids, result)
    for name, s in reach.items():
        limit_um = limits[name] * 1e3
        if s > REACH_FRACTION * limit_um:
            more = suggested_limit_um(s)
            fix = (
                f"set [numerics] zone_gap_limit_um = {more:g}"
                if more > limit_um
                else "the largest zone_gap_limit_um does not hold it: the torque (for the "
                "gears' Young's modulus), the flank modifications or a soft bearing (radial "
                "or tilting stiffness: the pinion floats or tilts) move the flanks further "
                "than the zone grid can represent"
            )
            raise ZoneReachError(
                f"contact grid '{name}': the load reaches cells whose unloaded gap is "
                f"{s:.1f} um above their section's smallest, more than "
                f"{REACH_FRACTION:g} x [numerics] zone_gap_limit_um = {limit_um:g} um; cells "
                f"beyond the limit may be in contact and are not on the grid: {fix}",
                partial={"zone_reach_um": reach},
            )
    return reach


__all__ = ["REACH_FRACTION", "check_zone_reach", "suggested_limit_um", "zone_reach"]
