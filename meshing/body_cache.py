"""The cached mesh file of a gear body, and the body loaded into DOLFINx.

The cache key is built from :meth:`meshing.gear_body.GearBody.params`, the level and the
active teeth; the mesh is built on rank 0 (:func:`meshing.body_mesh.build_body_mesh`).
"""

from __future__ import annotations

from meshing import cache, gmsh_util, sizing
from meshing.body_mesh import build_body_mesh, check_active
from meshing.gear_body import GearBody
from meshing.to_dolfinx import load_msh


def body_params(gb: GearBody, level, active_teeth=None) -> dict:
    """The cache-key parameters of the body mesh (``cache.key("body", ...)``): the body,
    the level and the active teeth; two placed gears with equal parameters share one mesh
    (and, in :class:`solvers.body_store.BodyStore`, one factorization)."""
    return {"body": gb.params(), "level": level, "active_teeth": check_active(gb, active_teeth)}


def body_mesh_file(gb: GearBody, level: int, active_teeth=None, comm=None, rebuild=False):
    """``(msh_path, meta)`` of the body mesh, from the cache or built on rank 0.

    Input is validated on every rank before gmsh runs (:class:`MeshingError`)."""
    gb.validate()
    sizing.check_level(level)
    act = check_active(gb, active_teeth)
    params = body_params(gb, level, act)

    def builder(path):
        with gmsh_util.session(gb.body) as gm:
            stats = build_body_mesh(gm, gb, level, act)
            gmsh_util.write_msh(path)
        return stats

    return cache.get_or_build("body", params, builder, comm=comm, rebuild=rebuild)


def load_body(gb: GearBody, level: int, comm, active_teeth=None, rebuild=False):
    """The body as a :class:`meshing.to_dolfinx.MeshBundle` (collective)."""
    path, meta = body_mesh_file(gb, level, active_teeth, comm=comm, rebuild=rebuild)
    return load_msh(path, comm, meta=meta)
