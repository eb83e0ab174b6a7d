"""Results of a contact solve: grid forces, line loads, resultants, displacement fields.

Resultants on body b about its centre c, two ways that must agree:

* from the contact forces: f_k = sigma_k F_k n_k (sigma = +1 on side B, -1 on side A),
  R = sum_k f_k, M = sum_k (x_k - c) x f_k;
* from the assembled residual r = K u - f of the body (full system, no constraints, u with
  the superposed rigid motion; K psi = 0 for a rigid field psi), summed over the DOFs that
  no support holds: R = sum_i r_i, M = sum_i (x_i - c) x r_i. On those DOFs r = G^T F,
  the consistent nodal forces of the contact, and Lagrange bases reproduce constants and
  linear fields, so both sums equal the contact ones up to the solver's round-off. The
  same sums over the support DOFs give the support reaction (bearing, clamp).

Everything is reported in the scene frame: a body assembled in its own frame and placed by
a rigid map (:meth:`solvers.elastic_body.ElasticBody.place`) has its residual forces, DOF
positions and centre mapped to the scene before they are summed.

Moments are N mm here (report N m by dividing by 1000); in 2D the moment is the scalar M_z
and forces are per unit thickness. Every sum over FE DOFs goes through
:func:`solvers.elastic_body.mpi_sum`, the one helper that reduces across ranks.
"""

from __future__ import annotations

import errno
import shutil
from pathlib import Path

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import dolfinx.io
import numpy as np

from solvers.contact import ContactProblem, ContactResult
from solvers.elastic_body import ElasticBody, mpi_sum


def _moment(d: np.ndarray, f: np.ndarray) -> np.ndarray:
    """sum_i d_i x f_i (3-vector in 3D, scalar M_z in 2D)."""
    if d.shape[1] == 2:
        return np.asarray(np.sum(d[:, 0] * f[:, 1] - d[:, 1] * f[:, 0]))
    return np.cross(d, f).sum(axis=0)


def contact_resultant(
    problem: ContactProblem, result: ContactResult, body: str, centre=None
) -> tuple[np.ndarray, np.ndarray]:
    """(force, moment about centre) of the contact forces acting on ``body``."""
    c = _centre(problem, body, centre)
    force = np.zeros(problem.gdim)
    moment = np.zeros(3) if problem.gdim == 3 else np.zeros(())
    for i, p in enumerate(problem.pairs):
        sl = slice(problem.offsets[i], problem.offsets[i + 1])
        for side, name, x in (("a", p.body_a, p.grid.x_a), ("b", p.body_b, p.grid.x_b)):
            if name != body:
                continue
            sign = 1.0 if side == "b" else -1.0
            f = sign * result.forces[sl, None] * np.asarray(p.grid.normals, float)
            force += f.sum(axis=0)
            moment = moment + _moment(np.asarray(x, float) - c, f)
    return force, moment


def residual_resultant(
    problem: ContactProblem, result: ContactResult, body: str, centre=None
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Resultants from r = K u - f: {"contact": (R, M) on free DOFs, "support": (R, M)}."""
    b: ElasticBody = problem.bodies[body]
    c = _centre(problem, body, centre)
    u = result.displacements[body]
    r = b.K.createVecLeft()
    b.K.mult(u, r)
    r.axpy(-1.0, b.f)
    n = b.n_own
    gd = b.gdim
    rv = r.getArray(readonly=True)[:n]
    x = b.dof_x[:n]
    comp = b.dof_comp[:n]
    x = b.to_scene(x)
    out = {}
    for key, mask in (("contact", ~b.support_mask), ("support", b.support_mask)):
        f = np.zeros((n, gd))
        f[np.arange(n)[mask], comp[mask]] = rv[mask]
        f = f @ b.rotation.T  # body-frame nodal forces in the scene frame
        force = mpi_sum(b.comm, f.sum(axis=0))
        moment = mpi_sum(b.comm, _moment(x - c, f))
        out[key] = (force, moment)
    return out


def _centre(problem: ContactProblem, body: str, centre) -> np.ndarray:
    if centre is not None:
        return np.asarray(centre, float)[: problem.gdim]
    if body in problem.bodies:
        return problem.bodies[body].scene_centre
    return np.zeros(problem.gdim)


def resultants(problem: ContactProblem, result: ContactResult) -> dict[str, dict]:
    """For every FE body: contact and residual resultants about its own centre."""
    out = {}
    for name in problem.bodies:
        fc, mc = contact_resultant(problem, result, name)
        res = residual_resultant(problem, result, name)
        out[name] = {
            "centre": problem.bodies[name].centre.tolist(),
            "contact_force": fc,
            "contact_moment": mc,
            "residual_force": res["contact"][0],
            "residual_moment": res["contact"][1],
            "support_force": res["support"][0],
            "support_moment": res["support"][1],
        }
    return out


def line_load(problem: ContactProblem, result: ContactResult, pair: int = 0) -> np.ndarray:
    """Load per unit length along a contact line: q_s = sum_{k in station s} F_k / L_s (N/mm).

    Without stations (a 2D grid, per unit thickness) the whole grid is one station.
    """
    p = problem.pairs[pair]
    F = result.forces[problem.offsets[pair] : problem.offsets[pair + 1]]
    if p.grid.stations is None:
        return np.array([F.sum()])
    st = np.asarray(p.grid.stations)
    q = np.zeros(len(p.grid.station_length))
    np.add.at(q, st, F)
    return q / np.asarray(p.grid.station_length, float)


#: room for BP4's metadata and index beside the arrays :func:`vtx_bytes` counts (a test holds
#: the estimate above what is written)
VTX_SIZE_MARGIN = 1.5


def vtx_bytes(problem: ContactProblem) -> int:
    """An upper estimate of the bytes :func:`write_vtx` writes, every rank's part summed: VTX
    writes each field on its own space's nodes (P2: the edge midpoints too), as 3D
    coordinates and a 3-component value per node, and the cells over those nodes, 8 bytes a
    number."""
    local = 0
    for b in problem.bodies.values():
        topo = b.mesh.topology
        cells = topo.index_map(topo.dim).size_local
        nodes = b.V.dofmap.index_map.size_local + b.V.dofmap.index_map.num_ghosts
        per_cell = b.V.dofmap.dof_layout.num_dofs
        local += 8 * (6 * nodes + cells * (per_cell + 2))
    comm = next(iter(problem.bodies.values())).comm
    return int(VTX_SIZE_MARGIN * comm.allreduce(local))


def check_room(folder: Path, problem: ContactProblem) -> None:
    """OSError (ENOSPC) on every rank when the file system of ``folder`` has less room than
    :func:`vtx_bytes`: ADIOS2 aborts the process on a full disk (a C++ abort, no Python
    error), so the write is not started. Decided on rank 0 and shared, so every rank agrees
    before the collective writer is opened."""
    comm = next(iter(problem.bodies.values())).comm
    need = vtx_bytes(problem)
    free = None
    if comm.rank == 0:
        where = Path(folder)
        while not where.exists() and where != where.parent:
            where = where.parent
        free = shutil.disk_usage(where).free
    free = comm.bcast(free, root=0)
    if free < need:
        raise OSError(
            errno.ENOSPC,
            f"{need / 1e6:.0f} MB needed for the fields, {free / 1e6:.0f} MB free on its file "
            "system",
            str(folder),
        )


def write_vtx(folder: str | Path, problem: ContactProblem, result: ContactResult) -> list[Path]:
    """Displacement of every body (rigid part included) as VTX, ``folder/<body>.bp``, in the
    scene frame: each body's mesh and field are placed for the write and put back after.
    Refused up front where the file system has not the room (:func:`check_room`)."""
    folder = Path(folder)
    check_room(folder, problem)
    paths = []
    for name, b in problem.bodies.items():
        fn = b.function(result.displacements[name], name="displacement")
        gd = b.gdim
        vals = fn.x.array.reshape(-1, gd)
        vals[:] = vals @ b.rotation.T
        x = b.mesh.geometry.x
        x_body = x.copy()
        x[:, :gd] = b.to_scene(x_body[:, :gd])
        path = folder / f"{name}.bp"
        try:
            with dolfinx.io.VTXWriter(b.comm, str(path), [fn], engine="BP4") as w:
                w.write(0.0)
        finally:
            x[:] = x_body
        paths.append(path)
    return paths
