"""Small helpers around the gmsh session (one process-wide gmsh state) and the meshing
steps shared by every body (gear bodies and the carrier): sampling a CAD face, physical
groups, mesher options, the quality floor and the mesh statistics.

The helpers that act on a model take the ``gmsh`` module as an argument; ``gmsh`` itself is
imported lazily (heavy), so this module stays importable without it.
"""

from __future__ import annotations

import contextlib
import signal
import threading

import numpy as np

from meshing import sizing

# gmsh is heavy: it is imported lazily, inside session() and write_msh().


def initialize() -> None:
    """Initialize gmsh (not interruptible: Ctrl-C stays Python's) and put back the Python
    handlers of SIGTERM and SIGINT: gmsh's first initialize resets the process's signal
    handlers at the C level (OpenCASCADE's), while Python still reports its own, so a
    ``kill`` of a serial run after its first mesh ended it with status 143 instead of the
    documented interrupt (exit 130, :func:`studies.cli.interrupt_on_sigterm`, factor
    folders removed). Only the main thread can set handlers; elsewhere none were set."""
    import gmsh

    main = threading.current_thread() is threading.main_thread()
    kept = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGINT)} if main else {}
    gmsh.initialize(interruptible=False)
    for signum, handler in kept.items():
        if handler is not None:  # None: set outside Python, nothing to put back
            signal.signal(signum, handler)


@contextlib.contextmanager
def session(model_name: str, verbose: bool = False):
    """A fresh gmsh model named ``model_name``; gmsh is initialized if needed and finalized
    again only if this call initialized it. Yields the ``gmsh`` module."""
    import gmsh

    owner = not gmsh.isInitialized()
    if owner:
        initialize()
    # options are global to a gmsh session that another module may have started and left
    # open (solvers.simple_meshes): from the defaults, so a mesh is the same in any process
    gmsh.option.restoreDefaults()
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
    import gmsh

    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(str(path))


def group_nodes(path) -> dict:
    """Node coordinates (N, 3) of every named physical group of the mesh file ``path``."""
    out = {}
    with session("inspect") as gm:
        gm.merge(str(path))
        for dim, tag in gm.model.getPhysicalGroups():
            name = gm.model.getPhysicalName(dim, tag)
            _, xyz = gm.model.mesh.getNodesForPhysicalGroup(dim, tag)
            out[name] = np.asarray(xyz).reshape(-1, 3)
    return out


def sample_surface(gmsh, tag: int, n: int = 3) -> np.ndarray:
    """Points (n * n, 3) of CAD surface ``tag`` on an ``n`` x ``n`` grid of parameter
    points (cell centres of the parametrization bounds), for naming faces by geometry."""
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    fr = (np.arange(n) + 0.5) / n
    uv = []
    for fu in fr:
        for fv in fr:
            uv += [lo[0] + fu * (hi[0] - lo[0]), lo[1] + fv * (hi[1] - lo[1])]
    xyz = np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3)
    return xyz


def add_physical_groups(gmsh, groups: dict[str, list[int]], volumes: dict[str, list[int]]):
    """Add the named physical groups (sorted by name, so tag integers are reproducible)."""
    for name in sorted(volumes):
        gmsh.model.addPhysicalGroup(3, sorted(volumes[name]), name=name)
    for name in sorted(groups):
        gmsh.model.addPhysicalGroup(2, sorted(groups[name]), name=name)


def mesh_options(gmsh) -> None:
    """Mesher choice and options shared by every body mesh (deterministic, linear tets)."""
    gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay surfaces
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)  # HXT: faster, better minimum quality
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.option.setNumber("Mesh.HighOrderOptimize", 0)  # curve_elements runs it where needed
    # One thread: HXT is then deterministic (with 2 threads the same input gave a flat tet in
    # one run out of three); it is fast enough alone.
    gmsh.option.setNumber("General.NumThreads", 1)


def enforce_quality(gmsh) -> bool:
    """Run the (slower, ~10 s per 100k tets) Netgen optimiser if the minimum SICN is below
    :data:`meshing.sizing.MIN_SICN`; True if it ran. Rare: one tet in 135k of the full
    case 1 ring with refined mesh zones came out at 0.107 (Netgen: 0.26)."""
    _, etags, _ = gmsh.model.mesh.getElements(3)
    tags_all = np.concatenate([np.asarray(t) for t in etags])
    q = np.asarray(gmsh.model.mesh.getElementQualities(tags_all, "minSICN"))
    if q.min() >= sizing.MIN_SICN:
        return False
    gmsh.model.mesh.optimize("Netgen", force=True)
    return True


def curve_elements(gmsh) -> dict:
    """Make the current 3D mesh second order (10-node tets) with the edge nodes of boundary
    faces on the CAD faces, so a curved face (a root fillet) is no longer a set of flat
    facets with a kink at every edge; the straight-sided P2 sector's ISO-line stress
    converged at an observed order of about 0.8 over 0.15 / 0.1 / 0.067 mm fillets, the
    curved one at about 2.3 (1-GB sun, level-1 driver; docs/validation.md). Curving a fine mesh on a
    small fillet can invert tets (48 of the 660k of 1-GB's 0.067 mm ring sector): those are
    untangled by gmsh's high-order optimiser; :class:`MeshingError` if any stays inverted.
    Returns the minimum scaled Jacobian (> 0: every tet valid) and whether the optimiser ran.
    gmsh's options are global to the process: the optimiser's is set back to what it was,
    so a later mesh does not depend on this one (:func:`mesh_options` sets it to 0)."""
    gmsh.model.mesh.setOrder(2)

    def worst() -> float:
        _, etags, _ = gmsh.model.mesh.getElements(3)
        tags_all = np.concatenate([np.asarray(t) for t in etags])
        return float(np.min(gmsh.model.mesh.getElementQualities(tags_all, "minSJ")))

    q = worst()
    optimized = q <= 0.0
    if optimized:
        kept = gmsh.option.getNumber("Mesh.HighOrderOptimize")
        gmsh.option.setNumber("Mesh.HighOrderOptimize", 2)
        try:
            gmsh.model.mesh.optimize("HighOrder", force=True)
        finally:
            gmsh.option.setNumber("Mesh.HighOrderOptimize", kept)
        q = worst()
        if q <= 0.0:
            raise sizing.MeshingError(
                f"curved (second-order) mesh: an element stays inverted after the high-order "
                f"optimiser (minimum scaled Jacobian {q:.3g}); use geometry_order 1 or "
                "another size"
            )
    return {"min_scaled_jacobian": q, "high_order_optimized": optimized}


def mesh_stats(gmsh) -> dict:
    """Element/node counts and quality of the 3D mesh in the current model."""
    etypes, etags, _ = gmsh.model.mesh.getElements(3)
    tags_all = np.concatenate([np.asarray(t) for t in etags]) if etags else np.array([])
    q = np.asarray(gmsh.model.mesh.getElementQualities(tags_all, "minSICN"))
    vol = np.asarray(gmsh.model.mesh.getElementQualities(tags_all, "volume"))
    node_tags, _, _ = gmsh.model.mesh.getNodes()
    return {
        "elements": len(tags_all),
        "nodes": len(node_tags),
        "min_sicn": float(q.min()) if len(q) else float("nan"),
        "p01_sicn": float(np.percentile(q, 1)) if len(q) else float("nan"),
        "volume": float(vol.sum()),
        "element_types": [int(e) for e in etypes],
    }
