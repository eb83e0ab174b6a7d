"""One helical gear body (full gear or sector of n teeth) as a tagged gmsh OCC model.

The solid is a loft (``occ.addThruSections``) through ``n_sections`` transverse sections.
Each section is the exact numpy outline of :func:`meshing.gear_geometry.tooth_profile`
(involute flanks, trochoidal fillets, tip arcs) turned by ``gear.helix_rotation(z)``; the
flanks and fillets are interpolating splines with the exact curve tangents at their ends
(so the fillet meets the flank tangentially). Fillet and the half root land next to it are
one curve, so every tooth space gives two faces (``fillet_neg`` of one tooth and
``fillet_pos`` of the next) and no sliver. Full gears get their bore (external) or rim
(internal) by a boolean with an exact cylinder; sectors are lofted with their cut lines
and inner (or outer) arc in the section.

Faces are named by geometry, never by creation order: every face is sampled on a 3 x 3
grid of parameter points, the points are turned back by the helix rotation, and the
radius, axial position and polar angle decide body surface, tooth index, side and kind
(:func:`classify_surfaces`).
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import asdict, dataclass

import numpy as np

from meshing import sizing
from meshing import tags as T
from meshing.sizing import MeshingError

MIN_SECTIONS = 5  # the feasibility probe: 3 sections deviate 0.64 mm, 5+ sections < 1 um


@dataclass(frozen=True)
class GearBody:
    """What to build: a gear (GearSpec), which teeth, and the bore or rim.

    ``first_tooth``/``n_teeth``: the sector holds the teeth ``first_tooth`` ...
    ``first_tooth + n_teeth - 1`` (mod z) and is cut in the middle of the two tooth spaces
    at its ends; ``n_teeth=None`` is the full gear. ``inner_radius`` is the bore radius of
    an external gear, ``outer_radius`` the rim (outside) radius of an internal gear.
    """

    gear: object  # meshing.gear_geometry.GearSpec
    name: str | None = None  # body name in the tags (default: gear.name)
    first_tooth: int = 0
    n_teeth: int | None = None
    inner_radius: float | None = None
    outer_radius: float | None = None
    n_sections: int = 9  # 9 sections: node deviation from the helicoid ~0.01 um
    n_involute: int = 20
    n_fillet: int = 14

    @property
    def body(self) -> str:
        return self.name if self.name is not None else self.gear.name

    @property
    def full(self) -> bool:
        return self.n_teeth is None

    @property
    def teeth(self) -> list[int]:
        z = self.gear.teeth
        n = z if self.full else self.n_teeth
        return [(self.first_tooth + i) % z for i in range(n)]

    @property
    def cut_angles(self) -> tuple[float, float] | None:
        """Polar angles (z = 0, gear frame) of the neg and pos sector cuts; None if full."""
        if self.full:
            return None
        p = 2.0 * math.pi / self.gear.teeth
        return (self.first_tooth - 0.5) * p, (self.first_tooth + self.n_teeth - 0.5) * p

    def validate(self) -> None:
        """Raise :class:`MeshingError` naming the field and the allowed range."""
        g = self.gear
        T.check_body_name(self.body)
        z = g.teeth
        if self.n_teeth is not None:
            if isinstance(self.n_teeth, bool) or not isinstance(self.n_teeth, int):
                raise MeshingError(f"{self.body}: n_teeth = {self.n_teeth!r}: must be an integer")
            if not 1 <= self.n_teeth <= z // 2:
                raise MeshingError(
                    f"{self.body}: n_teeth = {self.n_teeth}: a sector holds 1 to {z // 2} teeth "
                    f"(half of z = {z}); use n_teeth=None for the full gear"
                )
        if not isinstance(self.first_tooth, int) or not 0 <= self.first_tooth < z:
            raise MeshingError(
                f"{self.body}: first_tooth = {self.first_tooth!r}: must be an integer "
                f"from 0 to {z - 1}"
            )
        if not isinstance(self.n_sections, int) or not MIN_SECTIONS <= self.n_sections <= 64:
            raise MeshingError(
                f"{self.body}: n_sections = {self.n_sections!r}: must be an integer from "
                f"{MIN_SECTIONS} to 64 (fewer sections do not follow the helicoid)"
            )
        for field, val, lo in (("n_involute", self.n_involute, 8), ("n_fillet", self.n_fillet, 6)):
            if not isinstance(val, int) or not lo <= val <= 200:
                raise MeshingError(f"{self.body}: {field} = {val!r}: must be from {lo} to 200")
        m = g.normal_module
        if g.internal:
            if self.inner_radius is not None:
                raise MeshingError(f"{self.body}: inner_radius: an internal gear has no bore")
            lo = g.root_radius + 1.0 * m
            if self.outer_radius is None or not self.outer_radius >= lo:
                raise MeshingError(
                    f"{self.body}: outer_radius = {self.outer_radius!r}: the rim radius of an "
                    f"internal gear must be >= root radius + 1 module = {lo:.3f} mm"
                )
        else:
            if self.outer_radius is not None:
                raise MeshingError(f"{self.body}: outer_radius: only for internal gears")
            hi = g.root_radius - 1.0 * m
            if self.inner_radius is None or not 0.0 < self.inner_radius <= hi:
                raise MeshingError(
                    f"{self.body}: inner_radius = {self.inner_radius!r}: the bore radius must "
                    f"be > 0 and <= root radius - 1 module = {hi:.3f} mm"
                )

    def params(self) -> dict:
        """Canonical parameters (for the cache key)."""
        d = {k: v for k, v in asdict(self).items() if k != "gear"}
        d["gear"] = {k: v for k, v in asdict(self.gear).items()}
        d["body"] = self.body
        return d


# --------------------------------------------------------------------------------------
# 2D outline (gear frame, z = 0)
# --------------------------------------------------------------------------------------


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
class _Seg:
    """A curve of the outline: a spline through ``pts`` or a circular arc (origin)."""

    kind: str  # "spline" | "arc" | "line"
    pts: np.ndarray  # (N,2); for an arc/line: the two end points
    t0: np.ndarray | None = None  # spline end tangents (unit), or None
    t1: np.ndarray | None = None


def _root_arc_points(r: float, a0: float, a1: float, spacing: float) -> np.ndarray:
    n = max(2, math.ceil(abs(a1 - a0) * r / spacing) + 1)
    a = np.linspace(a0, a1, n)
    return np.c_[r * np.cos(a), r * np.sin(a)]


def _tooth_segments(gb: GearBody, prof) -> list[_Seg]:
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
        _Seg("spline", a_neg, root_tangent(a_neg, -half_pitch), t_flank_neg0),
        _Seg("spline", fl_neg, t_flank_neg0, t_flank_neg1),
        _Seg("arc", np.vstack([fl_neg[-1], fl_pos[-1]])),
        _Seg("spline", fl_pos[::-1], -t_flank_pos1, -t_flank_pos0),
        _Seg("spline", a_pos[::-1], -t_flank_pos0, -root_tangent(a_pos, half_pitch)),
    ]
    return segs


def outline_segments(gb: GearBody, prof, teeth: bool = True) -> list[_Seg]:
    """Outline segments of the body at z = 0 (gear frame), CCW, a closed loop: the teeth
    (if ``teeth``) and, for a sector, the cut lines and the inner (outer) arc."""
    z = gb.gear.teeth
    pitch = 2.0 * math.pi / z
    base = _tooth_segments(gb, prof)
    segs: list[_Seg] = []
    for k in gb.teeth if teeth else []:
        R = _rot(k * pitch)
        for s in base:
            segs.append(
                _Seg(
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
        segs.append(_Seg("line", np.vstack([e(a_pos, r_root), e(a_pos, r_in)])))
        # Arc back from a_pos to a_neg, split into pieces of at most 60 degrees.
        n_arc = max(1, math.ceil((a_pos - a_neg) / math.radians(60.0)))
        angles = np.linspace(a_pos, a_neg, n_arc + 1)
        for a0, a1 in itertools.pairwise(angles):
            segs.append(_Seg("arc", np.vstack([e(a0, r_in), e(a1, r_in)])))
        segs.append(_Seg("line", np.vstack([e(a_neg, r_in), e(a_neg, r_root)])))
    return segs


# --------------------------------------------------------------------------------------
# gmsh model
# --------------------------------------------------------------------------------------


def _add_curves(occ, segs: list[_Seg], snap: float = 1e-9) -> list[int]:
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
    tooth0 = _add_curves(occ, _tooth_segments(gb, prof))
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


def section_heights(gb: GearBody) -> np.ndarray:
    b = gb.gear.face_width
    return np.linspace(-0.5 * b, 0.5 * b, gb.n_sections)


def build_geometry(gmsh, gb: GearBody, prof=None) -> int:
    """Add the solid of ``gb`` to the current gmsh model (OCC); return its volume tag.

    Sectors: one loft through the closed section wires (teeth, cut lines, inner arc).
    Full gears: the toothed faces are lofted as surfaces, the bore (or rim) cylinder and
    the two annular end faces are added, and the faces are sewn into a volume (an OCC
    boolean of the loft with a cylinder gives the same solid but took 9 s for 26 teeth).
    """
    from meshing import gear_geometry as gg

    gb.validate()
    g = gb.gear
    if prof is None:
        prof = gg.tooth_profile(g, gb.n_involute, gb.n_fillet)
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


def _sample_surface(gmsh, tag: int, n: int = 3) -> np.ndarray:
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    fr = (np.arange(n) + 0.5) / n
    uv = []
    for fu in fr:
        for fv in fr:
            uv += [lo[0] + fu * (hi[0] - lo[0]), lo[1] + fv * (hi[1] - lo[1])]
    xyz = np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3)
    return xyz


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
        xyz = _sample_surface(gmsh, s)
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


def add_physical_groups(gmsh, groups: dict[str, list[int]], volumes: dict[str, list[int]]):
    """Add the named physical groups (sorted by name, so tag integers are reproducible)."""
    for name in sorted(volumes):
        gmsh.model.addPhysicalGroup(3, sorted(volumes[name]), name=name)
    for name in sorted(groups):
        gmsh.model.addPhysicalGroup(2, sorted(groups[name]), name=name)


def surface_sizes(
    gb: GearBody, groups: dict[str, list[int]], level: int, active_teeth
) -> dict[int, float]:
    """Surface tag -> element size: flanks and fillets of the active teeth fine, other
    teeth at the tooth size, bore/rim with ``per_circle`` segments a turn, the rest coarse."""
    lv = sizing.check_level(level)
    active = set(active_teeth)
    r_circ = gb.outer_radius if gb.gear.internal else gb.inner_radius
    out: dict[int, float] = {}
    for name, surfs in groups.items():
        p = T.parse(name)
        if p.tooth is not None:
            on = p.tooth in active
            if p.kind in (T.FLANK_POS, T.FLANK_NEG):
                h = lv.fine if on else lv.tooth
            elif p.kind in (T.FILLET_POS, T.FILLET_NEG):
                h = lv.fillet if on else lv.fillet_far
            else:
                h = lv.tooth
        elif p.kind in (T.BORE, T.RIM):
            h = min(lv.coarse, 2.0 * math.pi * r_circ / lv.per_circle)
        else:
            continue
        for s in surfs:
            out[s] = h
    return out


def structure_fillets(gmsh, gb: GearBody, groups, level: int, active_teeth) -> None:
    """Mesh the fillet faces as structured (transfinite) strips.

    A fillet is about 1.3 mm wide with a radius of about 0.5 mm but as long as the face
    width: an isotropic size fine enough across it would be wasteful along it, and sized
    from its corners alone it is spanned by single chords (the mesh then loses 5-10 % of
    the fillet area and adds ~0.7 % to the gear volume). Across: ``fillet`` (active teeth)
    or ``fillet_far`` segments; along: one count for every fillet of the body, from the
    finest of ``2 fillet`` (active teeth) and ``tooth``, so opposite sides always match.
    """
    lv = sizing.check_level(level)
    active = set(active_teeth)
    faces = []
    for name, surfs in groups.items():
        p = T.parse(name)
        if p.kind in (T.FILLET_POS, T.FILLET_NEG):
            h = lv.fillet if p.tooth in active else lv.fillet_far
            faces += [(sf, h) for sf in surfs]
    if not faces:
        return
    along = min(lv.tooth, *(2.0 * h for _, h in faces))
    transverse: dict[int, int] = {}
    longitudinal: set[int] = set()
    for sf, h in faces:
        curves = [abs(c) for _, c in gmsh.model.getBoundary([(2, sf)], oriented=False)]
        if len(curves) != 4:
            return  # not a 4-sided strip: leave the whole body unstructured
        for c in curves:
            ends = gmsh.model.getBoundary([(1, c)], oriented=False)
            zs = [gmsh.model.getValue(0, abs(pt), [])[2] for _, pt in ends]
            length = gmsh.model.occ.getMass(1, c)
            if abs(zs[0] - zs[-1]) < 1e-6:
                transverse[c] = max(transverse.get(c, 2), math.ceil(length / h) + 1)
            else:
                longitudinal.add(c)
    helix_len = max(gmsh.model.occ.getMass(1, c) for c in longitudinal)
    n_along = math.ceil(helix_len / along) + 1
    for c, n in transverse.items():
        gmsh.model.mesh.setTransfiniteCurve(c, n)
    for c in longitudinal:
        gmsh.model.mesh.setTransfiniteCurve(c, n_along)
    for sf, _ in faces:
        gmsh.model.mesh.setTransfiniteSurface(sf, arrangement="Alternate")


def mesh_options(gmsh) -> None:
    gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay surfaces
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)  # HXT: faster, better minimum quality
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    # One thread: HXT is then deterministic (with 2 threads the same input gave a flat tet in
    # one run out of three); it is fast enough alone.
    gmsh.option.setNumber("General.NumThreads", 1)


def enforce_quality(gmsh) -> bool:
    """Run the (slower, ~10 s per 100k tets) Netgen optimiser if the minimum SICN is below
    :data:`meshing.sizing.MIN_SICN`; True if it ran. Rare: one tet in 135k of the full
    case 1 ring with refined mesh zones came out at 0.107 (Netgen: 0.26)."""
    _, etags, _ = gmsh.model.mesh.getElements(3)
    tags_all = np.concatenate([np.asarray(t) for t in etags])
    q = np.asarray(gmsh.model.mesh.getElementQualities(tags_all, "minSICN"))
    if q.min() >= sizing.MIN_SICN:
        return False
    gmsh.model.mesh.optimize("Netgen", force=True)
    return True


def mesh_stats(gmsh) -> dict:
    """Element/node counts and quality of the 3D mesh in the current model."""
    etypes, etags, _ = gmsh.model.mesh.getElements(3)
    tags_all = np.concatenate([np.asarray(t) for t in etags]) if etags else np.array([])
    q = np.asarray(gmsh.model.mesh.getElementQualities(tags_all, "minSICN"))
    vol = np.asarray(gmsh.model.mesh.getElementQualities(tags_all, "volume"))
    node_tags, _, _ = gmsh.model.mesh.getNodes()
    return {
        "elements": len(tags_all),
        "nodes": len(node_tags),
        "min_sicn": float(q.min()) if len(q) else float("nan"),
        "p01_sicn": float(np.percentile(q, 1)) if len(q) else float("nan"),
        "volume": float(vol.sum()),
        "element_types": [int(e) for e in etypes],
    }


def build_body_mesh(gmsh, gb: GearBody, level: int, active_teeth=None) -> dict:
    """Build, tag and mesh ``gb`` in the current (empty) gmsh model; return statistics.

    ``active_teeth``: tooth indices of this body meshed at the fine size (default: all
    teeth of a sector, none of a full gear).
    """
    gb.validate()
    sizing.check_level(level)
    active_teeth = set(check_active(gb, active_teeth))
    t0 = time.perf_counter()
    vol = build_geometry(gmsh, gb)
    groups = classify_surfaces(gmsh, gb, vol)
    add_physical_groups(gmsh, groups, {T.volume(gb.body): [vol]})
    t_geo = time.perf_counter() - t0
    sizing.apply_sizes(gmsh, level, surface_sizes(gb, groups, level, active_teeth))
    structure_fillets(gmsh, gb, groups, level, active_teeth)
    mesh_options(gmsh)
    t1 = time.perf_counter()
    gmsh.model.mesh.generate(3)
    netgen = enforce_quality(gmsh)
    t_mesh = time.perf_counter() - t1
    stats = mesh_stats(gmsh)
    stats.update(
        netgen_optimized=netgen,
        geometry_seconds=t_geo,
        mesh_seconds=t_mesh,
        names=[*sorted(groups), T.volume(gb.body)],
        active_teeth=sorted(active_teeth),
    )
    return stats


def check_active(gb: GearBody, active_teeth) -> list[int]:
    """Validated sorted active teeth (default: all teeth of a sector, none of a full gear)."""
    if active_teeth is None:
        return [] if gb.full else sorted(gb.teeth)
    act = sorted({int(k) for k in active_teeth})
    bad = set(act) - set(gb.teeth)
    if bad:
        raise MeshingError(
            f"{gb.body}: active teeth {sorted(bad)} are not in the body (teeth {gb.teeth})"
        )
    return act


def body_mesh_file(gb: GearBody, level: int, active_teeth=None, comm=None, rebuild=False):
    """``(msh_path, meta)`` of the body mesh, from the cache or built on rank 0.

    Input is validated on every rank before gmsh runs (:class:`MeshingError`)."""
    from meshing import cache, gmsh_util

    gb.validate()
    sizing.check_level(level)
    act = check_active(gb, active_teeth)
    params = {"body": gb.params(), "level": level, "active_teeth": act}

    def builder(path):
        with gmsh_util.session(gb.body) as gm:
            stats = build_body_mesh(gm, gb, level, act)
            gmsh_util.write_msh(path)
        return stats

    return cache.get_or_build("body", params, builder, comm=comm, rebuild=rebuild)


def load_body(gb: GearBody, level: int, comm, active_teeth=None, rebuild=False):
    """The body as a :class:`meshing.to_dolfinx.MeshBundle` (collective)."""
    from meshing.to_dolfinx import load_msh

    path, meta = body_mesh_file(gb, level, active_teeth, comm=comm, rebuild=rebuild)
    return load_msh(path, comm, meta=meta)
