"""A gear body as a gmsh OCC solid, with its faces named by geometry.

The solid is a loft (``occ.addThruSections``) through ``n_sections`` transverse sections,
each the outline of :mod:`meshing.body_outline` turned by ``gear.helix_rotation(z)``. Full
gears get their bore (external) or rim (internal) as an exact cylinder sewn to the toothed
loft and the end faces; sectors are lofted with their cut lines and inner (or outer) arc in
the section.

Faces are named by geometry, never by creation order: every face is sampled on a 3 x 3
grid of parameter points, the points are turned back by the helix rotation, and the
radius, axial position and polar angle decide body surface, tooth index, side and kind
(:func:`classify_surfaces`). The ``gmsh`` module is passed in by the caller.
"""

from __future__ import annotations

import math

import numpy as np

from gears.profile import tooth_profile
from meshing import tags as T
from meshing.body_outline import OutlineSegment, outline_segments, section_heights, tooth_segments
from meshing.gear_body import GearBody
from meshing.gmsh_util import sample_surface

# --------------------------------------------------------------------------------------
# Solid
# --------------------------------------------------------------------------------------


def _add_curves(occ, segs: list[OutlineSegment], snap: float = 1e-9) -> list[int]:
    """Add the curves of ``segs`` (z = 0); end points shared, interpolation points removed."""
    cache: dict[tuple[int, int], int] = {}

    def point(p: np.ndarray) -> int:
        key = (round(p[0] / snap), round(p[1] / snap))
        if key not in cache:
            cache[key] = occ.addPoint(float(p[0]), float(p[1]), 0.0)
        return cache[key]

    centre = occ.addPoint(0.0, 0.0, 0.0)
    curves: list[int] = []
    stray = [centre]  # interpolation points and the arc centre are not part of a curve
    for s in segs:
        if s.kind == "spline":
            inner = [occ.addPoint(float(p[0]), float(p[1]), 0.0) for p in s.pts[1:-1]]
            tags = [point(s.pts[0]), *inner, point(s.pts[-1])]
            tangents = [s.t0[0], s.t0[1], 0.0, s.t1[0], s.t1[1], 0.0]
            curves.append(occ.addSpline(tags, tangents=[float(t) for t in tangents]))
            stray += inner
        elif s.kind == "arc":
            curves.append(occ.addCircleArc(point(s.pts[0]), centre, point(s.pts[1])))
        else:
            curves.append(occ.addLine(point(s.pts[0]), point(s.pts[1])))
    occ.remove([(0, t) for t in stray])
    return curves


def _section_wires(occ, gb: GearBody, prof) -> list[int]:
    """The wires of the transverse sections at ``section_heights(gb)``.

    Tooth 0 is drawn once from the profile points; the other teeth and all sections are
    copies turned by the pitch and the helix rotation (free interpolation points cost
    O(model size) each to remove from OCC, so they are created for one tooth only).
    """
    g = gb.gear
    pitch = 2.0 * math.pi / g.teeth
    tooth0 = _add_curves(occ, tooth_segments(gb, prof))
    closing = _add_curves(occ, outline_segments(gb, prof, teeth=False))
    curves0: list[int] = []
    for k in gb.teeth:
        copy = occ.copy([(1, c) for c in tooth0])
        occ.rotate(copy, 0, 0, 0, 0, 0, 1, k * pitch)
        curves0 += [t for _, t in copy]
    occ.remove([(1, c) for c in tooth0], recursive=True)
    curves0 += closing
    wires = []
    for z in section_heights(gb):
        copy = occ.copy([(1, c) for c in curves0])
        occ.rotate(copy, 0, 0, 0, 0, 0, 1, float(g.helix_rotation(z)))
        occ.translate(copy, 0, 0, float(z))
        wires.append(occ.addWire([t for _, t in copy], checkClosed=True))
    occ.remove([(1, c) for c in curves0], recursive=True)
    return wires


def build_geometry(gmsh, gb: GearBody, prof=None) -> int:
    """Add the solid of ``gb`` to the current gmsh model (OCC); return its volume tag.

    Sectors: one loft through the closed section wires (teeth, cut lines, inner arc).
    Full gears: the toothed faces are lofted as surfaces, the bore (or rim) cylinder and
    the two annular end faces are added, and the faces are sewn into a volume (an OCC
    boolean of the loft with a cylinder gives the same solid but took 9 s for 26 teeth).
    """
    gb.validate()
    g = gb.gear
    if prof is None:
        prof = tooth_profile(g, gb.n_involute, gb.n_fillet)
    occ = gmsh.model.occ
    heights = section_heights(gb)
    wires = _section_wires(occ, gb, prof)
    if not gb.full:
        out = occ.addThruSections(wires, makeSolid=True, makeRuled=False)
        _drop_wires(occ, wires[1:-1])
        vols = [t for d, t in out if d == 3]
        if len(vols) != 1:
            raise RuntimeError(f"{gb.body}: loft gave {len(vols)} volumes")
        vol = vols[0]
    else:
        toothed = occ.addThruSections(wires, makeSolid=False, makeRuled=False)
        _drop_wires(occ, wires[1:-1])
        r_cyl = gb.outer_radius if g.internal else gb.inner_radius
        circles = [
            occ.addCurveLoop([occ.addCircle(0, 0, float(z), r_cyl)]) for z in heights[[0, -1]]
        ]
        cyl = occ.addThruSections(circles, makeSolid=False, makeRuled=True)
        end_wires = (wires[0], wires[-1])
        # The first wire of a plane surface is its outer boundary.
        pairs = zip(circles, end_wires, strict=True)
        if g.internal:
            ends = [occ.addPlaneSurface([c, w]) for c, w in pairs]
        else:
            ends = [occ.addPlaneSurface([w, c]) for c, w in pairs]
        faces = [t for d, t in toothed + cyl if d == 2] + ends
        loop = occ.addSurfaceLoop(faces, sewing=True)
        vol = occ.addVolume([loop])
    occ.synchronize()
    # Remove the loft's construction entities (inner section wires and their points):
    # left in the model, they would be meshed as stray 1D elements.
    _remove_strays(gmsh)
    mass = occ.getMass(3, vol)
    if not mass > 0:
        raise RuntimeError(f"{gb.body}: built solid has volume {mass}")
    return vol


def _drop_wires(occ, wires: list[int]) -> None:
    """Remove construction wires (and their curves and points) from the OCC model."""
    occ.remove([(1, w) for w in wires], recursive=True)


def _remove_strays(gmsh) -> None:
    """Remove every entity of the model that is not on the closure of a volume."""
    keep = set()
    for v in gmsh.model.getEntities(3):
        keep.add(v)
        for s in gmsh.model.getBoundary([v], combined=False, oriented=False):
            keep.add(s)
            for c in gmsh.model.getBoundary([s], combined=False, oriented=False):
                keep.add(c)
                for p in gmsh.model.getBoundary([c], combined=False, oriented=False):
                    keep.add(p)
    stray = [e for e in gmsh.model.getEntities() if e not in keep and e[0] < 3]
    # Highest dimension first so lower entities are free when their turn comes.
    stray.sort(key=lambda e: -e[0])
    if stray:
        gmsh.model.occ.remove(stray, recursive=False)
        gmsh.model.occ.synchronize()


# --------------------------------------------------------------------------------------
# Classification by geometry
# --------------------------------------------------------------------------------------


def _wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def classify_surfaces(gmsh, gb: GearBody, vol: int, tol: float = 2e-3) -> dict[str, list[int]]:
    """Map tag name -> surface tags for the boundary of ``vol`` (gear frame, unplaced)."""
    g = gb.gear
    z_teeth = g.teeth
    pitch = 2.0 * math.pi / z_teeth
    b = g.face_width
    r_lo_fl, r_hi_fl = sorted((g.form_radius, g.tip_radius))
    r_lo_fi, r_hi_fi = sorted((g.root_radius, g.form_radius))
    r_in = gb.outer_radius if g.internal else gb.inner_radius
    body_kind = T.RIM if g.internal else T.BORE
    out: dict[str, list[int]] = {}
    teeth = set(gb.teeth)
    for _, s in gmsh.model.getBoundary([(3, vol)], combined=False, oriented=False):
        xyz = sample_surface(gmsh, s)
        x, y, zc = xyz[:, 0], xyz[:, 1], xyz[:, 2]
        r = np.hypot(x, y)
        th = np.arctan2(y, x) - np.asarray(g.helix_rotation(zc), float)
        if np.all(np.abs(zc - 0.5 * b) < tol):
            name = T.surface(gb.body, T.END_ZPOS)
        elif np.all(np.abs(zc + 0.5 * b) < tol):
            name = T.surface(gb.body, T.END_ZNEG)
        elif np.all(np.abs(r - r_in) < 10 * tol):
            name = T.surface(gb.body, body_kind)
        elif not gb.full and np.all(np.abs(_wrap(th - gb.cut_angles[1])) < 1e-4):
            name = T.surface(gb.body, T.CUT_POS)
        elif not gb.full and np.all(np.abs(_wrap(th - gb.cut_angles[0])) < 1e-4):
            name = T.surface(gb.body, T.CUT_NEG)
        else:
            k = int(np.round(np.mean(np.unwrap(th)) / pitch)) % z_teeth
            psi = _wrap(th - k * pitch)
            side = "pos" if np.mean(psi) > 0 else "neg"
            if k not in teeth:
                name = T.surface(gb.body, T.OTHER)
            elif np.all(np.abs(r - g.tip_radius) < tol):
                name = T.tooth(gb.body, k, T.TIP)
            elif np.all((r > r_lo_fl - tol) & (r < r_hi_fl + tol)):
                name = T.flank(gb.body, k, side)
            elif np.all((r > r_lo_fi - tol) & (r < r_hi_fi + tol)):
                name = T.fillet(gb.body, k, side)
            else:
                name = T.surface(gb.body, T.OTHER)
        out.setdefault(name, []).append(s)
    return out
