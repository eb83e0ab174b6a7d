"""Small helpers around the gmsh session (one process-wide gmsh state)."""

from __future__ import annotations

import contextlib

import gmsh


@contextlib.contextmanager
def session(model_name: str, verbose: bool = False):
    """A fresh gmsh model named ``model_name``; gmsh is initialized if needed and finalized
    again only if this call initialized it. Yields the ``gmsh`` module."""
    owner = not gmsh.isInitialized()
    if owner:
        gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
    gmsh.model.add(model_name)
    try:
        yield gmsh
    finally:
        gmsh.model.remove()
        if owner:
            gmsh.finalize()


def write_msh(path) -> None:
    """Write the current model's mesh (physical groups only) as MSH 4.1."""
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(str(path))


def group_nodes(path) -> dict:
    """Node coordinates (N, 3) of every named physical group of the mesh file ``path``."""
    import numpy as np

    out = {}
    with session("inspect") as gm:
        gm.merge(str(path))
        for dim, tag in gm.model.getPhysicalGroups():
            name = gm.model.getPhysicalName(dim, tag)
            _, xyz = gm.model.mesh.getNodesForPhysicalGroup(dim, tag)
            out[name] = np.asarray(xyz).reshape(-1, 3)
    return out
