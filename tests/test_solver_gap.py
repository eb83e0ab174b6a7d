"""Gap operator (solvers.gap_operator) against fields it must reproduce exactly.

A P2 field interpolates any quadratic exactly, so n . u at a point (or the patch mean of a
Gauss rule that integrates cubics exactly) must match the analytic value to round-off.
"""

import math

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import numpy as np
import pytest
from mpi4py import MPI

from solvers import simple_meshes as sm
from solvers.contact_grid import ContactGrid, line_grid_2d
from solvers.elastic_body import ElasticBody, Material
from solvers.errors import GapOperatorError
from solvers.gap_operator import gap_matrix
from solvers.rigid_coupling import RigidCoupling


def _field(x):
    return np.stack([0.3 * x[:, 0] ** 2 - 0.1 * x[:, 0] * x[:, 1], 0.2 * x[:, 1] ** 2 + x[:, 0]])


@pytest.fixture(scope="module")
def disc_body():
    mb = sm.disc(MPI.COMM_WORLD, 10.0, bore=3.0, h_min=1.0, h_max=2.0)
    body = ElasticBody(
        "disc",
        mb.mesh,
        mb.facet_tags,
        mb.tags,
        Material(210e3, 0.3),
        2,
        couplings=[RigidCoupling("bore", "bore", (0.0, 0.0), (math.inf,) * 3)],
    )
    body.setup()
    return body


def _reduced_field(body):
    """Reduced vector holding the quadratic field on every non-slaved DOF (q = 0)."""
    x = body.K_red.createVecRight()
    n = body.n_own
    vals = _field(body.dof_x[:n])[body.dof_comp[:n], np.arange(n)]
    arr = x.getArray()
    arr[:n] = np.where(body.slaved, 0.0, vals)
    return x


def _grid(n_pts, spread):
    rng = np.random.default_rng(7)
    ang = rng.uniform(0, 2 * math.pi, n_pts)
    r = rng.uniform(7.0, 9.5, n_pts)  # inside, cells clear of the (slaved) bore DOFs
    pts = np.c_[r * np.cos(ang), r * np.sin(ang)]
    nrm = np.c_[np.cos(ang + 0.3), np.sin(ang + 0.3)]
    if spread:
        return line_grid_2d("g", pts, pts, nrm, np.zeros(n_pts), 0.4, n_spread=2)
    return ContactGrid("g", pts, pts, nrm, np.zeros(n_pts), np.ones(n_pts))


@pytest.mark.parametrize("spread", [False, True])
def test_gap_operator_reproduces_quadratic_fields(disc_body, spread):
    body = disc_body
    grid = _grid(200, spread)
    G, h = gap_matrix(body, [(0, grid, "b")], grid.n)
    y = G.createVecLeft()
    G.mult(_reduced_field(body), y)
    got = np.concatenate(body.comm.allgather(y.getArray(readonly=True).copy()))
    if spread:
        # exact patch mean of n . u over s in [-0.2, 0.2] along the tangent (3-point Gauss)
        s, w = np.polynomial.legendre.leggauss(3)
        t = grid.tangents[:, 0, :]
        expect = sum(
            wi / 2 * np.einsum("ck,kc->k", _field(grid.x_b + si * 0.2 * t), grid.normals)
            for si, wi in zip(s, w, strict=True)
        )
    else:
        expect = np.einsum("ck,kc->k", _field(grid.x_b), grid.normals)
    # P2 interpolates the quadratic exactly; 2-point Gauss integrates it exactly:
    # only round-off of the pull-back and tabulation remains (values O(30))
    assert np.abs(got - expect).max() < 1e-10 * np.abs(expect).max()
    assert np.all(h > 0)  # every point found a cell


def test_points_outside_the_body_are_refused(disc_body):
    pts = np.array([[30.0, 0.0], [9.0, 0.0]])
    grid = ContactGrid("off", pts, pts, np.tile([1.0, 0.0], (2, 1)), np.zeros(2), np.ones(2))
    with pytest.raises(GapOperatorError, match="1 of 2 contact points are not inside"):
        gap_matrix(disc_body, [(0, grid, "a")], 2)


def test_a_mesh_keeps_its_tree_and_the_gap_operator_is_the_same(disc_body):
    """The cell tree is built once per mesh (the bodies keep their meshes over the mesh
    positions) and a second gap operator on the cached tree equals the first to the bit;
    another mesh gets its own tree, and a tree does not keep its mesh alive."""
    import gc
    import weakref

    from solvers.gap_operator import _TREES, cell_tree

    mesh = disc_body.mesh
    grid = _grid(50, False)
    G1, h1 = gap_matrix(disc_body, [(0, grid, "b")], grid.n)
    trees = dict(_TREES[mesh])
    assert len(trees) == 1
    G2, h2 = gap_matrix(disc_body, [(0, grid, "b")], grid.n)
    assert _TREES[mesh] == trees  # no new tree: the same object
    ((key, tree),) = trees.items()
    assert cell_tree(mesh, *key) is tree
    a1, a2 = (G.convert("dense").getDenseArray().copy() for G in (G1, G2))
    assert np.array_equal(a1, a2) and np.array_equal(h1, h2)
    other = sm.disc(MPI.COMM_WORLD, 10.0, bore=3.0, h_min=1.0, h_max=2.0).mesh
    tdim = other.topology.dim
    cell_tree(other, tdim, other.topology.index_map(tdim).size_local, 0.01)
    assert other in _TREES and len(_TREES[other]) == 1
    gone = weakref.ref(other)
    del other
    gc.collect()
    assert gone() is None
