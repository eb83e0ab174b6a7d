"""The displacement fields are not started on a file system without room for them: ADIOS2
aborts the process on a full disk (issue 57: ``iostream error``, status 134, no one-line
error), so solvers.results.write_vtx refuses up front with ENOSPC, which the driver turns
into a warning that keeps the solved position."""

import errno
from collections import namedtuple

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import pytest
from mpi4py import MPI

from solvers import results
from solvers.verification import hertz_scene

Usage = namedtuple("Usage", "total used free")


@pytest.fixture(scope="module")
def solved():
    problem, _ = hertz_scene(MPI.COMM_WORLD, h_min=0.5, degree=2)
    return problem, problem.solve()


def test_the_estimate_bounds_what_is_written(solved, tmp_path):
    """P2 in 2D: VTX writes the field's own nodes as 3D points and values, the case where
    the mesh's own nodes would undercount by half."""
    problem, result = solved
    paths = results.write_vtx(tmp_path / "fields", problem, result)
    written = sum(f.stat().st_size for p in paths for f in p.rglob("*") if f.is_file())
    assert written <= results.vtx_bytes(problem)
    assert written >= results.vtx_bytes(problem) / results.VTX_SIZE_MARGIN / 2  # not idle


def test_no_room_is_enospc_before_anything_is_written(solved, tmp_path, monkeypatch):
    problem, result = solved
    need = results.vtx_bytes(problem)
    monkeypatch.setattr(results.shutil, "disk_usage", lambda p: Usage(10 * need, 0, need - 1))
    with pytest.raises(OSError) as err:
        results.write_vtx(tmp_path / "new" / "fields", problem, result)
    assert err.value.errno == errno.ENOSPC and "MB needed for the fields" in str(err.value)
    assert not (tmp_path / "new").exists()
