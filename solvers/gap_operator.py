"""Gap operator: the sparse map from a body's reduced DOFs to normal displacements at grid points.

For body b on side s (sign sigma = +1 on side B, -1 on side A) and grid row k,

    (G_b u_red)_k = sigma_k sum_q w_kq n_k . u_b(x_kq),   u_b = P_b u_red             (1)

where x_kq are the spreading points of grid cell k (:mod:`solvers.contact_grid`) with weights
w_kq (sum 1). u_b(x) = sum_i phi_i(X(x)) u_i is evaluated by point location: a bounding-box
tree over the rank's owned cells, the colliding candidates, the affine pull-back
X = J^{-1}(x - x_0) and the basis tabulated at X (Basix). A point on the exact (curved)
surface may lie just outside the faceted mesh (by ~h^2 / 8R); the candidate cell with the
smallest excursion outside the reference simplex is used (the affine field is extrapolated).
Each point is owned by exactly one rank (smallest excursion, then lowest rank), decided by two
Allreduce calls that every rank joins, also a rank that owns no point.

Grid points and normals come in the scene frame and are mapped into the body frame by the
body's placement (x_b = Q^T (x - t), n_b = Q^T n; :meth:`solvers.elastic_body.ElasticBody.
place`), so a body factorized once serves every mesh position.

G is a PETSc AIJ matrix (rows: all grid points of the problem, columns: the body's reduced
layout), formed as G_full P_b so that points on coupled surfaces are handled too.
"""

from __future__ import annotations

import weakref

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import dolfinx
import dolfinx.geometry
import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from solvers.errors import GapOperatorError

#: each mesh's bounding-box tree of its owned cells, by padding: built once per mesh and kept
#: while the mesh lives. A body keeps its mesh at every mesh position (the points are turned
#: into the body's frame, not the mesh), so a tree per call was rebuilding the same tree,
#: about a tenth of a reused level-1 position (measured: docs/performance.md)
_TREES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def cell_tree(mesh, tdim: int, n_cells: int, padding: float) -> dolfinx.geometry.BoundingBoxTree:
    """The bounding-box tree of ``mesh``'s first ``n_cells`` cells (the owned ones) with
    ``padding`` on this rank: built on the first call, then the same tree (the same
    collisions, so the same gap operator to the bit)."""
    trees = _TREES.setdefault(mesh, {})
    key = (tdim, n_cells, float(padding))
    if key not in trees:
        cells = np.arange(n_cells, dtype=np.int32)
        trees[key] = dolfinx.geometry.bb_tree(mesh, tdim, padding=padding, entities=cells)
    return trees[key]


#: largest accepted excursion outside the reference simplex of the chosen cell (barycentric)
MAX_EXCURSION = 0.5


def locate(body, points: np.ndarray, padding: float | None = None, curved: bool = False):
    """Locate points in a body's mesh; collective. ``curved``: also a mesh of curved
    (second-order) simplices, located by the straight simplex through each cell's vertices:
    the reference coordinates are then those of the straight cell, off by the cell's sag (a
    few um on a root-stress sector's flanks), which is all a point force's consistent nodal
    loads need (:mod:`solvers.root_submodel`); the gap operator takes affine cells only.

    Returns:
        (owned mask (m,), cell (m,) local index or -1, reference coords (m, tdim),
        cell size h (m,) replicated on all ranks).
    """
    mesh, comm = body.mesh, body.comm
    tdim = mesh.topology.dim
    gdim = body.gdim
    m = len(points)
    if (mesh.geometry.cmaps[0].degree != 1 and not curved) or mesh.topology.cell_type.name not in (
        "triangle",
        "tetrahedron",
    ):
        raise GapOperatorError(f"body '{body.name}': the gap operator needs affine simplices")
    n_cells = mesh.topology.index_map(tdim).size_local
    if padding is None:
        x = mesh.geometry.x
        lo_l = x.min(axis=0) if len(x) else np.full(3, np.inf)
        hi_l = x.max(axis=0) if len(x) else np.full(3, -np.inf)
        lo, hi = np.empty(3), np.empty(3)
        comm.Allreduce(np.ascontiguousarray(lo_l, dtype=float), lo, op=MPI.MIN)
        comm.Allreduce(np.ascontiguousarray(hi_l, dtype=float), hi, op=MPI.MAX)
        padding = 1e-3 * float(np.linalg.norm(hi - lo))
    pts3 = np.zeros((m, 3))
    pts3[:, :gdim] = points
    best_d = np.full(m, np.inf)
    best_c = np.full(m, -1, dtype=np.int32)
    best_X = np.zeros((m, tdim))
    if n_cells > 0 and m > 0:
        tree = cell_tree(mesh, tdim, n_cells, padding)
        coll = dolfinx.geometry.compute_collisions_points(tree, pts3)
        offs = coll.offsets
        cells = coll.array
        pid = np.repeat(np.arange(m), np.diff(offs))
        if len(cells):
            nodes = mesh.geometry.dofmaps[0][cells][:, : tdim + 1]
            xv = mesh.geometry.x[nodes][:, :, :gdim]  # (p, tdim+1, gdim)
            J = np.transpose(xv[:, 1:, :] - xv[:, :1, :], (0, 2, 1))  # (p, gdim, tdim)
            rhs = points[pid] - xv[:, 0, :]
            X = np.linalg.solve(J, rhs[:, :, None])[:, :, 0]
            bary = np.column_stack([1.0 - X.sum(axis=1), X])
            d = np.maximum(0.0, -bary.min(axis=1))
            order = np.lexsort((d, pid))
            first = np.ones(len(order), dtype=bool)
            first[1:] = pid[order][1:] != pid[order][:-1]
            sel = order[first]
            best_d[pid[sel]] = d[sel]
            best_c[pid[sel]] = cells[sel]
            best_X[pid[sel]] = X[sel]
    d_min = np.empty(m)
    comm.Allreduce(best_d, d_min, op=MPI.MIN)
    cand = np.where((best_d == d_min) & np.isfinite(best_d), comm.rank, comm.size).astype(np.int32)
    owner = np.empty(m, dtype=np.int32)
    comm.Allreduce(cand, owner, op=MPI.MIN)
    bad = ~np.isfinite(d_min) | (d_min > MAX_EXCURSION)
    if np.any(bad):
        k = np.flatnonzero(bad)
        raise GapOperatorError(
            f"body '{body.name}': {len(k)} of {m} contact points are not inside the mesh "
            f"(first at {points[k[0]]}, excursion {d_min[k[0]]:.3g} in reference "
            f"coordinates); the grid must lie on this body's surface"
        )
    mine = owner == comm.rank
    h = np.zeros(m)
    if np.any(mine):
        h[mine] = mesh.h(tdim, best_c[mine])
    hh = np.empty(m)
    comm.Allreduce(h, hh, op=MPI.SUM)
    return mine, np.where(mine, best_c, -1), best_X, hh


def gap_matrix(body, blocks, n_rows: int) -> tuple[PETSc.Mat, np.ndarray]:
    """Assemble G_b (n_rows x reduced DOFs of the body), eq. (1).

    Args:
        body: a set-up :class:`solvers.elastic_body.ElasticBody`.
        blocks: list of (row offset, grid, side "a"/"b") entries for this body.
        n_rows: total number of grid points in the problem.

    Returns:
        (G_b, h) with h the size of the cell holding each grid point (0 on other rows).
    """
    comm, gdim = body.comm, body.gdim
    V = body.V
    bs = V.dofmap.index_map_bs
    elem = V.element.basix_element
    dofs_cell = V.dofmap.list
    rows, cols, vals = [], [], []
    h_rows = np.zeros(n_rows)
    for offset, grid, side in blocks:
        sign = 1.0 if side == "b" else -1.0
        pts, parent, wq = grid.spread_points(side)
        pts = body.to_body(pts)  # the grid is in the scene frame, the body in its own
        mine, cells, X, h = locate(body, pts, None)
        np.maximum.at(h_rows, offset + parent, h)
        if not np.any(mine):
            continue
        phi = elem.tabulate(0, X[mine])[0, :, :, 0]  # (p, ndofs)
        c = cells[mine]
        blk = dofs_cell[c]  # (p, ndofs) local block indices
        nrm = np.asarray(grid.normals, dtype=float)[parent[mine]] @ body.rotation  # body frame
        w = sign * wq[mine]
        r = offset + parent[mine]
        for comp in range(gdim):
            loc = blk * bs + comp
            rows.append(np.repeat(r, blk.shape[1]))
            cols.append(body.full_global[loc].ravel())
            vals.append((w[:, None] * nrm[:, comp, None] * phi).ravel())
    ri = np.concatenate(rows) if rows else np.zeros(0)
    ci = np.concatenate(cols) if cols else np.zeros(0)
    vi = np.concatenate(vals) if vals else np.zeros(0)
    G = PETSc.Mat().create(comm=comm)
    N_full = body.K.getSize()[0]
    G.setSizes(((PETSc.DECIDE, n_rows), (body.n_own, N_full)))
    G.setType(PETSc.Mat.Type.AIJ)
    G.setPreallocationCOO(ri.astype(PETSc.IntType), ci.astype(PETSc.IntType))
    G.setValuesCOO(vi, addv=PETSc.InsertMode.ADD_VALUES)
    G.assemble()
    G_red = G.matMult(body.P)
    return G_red, h_rows
