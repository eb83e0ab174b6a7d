"""The body meshes of a scene in DOLFINx, each in its own gear frame.

Each gear body is meshed alone in its gear frame and cached (:mod:`meshing.body_cache`).
Here it is loaded collectively and left in that frame: a mesh position turns a gear rigidly
about its own axis, so the solver places the body in the scene by a rigid map
(``PlacedGear.placement``) and one stiffness and factorization of the body serve every
position. ``memo`` (a dict owned by the caller) keeps loaded meshes across positions.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from meshing import tags as T
from meshing.body_cache import body_mesh_file
from meshing.carrier import carrier_mesh_file
from meshing.to_dolfinx import MeshBundle, load_msh


@dataclass(frozen=True)
class BodyMesh:
    """A loaded gear body mesh (body frame) and its facet tag names."""

    name: str
    bundle: MeshBundle
    tags: dict[str, int]  # facet tag name -> integer tag
    key: str  # mesh cache entry (file name): the identity of this mesh


def _load(name: str, path, meta, comm, memo: dict | None) -> BodyMesh:
    key = Path(path).name
    if memo is not None and key in memo:
        return memo[key]
    bundle = load_msh(path, comm, meta=meta)
    tags = {nm: tag for nm, (dim, tag) in bundle.names.items() if dim == 2}
    out = BodyMesh(name, bundle, tags, key)
    if memo is not None:
        memo[key] = out
    return out


def load_body_mesh(placed_gear, level: int, comm, memo: dict | None = None) -> BodyMesh:
    """The mesh of one placed gear's body (collective), from ``memo`` if already loaded."""
    pg = placed_gear
    path, meta = body_mesh_file(pg.body, level, pg.active_teeth, comm=comm)
    return _load(pg.name, path, meta, comm, memo)


def load_body_meshes(scene, level: int, comm, memo: dict | None = None) -> dict[str, BodyMesh]:
    """Body name -> :class:`BodyMesh` of every gear of the scene, and of the carrier under
    ``"carrier"`` if the scene has one (collective; the carrier is in the scene frame)."""
    out = {g.name: load_body_mesh(g, level, comm, memo) for g in scene.gears}
    if scene.carrier is not None:
        path, meta = carrier_mesh_file(scene.carrier, level, comm=comm)
        out[T.CARRIER] = _load(T.CARRIER, path, meta, comm, memo)
    return out
