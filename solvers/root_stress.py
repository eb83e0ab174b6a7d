"""Tooth root (bending) stress from the FE displacement at the fillets of the loaded teeth.

For a solved gear train (:func:`solvers.gear_train.build_gear_train` + ``problem.solve()``)
and each gear body, the stress of the FE field

    sigma = lambda tr(eps) I + 2 mu eps,   eps = (grad u + grad u^T) / 2      (MPa, mm)

is evaluated at the midpoint of every cell that has a facet on a root fillet
(``<body>/toothNN/fillet_pos`` and ``fillet_neg``, :mod:`meshing.tags`) of a tooth that
carries load, i.e. a tooth named in the contact-grid lines of the model (driver and driven
tooth of every line of :class:`solvers.flank_grid.FlankGridInfo`). For P1 the stress is
constant per cell, so the midpoint value is the cell value; for P2 it is the midpoint value.
The reported number is the largest maximum principal stress over those cells (tension
positive), with where it sits: tooth, fillet side (``pos``/``neg``, geometric side of the
body frame), z of the cell midpoint (scene frame, mm from mid face width) and its radius from
the body centre.

Both fillets of a loaded tooth are searched: the one under the loaded flank is in tension
(the tooth bends away from the load), the other in compression, so the maximum tensile
principal stress picks the tension fillet without the side being fixed here; the side found
is reported and can be checked against the scene's drive flanks.

A gear in one mesh is reported under its own name (``sun``, ``ring``); a pinion carries load
at two meshes, on different teeth, and is reported per mate: ``<pinion>_<mate>_side`` (case
1: ``pinion_sun_side`` and ``pinion_ring_side``; case 2: ``SP_sun_side``, ``SP_RP_side``,
``RP_SP_side``, ``RP_ring_side``), see :func:`loaded_teeth`.

Accuracy: cell stresses of linear tetrahedra at a coarse fillet (a few elements across the
fillet radius) underestimate the peak surface stress (the cell value is a volume average of a
steep gradient, taken at the cell midpoint, not the surface). Treat the values as a mesh
dependent lower estimate; refine (level, degree) to converge.

Collective over the mesh communicator: every rank evaluates its owned cells (possibly none)
and the maximum with its location is reduced across ranks (allgather of one record per rank).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import dolfinx
import dolfinx.fem
import numpy as np
import ufl

from gears.train import mesh_side_keys
from meshing import tags as tagnames


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


def loaded_teeth(model) -> dict[str, list[int]]:
    """Teeth named in the contact-grid lines, per output key (see :func:`loaded_fillets`)."""
    out = {}
    for key, _, grid, which in loaded_fillets(model.scene):
        lines = model.grids[grid][1].lines
        out[key] = sorted({int(ln[which]) for ln in lines})
    return out


def _stress_expression(body, u: dolfinx.fem.Function) -> dolfinx.fem.Expression:
    mat = body.material
    eps = ufl.sym(ufl.grad(u))
    sig = mat.lam * ufl.tr(eps) * ufl.Identity(body.gdim) + 2.0 * mat.mu * eps
    tdim = body.mesh.topology.dim
    mid = np.full((1, tdim), 1.0 / (tdim + 1))  # midpoint of the reference simplex
    return dolfinx.fem.Expression(sig, mid)


def _fillet_cells(body, facet_tag: int) -> np.ndarray:
    """Owned cells with a facet of tag ``facet_tag`` (may be empty on a rank)."""
    mesh = body.mesh
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    facets = body.facet_tags.find(facet_tag)
    if facets.size == 0:
        return np.zeros(0, dtype=np.int32)
    cells = dolfinx.mesh.compute_incident_entities(mesh.topology, facets, tdim - 1, tdim)
    n_own = mesh.topology.index_map(tdim).size_local
    return np.unique(cells[cells < n_own]).astype(np.int32)


def _body_max(body, u, teeth, centre) -> dict:
    """Largest max principal stress over the fillet cells of ``teeth`` (collective)."""
    expr = _stress_expression(body, u)
    tdim = body.mesh.topology.dim
    best = (-np.inf, -1, "", np.nan, np.nan)  # value, tooth, side, z, radius
    n_cells = 0
    for t in teeth:
        for side in ("pos", "neg"):
            name = tagnames.fillet(body.name, t, side)
            tag = body.tags.get(name)
            cells = np.zeros(0, np.int32) if tag is None else _fillet_cells(body, tag)
            n_cells += cells.size
            if cells.size == 0:
                continue
            vals = expr.eval(body.mesh, cells).reshape(cells.size, body.gdim, body.gdim)
            s1 = np.linalg.eigvalsh(vals)[:, -1]
            k = int(np.argmax(s1))
            if s1[k] > best[0]:
                x = dolfinx.mesh.compute_midpoints(body.mesh, tdim, cells[k : k + 1])[0]
                r = float(np.linalg.norm(x[:2] - np.asarray(centre, float)[:2]))
                z = float(x[2]) if body.gdim == 3 else 0.0
                best = (float(s1[k]), int(t), side, z, r)
    allbest = body.comm.allgather(best)
    n_all = body.comm.allreduce(n_cells)
    v, t, side, z, r = max(allbest, key=lambda b: b[0])
    if not np.isfinite(v):
        return {"max_principal_MPa": None, "tooth": None, "side": None, "z_mm": None,
                "radius_mm": None, "teeth": list(teeth), "cells": int(n_all)}  # fmt: skip
    return {"max_principal_MPa": v, "tooth": t, "side": side, "z_mm": z, "radius_mm": r,
            "teeth": list(teeth), "cells": int(n_all)}  # fmt: skip


def root_stress(model, result) -> dict:
    """Fillet stress of the loaded teeth of a solved gear train (collective; same on every
    rank).

    Returns per output key of :func:`loaded_fillets` (case 1: ``sun``, ``pinion_sun_side``,
    ``pinion_ring_side``, ``ring``) the max tensile principal stress (MPa, None if no fillet
    cell anywhere) and ``locations`` -> per key the tooth,
    fillet side, z (mm), radius from the body centre (mm), the teeth searched and the number
    of cells.
    """
    p = model.problem
    teeth = loaded_teeth(model)
    fields = {}
    out: dict = {}
    locs = {}
    for key, name, _, _ in loaded_fillets(model.scene):
        b = p.bodies[name]
        if name not in fields:
            fields[name] = b.function(result.displacements[name], name="displacement")
        rec = _body_max(b, fields[name], teeth[key], b.centre)
        out[key] = rec.pop("max_principal_MPa")
        locs[key] = rec
    out["locations"] = locs
    return out
