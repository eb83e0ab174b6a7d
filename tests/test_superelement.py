"""The condensed stiffness of an elastic body at its reference points (solvers.superelement)
against a direct FE solve of the same body under the same reference loads."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import numpy as np
from mpi4py import MPI

from solvers import simple_meshes as sm
from solvers.elastic_body import Dirichlet, ElasticBody, Material
from solvers.rigid_coupling import RigidCoupling
from solvers.superelement import Superelement

STEEL = Material(206e3, 0.3)


def _tube(load=None):
    """A steel tube (R 20, bore 8, length 20 mm) clamped on its outer surface, its bore a
    rigid ring on a free reference point at the centre (optionally loaded)."""
    mb = sm.hollow_cylinder(MPI.COMM_WORLD, 20.0, 8.0, 20.0, 4.0)
    ring = RigidCoupling("bore", "bore", (0.0, 0.0, 0.0), (0.0,) * 6, load=load)
    return ElasticBody(
        "tube",
        mb.mesh,
        mb.facet_tags,
        mb.tags,
        STEEL,
        1,
        couplings=[ring],
        dirichlet=[Dirichlet("outer")],
    )


def test_condensed_stiffness_matches_a_direct_solve():
    se = Superelement(_tube())
    S, F = se.S, se.F
    # a stiffness: symmetric (F is symmetrised; the raw asymmetry is MUMPS round-off) and
    # positive definite (the tube is clamped, so every reference motion costs energy)
    assert np.allclose(S, S.T, rtol=0, atol=1e-9 * np.abs(S).max())
    assert np.linalg.eigvalsh(S).min() > 0
    # the same reference loads applied through the coupling and solved directly: the
    # reference displacements are F @ loads, the field is X loads (one factorization each,
    # different right-hand sides: agreement to round-off, 1e-9 of the largest entry)
    loads = np.array([1.0e3, -2.0e3, 5.0e2, 3.0e4, -1.0e4, 2.0e4])  # N, N mm
    direct = _tube(load=loads)
    direct.setup()
    x = direct.solve(direct.f_red)
    q = direct.reference_dofs(x)["bore"]
    assert np.allclose(q, F @ loads, rtol=0, atol=1e-9 * np.abs(q).max())
    u_se = se.displacement(loads).getArray(readonly=True)
    u_direct = direct.expand(x).getArray(readonly=True)
    assert np.allclose(u_se, u_direct, rtol=0, atol=1e-9 * np.abs(u_direct).max())
    # a radial load on the bore moves it along the load (x), not across it (y): the tube is
    # symmetric about the xz-plane, so F_yx vanishes to the mesh's asymmetry (< 2 %)
    assert F[0, 0] > 0 and abs(F[1, 0]) < 0.02 * F[0, 0]


def test_a_released_body_frees_its_solver_and_sets_up_again():
    """ElasticBody.release frees the factorization and the matrices (the one-position runs
    free the global bodies before the root-stress submodels); set up again, the body gives
    the same solution to round-off."""
    loads = np.array([1.0e3, -2.0e3, 5.0e2, 3.0e4, -1.0e4, 2.0e4])
    body = _tube(load=loads)
    body.setup()
    before = body.solve(body.f_red).getArray(readonly=True).copy()
    body.release()
    assert not body.ready and body.ksp is None and body.K is None and body.K_red is None
    body.setup()
    after = body.solve(body.f_red).getArray(readonly=True)
    assert np.allclose(after, before, rtol=0, atol=1e-12 * np.abs(before).max())
