"""A body's FE compliance columns kept in its own frame (solvers.body_columns): a problem that
places the same rows on the same bodies reads them instead of solving, and gets the answer
it would have solved; rows elsewhere on the body, or another body, are solved.

The scene is the zone-model roller on a block of tests/test_contact_zone_fe.py (level of a
unit test: about 2 s)."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
from dataclasses import replace

import numpy as np
import pytest
from mpi4py import MPI

from solvers import body_columns as bc
from solvers.body_columns import BodyColumns, node_keys
from solvers.contact import ContactPair, ContactProblem
from solvers.contact_grid import ContactGrid, ZoneLink
from solvers.elastic_body import Material
from solvers.modulus_scaling import ScaledBody
from solvers.verification import roller_scene
from tests.test_contact_zone_fe import H, Q, _problem


def _again(problem, pair=None, bodies=None, load=None):
    """A new problem on ``problem``'s bodies (or ``bodies``), pair and rigid unknown."""
    ru = problem.rigid_unknowns[0]
    return ContactProblem(
        bodies or list(problem.bodies.values()),
        [pair or problem.pairs[0]],
        [replace(ru, load=ru.load if load is None else load)],
        penalty_factor=100.0,
    )


def _shifted(pair: ContactPair, dz: float) -> ContactPair:
    """The pair with its fine and coarse grids moved by dz along the roller's axis."""

    def move(g: ContactGrid) -> ContactGrid:
        d = np.array([0.0, 0.0, dz])
        return replace(g, x_a=np.asarray(g.x_a) + d, x_b=np.asarray(g.x_b) + d)

    lk = pair.link
    return replace(pair, grid=move(pair.grid), link=ZoneLink(move(lk.coarse), *_link_rest(lk)))


def _link_rest(lk: ZoneLink):
    return (
        lk.parent,
        lk.plane,
        lk.half,
        lk.plane_coarse,
        lk.half_coarse,
        lk.group,
        lk.group_coarse,
        lk.depth_a,
        lk.depth_b,
    )


@pytest.fixture(scope="module")
def first():
    problem, info = _problem(MPI.COMM_WORLD)
    return problem, info, problem.solve()


def test_a_second_problem_reads_the_kept_columns(first):
    problem, _, r1 = first
    assert problem.timings["compliance_solves"] > 0
    assert problem.timings["compliance_columns_kept"] == 0
    # twice the load on the same bodies and rows: every column it needs is kept
    again = _again(problem, load=2.0 * problem.rigid_unknowns[0].load)
    r2 = again.solve()
    assert again.timings["compliance_solves"] == 0
    assert again.timings["compliance_columns_kept"] > 0
    # the reference: the same problem on bodies set up afresh, which solves its columns;
    # the same factors and right-hand sides, so round-off of the multi-RHS blocking only
    fresh, _ = _problem(MPI.COMM_WORLD)
    ref = _again(fresh, load=2.0 * fresh.rigid_unknowns[0].load).solve()
    assert np.abs(r2.forces - ref.forces).max() <= 1e-10 * ref.forces.max()
    assert r2.rigid["approach"] == pytest.approx(ref.rigid["approach"], rel=1e-10)
    # force control: the grid carries the doubled load
    assert r2.forces.sum() == pytest.approx(2.0 * r1.forces.sum(), rel=1e-9)


def test_rows_elsewhere_on_the_body_are_solved(first):
    problem, _, _ = first
    moved = _again(problem, pair=_shifted(problem.pairs[0], 0.25))
    moved.solve()
    # other body-frame rows: nothing of the first problem's columns applies
    assert moved.timings["compliance_columns_kept"] == 0
    assert moved.timings["compliance_solves"] > 0


def test_a_modulus_view_reads_the_columns_divided_by_its_scale(first):
    problem, info, _ = first
    stiff = [
        ScaledBody(b, Material(2.0 * b.material.E, b.material.nu)) for b in problem.bodies.values()
    ]
    view = _again(problem, bodies=stiff)
    r = view.solve()
    assert view.timings["compliance_solves"] == 0
    # reference: bodies of 2 E set up and solved afresh
    fresh, _ = _problem(MPI.COMM_WORLD)
    for b in fresh.bodies.values():
        b.material = Material(2.0 * b.material.E, b.material.nu)
    ref = _again(fresh).solve()
    # K(2E) = 2 K(E): the same numbers to round-off; a view read without its scale is off
    # by a factor of 2 in the approach
    assert r.rigid["approach"] == pytest.approx(ref.rigid["approach"], rel=1e-9)
    assert np.abs(r.forces - ref.forces).max() <= 1e-9 * ref.forces.max()
    assert r.forces.sum() == pytest.approx(Q * info["L"], rel=1e-9)


def test_a_line_grid_view_reads_the_surface_columns_divided_by_its_scale():
    """Without a zone link every grid point is an FE point (C = the surface entries S)."""
    base, _ = roller_scene(MPI.COMM_WORLD, h_min=H, degree=1, q=Q)
    base.solve()
    stiff = [
        ScaledBody(b, Material(2.0 * b.material.E, b.material.nu)) for b in base.bodies.values()
    ]
    view = _again(base, bodies=stiff)
    r = view.solve()
    assert view.timings["compliance_solves"] == 0 and not view.zoned
    fresh, _ = roller_scene(MPI.COMM_WORLD, h_min=H, degree=1, q=Q)
    for b in fresh.bodies.values():
        b.material = Material(2.0 * b.material.E, b.material.nu)
    ref = fresh.solve()
    # the penalty system amplifies round-off (tests/test_modulus_scaling.py: 1e-8 measured)
    assert r.rigid["approach"] == pytest.approx(ref.rigid["approach"], rel=1e-7)
    assert np.abs(r.forces - ref.forces).max() <= 1e-6 * ref.forces.max()


def test_a_column_missing_a_row_is_completed_from_that_rows_column(first):
    """A kept column that lacks one row (as when another problem kept one section more) is
    completed by symmetry from that row's own surface and depth columns: two solves per
    body instead of every column, and the answer of the full solve."""
    problem, _, r1 = first
    for name, body in problem.bodies.items():
        store = bc.body_columns(body)
        lost = store.nodes(problem.row_keys[name])[0]
        for j, (r, s, d) in list(store._cols.items()):
            k = r != lost
            store._cols[j] = (r[k], s[k], d[k])
            store.entries -= int((~k).sum())
    again = _again(problem)
    r = again.solve()
    # one row on each of the two bodies: its surface column and its depth row's column
    assert again.timings["compliance_solves"] == 4
    assert again.timings["compliance_columns_kept"] > 0
    # S[n, j] = S[j, n] and D[n, j] from the depth row's column: equal up to round-off
    assert np.abs(r.forces - r1.forces).max() <= 1e-9 * r1.forces.max()
    assert r.rigid["approach"] == pytest.approx(r1.rigid["approach"], rel=1e-10)


def test_columns_dropped_past_the_cap_are_solved_again(first, monkeypatch):
    """Past MAX_ENTRIES the oldest columns go (a call keeps its own): rows elsewhere on the
    body push the first problem's columns out, and a problem on the first rows then solves
    them again and gets the same answer."""
    problem, _, r1 = first
    monkeypatch.setattr(bc, "MAX_ENTRIES", 1)
    _again(problem, pair=_shifted(problem.pairs[0], -0.25)).solve()
    again = _again(problem)
    r = again.solve()
    assert again.timings["compliance_solves"] > 0
    assert again.timings["compliance_columns_kept"] == 0
    assert np.abs(r.forces - r1.forces).max() <= 1e-10 * r1.forces.max()


def test_a_column_is_known_only_at_the_rows_it_was_formed_for():
    store = BodyColumns()
    pts = np.arange(12.0).reshape(4, 1, 3)
    keys = node_keys(pts, np.ones((4, 1)), np.tile([0.0, 1.0, 0.0], (4, 1)))
    nodes = store.nodes(keys)
    assert list(nodes) == [0, 1, 2, 3]
    # a point moved by less than the key's quantum is the same node; by more, a new one
    near = node_keys(pts[:1] + 0.1 * bc.KEY_QUANTUM, np.ones((1, 1)), np.array([[0.0, 1.0, 0.0]]))
    far = node_keys(pts[:1] + 1e-6, np.ones((1, 1)), np.array([[0.0, 1.0, 0.0]]))
    assert store.nodes(near)[0] == 0 and store.nodes(far)[0] == 4
    S = np.arange(6.0).reshape(3, 2)
    store.write(nodes[[2, 0, 1]], nodes[:2], S)
    assert list(store.known_columns(nodes[:3], nodes[:2])) == [True, True]
    assert list(store.known_columns(nodes, nodes[:2])) == [False, False]  # row 3 missing
    assert not store.known_columns(nodes[:1], nodes[2:3])[0]
    got, dep = store.read(nodes[:3], nodes[:2])
    assert np.array_equal(got, S[[1, 2, 0]]) and not dep.any()
