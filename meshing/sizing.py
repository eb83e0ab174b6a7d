"""Resolution ladder and element sizes.

Every mesh takes a ``level`` (0 = coarsest, for CI; ``DEFAULT_LEVEL`` for ``make meshes``).
A level fixes, in mm (see :class:`Level`): ``fine`` on the flanks of the *active* teeth
(in or next to a mesh zone, where contact loads are read), ``fillet`` across their root
fillets (where root stress is read; the fillets are structured strips, see
:func:`meshing.body_mesh.structure_fillets`), ``tooth``/``fillet_far`` on all other teeth,
``coarse`` in the body, and the number of segments around a bore or rim.

The case gears have m_n = 1.59 mm (tooth about 2.5 mm thick at the pitch circle): level 0
puts about 3 elements across an active tooth (a CI smoke test, not for stress), level 1
about 4, level 2 about 6 and level 3 about 8; a pinion fillet gets 3, 3, 5 and 7 across.
Measured sizes (case 1 one-branch scene, cold build on 2 cores): level 0 174k tets in 4 s,
level 1 340k in 5 s, level 2 1.09M in 10 s, level 3 2.76M in 21 s (0.6 GB).
"""

from __future__ import annotations

from dataclasses import dataclass


class MeshingError(ValueError):
    """Bad meshing input, detected before gmsh runs; the message names field and range."""


@dataclass(frozen=True)
class Level:
    fine: float  # flanks of active teeth
    fillet: float  # fillets of active teeth (about 1.3 mm wide, radius ~0.5 mm)
    tooth: float  # flanks and tips of the other teeth, tips of active teeth
    fillet_far: float  # fillets of the other teeth
    coarse: float  # body (rim, web, end faces, cut faces)
    per_circle: int  # segments per full turn of a bore or rim


LEVELS: tuple[Level, ...] = (
    Level(fine=1.0, fillet=0.6, tooth=1.6, fillet_far=1.0, coarse=4.0, per_circle=48),  # 0: CI
    Level(fine=0.7, fillet=0.45, tooth=1.2, fillet_far=0.8, coarse=3.0, per_circle=64),  # 1
    Level(fine=0.45, fillet=0.3, tooth=1.0, fillet_far=0.6, coarse=2.5, per_circle=96),  # 2
    Level(fine=0.3, fillet=0.2, tooth=0.8, fillet_far=0.5, coarse=2.0, per_circle=128),  # 3
    Level(fine=0.2, fillet=0.15, tooth=0.7, fillet_far=0.45, coarse=2.0, per_circle=160),  # 4
)
DEFAULT_LEVEL = 1
# Stated minimum element quality (gmsh minSICN, 1 = regular tet, <= 0 inverted) of every
# mesh at every level; HXT gives 0.19-0.35 on the case bodies, and a mesh below this
# floor gets the Netgen optimiser (meshing.gmsh_util.enforce_quality).
MIN_SICN = 0.15


def check_level(level) -> Level:
    """The :class:`Level` for ``level``; :class:`MeshingError` if out of range."""
    if isinstance(level, bool) or not isinstance(level, int) or not 0 <= level < len(LEVELS):
        last = len(LEVELS) - 1
        raise MeshingError(
            f"level = {level!r}: must be an integer from 0 to {last}, the mesh resolution "
            f"ladder (flank elements {LEVELS[0].fine:g} mm at level 0, for CI, to "
            f"{LEVELS[last].fine:g} mm at level {last}; meshing.sizing.LEVELS)"
        )
    return LEVELS[level]


def apply_sizes(gmsh, level: int, surface_sizes: dict[int, float]) -> None:
    """Set the element sizes of ``level`` in the current (synchronized) gmsh model.

    ``surface_sizes``: surface tag -> size. Each CAD point gets the smallest size of the
    surfaces it bounds (``coarse`` if none); gmsh interpolates along the curves and extends
    the boundary sizes into surfaces and volumes, so the size grows linearly from the
    flanks into the body. (A Distance/Threshold field on the lofted B-spline faces gave
    similar meshes but cost seconds per face to sample.) Fillet faces need their own small
    size: sized from their corners alone, a 1.3 mm wide fillet is spanned by single chords
    and the mesh loses 5-10 % of the fillet area.
    """
    lv = check_level(level)
    size: dict[int, float] = {p: lv.coarse for _, p in gmsh.model.getEntities(0)}
    for s, h in surface_sizes.items():
        for _, p in gmsh.model.getBoundary([(2, s)], combined=False, recursive=True):
            size[abs(p)] = min(size.get(abs(p), lv.coarse), h)
    for p, h in size.items():
        gmsh.model.mesh.setSize([(0, p)], h)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 1)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", lv.coarse)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5 * min(lv.fine, lv.fillet))
