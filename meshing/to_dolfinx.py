"""Collective conversion of a tagged gmsh mesh (.msh) to DOLFINx, with tag names.

The file is read on one rank of the communicator and the mesh distributed (dolfinx.io.gmsh);
every rank gets the same ``names`` dict (tag name -> (dim, integer tag)). Look regions up
by name, never by integer: ``bundle.facets("pinion/bore")``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from meshing import gmsh_util

# dolfinx and mpi4py are heavy: they are imported lazily, inside the functions that use them.


@dataclass
class MeshBundle:
    mesh: object  # dolfinx.mesh.Mesh
    cell_tags: object  # dolfinx.mesh.MeshTags (cells; one tag per body volume)
    facet_tags: object  # dolfinx.mesh.MeshTags (facets; one tag per named surface)
    names: dict[str, tuple[int, int]]  # name -> (dim, tag)
    meta: dict = field(default_factory=dict)  # parameters, statistics, scene report

    def tag(self, name: str) -> int:
        try:
            return self.names[name][1]
        except KeyError:
            raise KeyError(f"no physical group named {name!r}") from None

    def facets(self, name: str) -> np.ndarray:
        """Local indices of the facets of surface group ``name``."""
        dim, tag = self.names[name]
        if dim != self.mesh.topology.dim - 1:
            raise KeyError(f"{name!r} is not a surface group")
        return self.facet_tags.find(tag)

    def cells(self, name: str) -> np.ndarray:
        """Local indices of the cells of volume group ``name``."""
        dim, tag = self.names[name]
        if dim != self.mesh.topology.dim:
            raise KeyError(f"{name!r} is not a volume group")
        return self.cell_tags.find(tag)

    def surface_names(self) -> list[str]:
        return sorted(n for n, (d, _) in self.names.items() if d == 2)

    def volume_names(self) -> list[str]:
        return sorted(n for n, (d, _) in self.names.items() if d == 3)


def load_msh(path: str | Path, comm, rank: int = 0, meta: dict | None = None) -> MeshBundle:
    """Read ``path`` on ``rank`` and distribute it over ``comm`` (collective)."""
    import dolfinx_solver  # noqa: F401  (must precede dolfinx)
    from dolfinx.io import gmsh as dgmsh

    if comm.rank == rank:
        with gmsh_util.session("load") as gm:
            gm.merge(str(path))
            data = dgmsh.model_to_mesh(gm.model, comm, rank, gdim=3)
    else:
        data = dgmsh.model_to_mesh(None, comm, rank, gdim=3)
    names = {str(n): (int(g.dim), int(g.tag)) for n, g in data.physical_groups.items()}
    names = comm.bcast(names if comm.rank == rank else None, root=rank)
    return MeshBundle(data.mesh, data.cell_tags, data.facet_tags, names, dict(meta or {}))


def global_volume(bundle: MeshBundle, name: str | None = None) -> float:
    """Volume of the whole mesh or of volume group ``name`` (collective)."""
    import dolfinx_solver  # noqa: F401
    import ufl
    from dolfinx import fem
    from mpi4py import MPI

    mesh = bundle.mesh
    if name is None:
        form = fem.form(fem.Constant(mesh, 1.0) * ufl.dx(domain=mesh))
    else:
        dx = ufl.Measure("dx", domain=mesh, subdomain_data=bundle.cell_tags)
        form = fem.form(fem.Constant(mesh, 1.0) * dx(bundle.tag(name)))
    return mesh.comm.allreduce(fem.assemble_scalar(form), op=MPI.SUM)


def global_facet_counts(bundle: MeshBundle) -> dict[str, int]:
    """Number of (owned) facets per surface group, summed over ranks (collective)."""
    from mpi4py import MPI

    mesh = bundle.mesh
    fdim = mesh.topology.dim - 1
    n_owned = mesh.topology.index_map(fdim).size_local
    out = {}
    for name in bundle.surface_names():
        f = bundle.facets(name)
        out[name] = mesh.comm.allreduce(int(np.count_nonzero(f < n_owned)), op=MPI.SUM)
    return out
