"""Mesh a gear body in the current gmsh model: element sizes, structured fillets, tags.

The active teeth (in or next to a mesh zone) get the fine sizes of the level on their
flanks and fillets, the other teeth the tooth sizes, the bore or rim a fixed number of
segments a turn; the fillets are structured strips (:func:`structure_fillets`). The
``gmsh`` module is passed in by the caller (:mod:`meshing.body_cache` opens the session).
"""

from __future__ import annotations

import math
import time

from meshing import sizing
from meshing import tags as T
from meshing.body_geometry import build_geometry, classify_surfaces
from meshing.gear_body import GearBody
from meshing.gmsh_util import (
    add_physical_groups,
    curve_elements,
    enforce_quality,
    mesh_options,
    mesh_stats,
)
from meshing.sizing import MeshingError


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


def fillet_size(gb: GearBody, lv, kind: str, tooth: int, active: set[int]) -> float:
    """The size across a fillet: ``lv.fillet`` on the active teeth (only on the fillets
    ``gb.fine_fillets`` names, if it names any), else ``lv.fillet_far``."""
    if tooth not in active:
        return lv.fillet_far
    if gb.fine_fillets is None:
        return lv.fillet
    side = "pos" if kind == T.FILLET_POS else "neg"
    return lv.fillet if (tooth, side) in set(gb.fine_fillets) else lv.fillet_far


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
                h = fillet_size(gb, lv, p.kind, p.tooth, active)
            else:
                h = lv.tooth
        elif p.kind in (T.BORE, T.RIM):
            h = min(lv.coarse, 2.0 * math.pi * r_circ / lv.per_circle)
        else:
            continue
        for s in surfs:
            out[s] = h
    return out


def _strips_sharing_curves(longs: dict[int, list[int]]) -> list[list[int]]:
    """The faces of ``longs`` (face -> longitudinal curves) grouped by shared curves (the
    two fillets of a tooth space share their root line): each group needs one count."""
    parent = {sf: sf for sf in longs}

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    owner: dict[int, int] = {}
    for sf, curves in longs.items():
        for c in curves:
            if c in owner:
                parent[root(sf)] = root(owner[c])
            else:
                owner[c] = sf
    groups: dict[int, list[int]] = {}
    for sf in longs:
        groups.setdefault(root(sf), []).append(sf)
    return [sorted(g) for _, g in sorted(groups.items())]


def structure_fillets(gmsh, gb: GearBody, groups, level: int, active_teeth) -> None:
    """Mesh the fillet faces as structured (transfinite) strips.

    A fillet is about 1.3 mm wide with a radius of about 0.5 mm but as long as the face
    width: an isotropic size fine enough across it would be wasteful along it, and sized
    from its corners alone it is spanned by single chords (the mesh then loses 5-10 % of
    the fillet area and adds ~0.7 % to the gear volume). Across: ``fillet`` (active teeth)
    or ``fillet_far`` segments (``fillet`` only on ``gb.fine_fillets`` if it names any);
    along: one count for every fillet of the body, from the finest of ``2 x`` their across
    size and ``tooth``, so opposite sides of a strip always match. A body that names
    ``fine_fillets`` gets one count per group of fillets sharing a longitudinal curve (the
    two of a tooth space) instead, or its few fine fillets would refine every fillet of the
    body along the face width. The scenes name their fine fillets
    (:func:`meshing.scenes.tension_fillets`), so every scene body is meshed this way; a
    body that names none (a standalone body of the tests) keeps one count for all.

    Through the depth the tets follow the strips: HXT sizes the volume from the longest
    surface edge at each node, so the tets on a fillet are about 2 ``fillet`` high (measured
    on the case-1 sun sector, level-1 flanks: median height 0.55 mm at fillet 0.3, 0.29 mm
    at 0.15; along ``4 fillet`` they were 0.86 / 0.47 mm with half the nodes) and grow
    into the body; the refined region costs about 3000 / fillet^2 nodes (fillet in mm) on
    that sector (7 active teeth), ten volume nodes for each fillet surface node.
    """
    lv = sizing.check_level(level)
    active = set(active_teeth)
    faces = []
    for name, surfs in groups.items():
        p = T.parse(name)
        if p.kind in (T.FILLET_POS, T.FILLET_NEG):
            h = fillet_size(gb, lv, p.kind, p.tooth, active)
            faces += [(sf, h) for sf in surfs]
    if not faces:
        return
    transverse: dict[int, int] = {}
    longs: dict[int, list[int]] = {}  # face -> its two longitudinal curves
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
                longs.setdefault(sf, []).append(c)
    for c, n in transverse.items():
        gmsh.model.mesh.setTransfiniteCurve(c, n)
    size = dict(faces)
    # one group of every fillet unless fine_fillets names some (see the docstring)
    groups_along = [sorted(longs)] if gb.fine_fillets is None else _strips_sharing_curves(longs)
    for comp in groups_along:
        curves = {c for sf in comp for c in longs[sf]}
        along = min(lv.tooth, *(2.0 * size[sf] for sf in comp))
        helix_len = max(gmsh.model.occ.getMass(1, c) for c in curves)
        for c in curves:
            gmsh.model.mesh.setTransfiniteCurve(c, math.ceil(helix_len / along) + 1)
    for sf, _ in faces:
        gmsh.model.mesh.setTransfiniteSurface(sf, arrangement="Alternate")


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
    curved = curve_elements(gmsh) if gb.geometry_order == 2 else {}
    t_mesh = time.perf_counter() - t1
    stats = mesh_stats(gmsh)
    stats.update(
        netgen_optimized=netgen,
        geometry_order=gb.geometry_order,
        **curved,
        geometry_seconds=t_geo,
        mesh_seconds=t_mesh,
        names=[*sorted(groups), T.volume(gb.body)],
        active_teeth=sorted(active_teeth),
    )
    return stats
