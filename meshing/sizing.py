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

Fillet sizes. The P1 surface root stress (:mod:`solvers.root_stress`) is far from converged
at the fillet sizes of this ladder, and the size at which it levels off fits in memory only
if just the fillets that are read are refined, which the scenes do not yet say: so the sizes
are left as they were. A fillet-only ladder (:func:`with_fillet`, ``python -m
studies.fillet_study``; 1-GB, sun angle 0, P1, serial, one child process per run; surface
maximum in MPa; the level-0 and the first three "loaded only" runs shared the 2 cores with
other jobs, so their times are upper bounds):

    flanks   fillet  DOFs   run (s)  peak GB   sun  pinion/sun  pinion/ring  ring
    level 0  0.6     129k    10      1.2       552   535         593          442
    level 0  0.45    184k    23      1.8       580   635         739          476
    level 0  0.3     333k    45      3.6       719   758         885          521
    level 0  0.25    430k    73      4.9       762   772         834          689
    level 1  0.45    248k    34      2.8       614   676         744          497
    level 1  0.35    337k    60      4.0       636   693         718          527
    level 1  0.3     430k    65      5.4       755   722         897          589
    level 1  0.25    559k    69      7.2       739   796         880          643
    loaded only, level-1 flanks (``GearBody.fine_fillets``: the tension fillets of the
    teeth loaded at this position, 14 of the 52 fillets of the active teeth; the others at
    fillet_far):
    level 1  0.45    184k    17      1.9       571   668         680          526
    level 1  0.3     236k    34      2.6       714   677         780          680
    level 1  0.2     328k    40      3.9       873   823         936          608
    level 1  0.15    434k    46      5.4       866   932         968          658
    level 1  0.12    547k    70      7.0       901   928        1030          654

Every fillet of the active teeth at 0.2 mm with level-1 flanks would be 798k DOFs (about
11 GB, not run). Down to 0.25 mm the values rise by 10-25 % per step of 1.5 in size; from
0.2 to 0.12 mm (loaded only) they level off and scatter: 0.15 -> 0.12 mm changes them by
+4, -0.4, +6 and -0.5 %, the ISO-line value of the sun by -0.3 % (842, 825, 823). The
scatter is the estimator's: the surface maximum moves between neighbouring surface nodes
(5-8 % apart) and with the mesh of the other fillets (up to 10 %, loaded only against all
active at 0.45 mm; up to 7 % when only the far teeth's strips change, see
:func:`meshing.body_mesh.structure_fillets`). The P1 recovery is first order in the height
of the cells on the fillet, about 2 fillet sizes (it recovers the value about a quarter of
a cell deep, and the stress falls to a fifth within 0.7-0.8 mm of the surface), so the
fillet must be about 0.15 mm (cells about 0.3 mm high) for a value within the 5 % scatter;
at level 1 (0.45 mm) the surface value is 24-32 % below the 0.12 mm value.
P2 at level 0 (fillet 0.6 mm, 883k DOFs, 14.7 GB; the convergence study) gave 807 / 831 /
902 / 594, 9-12 % below the 0.12 mm P1 values.

The refined fillets cost about 3000 / fillet^2 nodes per sector of 7 active teeth
(:func:`meshing.body_mesh.structure_fillets`). Refining only the tension fillets of the
teeth in contact (``GearBody.fine_fillets``, which the scene would set from its zones'
contact lines and drive sides) makes 0.15 mm at level 1 cost 434k DOFs, 5.4 GB and 46 s a
position instead of 248k, 2.8 GB and 34 s (the bodies are reused across positions only if
those fillets do not change with the position).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace


class MeshingError(ValueError):
    """Bad meshing input, detected before gmsh runs; the message names field and range."""


@dataclass(frozen=True)
class Level:
    fine: float  # flanks of active teeth
    fillet: float  # fillets of active teeth (about 1.3 mm wide, radius ~0.5 mm; only those
    # of GearBody.fine_fillets when a body names them)
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


def with_fillet(level, fillet: float) -> Level:
    """``level`` (an index of :data:`LEVELS` or a :class:`Level`) with the fillet size of
    the active teeth set to ``fillet`` (mm): a fillet-only refinement at fixed flank and body
    sizes (studies/fillet_study.py). Pass the returned :class:`Level` wherever a level is
    taken; the mesh cache keys hold a :class:`Level`'s sizes (a level index is covered by
    the source of this module), so a changed size never reuses a cached mesh."""
    return check_level(replace(check_level(level), fillet=fillet))


def level_record(level) -> int | dict:
    """A level as JSON: its index, or the sizes of a :class:`Level` (checked)."""
    lv = check_level(level)
    if isinstance(level, Level):
        return {f.name: getattr(lv, f.name) for f in fields(Level)}
    return level


def check_level(level) -> Level:
    """The :class:`Level` for ``level`` (an index of :data:`LEVELS`, or a :class:`Level`
    itself, e.g. from :func:`with_fillet`, checked); :class:`MeshingError` if out of range."""
    if isinstance(level, Level):
        for f in fields(Level):
            v = getattr(level, f.name)
            if f.name == "per_circle":
                if isinstance(v, bool) or not isinstance(v, int) or v < 8:
                    raise MeshingError(f"level.per_circle = {v!r}: must be an integer >= 8")
            elif (
                isinstance(v, bool)
                or not isinstance(v, (int, float))
                or not (math.isfinite(v) and v > 0)
            ):
                raise MeshingError(f"level.{f.name} = {v!r}: must be a positive size in mm")
        return level
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
