"""Build (or fetch from the cache) the mesh of a scene and load it into DOLFINx.

Every body is meshed alone in its gear frame and cached by its parameters (gear data,
sector, bore, refined teeth, level); the scene mesh is the union of the placed body meshes,
cached by the scene's parameters. All input is validated on every rank before gmsh runs.
"""

from __future__ import annotations

import time
from pathlib import Path

from meshing import cache, sizing
from meshing.assemble import Placement, merge_meshes
from meshing.body_cache import body_mesh_file
from meshing.carrier import carrier_mesh_file
from meshing.scenes import Scene
from meshing.to_dolfinx import load_msh


def scene_mesh_file(scene: Scene, level: int, comm=None, rebuild: bool = False):
    """``(msh_path, meta)`` of the scene mesh at ``level`` (collective if ``comm``)."""
    sizing.check_level(level)
    for g in scene.gears:
        g.body.validate()
    t0 = time.perf_counter()
    parts: list[tuple[Path, Placement]] = []
    body_meta = {}
    for g in scene.gears:
        path, meta = body_mesh_file(g.body, level, g.active_teeth, comm=comm, rebuild=rebuild)
        parts.append((path, g.placement))
        body_meta[g.name] = meta
    if scene.carrier is not None:
        path, meta = carrier_mesh_file(scene.carrier, level, comm=comm, rebuild=rebuild)
        parts.append((path, Placement()))
        body_meta["carrier"] = meta
    params = {"scene": scene.params(), "level": level, "parts": [str(p.name) for p, _ in parts]}

    def builder(out: Path) -> dict:
        stats = merge_meshes(parts, out)
        return {
            "bodies": {
                name: {
                    k: m.get(k)
                    for k in (
                        "elements",
                        "nodes",
                        "min_sicn",
                        "p01_sicn",
                        "volume",
                        "geometry_seconds",
                        "mesh_seconds",
                        "cached",
                    )
                }
                for name, m in body_meta.items()
            },
            "elements": sum(m["elements"] for m in body_meta.values()),
            "nodes": stats["nodes"],
            "min_sicn": min(m["min_sicn"] for m in body_meta.values()),
            "volume": sum(m["volume"] for m in body_meta.values()),
            "group_elements": stats["group_elements"],
            "report": scene.report(),
            "level": sizing.level_record(level),
        }

    path, meta = cache.get_or_build("scene", params, builder, comm=comm, rebuild=rebuild)
    meta["wall_seconds"] = time.perf_counter() - t0
    return path, meta


def load_scene(scene: Scene, level: int, comm, rebuild: bool = False):
    """The scene as one :class:`meshing.to_dolfinx.MeshBundle` (collective); ``meta`` holds
    the scene report (bodies, placements, zones, drive/coast flanks, what was left out)."""
    path, meta = scene_mesh_file(scene, level, comm=comm, rebuild=rebuild)
    return load_msh(path, comm, meta=meta)
