"""Needle bearing as a 6x6 diagonal spring on a rigidly coupled bore (solvers.rigid_coupling).

A hollow pinion (1000 x steel unless stated) sits on a bearing at its centre. The rigid bore
carries the whole load to the reference point, so by statics the reference point moves by
exactly load / spring, M / k_tilt and F / k_radial, whatever the body's stiffness; only the
round-off of the solve remains (measured 7e-12 and 1e-10). The body's own compliance shows
in series at the loaded surfaces (last test).
"""

import math

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import numpy as np
import pytest
from mpi4py import MPI

from solvers.errors import SingularBodyError
from solvers.verification import applied_resultant, pinion_bearing_scene

K_RADIAL, K_TILT = 5e5, 5e8


def _solve(body):
    body.setup()
    x = body.solve(body.f_red)
    return body.reference_dofs(x)["bearing"]


def test_pure_moment_tilts_by_m_over_k_tilt():
    body = pinion_bearing_scene(MPI.COMM_WORLD, moment=2.0e6, k_radial=K_RADIAL, k_tilt=K_TILT)
    q = _solve(body)
    force, moment = applied_resultant(body)
    # the end-face tractions are a pure moment about x: no net force, no other moment
    # (round-off of the assembled load, ~1e-16 relative)
    assert np.abs(force).max() < 1e-9 * abs(moment[0])
    assert abs(moment[1]) + abs(moment[2]) < 1e-9 * abs(moment[0])
    theta = q[3]  # rotation about the bearing's a_1 = x
    # spec: within 1 %; statics make it exact up to round-off (measured 7e-12)
    assert theta == pytest.approx(moment[0] / K_TILT, rel=1e-3)
    # a pure moment moves the centre by nothing but round-off (radial springs stay unloaded)
    assert np.abs(q[:3]).max() < 1e-9 * abs(theta) * 20.0


def test_radial_force_moves_by_f_over_k_radial():
    body = pinion_bearing_scene(MPI.COMM_WORLD, radial_force=1.0e4, k_radial=K_RADIAL)
    q = _solve(body)
    force, _moment = applied_resultant(body)
    assert force[0] == pytest.approx(1.0e4, rel=1e-2)  # faceted outer surface area, O(h^2)
    # spec: within 1 %; exact by statics up to round-off (measured 1e-10)
    assert q[0] == pytest.approx(force[0] / K_RADIAL, rel=1e-3)
    # no tilt: the uniform traction has no moment about the centre (symmetric mesh to h^2)
    assert abs(q[3]) + abs(q[4]) < 1e-3 * abs(q[0]) / 20.0


def _end_face_tilt(body, x_red):
    """Least-squares rotation about x of the end face z = +10: sum y u_z / sum y^2."""
    from solvers.elastic_body import mpi_sum

    u = body.expand(x_red).getArray(readonly=True)
    n = body.n_own
    xs, comp = body.dof_x[:n], body.dof_comp[:n]
    on = (np.abs(xs[:, 2] - 10.0) < 1e-9) & (comp == 2)
    y = xs[on, 1]
    num, den = mpi_sum(body.comm, np.array([np.sum(y * u[on]), np.sum(y * y)]))
    return num / den


def test_steel_pinion_adds_its_own_compliance_in_series():
    # The bore is rigid and carries the whole moment, so the reference point tilts by
    # M / k_tilt whatever the body's stiffness (statics); the loaded end face tilts by that
    # plus the body's own deformation: series springs.
    tilts = {}
    for name, E in (("stiff", 210e3 * 1e3), ("steel", 210e3)):
        body = pinion_bearing_scene(MPI.COMM_WORLD, moment=2.0e6, E=E)
        body.setup()
        x = body.solve(body.f_red)
        _, moment = applied_resultant(body)
        q = body.reference_dofs(x)["bearing"]
        assert q[3] == pytest.approx(moment[0] / K_TILT, rel=1e-6)  # round-off level
        tilts[name] = _end_face_tilt(body, x) / q[3] - 1.0
    # series springs: face tilt = M / k_tilt + c M / E, so the body's share scales exactly
    # with 1/E (linear elasticity, same mesh): 1000x from the stiff to the steel pinion, to
    # round-off of the solves (~1e-9 relative on a 1e-4 quantity for the stiff one)
    assert tilts["stiff"] > 0.0
    assert tilts["steel"] / tilts["stiff"] == pytest.approx(1000.0, rel=1e-4)


def test_free_spin_is_reported_as_singular():
    body = pinion_bearing_scene(MPI.COMM_WORLD, moment=1.0, hold_spin=False)
    with pytest.raises(SingularBodyError) as err:
        body.setup()
    assert err.value.body == "pinion"
    assert err.value.modes == ["rotation about z"]
    assert "pinion" in str(err.value) and "rotation about z" in str(err.value)


def test_body_left_free_names_all_six_modes():
    from solvers import simple_meshes as sm
    from solvers.elastic_body import ElasticBody, Material

    mb = sm.hollow_cylinder(MPI.COMM_WORLD, 20.0, 8.0, 20.0, 6.0)
    body = ElasticBody("loose", mb.mesh, mb.facet_tags, mb.tags, Material(210e3, 0.3), 1)
    with pytest.raises(SingularBodyError) as err:
        body.setup()
    assert err.value.body == "loose"
    assert len(err.value.modes) == 6


def test_bearing_frame_follows_the_axis():
    from solvers.rigid_coupling import bearing

    b = bearing("b", "bore", (0, 0, 0), (0, 1, 1), 1.0, 2.0, 3.0)
    a = np.asarray(b.axes)
    assert np.allclose(a @ a.T, np.eye(3), atol=1e-12)
    assert np.allclose(a[2], np.array([0, 1, 1]) / math.sqrt(2))
    assert list(b.stiffness) == [1.0, 1.0, 3.0, 2.0, 2.0, 0.0]  # spin free
