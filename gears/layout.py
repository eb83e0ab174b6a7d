"""Planet layout clearance: the tip circles of gears that do not mesh must not overlap.

A branch is one pinion (single pinion) or an SP-RP pair (double pinion). With the sun at the
origin, the pinions of the branch at carrier angle psi sit at

    single pinion:  c = a1 u(psi)
    double pinion:  c_SP = a1 u(psi),  c_RP = a3 u(psi + psi_t),
                    psi_t = acos((a1^2 + a3^2 - a2^2) / (2 a1 a3))

(a1, a2, a3 the sun-SP, SP-RP and RP-ring centre distances, u(t) = (cos t, sin t); the RP
counter-clockwise of the SP, as the scenes place it: :func:`meshing.scenes.branch_centres`
is :func:`pinion_centres`). Gears that do not mesh then clear each
other when (all mm, r_a the tip radii, the ring's its inner tip circle):

* pinions of two branches: |c_i - c_j| > r_a,i + r_a,j;
* double pinion, in one branch: the RP clears the sun, a3 > r_a,sun + r_a,RP, and the SP
  clears the ring, a1 + r_a,SP < r_a,ring.

The clearance is the left side minus the right (negative: the tip circles overlap). Tip
circles, not the teeth: tips that clear at every angle never touch, whatever the phases.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from gears.analytic.double_pinion import triangle_angles


def pinion_centres(
    centre_distances: Sequence[float], psi: float, rp_side: int = 1, radial_offset: float = 0.0
) -> list[tuple[float, float]]:
    """The centres (mm) of the pinions of the branch at carrier angle ``psi`` (rad): one
    (single pinion, ``centre_distances`` = sun-pinion, pinion-ring) or SP, RP (double pinion,
    sun-SP, SP-RP, RP-ring; ``rp_side`` +1: the RP counter-clockwise of the SP, -1 clockwise).
    ``radial_offset`` (mm) moves the (S)P outward from its centre distance."""
    a = list(centre_distances)
    r = a[0] + radial_offset
    first = (r * math.cos(psi), r * math.sin(psi))
    if len(a) == 2:
        return [first]
    a1, a2, a3 = a
    t = psi + rp_side * triangle_angles(a1, a2, a3).psi
    return [first, (a3 * math.cos(t), a3 * math.sin(t))]


def layout_clearances(
    names: Sequence[str],
    tip_radii: Sequence[float],
    centre_distances: Sequence[float],
    angles: Sequence[float],
) -> list[tuple[str, float]]:
    """(what, clearance mm) for every pair of gears that do not mesh (module docstring).
    ``names`` and ``tip_radii``: the power path, sun first and ring last; ``angles``: the
    branches' carrier angles (rad). Branch k's pinions are named ``<pinion><k + 1>``."""
    names, tips = list(names), list(tip_radii)
    pinions, pin_tips = names[1:-1], tips[1:-1]
    placed = []  # (branch, name, centre, tip radius) of every pinion
    for k, psi in enumerate(angles):
        centres = pinion_centres(centre_distances, psi)
        for p, r, c in zip(pinions, pin_tips, centres, strict=True):
            placed.append((k, f"{p}{k + 1}", c, r))
    out = [
        (f"{nj} and {ni}", math.dist(ci, cj) - ri - rj)
        for i, (ki, ni, ci, ri) in enumerate(placed)
        for kj, nj, cj, rj in placed[:i]
        if ki != kj  # in one branch the SP and RP mesh
    ]
    if len(pinions) == 2:
        a1, _, a3 = centre_distances
        sun, sp, rp, ring = names
        r_sun, r_sp, r_rp, r_ring = tips
        out.append((f"{rp} and {sun}", a3 - r_sun - r_rp))
        out.append((f"{sp} and {ring}", r_ring - a1 - r_sp))
    return out


__all__ = ["layout_clearances", "pinion_centres"]
