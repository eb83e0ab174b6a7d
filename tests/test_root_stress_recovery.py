"""Surface stress of solvers.root_stress on known fields (no solve: the displacement is
interpolated): the nodal surface values on a free face, exact for P2 where the field is in
the space, converging for P1; the point-on-facet lookup of the critical line."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import itertools
import math
from types import SimpleNamespace

import dolfinx
import numpy as np
from mpi4py import MPI

from solvers.elastic_body import Material
from solvers.root_stress import on_surface, surface_values

MAT = Material(210000.0, 0.3)


def _box(n):
    return dolfinx.mesh.create_box(
        MPI.COMM_SELF,
        [np.zeros(3), np.array([1.0, 1.0, 0.5])],
        [n, n, n // 2],
        dolfinx.mesh.CellType.tetrahedron,
    )


def _stress(grad):
    eps = 0.5 * (grad + grad.transpose(0, 2, 1))
    tr = np.trace(eps, axis1=1, axis2=2)
    return MAT.lam * tr[:, None, None] * np.eye(3) + 2.0 * MAT.mu * eps


def _cubic(x):
    """A displacement (3, n) cubic in x: its stress grows towards the face z = 0.5."""
    return np.stack(
        [
            1e-3 * x[2] ** 3 + 2e-4 * x[0] * x[1],
            5e-4 * x[0] ** 2 * x[2],
            -1e-3 * x[0] * x[2] ** 2 + 1e-4 * x[1] ** 3,
        ]
    )


def _cubic_stress(p):
    x, y, z = p.T
    g = np.zeros((len(p), 3, 3))  # g[i, a, b] = d u_a / d x_b
    g[:, 0, 0], g[:, 0, 1], g[:, 0, 2] = 2e-4 * y, 2e-4 * x, 3e-3 * z**2
    g[:, 1, 0], g[:, 1, 2] = 1e-3 * x * z, 5e-4 * x**2
    g[:, 2, 0], g[:, 2, 1], g[:, 2, 2] = -1e-3 * z**2, 3e-4 * y**2, -2e-3 * x * z
    return _stress(g)


def _quadratic(x):
    return np.stack(
        [
            1e-3 * x[2] ** 2 + 2e-4 * x[0] * x[1],
            5e-4 * x[0] * x[2],
            -1e-3 * x[0] ** 2 + 1e-4 * x[1] * x[2],
        ]
    )


def _quadratic_stress(p):
    x, y, z = p.T
    g = np.zeros((len(p), 3, 3))
    g[:, 0, 0], g[:, 0, 1], g[:, 0, 2] = 2e-4 * y, 2e-4 * x, 2e-3 * z
    g[:, 1, 0], g[:, 1, 2] = 5e-4 * z, 5e-4 * x
    g[:, 2, 0], g[:, 2, 1], g[:, 2, 2] = -2e-3 * x, 1e-4 * z, 1e-4 * y
    return _stress(g)


def _top(n, degree, disp):
    """Nodes, tensors, facets of the face z = 0.5 of an n x n x n/2 box."""
    mesh = _box(n)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (3,)))
    u = dolfinx.fem.Function(V)
    u.interpolate(disp)
    top = dolfinx.mesh.locate_entities_boundary(mesh, 2, lambda x: np.isclose(x[2], 0.5))
    body = SimpleNamespace(mesh=mesh, material=MAT, degree=degree, gdim=3, comm=MPI.COMM_SELF)
    return surface_values(body, u, [np.zeros(0, np.int32), top.astype(np.int32)])


def _error(n, degree, disp, exact):
    """Largest error of the surface tensors at the face's inner nodes (0.2 <= x, y <= 0.8),
    relative to the largest exact component there."""
    nodes, tensors, _ = _top(n, degree, disp)
    x = nodes[:, 1:4]
    inner = np.all((x[:, :2] >= 0.2 - 1e-9) & (x[:, :2] <= 0.8 + 1e-9), axis=1)
    want = exact(x[inner])
    return np.abs(tensors[inner] - want).max() / np.abs(want).max()


def test_nodes_and_facets_of_the_face():
    n = 4
    nodes, tensors, facets = _top(n, 1, _cubic)
    assert len(nodes) == (n + 1) ** 2 and np.all(nodes[:, 0] == 1)  # the second group
    assert len(facets) == 2 * n * n and tensors.shape == (len(nodes), 3, 3)
    assert np.allclose(nodes[:, 3], 0.5)
    # every facet's three corners are nodes of the face, in its group
    assert np.all(facets[:, 0] == 1) and facets[:, 1:].max() < len(nodes)


def test_p2_surface_values_are_exact_for_a_quadratic_displacement():
    # a quadratic displacement is in the P2 space; each cell's linear stress evaluated at
    # the vertex is the exact value; 1e-9 relative: round-off
    assert _error(4, 2, _quadratic, _quadratic_stress) < 1e-9


def test_surface_values_converge():
    """P1 (cell constants averaged at the surface nodes) converges with order about 1 and
    P2 (the cells' linear stress at the node) with order about 2 for a cubic displacement on
    three meshes, h halved twice (measured P1 0.92 and 0.96, P2 2.00; bounds 0.8, 1.6)."""
    for degree, p_min in ((1, 0.8), (2, 1.6)):
        err = [_error(n, degree, _cubic, _cubic_stress) for n in (4, 8, 16)]
        orders = [math.log2(a / b) for a, b in itertools.pairwise(err)]
        assert min(orders) > p_min, (degree, err, orders)


def test_point_on_facet_interpolation():
    # points on the face: the facet under each and weights that reproduce the point, so a
    # field linear on the face is interpolated exactly; a point off the face reports its
    # distance to the facet plane
    nodes, _, facets = _top(4, 1, _cubic)
    corners = nodes[facets[:, 1:], 1:4]
    rng = np.random.default_rng(3)
    pts = np.c_[rng.uniform(0, 1, (20, 2)), np.full(20, 0.5)]
    f, w, d = on_surface(pts, corners)
    assert np.allclose(np.einsum("pk,pkd->pd", w, corners[f]), pts, atol=1e-12)
    assert np.all(w >= -1e-6) and np.allclose(w.sum(1), 1.0) and np.all(d < 1e-12)
    _, _, d = on_surface(np.array([[0.5, 0.5, 0.53]]), corners)
    assert abs(d[0] - 0.03) < 1e-12
