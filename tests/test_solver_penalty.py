"""Penalty sweep over three decades on the Hertz problem (solvers.contact).

eps = factor * E* / h. The condensed system is exactly K + G_A^T E G_A, so the answers
converge to the eps -> inf limit of the same discrete model with an error ~ 1 / factor:
successive decade differences must shrink by about ten, and the top decade must move the
answers by less than 1 %.
"""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import numpy as np
import pytest
from mpi4py import MPI

from solvers.errors import PenaltyConditioningError
from solvers.results import resultants
from solvers.verification import hertz_measures, hertz_scene

FACTORS = [1.0, 10.0, 100.0, 1000.0]


@pytest.fixture(scope="module")
def scene():
    # coarser than test_solver_hertz (h = 0.7 mm): the sweep needs no Hertz accuracy
    return hertz_scene(MPI.COMM_WORLD, h_min=0.7, degree=2)


def test_displacement_controlled_force_converges(scene):
    problem, _info = scene
    # prescribe the approach the force-controlled solve needs for P at factor 100
    delta = problem.solve(penalty_factor=100.0).rigid["approach"]
    forces, moments = [], []
    for f in FACTORS:
        res = problem.solve(penalty_factor=f, prescribed={"approach": delta})
        forces.append(res.forces.sum())
        # moment of the contact on the block about its corner: the resultant's line matters
        r = resultants(problem, res)["block"]
        moments.append(float(r["contact_moment"] - 100.0 * r["contact_force"][1]))
    forces, moments = np.array(forces), np.array(moments)
    d = np.abs(np.diff(forces)) / forces[-1]
    # the top decade moves the resultant force and moment by < 1 % (spec)
    assert d[-1] < 1e-2
    assert abs(moments[-1] - moments[-2]) < 1e-2 * abs(moments[-1])
    # penalty error ~ 1 / eps: each decade shrinks the change ~10x (allow >= 4x: the active
    # set changes by whole grid points between factors)
    assert d[0] / d[1] > 4 and d[1] / d[2] > 4
    # force grows monotonically towards the rigid-penalty limit
    assert np.all(np.diff(forces) > 0)


def test_force_controlled_approach_converges(scene):
    problem, info = scene
    approach = np.array(
        [
            hertz_measures(problem, problem.solve(penalty_factor=f), info)["approach"]
            for f in FACTORS
        ]
    )
    d = np.abs(np.diff(approach)) / approach[-1]
    assert d[-1] < 1e-2  # top decade < 1 %
    assert d[0] / d[1] > 4 and d[1] / d[2] > 4  # ~1/eps convergence


def test_ill_conditioning_penalty_is_refused(scene):
    problem, _ = scene
    with pytest.raises(PenaltyConditioningError, match="ill-conditioned") as err:
        problem.solve(penalty_factor=1e13)
    assert "penalty" in err.value.partial
