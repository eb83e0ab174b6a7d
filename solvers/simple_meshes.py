"""Small gmsh bodies with named facet tags, for verifying the solvers on closed forms.

Not gear meshes (those are :mod:`meshing`'s): discs, blocks, half discs and hollow
cylinders, refined towards a point by a size field
h(x) = min(h_max, h_min + grade * max(0, |x - x_c| - plateau)).
Every boundary entity is selected by geometry (bounding box), never by creation order.
The model is built on rank 0 of ``comm`` and distributed by DOLFINx.
"""

from __future__ import annotations

from dataclasses import dataclass

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import dolfinx
import dolfinx.io.gmsh
import gmsh
import numpy as np
from mpi4py import MPI

from meshing import gmsh_util


@dataclass
class MeshBundle:
    """A DOLFINx mesh with its facet tags and the facet tag name -> integer table."""

    mesh: dolfinx.mesh.Mesh
    facet_tags: dolfinx.mesh.MeshTags
    tags: dict[str, int]


def _start(name: str) -> None:
    if not gmsh.isInitialized():
        gmsh_util.initialize()
    # gmsh options are global to the session and outlive a model: start from the defaults,
    # so a mesh does not depend on what was meshed before in this process (a body mesh's
    # HXT mesher left set gave the roller 4083 cells instead of 4809)
    gmsh.option.restoreDefaults()
    gmsh.option.setNumber("General.Terminal", 0)
    # and set every size option used here
    for opt, val in (
        ("MeshSizeMin", 0.0),
        ("MeshSizeMax", 1e22),
        ("MeshSizeExtendFromBoundary", 1),
        ("MeshSizeFromPoints", 1),
        ("MeshSizeFromCurvature", 0),
    ):
        gmsh.option.setNumber(f"Mesh.{opt}", val)
    gmsh.model.add(name)


def _size_field(
    h_min: float, h_max: float, grade: float, x_c, plateau: float = 0.0, line_z: bool = False
) -> None:
    """Background size h_min near the point(s) x_c (one point or a list), grading out.

    With ``line_z`` the distance ignores z: refinement along the line through x_c parallel to z.
    """
    pts = [x_c] if np.ndim(x_c[0]) == 0 else list(x_c)
    f = gmsh.model.mesh.field.add("MathEval")
    ds = []
    for p in pts:
        dz = "" if line_z else f"+(z-({p[2] if len(p) > 2 else 0.0}))^2"
        ds.append(f"Sqrt((x-({p[0]}))^2+(y-({p[1]}))^2{dz})")
    d = ds[0]
    for e in ds[1:]:
        d = f"Min({d}, {e})"
    gmsh.model.mesh.field.setString(
        f, "F", f"Min({h_max}, {h_min} + {grade}*Max(0, {d} - {plateau}))"
    )
    gmsh.model.mesh.field.setAsBackgroundMesh(f)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{opt}", 0)


def _finish(comm: MPI.Comm, gdim: int, groups: dict[str, list[int]], order: int = 1):
    """Add physical groups (facets by name, one volume/surface group), mesh, convert."""
    if comm.rank == 0:
        tags = {}
        for i, (name, ents) in enumerate(groups.items(), start=1):
            gmsh.model.addPhysicalGroup(gdim - 1, ents, tag=i, name=name)
            tags[name] = i
        cells = [t for _, t in gmsh.model.getEntities(gdim)]
        gmsh.model.addPhysicalGroup(gdim, cells, tag=100, name="solid")
        gmsh.model.mesh.generate(gdim)
        gmsh.model.mesh.setOrder(order)
    data = dolfinx.io.gmsh.model_to_mesh(gmsh.model if comm.rank == 0 else None, comm, 0, gdim)
    if comm.rank == 0:
        gmsh.model.remove()
    tags = {k: int(v.tag) for k, v in data.physical_groups.items() if v.dim == gdim - 1}
    return MeshBundle(data.mesh, data.facet_tags, tags)


def _entities_in_box(dim: int, lo, hi, tol: float = 1e-6) -> list[int]:
    lo = np.asarray(lo, dtype=float) - tol
    hi = np.asarray(hi, dtype=float) + tol
    ents = gmsh.model.getEntitiesInBoundingBox(*lo, *hi, dim)
    return [t for _, t in ents]


def disc(
    comm: MPI.Comm,
    radius: float,
    centre=(0.0, 0.0),
    bore: float = 0.0,
    h_min: float = 0.5,
    h_max: float = 5.0,
    grade: float = 0.3,
    refine_at=None,
    plateau: float = 0.0,
) -> MeshBundle:
    """2D disc (optionally with a concentric bore); facets "outer" (and "bore")."""
    cx, cy = centre
    if comm.rank == 0:
        _start("disc")
        occ = gmsh.model.occ
        d = occ.addDisk(cx, cy, 0, radius, radius)
        if bore > 0:
            b = occ.addDisk(cx, cy, 0, bore, bore)
            occ.cut([(2, d)], [(2, b)])
        occ.synchronize()
        curves = [t for _, t in gmsh.model.getEntities(1)]
        inner = _entities_in_box(1, (cx - bore, cy - bore, 0), (cx + bore, cy + bore, 0))
        groups = {"outer": [c for c in curves if c not in inner]}
        if bore > 0:
            groups["bore"] = inner
        rp = refine_at if refine_at is not None else (cx, cy + radius)
        _size_field(h_min, h_max, grade, (*rp, 0.0), plateau)
    else:
        groups = {}
    return _finish(comm, 2, groups)


def half_disc(
    comm: MPI.Comm,
    radius: float,
    h_min: float = 0.5,
    h_max: float = 5.0,
    grade: float = 0.3,
    plateau: float = 0.0,
) -> MeshBundle:
    """2D lower half disc, centre (0, R), touching y = 0 at the origin; facets "arc", "top"."""
    if comm.rank == 0:
        _start("half_disc")
        occ = gmsh.model.occ
        d = occ.addDisk(0, radius, 0, radius, radius)
        r = occ.addRectangle(-2 * radius, radius, 0, 4 * radius, 2 * radius)
        occ.cut([(2, d)], [(2, r)])
        occ.synchronize()
        top = _entities_in_box(1, (-radius, radius, 0), (radius, radius, 0))
        arc = [t for _, t in gmsh.model.getEntities(1) if t not in top]
        groups = {"arc": arc, "top": top}
        _size_field(h_min, h_max, grade, (0.0, 0.0, 0.0), plateau)
    else:
        groups = {}
    return _finish(comm, 2, groups)


def block(
    comm: MPI.Comm,
    half_width: float,
    depth: float,
    h_min: float = 0.5,
    h_max: float = 5.0,
    grade: float = 0.3,
    plateau: float = 0.0,
) -> MeshBundle:
    """2D block [-W, W] x [-H, 0], refined towards the origin; facets "top", "bottom", "sides"."""
    if comm.rank == 0:
        _start("block")
        occ = gmsh.model.occ
        occ.addRectangle(-half_width, -depth, 0, 2 * half_width, depth)
        occ.synchronize()
        w, h = half_width, depth
        groups = {
            "top": _entities_in_box(1, (-w, 0, 0), (w, 0, 0)),
            "bottom": _entities_in_box(1, (-w, -h, 0), (w, -h, 0)),
            "sides": _entities_in_box(1, (-w, -h, 0), (-w, 0, 0))
            + _entities_in_box(1, (w, -h, 0), (w, 0, 0)),
        }
        _size_field(h_min, h_max, grade, (0.0, 0.0, 0.0), plateau)
    else:
        groups = {}
    return _finish(comm, 2, groups)


def hollow_cylinder(
    comm: MPI.Comm, radius: float, bore: float, length: float, h: float
) -> MeshBundle:
    """3D hollow cylinder about z, centred at the origin; facets "outer", "bore", "end_top",
    "end_bottom"."""
    if comm.rank == 0:
        _start("hollow_cylinder")
        occ = gmsh.model.occ
        c = occ.addCylinder(0, 0, -length / 2, 0, 0, length, radius)
        b = occ.addCylinder(0, 0, -length / 2, 0, 0, length, bore)
        occ.cut([(3, c)], [(3, b)])
        occ.synchronize()
        z = length / 2
        top = _entities_in_box(2, (-radius, -radius, z), (radius, radius, z))
        bot = _entities_in_box(2, (-radius, -radius, -z), (radius, radius, -z))
        inner = _entities_in_box(2, (-bore, -bore, -z), (bore, bore, z))
        outer = [t for _, t in gmsh.model.getEntities(2) if t not in top + bot + inner]
        groups = {"outer": outer, "bore": inner, "end_top": top, "end_bottom": bot}
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    else:
        groups = {}
    return _finish(comm, 3, groups)


def toothed_disc(
    comm: MPI.Comm,
    centre,
    r_hub: float,
    bore: float,
    teeth,
    r_tip: float,
    h_min: float = 0.1,
    h_max: float = 4.0,
    grade: float = 0.25,
    plateau: float = 0.5,
) -> MeshBundle:
    """2D gear-like body: hub annulus (bore .. r_hub) united with tooth lobes.

    Each tooth lobe is disc(c_k, rho_k) cut to the tip circle r_tip; its circular flank is the
    osculating circle of an involute (centre c_k on the base circle, radius rho_k), so the
    flank through the contact point is exact to second order. ``teeth`` is a list of
    (c_k, rho_k, contact point); the mesh is refined at the contact points.
    Facets: "bore" and "outer".
    """
    cx, cy = centre
    if comm.rank == 0:
        _start("toothed_disc")
        occ = gmsh.model.occ
        hub = occ.addDisk(cx, cy, 0, r_hub, r_hub)
        lobes = []
        for c, rho, _ in teeth:
            lobe = occ.addDisk(c[0], c[1], 0, rho, rho)
            tip = occ.addDisk(cx, cy, 0, r_tip, r_tip)
            out, _ = occ.intersect([(2, lobe)], [(2, tip)])
            lobes += out
        body, _ = occ.fuse([(2, hub)], lobes)
        b = occ.addDisk(cx, cy, 0, bore, bore)
        occ.cut(body, [(2, b)])
        occ.synchronize()
        inner = _entities_in_box(1, (cx - bore, cy - bore, 0), (cx + bore, cy + bore, 0))
        groups = {
            "outer": [t for _, t in gmsh.model.getEntities(1) if t not in inner],
            "bore": inner,
        }
        _size_field(h_min, h_max, grade, [(*p, 0.0) for _, _, p in teeth], plateau)
    else:
        groups = {}
    return _finish(comm, 2, groups)


def roller(
    comm: MPI.Comm,
    radius: float,
    length: float,
    bore: float,
    h_min: float = 1.0,
    h_max: float = 5.0,
    grade: float = 0.3,
    plateau: float = 0.0,
) -> MeshBundle:
    """3D hollow roller, axis z through (0, R, 0), z in [-L/2, L/2], touching y = 0 along z.

    Refined along the contact line x = y = 0. Facets "outer", "bore", "ends".
    """
    if comm.rank == 0:
        _start("roller")
        occ = gmsh.model.occ
        c = occ.addCylinder(0, radius, -length / 2, 0, 0, length, radius)
        b = occ.addCylinder(0, radius, -length / 2, 0, 0, length, bore)
        occ.cut([(3, c)], [(3, b)])
        occ.synchronize()
        z = length / 2
        ends = _entities_in_box(2, (-radius, 0, z), (radius, 2 * radius, z))
        ends += _entities_in_box(2, (-radius, 0, -z), (radius, 2 * radius, -z))
        inner = _entities_in_box(2, (-bore, radius - bore, -z), (bore, radius + bore, z))
        outer = [t for _, t in gmsh.model.getEntities(2) if t not in ends + inner]
        groups = {"outer": outer, "bore": inner, "ends": ends}
        _size_field(h_min, h_max, grade, (0.0, 0.0, 0.0), plateau, line_z=True)
    else:
        groups = {}
    return _finish(comm, 3, groups)


def block3d(
    comm: MPI.Comm,
    half_width: float,
    depth: float,
    length: float,
    h_min: float = 1.0,
    h_max: float = 8.0,
    grade: float = 0.3,
    plateau: float = 0.0,
) -> MeshBundle:
    """3D block [-W, W] x [-H, 0] x [-L/2, L/2], refined along x = y = 0; facets "top",
    "bottom", "sides"."""
    if comm.rank == 0:
        _start("block3d")
        occ = gmsh.model.occ
        occ.addBox(-half_width, -depth, -length / 2, 2 * half_width, depth, length)
        occ.synchronize()
        w, h, z = half_width, depth, length / 2
        top = _entities_in_box(2, (-w, 0, -z), (w, 0, z))
        bottom = _entities_in_box(2, (-w, -h, -z), (w, -h, z))
        sides = [t for _, t in gmsh.model.getEntities(2) if t not in top + bottom]
        groups = {"top": top, "bottom": bottom, "sides": sides}
        _size_field(h_min, h_max, grade, (0.0, 0.0, 0.0), plateau, line_z=True)
    else:
        groups = {}
    return _finish(comm, 3, groups)
