"""Boussinesq influence coefficients (solvers.halfspace) against closed forms: Love's
uniformly loaded rectangle and Hertz line contact solved on a half-space grid."""

import math

import numpy as np
import pytest

from gears.contact_stress import hertz_line_contact
from solvers.halfspace import influence_matrix, rectangle_integral


def _brute(x, y, xc, yc, a, b, n=400):
    """Midpoint rule of int int 1/r over the rectangle (a singular point is avoided by the
    midpoints; converges as 1/n)."""
    s = (np.arange(n) + 0.5) / n
    X, Y = np.meshgrid(xc - a + 2 * a * s, yc - b + 2 * b * s, indexing="ij")
    return float((1.0 / np.hypot(X - x, Y - y)).sum() * (4 * a * b) / n**2)


@pytest.mark.parametrize(
    "obs", [(0.0, 0.0), (0.3, -0.2), (1.0, 0.5), (2.5, 1.7), (-4.0, 0.1), (1.0, 0.0)]
)
def test_rectangle_integral_matches_quadrature(obs):
    # inside, on an edge, on a corner and outside the 2 x 1 rectangle
    got = rectangle_integral(obs[0], obs[1], 0.0, 0.0, 1.0, 0.5)
    ref = _brute(obs[0], obs[1], 0.0, 0.0, 1.0, 0.5, n=1200)
    # the midpoint rule's error near the 1/r singularity is O(h log h): 0.3 % at n = 1200
    assert got == pytest.approx(ref, rel=3e-3)


def test_square_centre_deflection_is_loves_closed_form():
    # Love: the centre of a square of side 2a under p sinks by (1 - nu^2)/(pi E) p 8 a ln(1 + 2^0.5)
    a, e_star = 0.7, 1.15e5
    H = influence_matrix(np.zeros((1, 2)), np.full((1, 2), a), e_star)
    p = 1.0 / (4 * a * a)
    assert H[0, 0] == pytest.approx(
        p * 8 * a * math.log(1 + math.sqrt(2)) / (math.pi * e_star), rel=1e-12
    )
    # far away a patch acts as a point force: w = F / (pi E* r)
    far = influence_matrix(
        np.zeros((1, 2)),
        np.full((1, 2), a),
        e_star,
        observers=(np.array([[50.0, 0.0]]), np.full((1, 2), a)),
    )
    assert far[0, 0] == pytest.approx(1 / (math.pi * e_star * 50.0), rel=1e-3)  # (a/r)^2 terms


def test_averaged_observation_is_reciprocal():
    # patch-averaged observation on patches of different size: H_ij A_i ... Betti for the
    # mean over patch i of w due to uniform load on j: A_j H_ij sum equals A_i H_ji (both
    # are int_i int_j 1/r / (pi E*) per unit pressure on each)
    c = np.array([[0.0, 0.0], [1.3, 0.4], [-0.5, 2.0]])
    h = np.array([[0.2, 0.5], [0.4, 0.1], [0.3, 0.3]])
    H = influence_matrix(c, h, 2e5, n_obs=8)
    area = 4 * h[:, 0] * h[:, 1]
    M = H * area[None, :]
    # 8-point Gauss on a non-smooth (near) integrand: 1e-3
    assert np.allclose(M * area[:, None], (M * area[:, None]).T, rtol=1e-3)


def _solve_contact(H, g0, total):
    """Frictionless contact on a half-space grid: F >= 0, g = g0 + H F - delta >= 0,
    complementary, sum F = total (active-set iteration)."""
    n = len(g0)
    act = g0 <= np.sort(g0)[max(1, n // 20)]
    for _ in range(100):
        idx = np.flatnonzero(act)
        m = len(idx)
        M = np.zeros((m + 1, m + 1))
        M[:m, :m] = H[np.ix_(idx, idx)]
        M[:m, m] = -1.0
        M[m, :m] = 1.0
        sol = np.linalg.solve(M, np.r_[-g0[idx], total])
        F = np.zeros(n)
        F[idx] = sol[:m]
        g = g0 + H @ F - sol[m]
        new = (g < 0) | (F > 0)
        new[idx[sol[:m] < 0]] = False
        if np.array_equal(new, act):
            return F, sol[m]
        act = new
    raise RuntimeError("active set did not converge")


def test_hertz_line_contact_on_the_half_space_grid():
    # a cylinder (relative radius R) on a plane: gap v^2 / (2 R) across, a long strip along u
    R, e_star, w = 10.0, 1.15e5, 400.0
    b_ref, _ = hertz_line_contact(w, R, e_star)
    du, dv, L, V = 1.0, 0.02, 30.0, 0.36
    u = -L / 2 + du * (np.arange(round(L / du)) + 0.5)
    v = -V + dv * (np.arange(round(2 * V / dv)) + 0.5)
    U, Vv = np.meshgrid(u, v, indexing="ij")
    c = np.c_[U.ravel(), Vv.ravel()]
    H = influence_matrix(c, np.tile([du / 2, dv / 2], (len(c), 1)), e_star)
    F, _ = _solve_contact(H, c[:, 1] ** 2 / (2 * R), w * L)
    F = F.reshape(len(u), len(v))
    mid = F[len(u) // 2]
    w_mid = mid.sum() / du
    b_mid, p_mid = hertz_line_contact(w_mid, R, e_star)
    # the ends of a finite line contact carry more (edge of a flat-ended punch): the middle
    # carries less than the mean, but not by more than 15 % at L / b = 140
    assert 0.85 < w_mid / w < 1.0
    p = mid / (du * dv)
    # piecewise-constant pressure on cells of dv = b / 10: its peak is within 2 % of Hertz
    assert p.max() == pytest.approx(p_mid, rel=0.02)
    # half-width from the second moment (a^2 / 4 for the Hertz ellipse): one cell of b / 10
    b_num = 2 * math.sqrt((mid * v**2).sum() / mid.sum())
    assert b_num == pytest.approx(b_mid, rel=0.05)
    assert b_ref > b_mid  # the mean line load is the larger


def test_subsurface_tends_to_the_surface_and_to_the_point_force():
    from solvers.halfspace import subsurface_matrix

    E, nu, a = 2.06e5, 0.3, 0.5
    c, h = np.zeros((1, 2)), np.full((1, 2), a)
    # far away: a point force, u_z = (1 + nu) / (2 pi E) [d^2/rho^3 + 2 (1 - nu)/rho]
    o, d = np.array([[30.0, 0.0]]), np.array([2.0])
    rho = math.hypot(30.0, 2.0)
    want = (1 + nu) / (2 * math.pi * E) * (4.0 / rho**3 + 2 * (1 - nu) / rho)
    assert subsurface_matrix(o, d, c, h, E, nu)[0, 0] == pytest.approx(want, rel=1e-3)
    # just below the surface, away from the patch: Love's surface value (one body, E* = E_plane)
    o = np.array([[3.0, 1.0]])
    surf = influence_matrix(c, h, E / (1 - nu**2), observers=(o, h))[0, 0]
    # depth 1e-4 mm changes u_z by O(d / r): 1e-4
    assert subsurface_matrix(o, np.array([1e-4]), c, h, E, nu)[0, 0] == pytest.approx(
        surf, rel=1e-4
    )
