"""The submodel of the loaded teeth of one gear: a sector of the gear body around the teeth
whose root stress is read, with their tension fillets meshed finer than the global model
can afford (:mod:`solvers.root_submodel` drives it with the global solution).

The sector is canonical: it always starts at tooth 0 (``first_tooth = 0``) and holds the
``n_read`` teeth read plus ``SUBMODEL_MARGIN`` buffer teeth on each side, so one mesh (and
one factorization) serves every mesh position and every run of the gear: the sector of the
teeth t0 ... t0 + n_read - 1 is this one turned about the gear axis by
``(t0 - SUBMODEL_MARGIN) * 2 pi / z`` (:func:`sector_turn`), the teeth of a gear being
identical under a turn by the pitch. Its cut faces lie in the middle of the tooth spaces
beyond the buffer teeth, and its inner arc (external gear; the outer arc of an internal
gear) ``SUBMODEL_DEPTH`` modules from the root circle, or at the body's own bore (rim) if
that is nearer: there the global displacement is imposed. The read teeth's fillets on the
loaded side get the fillet size asked for, every other fillet the level's ``fillet_far``;
the sector of a global level is meshed at the next finer level (:func:`submodel_level`).
"""

from __future__ import annotations

import math
from dataclasses import replace

from meshing import sizing
from meshing.gear_body import GearBody
from meshing.sizing import MeshingError

#: buffer teeth between a read tooth and a cut face (the cut is a tooth space beyond them)
SUBMODEL_MARGIN = 1
#: normal modules from the root circle to the cut arc (or the body's bore / rim if nearer)
SUBMODEL_DEPTH = 2.5
#: element degree of the submodel (P2: the surface stress of a 0.2 mm fillet within 3 % of
#: the 0.1 mm value, where P1 needs 0.12 mm and is still not in the asymptotic range)
SUBMODEL_DEGREE = 2
#: size (mm) of the read fillets of a sector meshed at each level of meshing.sizing.LEVELS:
#: 1-GB at sun angle 0, driven by the level-0 solution, P2, surface value of sun / pinion sun
#: side / pinion ring side / ring (MPa): 0.3 mm 850 / 857 / 875 / 654, 0.2 mm 869 / 888 /
#: 942 / 676, 0.15 mm 872 / 865 / 943 / 663, 0.1 mm 875 / 871 / 954 / 666 (250-310k DOFs and
#: 10-16 s to factorize per submodel at 0.2 mm, 660-890k and 50-110 s at 0.1 mm)
SUBMODEL_FILLET = (0.3, 0.2, 0.15, 0.1, 0.08)
if len(SUBMODEL_FILLET) != len(sizing.LEVELS):  # one submodel size per global level
    raise ImportError("meshing.submodel.SUBMODEL_FILLET needs one size per meshing.sizing.LEVELS")
#: the sector of a global level is meshed this many levels finer (the finest level: its own).
#: 1-GB at roll 0 on the level-1 driver, sun / pinion sun side / pinion ring side / ring
#: (MPa): sectors of level 1 / 2 / 3 sizes 844 / 868 / 865, 845 / 861 / 861, 921 / 917 /
#: 915, 650 / 674 / 675. The level-1 sector is 2-4 % off and scatters up to 3 % when any
#: one of its sizes changes; level 2's is within 0.35 % of level 3's (1.4 % on ISO's tangent
#: lines) for twice the time (four keys, one process: 132 s against 66 s, set-up and solve)
SECTOR_STEP = 1
#: the sectors' geometry: 1 straight tets (the fillet a set of flat facets), 2 curved tets on
#: the CAD faces (:func:`meshing.gmsh_util.curve_elements`). 1-GB at roll 0 on the level-1
#: driver, level 2's sizes, read fillets 0.15 / 0.1 / 0.0667 mm, the sun's ISO-line value
#: (MPa): straight 822.0 / 811.2 / 803.4 (observed order 0.8), curved 816.1 / 810.0 / 807.6
#: (order 2.3); the other keys oscillate by up to 1.3 % curved, 2.4 % straight, but for
#: the pinion's sun-side surface, which converges on curved tets (order 2.0;
#: studies/convergence/sector_sizes.py).
#: Straight until the convergence records are solved again with curved sectors
SUBMODEL_GEOMETRY_ORDER = 1


def max_read_teeth(gear) -> int:
    """The most read teeth a sector of ``gear`` holds: with its buffer teeth at most half the
    gear (its cut faces then lie on either side of the gear axis)."""
    return gear.teeth // 2 - 2 * SUBMODEL_MARGIN


def submodel_body(
    gb: GearBody,
    n_read: int,
    side: str,
    depth: float = SUBMODEL_DEPTH,
    geometry_order: int | None = None,
) -> GearBody:
    """The canonical sector of ``gb``'s gear for ``n_read`` consecutive read teeth whose
    ``side`` (``"pos"``/``"neg"``) fillets are in tension (see the module docstring), of
    ``geometry_order`` (default :data:`SUBMODEL_GEOMETRY_ORDER`, read at the call)."""
    g = gb.gear
    if side not in ("pos", "neg"):
        raise MeshingError(f"{gb.body}: submodel side = {side!r}: must be 'pos' or 'neg'")
    most = max_read_teeth(g)
    if isinstance(n_read, bool) or not isinstance(n_read, int) or not 1 <= n_read <= most:
        raise MeshingError(
            f"{gb.body}: submodel of {n_read!r} read teeth: needs 1 to {most} (a sector "
            f"holds half of z = {g.teeth})"
        )
    n = n_read + 2 * SUBMODEL_MARGIN
    m = g.normal_module
    fine = tuple((SUBMODEL_MARGIN + i, side) for i in range(n_read))
    if g.internal:
        radii = {"outer_radius": min(gb.outer_radius, g.root_radius + depth * m)}
    else:
        radii = {"inner_radius": max(gb.inner_radius, g.root_radius - depth * m)}
    order = SUBMODEL_GEOMETRY_ORDER if geometry_order is None else geometry_order
    return replace(gb, first_tooth=0, n_teeth=n, fine_fillets=fine, geometry_order=order, **radii)


def sector_turn(gear, first_read: int) -> float:
    """The angle (rad, about +z) that carries the canonical sector onto the sector whose
    first read tooth is ``first_read``."""
    return (first_read - SUBMODEL_MARGIN) * 2.0 * math.pi / gear.teeth


def submodel_level(level) -> sizing.Level:
    """The sizes of the submodel of the global ``level``: those of level ``level +``
    :data:`SECTOR_STEP` (at most the finest), with the read fillets at that level's
    :data:`SUBMODEL_FILLET` (a :class:`meshing.sizing.Level` given as such, e.g. a
    fillet-study level, keeps its own sizes)."""
    if isinstance(level, sizing.Level):
        return sizing.check_level(level)
    sizing.check_level(level)
    sector = min(level + SECTOR_STEP, len(sizing.LEVELS) - 1)
    return sizing.with_fillet(sector, SUBMODEL_FILLET[sector])
