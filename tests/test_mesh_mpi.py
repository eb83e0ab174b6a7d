"""The same scene under ``mpiexec -n 2``: identical tag sets and total volume on all ranks.

Run by ``make test-mpi`` (every rank executes the test; collectives only, asserts on all
ranks). The mesh is built on rank 0 (or taken from the cache) and distributed.
"""

from __future__ import annotations

import math

import pytest

from cases.gearset import load_gearset
from meshing import scenes
from meshing.build import load_scene


@pytest.mark.mpi
def test_scene_loads_identically_in_parallel():
    from mpi4py import MPI

    from meshing.to_dolfinx import global_facet_counts, global_volume

    comm = MPI.COMM_WORLD
    scene = scenes.branch_scene(load_gearset("case1"), 0.0)
    bundle = load_scene(scene, 0, comm)
    meta = bundle.meta

    # identical name -> (dim, tag) tables on every rank
    tables = comm.allgather(sorted(bundle.names.items()))
    assert all(t == tables[0] for t in tables)
    assert set(bundle.volume_names()) == {g.name for g in scene.gears}

    # total and per-body volume: the distributed tets are gmsh's tets, so the sums agree
    # with the serial gmsh volumes to round-off (1e-10 relative)
    assert math.isclose(global_volume(bundle), meta["volume"], rel_tol=1e-10)
    for name, body in meta["bodies"].items():
        assert math.isclose(global_volume(bundle, name), body["volume"], rel_tol=1e-10)

    # every named surface survives distribution with all its triangles (exact counts)
    counts = global_facet_counts(bundle)
    for name, n in counts.items():
        assert n == meta["group_elements"][name], name
    n_cells = comm.allreduce(bundle.mesh.topology.index_map(3).size_local, op=MPI.SUM)
    assert n_cells == meta["elements"]
