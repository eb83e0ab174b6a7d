"""The zone contact model with finite elements (eq. (5) of solvers.contact): a steel roller
on a steel block (solvers.verification.roller_scene's bodies) under a line load, the
contact zone on a fine grid across the line with the FE compliance taken on one coarse
point per section. Checks Hertz at mid-length, the penalty no longer mattering, the FE
cost (columns) and the same answer under ``mpiexec -n 2``; and on a gear mesh (1-GA, level
0, one position: run it under ``flock /tmp/heavy.lock``, ~4 GB) Hertz at the loaded stations
and no line-load spike where the contact lines leave the path."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import math

import numpy as np
import pytest
from mpi4py import MPI

from gears.contact_stress import hertz_line_contact
from solvers.body_store import BodyStore
from solvers.contact import ContactPair, ContactProblem, psd_projection
from solvers.contact_grid import ContactGrid, ZoneLink
from solvers.results import contact_resultant, line_load, resultants
from solvers.verification import roller_scene
from studies.benchmarks.contact import run_case

H = 1.0  # element size at the contact (mm)
Q = 1.0e4  # N/mm


def _zone_pair(info) -> ContactPair:
    """Fine grid: per 1 mm section along z, cells across x from a_H / 5 growing by 1.3 up
    to h / 2 over |x| <= 2 a_H; coarse: one point per section at x = 0, patch h x h."""
    R, L, s, e_star = info["R"], info["L"], info["spacing"], info["e_star"]
    a = float(hertz_line_contact(info["q"], R, e_star)[0])
    d0 = a / 5
    right, w = [d0 / 2], d0
    while right[-1] < 2 * a:
        w = min(1.3 * w, s / 2)
        right.append(right[-1] + w)
    edges = np.r_[-np.array(right[::-1]), right]
    xc, dx = 0.5 * (edges[1:] + edges[:-1]), np.diff(edges)
    nz = round(L / s)
    zc = -L / 2 + s * (np.arange(nz) + 0.5)
    Z, X = np.meshgrid(zc, xc, indexing="ij")
    DX = np.broadcast_to(dx, Z.shape)
    sec = np.broadcast_to(np.arange(nz)[:, None], Z.shape).ravel()
    X, Z, DX = X.ravel(), Z.ravel(), DX.ravel()
    n = len(X)

    def grid(name, x, z, wx, st):
        m = len(x)
        t = np.zeros((m, 2, 3))
        t[:, 0, 2] = 1.0  # along the line (z) first, as the plane's u
        t[:, 1, 0] = 1.0
        y_r = R - np.sqrt(R**2 - x**2)
        return ContactGrid(
            name,
            np.c_[x, np.zeros(m), z],
            np.c_[x, y_r, z],
            np.tile([0.0, 1.0, 0.0], (m, 1)),
            y_r,
            s * wx,
            tangents=t,
            half_sizes=np.c_[np.full(m, s / 2), wx / 2],
            stations=st,
            station_length=np.full(nz, s),
        )

    fine = grid("roller-block", X, Z, DX, sec)
    coarse = grid("roller-block#coarse", np.zeros(nz), zc, np.full(nz, s), np.arange(nz))
    link = ZoneLink(
        coarse,
        sec,
        np.c_[Z, X],
        np.c_[np.full(n, s / 2), DX / 2],
        np.c_[zc, np.zeros(nz)],
        np.full((nz, 2), s / 2),
        np.zeros(n, int),
        np.zeros(nz, int),
        np.full(nz, s),
        np.full(nz, s),
    )
    return ContactPair(fine, "block", "roller", link=link)


def _problem(comm, factor=100.0):
    base, info = roller_scene(comm, h_min=H, degree=1, q=Q)
    pair = _zone_pair(info)
    problem = ContactProblem(
        list(base.bodies.values()), [pair], base.rigid_unknowns, penalty_factor=factor
    )
    return problem, info


@pytest.fixture(scope="module")
def solved():
    problem, info = _problem(MPI.COMM_WORLD)
    return problem, info, {f: problem.solve(penalty_factor=f) for f in (10.0, 100.0, 1e3, 1e4)}


def _mid(problem, res, info):
    """Line load and largest pressure of the two middle sections."""
    g = problem.pairs[0].grid
    q = line_load(problem, res, 0)
    nz = len(q)
    mid = [nz // 2 - 1, nz // 2]
    p = res.forces / g.weights
    pm = max(p[g.stations == k].max() for k in mid)
    return float(np.mean(q[mid])), float(pm)


def test_zone_hertz_at_mid_length(solved):
    problem, info, res = solved
    r = res[100.0]
    # equilibrium: the grid carries the applied line load
    assert r.forces.sum() == pytest.approx(Q * info["L"], rel=1e-9)
    q_mid, p_mid = _mid(problem, r, info)
    _, p_h = hertz_line_contact(q_mid, info["R"], info["e_star"])
    # piecewise-constant pressure on cells of a_H / 5 at the centre: its largest cell
    # value is within 3 % of the Hertz peak (the half-space test gives 2 % at a_H / 10)
    assert p_mid == pytest.approx(p_h, rel=0.03)
    # the FE compliance only on the coarse points: one column per section
    assert problem.n_fe == round(info["L"] / info["spacing"])
    assert problem.timings["compliance_columns"] <= problem.n_fe < problem.n / 10
    # the FE loads are the fine forces (G^T F): contact and residual resultants agree
    for v in resultants(problem, r).values():
        assert np.allclose(v["contact_force"], v["residual_force"], rtol=1e-8, atol=1e-6 * Q)


def test_zone_penalty_no_longer_matters(solved):
    problem, _, res = solved
    # zone points carry no penalty (exact contact on C of eq. (5)): four decades of the
    # factor give the same solve (round-off of the dense solve only)
    assert np.all(problem.exact)
    ref = res[100.0]
    for r in res.values():
        assert np.allclose(r.forces, ref.forces, rtol=1e-9, atol=1e-9 * ref.forces.max())
        assert r.rigid["approach"] == pytest.approx(ref.rigid["approach"], rel=1e-9)
    # complementarity: active points closed, inactive points open (to round-off)
    g = ref.gaps
    assert np.all(np.abs(g[ref.active]) < 1e-9 * np.abs(ref.rigid["approach"]))
    assert np.all(g[~ref.active] >= 0) and np.all(ref.forces[ref.active] > 0)


def test_psd_projection_clips_only_the_negative_part():
    """Eq. (6): the symmetric part loses its negative eigenvalues, nothing else changes."""
    rng = np.random.default_rng(7)
    Q_, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    lam = np.array([-2.0, -0.5, 0.1, 1.0, 3.0, 8.0])
    skew = rng.normal(size=(6, 6))
    skew = 0.1 * (skew - skew.T)
    M = (Q_ * lam) @ Q_.T + skew
    P, ratio = psd_projection(M)
    assert ratio == pytest.approx(2.0 / 8.0, rel=1e-12)
    assert np.allclose(P - P.T, M - M.T, atol=1e-12)  # the skew part is kept
    w = np.linalg.eigvalsh(0.5 * (P + P.T))
    assert np.allclose(np.sort(w), np.sort(np.maximum(lam, 0.0)), atol=1e-12)
    # the removed part is exactly the negative spectrum (nearest PSD, Frobenius norm)
    assert np.linalg.norm(M - P) == pytest.approx(math.hypot(2.0, 0.5), rel=1e-12)
    # a matrix whose symmetric part is already PSD is returned unchanged
    same, r0 = psd_projection((Q_ * np.abs(lam)) @ Q_.T + skew)
    assert r0 == 0.0 and np.array_equal(same, (Q_ * np.abs(lam)) @ Q_.T + skew)


def test_zone_blocks_are_positive_definite(solved):
    """Hard case (1-GB, level 2, found by the convergence ladder): the FE body correction
    D_FE - H_d, matched one coarse width below the flank, had negative eigenvalues on the
    pinion-ring mesh (-1.5e-5 mm/N against +6e-5), C_AA was indefinite and the active set
    cycled with cell forces of -20 kN. Since eq. (6) every tooth pair's block of C has a
    symmetric part at least H_f's, positive definite, whatever the FE's error; the solve
    records how much it clipped."""
    problem, _, res = solved
    problem.ensure_columns(np.arange(problem.n))  # every column (coarse ones: all formed)
    for g in problem.near:
        f = g["fine"]
        blk = problem.C[np.ix_(f, f)]
        w = np.linalg.eigvalsh(0.5 * (blk + blk.T))
        w_hf = np.linalg.eigvalsh(g["h_f"])
        assert w.min() >= w_hf.min() * (1 - 1e-9)
    assert 0.0 <= res[100.0].timings["correction_clipped"] < 1.0


@pytest.mark.mpi
def test_zone_parallel_equals_serial():
    out = {}
    for name, comm in (("par", MPI.COMM_WORLD), ("ser", MPI.COMM_SELF)):
        problem, _ = _problem(comm)
        r = problem.solve()
        fc, _ = contact_resultant(problem, r, "roller")
        out[name] = (r.forces, r.rigid["approach"], fc)
    # MUMPS on another partition changes the round-off only (see tests/test_solver_mpi.py)
    assert np.allclose(out["par"][0], out["ser"][0], rtol=1e-6, atol=1e-6 * out["ser"][0].max())
    assert out["par"][1] == pytest.approx(out["ser"][1], rel=1e-6)
    assert math.isclose(out["par"][2][1], out["ser"][2][1], rel_tol=1e-6)


# ------------------------------------------------------------------ a gear mesh (level 0)
@pytest.fixture(scope="module")
def gear_zone():
    # 1-GA (aligned), one branch, level 0, roll 0: the benchmark's run (studies.benchmarks.contact)
    return run_case("1-GA", "zone", 0, 0.0, [100.0], MPI.COMM_WORLD, BodyStore())


def test_zone_gear_mesh_hertz_and_line_ends(gear_zone):
    r = gear_zone
    # the fine grid's pressure on the loaded interior stations is Hertz at their line load:
    # cells of ~a_H / 2 at the line put the cell peak within 10 % (roller: 1 % at a_H / 5)
    for mesh, p in r["pressure"].items():
        assert 0.95 < p["p_over_hertz_median"] < 1.10, mesh
    # no spike where a contact line leaves the path: the load fades out beyond it (the line
    # grid carries 1.5-2.3 x the interior line load at these ends)
    path_ends = [e["ratio_end_to_interior"] for e in r["line_ends"] if e["where"] == "path_end"]
    assert path_ends and max(path_ends) < 1.0
    # a finer grid without the cost: FE columns on the coarse points only
    assert r["compliance_columns"] <= r["fe_points"] < r["grid_points"] / 3
    assert r["sweep"]["100"]["resultant_mismatch_rel"] < 1e-9
