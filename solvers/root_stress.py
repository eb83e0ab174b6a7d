"""Tooth root (bending) stress at the fillet surface of the loaded teeth, from the FE
displacement.

For a solved gear train (:func:`solvers.gear_train.build_gear_train` + ``problem.solve()``)
and each gear body, the stress of the FE field

    sigma = lambda tr(eps) I + 2 mu eps,   eps = (grad u + grad u^T) / 2      (MPa, mm)

is read on the root fillets (``<body>/toothNN/fillet_pos`` and ``fillet_neg``,
:mod:`meshing.tags`) of the teeth that carry load, i.e. the teeth named in the contact-grid
lines of the model (driver and driven tooth of every line of
:class:`solvers.flank_grid.FlankGridInfo`).

Surface value (:func:`surface_values`): at every vertex of those fillets, the mean over the
cells with a fillet facet at that vertex of each cell's own stress field evaluated at the
vertex (nodal averaging on the surface). For P2 the cell stress is linear and this is the
surface value with an O(h^2) error; for P1 it is the mean of the constant values of the
surface cells, whose error is O(h) (their values are volume averages reaching a cell deep
into a stress that peaks at the surface: a lower estimate that rises as the mesh is refined;
a least-squares extrapolation of the cell values to the surface was tried and rejected:
with one or two cell layers across a 0.85 mm fillet radius it either averaged in the deeper,
lower stresses or, fitted on the vertex patches, was unstable, 4.5-8x the cell values;
rechecked with the fillet-only ladder of studies/fillet/driver.py: a patch of radius 1.5-3
fillet edges also reaches the neighbouring tooth across the tooth space, and a fit kept to
the cells under the vertex (material side, along the normal) gave 450-760 MPa for the sun
at level 0 as the patch shrank from 2 to 1 edge deep (nodal 552, P2 807): no stable
extrapolation while the stress falls from its surface value to a fifth of it within the
first two cell layers, 0.7-0.8 mm; a strain-gauge reading, the plane stress of each fillet
facet's membrane strain from its vertex displacements, was lower still: 1-GB level 1 at
roll 0, sun / pinion sun side / ring side / ring 446 / 473 / 517 / 415 MPa at 0.45 mm and
603 / 583 / 609 / 458 at 0.3 mm, against 552 / 580 / 640 / 447 and 671 / 658 / 708 / 521
nodal: the coarse fillet's displacement itself carries too little of the concentration).
The fillet-only ladder (meshing/sizing.py docstring)
finds the P1 surface value levelling off, within a 5 % scatter, at fillet sizes of
0.12-0.15 mm; at the old level-1 fillet (0.45 mm) it was 24-32 % lower. The scenes now
refine the tension fillets of the teeth loaded in the mesh cycle (``GearBody.fine_fillets``)
to the level's ``fillet`` size, 0.15 mm at level 1 (1-GB at roll 0, the convergence study
of ``make``: 3-8 % below level 2's 0.12 mm); level 0 (0.45 mm) is a smoke value, 23-35 %
below level 1. P2 at level 0 (0.45 mm fillets) is 0.5-8 % below P1 at level 2 (with the
earlier 0.6 mm fillets it was 9-12 % below the 0.12 mm P1 values; before the fine fillets, on
1-GA at roll 0, P1 gave 0.64-0.70 of P2 level 0 at level 0, 0.68-0.78 at level 1 and
0.85-0.96 at level 2). The maximum principal stress (tension positive) of the
nodal tensors is evaluated

* at every fillet vertex of the loaded teeth farther than the face-end band from a face end
  (:func:`face_end_band`: one normal module, or the read fillet's element size if larger):
  the surface maximum (the value quoted), with its tooth, fillet side (``pos``/``neg``,
  geometric side of the body frame), z (mm from mid face width, body frame) and radius from
  the gear axis; within the band, ``face_end``: the fillet meets the end face in a corner
  and an edge load (the wider mate's contact running past the narrower gear's face)
  stresses it, a value that grows with refinement and is kept apart, as the contact stress
  keeps its edge points apart. The band is a fixed length, not a number of elements: the
  interior maximum often sits at its inner edge (the stress rises towards the loaded face
  end), so a band that shrank with the mesh would move the point read and the value would
  not converge; one module is about the distance over which the corner's disturbance of a
  fillet decays (a tooth's thickness at the root is about 2 modules);
* not within one read-fillet element (:data:`NEAR_LOAD_ELEMENTS`) of a point force of a
  submodel's contact loads (``load_points``): where a mate's tip touches the flank at the
  form circle, a force sits next to the fillet's top vertices, and its unresolved point-load
  field (a P2 spike of a few elements) read as root stress. 1-GB-R at position 0 read
  2431 MPa on the pinion's ring side at the form circle (r = 20.921 mm) against 1740-1882
  at the other positions, 1-GA at position 3 729 against 629-649; the largest value there
  is kept apart as ``near_load`` (the contact's own stress is the contact-stress reading's);
* along ISO 6336-3's critical line: the points of both fillets of every loaded tooth whose
  tangent makes 30 deg (external gear) or 60 deg (internal gear) with the tooth centre line
  (:func:`gears.iso6336_root.fillet_tangent_point` of the transverse section, turned with the
  helix along the face width, outside the face-end band), interpolated
  linearly on the fillet facet under each point; the largest value along the lines
  (``tangent``) with its z.

The largest cell (midpoint) value of the fillet cells, the earlier estimate, is kept as
``cell_max``. The surface and ISO-line maxima of the nodal tensors fitted by moving least
squares in each fillet's own coordinates (:mod:`solvers.surface_recovery`, which takes the
node-to-node scatter off a largest value) are kept as ``recovered``, from the same nodes
(interior, off the point forces' near field) and at the same line points; the reports
quote the recovered reading where a summary holds it
(:func:`postprocess.stress_tables.reported_root_stress`).

A gear in one mesh is reported under its own name (``sun``, ``ring``); a pinion carries load
at two meshes, on different teeth, and is reported per mate: ``<pinion>_<mate>_side`` (case
1: ``pinion_sun_side`` and ``pinion_ring_side``; case 2: ``SP_sun_side``, ``SP_RP_side``,
``RP_SP_side``, ``RP_ring_side``), see :func:`loaded_teeth`. Both fillets of a loaded tooth
are searched: the one under the loaded flank is in tension, the other in compression, so the
maximum tensile principal stress picks the tension fillet without fixing the side here.

Collective over the mesh communicator and rank-independent: every rank evaluates its owned
cells, the per-vertex and per-facet rows are gathered on every rank and sorted by their
coordinates, and every rank reduces the same data in the same order.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import math

import dolfinx
import dolfinx.fem
import numpy as np
import ufl

from gears.iso6336_root import fillet_tangent_point
from gears.train import mesh_side_keys
from meshing import tags as tagnames
from solvers.surface_recovery import fillet_coordinates, fillet_curve, recover, strip_spacings

REF_VERTICES = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
INSIDE = 1e-6  # barycentric tolerance of "the facet under a point"
#: fillet vertices nearer than this many read-fillet element sizes to a point force of a
#: submodel's contact loads are kept apart from the surface maximum (module docstring)
NEAR_LOAD_ELEMENTS = 1.0


def loaded_fillets(scene) -> list[tuple[str, str, str, str]]:
    """(output key, body, grid name, which tooth of the grid lines) per gear and mesh
    (keys of :func:`gears.train.mesh_side_keys`)."""
    pairs = [(zn.driver, zn.driven) for zn in scene.zones]
    which = {1: "driver_tooth", 2: "driven_tooth"}
    out = []
    for key, body, mate, i in mesh_side_keys(pairs):
        grid = f"{body}-{mate}" if i == 1 else f"{mate}-{body}"
        out.append((key, body, grid, which[i]))
    return out


def set_keys(scene) -> dict[str, str]:
    """Output key -> the key of the same gear and mesh in the gear set (``pinion2_sun_side``
    -> ``pinion_sun_side``, ``sun_pinion2_side`` -> ``sun``): what ISO's nominal stress is
    keyed by (:func:`postprocess.mesh_stress.iso_nominal_root_stress`)."""
    name = {g.name: g.gear_name for g in scene.gears}
    pairs = list(dict.fromkeys((name[zn.driver], name[zn.driven]) for zn in scene.zones))
    by_gear = {(g, m, i): k for k, g, m, i in mesh_side_keys(pairs)}
    out = {}
    for key, body, mate, i in mesh_side_keys([(zn.driver, zn.driven) for zn in scene.zones]):
        out[key] = by_gear[(name[body], name[mate], i)]
    return out


def grid_teeth(scene, grids) -> dict[str, list[int]]:
    """Teeth named in the lines of the drive grids ``grids`` (grid name -> (grid,
    :class:`solvers.flank_grid.FlankGridInfo`)) of ``scene``, per output key (see
    :func:`loaded_fillets`)."""
    out = {}
    for key, _, grid, which in loaded_fillets(scene):
        out[key] = sorted({int(ln[which]) for ln in grids[grid][1].lines})
    return out


def loaded_teeth(model) -> dict[str, list[int]]:
    """Teeth named in the contact-grid lines of a gear train, per output key."""
    return grid_teeth(model.scene, model.grids)


def max_principal(sig: np.ndarray) -> np.ndarray:
    """Largest eigenvalue of symmetric tensors (..., 3, 3)."""
    return np.linalg.eigvalsh(sig)[..., -1]


def _stress_expression(body, u: dolfinx.fem.Function, points: np.ndarray):
    mat = body.material
    eps = ufl.sym(ufl.grad(u))
    sig = mat.lam * ufl.tr(eps) * ufl.Identity(body.gdim) + 2.0 * mat.mu * eps
    return dolfinx.fem.Expression(sig, points)


def _gather_rows(comm, a: np.ndarray, width: int) -> np.ndarray:
    """Rows of every rank, concatenated and sorted lexicographically (rank-independent)."""
    parts = comm.allgather(np.ascontiguousarray(a, dtype=float).reshape(-1, width))
    rows = np.concatenate(parts) if parts else np.zeros((0, width))
    if len(rows) == 0:
        return rows
    return rows[np.lexsort(rows.T[::-1])]


def _fillet_groups(body, teeth) -> list[tuple[int, str, int]]:
    return [
        (t, side, body.tags[tagnames.fillet(body.name, t, side)])
        for t in teeth
        for side in ("pos", "neg")
        if tagnames.fillet(body.name, t, side) in body.tags
    ]


def tangent_line(gear, tooth: int, side: str, z: np.ndarray) -> np.ndarray:
    """Body-frame points (len(z), 3) of ISO's critical fillet point (30 deg tangent external,
    60 deg internal) of tooth ``tooth``, side ``side``, at axial positions z: the transverse
    point of tooth 0's pos fillet (:func:`gears.iso6336_root.fillet_tangent_point`), mirrored
    for neg, turned by 2 pi tooth / z_teeth and by the helix rotation at z."""
    p = np.asarray(fillet_tangent_point(gear)["point"], float)
    if side == "neg":
        p = p * np.array([1.0, -1.0])
    ang = 2.0 * math.pi * tooth / gear.teeth + np.asarray(gear.helix_rotation(z), float)
    c, s = np.cos(ang), np.sin(ang)
    return np.c_[c * p[0] - s * p[1], s * p[0] + c * p[1], z]


def _stress_at(expr: dolfinx.fem.Expression, mesh, cells: np.ndarray, n_points: int):
    """Stress (n_cells, n_points, 3, 3) of ``expr`` (:func:`_stress_expression`, built on
    every rank: its JIT compilation is collective) in ``cells``."""
    if cells.size == 0:
        return np.zeros((0, n_points, 3, 3))
    return expr.eval(mesh, cells).reshape(len(cells), n_points, 3, 3)


def surface_values(body, u, facet_groups: list[np.ndarray]):
    """Nodal surface stress on groups of boundary facets (local facet indices per group;
    collective; the same arrays on every rank, sorted).

    Returns ``nodes``: rows (group, x, y, z) of every vertex of every group,
    ``tensors`` (n, 3, 3): per node the mean over the group's facets at that vertex of the
    stress of the facet's cell at the vertex (module docstring), and ``facets``: rows
    (group, node index of each of the 3 vertices) of every facet.
    """
    mesh = body.mesh
    tdim = mesh.topology.dim
    for a, b in ((tdim - 1, tdim), (tdim - 1, 0), (tdim, 0), (0, tdim)):
        mesh.topology.create_connectivity(a, b)
    f2c, f2v = mesh.topology.connectivity(tdim - 1, tdim), mesh.topology.connectivity(tdim - 1, 0)
    c2v = mesh.topology.connectivity(tdim, 0)
    n_own = mesh.topology.index_map(tdim).size_local
    expr = _stress_expression(body, u, REF_VERTICES)  # collective
    vrows, frows = [], []
    for g, facets in enumerate(facet_groups):
        if facets.size == 0:
            continue
        cells = np.array([f2c.links(f)[0] for f in facets], dtype=np.int32)
        own = cells < n_own  # every facet once: by the rank owning its cell
        facets, cells = facets[own], cells[own]
        if facets.size == 0:
            continue
        fv = np.array([f2v.links(f) for f in facets]).reshape(-1, 3)
        cv = np.array([c2v.links(c) for c in cells]).reshape(-1, 4)
        local = np.argmax(cv[:, None, :] == fv[:, :, None], axis=2)  # facet vertex in cell
        sig = _stress_at(expr, mesh, cells, 4)  # geometry order = reference order
        x = mesh.geometry.x[
            dolfinx.mesh.entities_to_geometry(mesh, 0, fv.ravel().astype(np.int32)).ravel()
        ].reshape(-1, 3, 3)
        rows = np.arange(len(facets))[:, None]
        vsig = sig[rows, local]  # (n_facets, 3 vertices, 3, 3)
        vrows.append(np.c_[np.full(fv.size, g), x.reshape(-1, 3), vsig.reshape(-1, 9)])
        frows.append(np.c_[np.full(len(facets), g), x.reshape(-1, 9)])
    vr = _gather_rows(body.comm, np.vstack(vrows) if vrows else np.zeros((0, 13)), 13)
    fr = _gather_rows(body.comm, np.vstack(frows) if frows else np.zeros((0, 10)), 10)
    key = np.c_[vr[:, 0], np.round(vr[:, 1:4], 9)]
    nodes, inverse, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    tensors = np.zeros((len(nodes), 9))
    np.add.at(tensors, inverse.ravel(), vr[:, 4:])
    tensors = (tensors / np.maximum(count, 1)[:, None]).reshape(-1, 3, 3)
    lookup = {tuple(n): i for i, n in enumerate(nodes)}
    tri = np.array(
        [[lookup[(f[0], *np.round(f[1 + 3 * j : 4 + 3 * j], 9))] for j in range(3)] for f in fr],
        dtype=np.int64,
    ).reshape(-1, 3)
    return nodes, tensors, np.c_[fr[:, 0].astype(np.int64), tri]


def on_surface(points: np.ndarray, corners: np.ndarray):
    """Per point: the facet (index into ``corners`` (m, 3, 3)) under it and the barycentric
    weights of the point's projection there; the facet whose plane is nearest among those
    that contain the projection (all weights >= -INSIDE), else the facet with the nearest
    centroid (weights clipped to the facet). Also the distance to that facet's plane."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1)[:, None]
    out_f, out_w, out_d = [], [], []
    for p in points:
        d = ((p - a) * n).sum(1)
        q = p - d[:, None] * n
        v0, v1, v2 = b - a, c - a, q - a
        d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
        d20, d21 = (v2 * v0).sum(1), (v2 * v1).sum(1)
        den = d00 * d11 - d01 * d01
        w1, w2 = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
        w = np.c_[1.0 - w1 - w2, w1, w2]
        inside = np.flatnonzero(np.all(w >= -INSIDE, axis=1))
        if inside.size:
            k = int(inside[np.argmin(np.abs(d[inside]))])
            wk = w[k]
        else:
            k = int(np.argmin((((a + b + c) / 3.0 - p) ** 2).sum(1)))
            wk = np.clip(w[k], 0.0, None)
            wk /= wk.sum()
        out_f.append(k)
        out_w.append(wk)
        out_d.append(abs(float(d[k])))
    return np.array(out_f, dtype=np.int64), np.array(out_w).reshape(-1, 3), np.array(out_d)


def face_end_band(gear, h: float) -> float:
    """Width (mm) of the face-end band kept apart from the interior maximum: one normal module
    of ``gear``, or the fillet element size ``h`` if larger (module docstring)."""
    return max(float(gear.normal_module), float(h))


def near_loads(points: np.ndarray, loads: np.ndarray, reach: float) -> np.ndarray:
    """Mask of the ``points`` (n, 3) nearer than ``reach`` (mm) to any of the point forces
    at ``loads`` (m, 3)."""
    near = np.zeros(len(points), bool)
    if not len(points) or not len(loads) or reach <= 0.0:
        return near
    r = np.linalg.norm(points[:, :2], axis=1)  # only forces in the points' radial span
    rl = np.linalg.norm(loads[:, :2], axis=1)
    loads = loads[(rl > r.min() - reach) & (rl < r.max() + reach)]
    for i in range(0, len(points), 256):
        d2 = ((points[i : i + 256, None, :] - loads[None, :, :]) ** 2).sum(axis=2)
        near[i : i + 256] = (d2 < reach * reach).any(axis=1)
    return near


def body_root_stress(
    body, u, gear, keyed_teeth: dict[str, list[int]], load_points: np.ndarray | None = None
) -> dict:
    """Surface, tangent-line and cell maxima per key for one body (collective): ``body``
    anything with the ``name``, ``mesh``, ``facet_tags``, ``tags``, ``material``, ``gdim``
    and ``comm`` of :class:`solvers.elastic_body.ElasticBody`, its mesh in the gear's own
    frame (axis = z through the origin), ``u`` its displacement; ``keyed_teeth``: output key
    -> the teeth whose fillets are searched; ``load_points``: where the contact forces act
    on the body as point forces (its frame; a submodel's loads), whose near field is kept
    apart from the surface maximum (``near_load``, module docstring)."""
    mesh = body.mesh
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    all_teeth = sorted({t for ts in keyed_teeth.values() for t in ts})
    groups = _fillet_groups(body, all_teeth)
    facet_groups = [body.facet_tags.find(tag) for _, _, tag in groups]
    nodes, tensors, facets = surface_values(body, u, facet_groups)
    s1 = max_principal(tensors) if len(nodes) else np.zeros(0)
    gid = nodes[:, 0].astype(np.int64) if len(nodes) else np.zeros(0, np.int64)
    # the earlier estimate: the largest midpoint value of the fillet cells (owned)
    n_own = mesh.topology.index_map(tdim).size_local
    f2c = mesh.topology.connectivity(tdim - 1, tdim)
    cell_best = {}
    expr = _stress_expression(body, u, np.full((1, tdim), 1.0 / (tdim + 1)))  # collective
    for (t, side, _), fac in zip(groups, facet_groups, strict=True):
        cells = np.unique([f2c.links(f)[0] for f in fac]).astype(np.int32)
        cells = cells[cells < n_own]
        if cells.size:
            cell_best[(t, side)] = float(max_principal(_stress_at(expr, mesh, cells, 1)).max())
    cell_all = body.comm.allgather(cell_best)
    # size of the read fillets: the longest facet edge of the finest fillet (the refined
    # tension fillet; sets the z step of the critical line)
    corners = nodes[facets[:, 1:], 1:4] if len(facets) else np.zeros((0, 3, 3))
    edge = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).max(axis=1)
    h = min((float(edge[facets[:, 0] == g].max()) for g in np.unique(facets[:, 0])), default=0.0)
    b = gear.face_width
    band = face_end_band(gear, h)
    half = max(0.5 * b - band, 0.0)  # the critical line over the interior (as the surface max)
    forces_at = np.zeros((0, 3)) if load_points is None else np.asarray(load_points, float)
    near = near_loads(nodes[:, 1:4], forces_at, NEAR_LOAD_ELEMENTS * h)
    z = np.linspace(-half, half, max(math.ceil(2.0 * half / (0.25 * h)) + 1, 3) if h else 3)
    out = {}
    for key, teeth in keyed_teeth.items():
        gsel = [i for i, (t, _, _) in enumerate(groups) if t in teeth]
        rec = {"teeth": list(teeth), "fillet_h_mm": h, "face_end_band_mm": band}
        on = np.isin(gid, gsel)
        end = np.abs(nodes[:, 3]) > 0.5 * b - band if len(nodes) else np.zeros(0, bool)
        sel = np.flatnonzero(on & ~end & ~near)  # interior, off the point forces' near field
        rec["surface_points"] = int(np.count_nonzero(on))
        close = np.flatnonzero(on & ~end & near)
        rec["near_load"] = float(s1[close].max()) if close.size else None
        rec["near_load_mm"] = NEAR_LOAD_ELEMENTS * h if len(forces_at) else 0.0
        if sel.size:
            i = int(sel[np.argmax(s1[sel])])
            t, side, _ = groups[gid[i]]
            x = nodes[i, 1:4]
            rec.update(
                value=float(s1[i]),
                tooth=int(t),
                side=side,
                z_mm=float(x[2]),
                radius_mm=float(np.linalg.norm(x[:2])),
            )
        else:
            rec.update(value=None, tooth=None, side=None, z_mm=None, radius_mm=None)
        ends = np.flatnonzero(on & end)
        rec["face_end"] = float(s1[ends].max()) if ends.size else None
        best = (-np.inf, None, None, None, None)
        for g in gsel:
            t, side, _ = groups[g]
            fsel = facets[facets[:, 0] == g, 1:]
            if not len(fsel):
                continue
            line = tangent_line(gear, t, side, z)
            f, w, dist = on_surface(line, nodes[fsel, 1:4])
            vals = max_principal(np.einsum("pk,pkij->pij", w, tensors[fsel[f]]))
            k = int(np.argmax(vals))
            if vals[k] > best[0]:
                best = (float(vals[k]), t, side, float(z[k]), float(dist.max()))
        v, t, side, zk, dmax = best
        rec.update(
            tangent=v if t is not None else None,
            tangent_tooth=t,
            tangent_side=side,
            tangent_z_mm=zk,
            tangent_surface_offset_mm=dmax,
        )
        cells_v = [c[(t, s)] for c in cell_all for (t, s) in c if t in teeth]
        rec["cell_max"] = max(cells_v) if cells_v else None
        rec["recovered"] = recovered_maxima(
            gear, groups, gsel, nodes, tensors, facets, ~end & ~near, z
        )
        out[key] = rec
    return out


def recovered_maxima(gear, groups, gsel, nodes, tensors, facets, usable, z) -> dict:
    """The surface maximum and ISO line maximum of the moving least-squares recovery
    (:mod:`solvers.surface_recovery`) over the fillet groups ``gsel``, from their ``usable``
    nodes (interior, off the point forces' near field) and at the line's axial positions
    ``z``: values (MPa), tooth, side, z and radius as in :func:`body_root_stress`, and the
    strip spacings (h_s, h_z) of the group of the surface maximum. None where no strip
    gives a posed fit."""
    rec = dict(
        value=None,
        tooth=None,
        side=None,
        z_mm=None,
        radius_mm=None,
        tangent=None,
        tangent_tooth=None,
        tangent_side=None,
        tangent_z_mm=None,
        h_s_mm=None,
        h_z_mm=None,
    )
    if not gsel:
        return rec
    curve = fillet_curve(gear)
    p = np.asarray(fillet_tangent_point(gear)["point"], float)
    s_iso = float(fillet_coordinates(gear, 0, "pos", np.array([[p[0], p[1], 0.0]]), curve)[0, 0])
    gid = nodes[:, 0].astype(np.int64)
    best_s, best_t = -np.inf, -np.inf
    for g in gsel:
        t, side, _ = groups[g]
        idx = np.flatnonzero((gid == g) & usable)
        local = np.full(len(nodes), -1, np.int64)
        local[idx] = np.arange(len(idx))
        tri = local[facets[facets[:, 0] == g, 1:]]
        tri = tri[(tri >= 0).all(axis=1)]
        if not len(tri):
            continue
        sz = fillet_coordinates(gear, t, side, nodes[idx, 1:4], curve)
        h_s, h_z = strip_spacings(sz, tri)
        at_nodes = recover(sz, tensors[idx], sz, h_s, h_z)
        ok = np.flatnonzero(np.isfinite(at_nodes).all(axis=(1, 2)))
        s1 = max_principal(at_nodes[ok]) if ok.size else np.zeros(0)
        k = int(ok[np.argmax(s1)]) if ok.size else -1
        if ok.size and s1.max() > best_s:
            best_s = float(s1.max())
            x = nodes[idx[k], 1:4]
            rec.update(
                value=best_s,
                tooth=int(t),
                side=side,
                z_mm=float(x[2]),
                radius_mm=float(np.linalg.norm(x[:2])),
                h_s_mm=h_s,
                h_z_mm=h_z,
            )
        at = np.c_[np.full(len(z), s_iso), z]
        lt = recover(sz, tensors[idx], at, h_s, h_z)
        ok = np.isfinite(lt).all(axis=(1, 2))
        if ok.any():
            v = max_principal(lt[ok])
            j = int(np.argmax(v))
            if v[j] > best_t:
                best_t = float(v[j])
                rec.update(
                    tangent=best_t,
                    tangent_tooth=int(t),
                    tangent_side=side,
                    tangent_z_mm=float(at[ok][j, 1]),
                )
    return rec


def root_stress(model, result) -> dict:
    """Fillet stress of the loaded teeth of a solved gear train (collective; the same on
    every rank).

    Returns per output key of :func:`loaded_fillets` (case 1: ``sun``, ``pinion_sun_side``,
    ``pinion_ring_side``, ``ring``) the recovered surface maximum of the max principal
    stress (MPa, None without fillet); ``tangent``: per key the largest value along ISO's
    30 / 60 deg lines; ``cell_max``: per key the largest P1 cell (midpoint) value;
    ``face_end``: per key the largest surface value within the face-end band
    (:func:`face_end_band`, width ``face_end_band_mm``);
    ``locations``: per key the tooth, fillet side, z (mm), radius from the axis (mm) of the surface
    maximum, tooth / side / z of the tangent maximum and the largest distance of the
    line's points from the fillet facets under them (``tangent_surface_offset_mm``, a check
    that the line lies on the meshed fillet), the teeth searched, the longest fillet facet
    edge of the finest fillet searched (``fillet_h_mm``), the number of fillet vertices and
    the gear-set key
    (``set_key``, :func:`set_keys`);
    ``method``: the recovery in words.
    """
    p = model.problem
    teeth = loaded_teeth(model)
    per_body: dict[str, dict[str, list[int]]] = {}
    for key, name, _, _ in loaded_fillets(model.scene):
        per_body.setdefault(name, {})[key] = teeth[key]
    recs = {}
    for name, keyed in per_body.items():
        b = p.bodies[name]
        u = b.function(result.displacements[name], name="displacement")
        recs.update(body_root_stress(b, u, model.scene.gear(name).gear, keyed))
    degree = p.bodies[next(iter(per_body))].degree
    return collect(
        model.scene,
        recs,
        f"P{degree} cell stress at the fillet vertices, averaged over the surface cells",
    )


def collect(scene, recs: dict[str, dict], method: str) -> dict:
    """The records of :func:`body_root_stress` per output key, in the layout of
    :func:`root_stress` (values, ``tangent``, ``cell_max``, ``face_end``, ``locations``,
    ``method``)."""
    out: dict = {}
    locs = {}
    for key, _, _, _ in loaded_fillets(scene):
        rec = dict(recs[key])
        out[key] = rec.pop("value")
        locs[key] = rec
    for k, v in set_keys(scene).items():
        locs[k]["set_key"] = v
    out["tangent"] = {k: locs[k].pop("tangent") for k in locs}
    out["cell_max"] = {k: locs[k].pop("cell_max") for k in locs}
    out["face_end"] = {k: locs[k].pop("face_end") for k in locs}
    out["locations"] = locs
    out["method"] = method
    return out
