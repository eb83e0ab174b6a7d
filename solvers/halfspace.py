"""Boussinesq half-space influence coefficients of uniformly loaded rectangles (Love 1929).

A normal pressure p(x', y') on the surface of an elastic half-space moves the surface point
(x, y) normally by (Johnson, Contact Mechanics, eq. 3.20)

    w(x, y) = (1 - nu^2) / (pi E) int int p(x', y') / r dx' dy',   r = |(x - x', y - y')|,

and two bodies in contact approach each other by the sum of their two w, i.e. by the same
integral with (1 - nu^2)/E replaced by 1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b. For a
uniform pressure on the rectangle [x1, x2] x [y1, y2] the integral is Love's closed form,

    int_{x1}^{x2} int_{y1}^{y2} dx' dy' / r = G(x2 - x, y2 - y) - G(x1 - x, y2 - y)
                                          - G(x2 - x, y1 - y) + G(x1 - x, y1 - y),   (1)

    G(A, B) = sgn(A) sgn(B) [ |A| asinh(|B| / |A|) + |B| asinh(|A| / |B|) ],

G(A, B) being the integral of 1/r over [0, A] x [0, B] (odd in each argument; 0 when A or B
is 0). The influence coefficient of patch j (centre (x_j, y_j), half sizes (a_j, b_j),
unit force, i.e. pressure 1 / (4 a_j b_j)) at observation point i is

    H_ij = 1 / (pi E* 4 a_j b_j) * (1)(x_i, y_i; rectangle j)      (mm/N).             (2)

Observation at a point (collocation at the patch centre) or as the mean over a Gauss rule on
the observing patch (``n_obs`` points per direction): the latter matches the patch-averaged
gap rows of the FE gap operator (:mod:`solvers.contact_grid`), so the half-space part of
an FE compliance column can be subtracted consistently (:mod:`solvers.contact`).

Everything here is small dense numpy, computed identically on every MPI rank.
"""

from __future__ import annotations

import math

import numpy as np


def _g(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """G(A, B) of eq. (1): int_0^A int_0^B 1/r, odd in A and in B, 0 on the axes."""
    aa, bb = np.abs(a), np.abs(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(aa > 0, aa * np.arcsinh(bb / np.where(aa > 0, aa, 1.0)), 0.0)
        t2 = np.where(bb > 0, bb * np.arcsinh(aa / np.where(bb > 0, bb, 1.0)), 0.0)
    return np.sign(a) * np.sign(b) * (t1 + t2)


def rectangle_integral(x, y, xc, yc, a, b) -> np.ndarray:
    """int int 1/r over the rectangle |x' - xc| <= a, |y' - yc| <= b seen from (x, y),
    eq. (1) (mm); broadcasts."""
    dx1, dx2 = xc - a - x, xc + a - x
    dy1, dy2 = yc - b - y, yc + b - y
    return _g(dx2, dy2) - _g(dx1, dy2) - _g(dx2, dy1) + _g(dx1, dy1)


def influence_matrix(
    centres: np.ndarray,
    half_sizes: np.ndarray,
    e_star: float,
    n_obs: int = 1,
    observers: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """H_ij of eq. (2): the approach (mm) at patch i per unit force (N) on patch j.

    Args:
        centres: (n, 2) patch centres in the plane of the surface (mm).
        half_sizes: (n, 2) half extents (a, b) along the two plane axes (mm), > 0.
        e_star: contact modulus of the two bodies (MPa), 1/E* = sum (1 - nu^2)/E.
        n_obs: Gauss points per direction on the observing patch (1: its centre).
        observers: optional (centres, half_sizes) of the observing patches (default: the
            loaded ones), for a rectangular block H between two patch sets.
    """
    c = np.asarray(centres, float)
    h = np.asarray(half_sizes, float)
    if c.ndim != 2 or c.shape[1] != 2 or h.shape != c.shape or np.any(h <= 0):
        raise ValueError("influence_matrix: centres and half_sizes must be (n, 2), sizes > 0")
    if not (e_star > 0 and math.isfinite(e_star)):
        raise ValueError(f"influence_matrix: e_star = {e_star!r} must be finite and > 0")
    co, ho = (c, h) if observers is None else (np.asarray(o, float) for o in observers)
    s, w = np.polynomial.legendre.leggauss(n_obs)
    w = w / 2.0
    out = np.zeros((len(co), len(c)))
    for si, wi in zip(s, w, strict=True):
        for sj, wj in zip(s, w, strict=True):
            x = co[:, 0] + (si * ho[:, 0] if n_obs > 1 else 0.0)
            y = co[:, 1] + (sj * ho[:, 1] if n_obs > 1 else 0.0)
            cx, cy, a, b = c[None, :, 0], c[None, :, 1], h[None, :, 0], h[None, :, 1]
            out += wi * wj * rectangle_integral(x[:, None], y[:, None], cx, cy, a, b)
    return out / (math.pi * e_star * 4.0 * h[None, :, 0] * h[None, :, 1])


def subsurface_matrix(
    observers: np.ndarray,
    depth: np.ndarray,
    centres: np.ndarray,
    half_sizes: np.ndarray,
    youngs_modulus: float,
    poisson_ratio: float,
    n_gauss: int = 8,
) -> np.ndarray:
    """Normal displacement (mm) at depth d_i below the surface point i per unit force (N)
    spread uniformly over patch j, one half-space (E, nu): Boussinesq (Johnson eq. 3.21),

        u_z = F / (4 pi G) [ d^2 / rho^3 + 2 (1 - nu) / rho ],  rho^2 = r^2 + d^2,     (3)

    G = E / (2 (1 + nu)), integrated over the patch by an ``n_gauss`` x ``n_gauss`` Gauss
    rule (smooth for d > 0; d = 0 gives Love's surface value (1 - nu^2) / (pi E) / r).

    Args:
        observers: (m, 2) surface positions above the observation points (mm).
        depth: (m,) depths d_i > 0 below the surface (mm).
        centres, half_sizes: (n, 2) loaded patches as in :func:`influence_matrix`.
    """
    o = np.asarray(observers, float)
    d = np.asarray(depth, float)
    c = np.asarray(centres, float)
    h = np.asarray(half_sizes, float)
    if np.any(d <= 0) or np.any(h <= 0):
        raise ValueError("subsurface_matrix: depths and patch sizes must be > 0")
    g_mod = youngs_modulus / (2.0 * (1.0 + poisson_ratio))
    s, w = np.polynomial.legendre.leggauss(n_gauss)
    w = w / 2.0
    out = np.zeros((len(o), len(c)))
    for si, wi in zip(s, w, strict=True):
        for sj, wj in zip(s, w, strict=True):
            dx = c[None, :, 0] + si * h[None, :, 0] - o[:, None, 0]
            dy = c[None, :, 1] + sj * h[None, :, 1] - o[:, None, 1]
            rho = np.sqrt(dx * dx + dy * dy + d[:, None] ** 2)
            out += wi * wj * (d[:, None] ** 2 / rho**3 + 2.0 * (1.0 - poisson_ratio) / rho)
    return out / (4.0 * math.pi * g_mod)
