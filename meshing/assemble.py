"""Place body meshes (each meshed alone, in its own gear frame) into one scene mesh.

Each body is meshed on its own (cached per body), so bodies that touch along contact lines
never share or cross surface triangles; a scene mesh is the union of the body meshes, each
turned about its own axis and moved to its centre, with the names of its physical groups
kept. The bodies stay disjoint meshes in one file (one DOLFINx mesh, one volume tag per
body): the contact coupling between them is the solver's business.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshing import gmsh_util
from meshing.sizing import MeshingError


@dataclass(frozen=True)
class Placement:
    """Rigid placement of a body: turn by ``angle`` (rad) about its own z axis, then move
    its axis to ``centre`` = (x, y) (mm). z is kept: mid face width is z = 0 for all."""

    angle: float = 0.0
    centre: tuple[float, float] = (0.0, 0.0)

    def apply(self, xyz: np.ndarray) -> np.ndarray:
        """Body frame -> scene frame, for points (N, 3)."""
        xyz = np.asarray(xyz, float)
        c, s = math.cos(self.angle), math.sin(self.angle)
        out = np.empty_like(xyz)
        out[:, 0] = c * xyz[:, 0] - s * xyz[:, 1] + self.centre[0]
        out[:, 1] = s * xyz[:, 0] + c * xyz[:, 1] + self.centre[1]
        out[:, 2] = xyz[:, 2]
        return out

    def inverse(self, xyz: np.ndarray) -> np.ndarray:
        """Scene frame -> body frame, for points (N, 3)."""
        xyz = np.asarray(xyz, float)
        x = xyz[:, 0] - self.centre[0]
        y = xyz[:, 1] - self.centre[1]
        c, s = math.cos(self.angle), math.sin(self.angle)
        out = np.empty_like(xyz)
        out[:, 0] = c * x + s * y
        out[:, 1] = -s * x + c * y
        out[:, 2] = xyz[:, 2]
        return out


def _read_part(gm, path: Path):
    gm.model.add(f"part:{path.name}")
    gm.merge(str(path))
    node_tags, coords, _ = gm.model.mesh.getNodes()
    node_tags = np.asarray(node_tags, dtype=np.int64)
    coords = np.asarray(coords).reshape(-1, 3)
    groups = []
    for dim, ptag in gm.model.getPhysicalGroups():
        name = gm.model.getPhysicalName(dim, ptag)
        blocks = []
        for ent in gm.model.getEntitiesForPhysicalGroup(dim, ptag):
            types, _etags, enodes = gm.model.mesh.getElements(dim, ent)
            for t, n in zip(types, enodes, strict=True):
                blocks.append((int(t), np.asarray(n, dtype=np.int64)))
        groups.append((dim, name, blocks))
    gm.model.remove()
    return node_tags, coords, groups


def merge_meshes(parts: list[tuple[Path, Placement]], out_path: Path) -> dict:
    """Write the union of the placed body meshes ``parts`` to ``out_path`` (gmsh, rank 0).

    Returns counts per physical group. Names must not repeat across parts."""
    with gmsh_util.session("scene") as gm:
        seen: dict[str, str] = {}
        node_offset = 0
        elem_offset = 0
        counts: dict[str, int] = {}
        for path, placement in parts:
            node_tags, coords, groups = _read_part(gm, Path(path))
            gm.model.setCurrent("scene")
            # Renumber the part's nodes 1..n (DOLFINx wants contiguous node tags).
            order = np.argsort(node_tags)
            sorted_tags = node_tags[order]
            new_tags = np.arange(1, len(node_tags) + 1, dtype=np.int64) + node_offset
            vol = gm.model.addDiscreteEntity(3)
            gm.model.mesh.addNodes(3, vol, new_tags, placement.apply(coords[order]).ravel())
            phys: dict[int, list[tuple[int, str, list[int]]]] = {}
            for dim, name, blocks in groups:
                if name in seen:
                    raise MeshingError(f"physical group {name!r} is in {seen[name]} and {path}")
                seen[name] = str(path)
                ent = vol if dim == 3 else gm.model.addDiscreteEntity(dim)
                n_el = 0
                for etype, enodes in blocks:
                    mapped = new_tags[np.searchsorted(sorted_tags, enodes)]
                    _, _, _, nn, _, _ = gm.model.mesh.getElementProperties(etype)
                    ne = len(enodes) // nn
                    etags = np.arange(1, ne + 1, dtype=np.int64) + elem_offset
                    elem_offset += ne
                    n_el += ne
                    gm.model.mesh.addElementsByType(ent, etype, etags, mapped)
                counts[name] = n_el
                phys.setdefault(dim, []).append((ent, name, []))
            for dim, items in phys.items():
                for ent, name, _ in items:
                    gm.model.addPhysicalGroup(dim, [ent], name=name)
            node_offset += len(node_tags)
        gmsh_util.write_msh(out_path)
    return {"group_elements": counts, "nodes": node_offset}
