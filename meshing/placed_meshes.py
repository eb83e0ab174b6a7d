"""The body meshes of a scene in DOLFINx, each moved to its placement in the scene frame.

Each gear body is meshed alone in its gear frame and cached (:mod:`meshing.body_cache`);
here it is loaded collectively and its node coordinates are turned and moved by the gear's
placement, so the solver receives bodies in the scene frame and never builds meshes."""

from __future__ import annotations

from meshing.body_cache import load_body


def load_placed_body(placed_gear, level: int, comm):
    """``(bundle, facet tag names)`` of one placed gear (collective)."""
    bundle = load_body(placed_gear.body, level, comm, active_teeth=placed_gear.active_teeth)
    x = bundle.mesh.geometry.x
    x[:] = placed_gear.placement.apply(x)
    tags = {nm: tag for nm, (dim, tag) in bundle.names.items() if dim == 2}
    return bundle, tags


def load_scene_bodies(scene, level: int, comm) -> dict:
    """Body name -> ``(bundle, facet tag names)`` of every gear of the scene (collective)."""
    return {g.name: load_placed_body(g, level, comm) for g in scene.gears}
