"""Transverse outline of a gear body (gear frame, z = 0) as numpy curve segments.

Each segment is a piece of the exact :func:`gears.profile.tooth_profile` outline (involute
flanks, trochoidal fillets, tip arcs): the flanks and fillets become interpolating splines
with the exact curve tangents at their ends (so the fillet meets the flank tangentially).
Fillet and the half root land next to it are one curve, so every tooth space gives two
faces (``fillet_neg`` of one tooth and ``fillet_pos`` of the next) and no sliver. A sector
is closed by its cut lines and inner (or outer) arc. No gmsh here: the segments are turned
into CAD curves by :mod:`meshing.body_geometry`.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from meshing.gear_body import GearBody


def _rot(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def _involute_tangent(points: np.ndarray, base_radius: float, at_end: bool) -> np.ndarray:
    """Exact unit tangent of an involute of ``base_radius`` at its first or last point,
    oriented along the point order. The normal of an involute is tangent to the base
    circle, so the tangent is the radial direction of the base-circle contact point."""
    p = points[-1] if at_end else points[0]
    chord = (points[-1] - points[-2]) if at_end else (points[1] - points[0])
    r = float(np.hypot(*p))
    alpha = math.acos(min(1.0, base_radius / r))
    theta = math.atan2(p[1], p[0])
    cands = [np.array([math.cos(theta + s * alpha), math.sin(theta + s * alpha)]) for s in (1, -1)]
    best = max(cands, key=lambda t: abs(float(t @ chord)))
    return best if float(best @ chord) > 0 else -best


@dataclass
class OutlineSegment:
    """A curve of the outline: a spline through ``pts``, a circular arc about the origin or
    a line; the ``kind`` says which."""

    kind: str  # "spline" | "arc" | "line"
    pts: np.ndarray  # (N,2); for an arc/line: the two end points
    t0: np.ndarray | None = None  # spline end tangents (unit), or None
    t1: np.ndarray | None = None


def _root_arc_points(r: float, a0: float, a1: float, spacing: float) -> np.ndarray:
    n = max(2, math.ceil(abs(a1 - a0) * r / spacing) + 1)
    a = np.linspace(a0, a1, n)
    return np.c_[r * np.cos(a), r * np.sin(a)]


def tooth_segments(gb: GearBody, prof) -> list[OutlineSegment]:
    """Segments of tooth 0 in CCW order from the mid-space at -pi/z to that at +pi/z."""
    g = gb.gear
    z = g.teeth
    half_pitch = math.pi / z
    rb = g.base_radius
    rr = g.root_radius
    fil_neg = np.asarray(prof.fillet_neg, float)  # root -> involute start, -theta side
    fil_pos = np.asarray(prof.fillet_pos, float)
    fl_neg = np.asarray(prof.flank_neg, float)  # root -> tip
    fl_pos = np.asarray(prof.flank_pos, float)

    def with_land(fil: np.ndarray, mid_angle: float) -> np.ndarray:
        # Prepend the half root land (on the root circle) from the mid-space to the fillet.
        a_start = math.atan2(fil[0, 1], fil[0, 0])
        land = abs(a_start - mid_angle) * rr
        if land < 1e-4:
            out = fil.copy()
            out[0] = rr * np.array([math.cos(mid_angle), math.sin(mid_angle)])
            return out
        spacing = float(np.min(np.linalg.norm(np.diff(fil, axis=0), axis=1)))
        arc = _root_arc_points(rr, mid_angle, a_start, max(spacing, 0.02))
        return np.vstack([arc[:-1], fil])

    a_neg = with_land(fil_neg, -half_pitch)
    a_pos = with_land(fil_pos, +half_pitch)

    def root_tangent(fil: np.ndarray, mid_angle: float) -> np.ndarray:
        # At the mid-space the curve runs along the root circle (land) or, without land,
        # leaves it tangentially (the trochoid is tangent to the root circle).
        t = np.array([-math.sin(mid_angle), math.cos(mid_angle)])
        chord = fil[1] - fil[0]
        return t if float(t @ chord) > 0 else -t

    t_flank_neg0 = _involute_tangent(fl_neg, rb, at_end=False)
    t_flank_neg1 = _involute_tangent(fl_neg, rb, at_end=True)
    t_flank_pos0 = _involute_tangent(fl_pos, rb, at_end=False)
    t_flank_pos1 = _involute_tangent(fl_pos, rb, at_end=True)
    segs = [
        OutlineSegment("spline", a_neg, root_tangent(a_neg, -half_pitch), t_flank_neg0),
        OutlineSegment("spline", fl_neg, t_flank_neg0, t_flank_neg1),
        OutlineSegment("arc", np.vstack([fl_neg[-1], fl_pos[-1]])),
        OutlineSegment("spline", fl_pos[::-1], -t_flank_pos1, -t_flank_pos0),
        OutlineSegment("spline", a_pos[::-1], -t_flank_pos0, -root_tangent(a_pos, half_pitch)),
    ]
    return segs


def outline_segments(gb: GearBody, prof, teeth: bool = True) -> list[OutlineSegment]:
    """Outline segments of the body at z = 0 (gear frame), CCW, a closed loop: the teeth
    (if ``teeth``) and, for a sector, the cut lines and the inner (outer) arc."""
    z = gb.gear.teeth
    pitch = 2.0 * math.pi / z
    base = tooth_segments(gb, prof)
    segs: list[OutlineSegment] = []
    for k in gb.teeth if teeth else []:
        R = _rot(k * pitch)
        for s in base:
            segs.append(
                OutlineSegment(
                    s.kind,
                    s.pts @ R.T,
                    None if s.t0 is None else R @ s.t0,
                    None if s.t1 is None else R @ s.t1,
                )
            )
    if not gb.full:
        a_neg, a_pos = gb.cut_angles
        r_in = gb.outer_radius if gb.gear.internal else gb.inner_radius
        r_root = gb.gear.root_radius
        e = lambda a, r: r * np.array([math.cos(a), math.sin(a)])  # noqa: E731
        segs.append(OutlineSegment("line", np.vstack([e(a_pos, r_root), e(a_pos, r_in)])))
        # Arc back from a_pos to a_neg, split into pieces of at most 60 degrees.
        n_arc = max(1, math.ceil((a_pos - a_neg) / math.radians(60.0)))
        angles = np.linspace(a_pos, a_neg, n_arc + 1)
        for a0, a1 in itertools.pairwise(angles):
            segs.append(OutlineSegment("arc", np.vstack([e(a0, r_in), e(a1, r_in)])))
        segs.append(OutlineSegment("line", np.vstack([e(a_neg, r_in), e(a_neg, r_root)])))
    return segs


def section_heights(gb: GearBody) -> np.ndarray:
    """Axial positions (mm) of the ``gb.n_sections`` loft sections, end face to end face."""
    b = gb.gear.face_width
    return np.linspace(-0.5 * b, 0.5 * b, gb.n_sections)
