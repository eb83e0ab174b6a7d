"""Resolution ladder and element sizes.

Every mesh takes a ``level`` (0 = coarsest, for CI; ``DEFAULT_LEVEL`` for ``make meshes``).
A level fixes, in mm (see :class:`Level`): ``fine`` on the flanks of the *active* teeth
(in or next to a mesh zone, where contact loads are read), ``fillet`` across the root
fillets where root stress is read (``GearBody.fine_fillets``: the scenes name the tension
fillets of the teeth loaded anywhere in the mesh cycle, :func:`meshing.scenes.
tension_fillets`; the fillets are structured strips, see :func:`meshing.body_mesh.
structure_fillets`), ``fillet_far`` across every other fillet and ``tooth`` on the flanks of
the other teeth, ``coarse`` in the body, and the number of segments around a bore or rim.

The case gears have m_n = 1.59 mm (tooth about 2.5 mm thick at the pitch circle): level 0
puts about 3 elements across an active tooth (a CI smoke test, not for stress), level 1
about 4, level 2 about 6 and level 3 about 8. Measured sizes before the fillet sizes below
(case 1 one-branch scene, every active fillet at 0.6 / 0.45 / 0.3 / 0.2 mm, cold build on 2
cores): level 0 174k tets in 4 s, level 1 340k in 5 s, level 2 1.09M in 10 s, level 3 2.76M
in 21 s (0.6 GB).

Fillet sizes. The P1 surface root stress (:mod:`solvers.root_stress`) levels off only at
fillet sizes of 0.12-0.15 mm, which fit in memory only if just the fillets that are read are
refined. A fillet-only ladder (:func:`with_fillet`, ``python -m studies.fillet``;
1-GB, sun angle 0, P1, serial, one child process per run; surface maximum in MPa; the
level-0 and the first three "loaded only" runs of the old table shared the 2 cores with
other jobs, so their times are upper bounds):

    flanks   fillet  DOFs   run (s)  peak GB   sun  pinion/sun  pinion/ring  ring
    every fillet of the active teeth at ``fillet`` (the ladder before the scenes named
    fine fillets; level 0 and 1 are the old defaults 0.6 and 0.45 mm):
    level 0  0.6     129k    10      1.2       552   535         593          442
    level 0  0.45    184k    23      1.8       580   635         739          476
    level 0  0.3     333k    45      3.6       719   758         885          521
    level 0  0.25    430k    73      4.9       762   772         834          689
    level 1  0.45    248k    34      2.8       614   676         744          497
    level 1  0.35    337k    60      4.0       636   693         718          527
    level 1  0.3     430k    65      5.4       755   722         897          589
    level 1  0.25    559k    69      7.2       739   796         880          643
    loaded only (the tension fillets of the teeth loaded at this position, 14 of the 52
    fillets of the active teeth; the others at fillet_far):
    level 1  0.45    184k    17      1.9       571   668         680          526
    level 1  0.3     236k    34      2.6       714   677         780          680
    level 1  0.2     328k    40      3.9       873   823         936          608
    level 1  0.15    434k    46      5.4       866   932         968          658
    level 1  0.12    547k    70      7.0       901   928        1030          654
    the scenes' fine fillets (the tension fillets of the teeth loaded anywhere in the mesh
    cycle: sun 5, pinion 9, ring 4; the others at fillet_far; another engineer's job shared
    the cores, and the 0.15 mm time includes building the meshes):
    level 0  0.45    127k    11      1.3       573   604         748          505
    level 0  0.3     178k    16      1.9       701   761         774          674
    level 1  0.45    193k    17      2.1       600   638         689          499
    level 1  0.3     259k    25      3.0       704   720         807          563
    level 1  0.2     381k    37      4.7       828   806         955          606
    level 1  0.15    522k    64      6.7       870   849         981          653
    level 1  0.12    671k    96      8.7       913   925        1046          663

Down to 0.25 mm the values rise by 10-25 % per step of 1.5 in size; from 0.2 to 0.12 mm
they level off and scatter: 0.15 -> 0.12 mm changes them by +4, -0.4, +6 and -0.5 % (loaded
only) and by +5, +9, +7 and +1.5 % (the scenes' fillets), the ISO-line value of the sun by
-0.3 % (842, 825, 823). The scatter is the estimator's: the surface maximum moves between
neighbouring surface nodes (5-8 % apart) and with the mesh of the other fillets (up to 10 %,
loaded only against all active at 0.45 mm; up to 7 % when only the far teeth's strips
change, see :func:`meshing.body_mesh.structure_fillets`; the pinion's sun side is 932 loaded
only and 849 with the cycle's fillets at 0.15 mm). The P1 recovery is first order in the
height of the cells on the fillet, about 2 fillet sizes (it recovers the value about a
quarter of a cell deep, and the stress falls to a fifth within 0.7-0.8 mm of the surface),
so the fillet must be about 0.15 mm (cells about 0.3 mm high) for a value within the 5 %
scatter; at the old level-1 fillet (0.45 mm) the surface value was 24-32 % below the 0.12
mm value. P2 at level 0 (fillet 0.6 mm, 883k DOFs, 14.7 GB; the convergence study) gave
807 / 831 / 902 / 594, 9-12 % below the 0.12 mm P1 values.

The ladder. Level 1 (the default) reads the root stress on 0.15 mm fillets: 1.5-8 % below
the 0.12 mm values at this position (sun -5, pinion sun side -8, ring side -6, ring -1.5 %;
the pinion's sun side 8.5 % below its loaded-only 0.12 mm value), against 24-32 % below
with the old 0.45 mm; it costs 522k DOFs, 6.7 GB and about 60 s at the first position of a
study (12 s at each further one, the bodies reused) instead of 248k, 2.8 GB and 20 s (5 s).
Level 0 (CI) keeps its cost: 0.45 mm on the named fillets and 1.0 mm on the others is 127k
DOFs, 11 s, 1.3 GB (before: every active fillet at 0.6 mm, 129k, 10 s, 1.2 GB); its root
stress is a smoke value (24-37 % below the 0.12 mm values). Levels 2, 3, 4 go on refining the
fillet below its levelling-off size, 0.12, 0.1 and 0.08 mm (every level a different fillet
size, as the three-grid extrapolation of :mod:`studies.convergence.reduction` needs);
meshed, not solved here: level 2 about 1.1M DOFs (before 692k DOFs, 10.1 GB; expect
about 15 GB), level 3 about 2.1M, level 4 about 3.9M (meshed in 8 min, with one more
pinion fillet); case 2 (2B-GA, 4 bodies) at level 1 about 838k DOFs instead of 370k. The
refined fillets cost about 3000 / fillet^2 nodes per sector of 7 active teeth
(:func:`meshing.body_mesh.structure_fillets`); refining every fillet of the active teeth at
0.2 mm with level-1 flanks would be 798k DOFs (about 11 GB, not run).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace


class MeshingError(ValueError):
    """Bad meshing input, detected before gmsh runs; the message names field and range."""


@dataclass(frozen=True)
class Level:
    fine: float  # flanks of active teeth
    fillet: float  # the fillets GearBody.fine_fillets names (the scenes: the tension fillets
    # of the teeth loaded in the mesh cycle; about 1.3 mm wide, radius ~0.5 mm); a body that
    # names none (fine_fillets None): every fillet of its active teeth
    tooth: float  # flanks and tips of the other teeth, tips of active teeth
    fillet_far: float  # fillets of the other teeth
    coarse: float  # body (rim, web, end faces, cut faces)
    per_circle: int  # segments per full turn of a bore or rim


LEVELS: tuple[Level, ...] = (
    Level(fine=1.0, fillet=0.45, tooth=1.6, fillet_far=1.0, coarse=4.0, per_circle=48),  # 0: CI
    Level(fine=0.7, fillet=0.15, tooth=1.2, fillet_far=0.8, coarse=3.0, per_circle=64),  # 1
    Level(fine=0.45, fillet=0.12, tooth=1.0, fillet_far=0.6, coarse=2.5, per_circle=96),  # 2
    Level(fine=0.3, fillet=0.1, tooth=0.8, fillet_far=0.5, coarse=2.0, per_circle=128),  # 3
    Level(fine=0.2, fillet=0.08, tooth=0.7, fillet_far=0.45, coarse=2.0, per_circle=160),  # 4
)
DEFAULT_LEVEL = 1
# Stated minimum element quality (gmsh minSICN, 1 = regular tet, <= 0 inverted) of every
# mesh at every level; HXT gives 0.19-0.35 on the case bodies, and a mesh below this
# floor gets the Netgen optimiser (meshing.gmsh_util.enforce_quality).
MIN_SICN = 0.15


def with_fillet(level, fillet: float) -> Level:
    """``level`` (an index of :data:`LEVELS` or a :class:`Level`) with the fillet size of
    the named fine fillets (every fillet of the active teeth of a body that names none) set
    to ``fillet`` (mm): a fillet-only refinement at fixed flank and body sizes
    (studies/fillet/driver.py). Pass the returned :class:`Level` wherever a level is
    taken; the mesh cache keys hold a :class:`Level`'s sizes (a level index is covered by
    the source of this module), so a changed size never reuses a cached mesh."""
    return check_level(replace(check_level(level), fillet=fillet))


def with_sizes(
    level: int, flank_level: int | None = None, fillet_level: int | None = None
) -> Level:
    """The sizes of ``level`` with the flank elements of the active teeth at level
    ``flank_level``'s and the named fine fillets at level ``fillet_level``'s (indices of
    :data:`LEVELS`; None keeps ``level``'s): an off-ladder run of a convergence study
    (:mod:`studies.convergence.driver`, ``--extra L:D:F[:R]``), whose contact grid follows the
    flank size as at every level (:func:`studies.position.solve_position`). The other
    teeth, the other fillets and the body keep ``level``'s sizes, and the root stress is
    read on ``level``'s sector (:func:`meshing.submodel.submodel_level` of the index)."""
    lv = check_level(level)
    if flank_level is not None:
        lv = replace(lv, fine=check_level(flank_level).fine)
    if fillet_level is not None:
        lv = replace(lv, fillet=check_level(fillet_level).fillet)
    return check_level(lv)


def run_sizes(
    level: int, flank_level: int | None = None, fillet_level: int | None = None
) -> int | Level:
    """``level`` itself when a run keeps the level's own sizes (an index: how the mesh
    cache, the records and the summaries name it), else :func:`with_sizes`."""
    if flank_level is None and fillet_level is None:
        check_level(level)
        return level
    return with_sizes(level, flank_level, fillet_level)


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
