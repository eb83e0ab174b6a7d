"""Hard cases stop with a clear message and keep what was computed (solvers.errors)."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import pytest
from mpi4py import MPI

from solvers.contact import RigidUnknown
from solvers.errors import (
    ActiveSetError,
    NoContactError,
    RigidUnknownError,
    SingularBodyError,
    SolverError,
)
from solvers.verification import hertz_scene, planetary_scene


@pytest.fixture(scope="module")
def hertz():
    return hertz_scene(MPI.COMM_WORLD, h_min=1.0, degree=1)


def test_flanks_that_do_not_touch_are_reported(hertz):
    problem, _ = hertz
    # displacement control: the cylinder lifted by 0.5 mm never reaches the block
    with pytest.raises(NoContactError, match="do not touch") as err:
        problem.solve(prescribed={"approach": 0.5})
    assert "cylinder-block" in str(err.value)  # names the pair
    assert err.value.partial["gaps"].min() > 0.4  # the gaps are kept, not zeros
    assert isinstance(err.value, SolverError)


def test_active_set_non_convergence_reports_the_history(hertz):
    problem, _ = hertz
    with pytest.raises(ActiveSetError, match="did not converge in 1") as err:
        problem.solve(max_iter=1)
    hist = err.value.partial["history"]
    assert [h["iteration"] for h in hist] == [0]
    assert all(k in hist[0] for k in ("active", "added", "removed", "min_gap", "total_force"))
    assert err.value.partial["forces"].sum() == pytest.approx(35e3)  # last iterate kept


def test_rigid_unknown_that_contact_cannot_balance(hertz):
    problem, _ = hertz
    ghost = RigidUnknown("ghost", "nowhere", direction=(0.0, 1.0), load=1.0)
    problem.obstacles.add("nowhere")
    problem.rigid_unknowns.append(ghost)
    try:
        import numpy as np

        problem.R = np.c_[problem.R, np.zeros(problem.n)]  # no grid point sees it
        with pytest.raises(RigidUnknownError, match="ghost"):
            problem.solve()
    finally:
        problem.rigid_unknowns.pop()
        problem.R = problem.R[:, :-1]


def test_planet_spin_left_free_names_the_body_and_mode():
    problem, _ = planetary_scene(MPI.COMM_WORLD, torque=9e3, h_min=0.3, degree=1)
    # drop the planet-spin unknown: nothing restrains the spin (no stabilising spring)
    problem.rigid_unknowns = [u for u in problem.rigid_unknowns if u.name != "planet_spin"]
    with pytest.raises(SingularBodyError) as err:
        problem.solve()
    assert err.value.body == "planet"
    assert err.value.modes == ["rotation about z"]
