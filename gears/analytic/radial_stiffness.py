"""Radial mesh stiffness under load and the floating-sun stability model (pust2016).

Radial (centre-distance) stiffness of a loaded mesh at constant transmitted torque: the
normal force F in the transverse plane of action stays constant, the operating pressure
angle follows cos(alpha) = (rb1 +- rb2) / a, and so does the separating force F sin(alpha)::

    external: k_r,ext = -F cos^2(alpha) / ((r1 + r2) sin(alpha))
                      = -F cos^3(alpha) / ((rb1 + rb2) sin(alpha))           (negative)
    internal: k_r,int = +F cos^2(alpha) / ((r_ring - r_planet) sin(alpha))
                      = +F cos^3(alpha) / ((rb_ring - rb_planet) sin(alpha))  (positive)

with r the operating pitch radii and rb = r cos(alpha) the base radii (the two forms are the
same number). For a helical mesh F is the transverse normal force Ft / cos(alpha_wt), so
k_r = -+Ft / (a tan(alpha_wt)).

Floating sun with one planet branch (2 DOF: sun y3, planet y2), k_r = |k_r,ext|::

    m3 y3'' - k_r (y3 - y2) + k3 y3 = 0
    m2 y2'' + k_r y3 + k_c y2 = 0
    m2 m3 W^4 - (m3 k_c + m2 (k3 - k_r)) W^2 + k_c k3 - k_r (k_c + k_r) = 0

The lower root W1^2 changes sign at k3 = k_r (k_c + k_r) / k_c (= k_r for k_c >> k_r).

Units: SI (N, m, kg) for the pust2016 example; any consistent set works.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def k_r_external(force: float, alpha: float, r1: float, r2: float) -> float:
    """k_r,ext = -F cos^2(a) / ((r1 + r2) sin(a)); pitch radii r1, r2, alpha in rad."""
    return -force * math.cos(alpha) ** 2 / ((r1 + r2) * math.sin(alpha))


def k_r_internal(force: float, alpha: float, r_ring: float, r_planet: float) -> float:
    """k_r,int = +F cos^2(a) / ((r_ring - r_planet) sin(a)); pitch radii, alpha in rad."""
    return force * math.cos(alpha) ** 2 / ((r_ring - r_planet) * math.sin(alpha))


def k_r_external_base(force: float, alpha: float, rb1: float, rb2: float) -> float:
    """Base-radius form: k_r,ext = -F cos^3(a) / ((rb1 + rb2) sin(a))."""
    return -force * math.cos(alpha) ** 3 / ((rb1 + rb2) * math.sin(alpha))


def k_r_internal_base(force: float, alpha: float, rb_ring: float, rb_planet: float) -> float:
    """Base-radius form: k_r,int = +F cos^3(a) / ((rb_ring - rb_planet) sin(a))."""
    return force * math.cos(alpha) ** 3 / ((rb_ring - rb_planet) * math.sin(alpha))


def separating_force(force: float, base_radius_sum: float, centre_distance: float) -> float:
    """Radial mesh force F sin(alpha(a)) at constant transmitted torque, with
    cos(alpha) = rb_sum / a (rb_sum = rb1 + rb2 external, rb_ring - rb_planet internal).

    Its derivative in the centre distance a is F cos^2(alpha) / (a sin(alpha)) = |k_r| for
    both meshes. External mesh: the force pushing the wheels apart grows as they separate
    (a negative, destabilising spring). Internal mesh: the force pushing the planet back
    towards the ring axis grows as the planet moves out (a positive, restoring spring).
    """
    return force * math.sqrt(1.0 - (base_radius_sum / centre_distance) ** 2)


def k_r_helical(
    tangential_force: float, alpha_wt: float, centre_distance: float, internal: bool = False
) -> float:
    """Radial stiffness of a helical mesh in its transverse plane: -+Ft / (a tan(alpha_wt)).

    ``tangential_force`` at the operating pitch circle, ``alpha_wt`` the operating
    transverse pressure angle (rad); negative for an external mesh, positive internal.
    Units follow the inputs (N and mm give N/mm).
    """
    k = tangential_force / (centre_distance * math.tan(alpha_wt))
    return k if internal else -k


def floating_sun_matrices(
    m2: float, m3: float, k_c: float, k3: float, k_r: float
) -> tuple[np.ndarray, np.ndarray]:
    """(K, M) of the 2-DOF model, unknowns ordered (y3 sun, y2 planet)."""
    stiffness = np.array([[k3 - k_r, k_r], [k_r, k_c]], dtype=float)
    mass = np.diag([m3, m2]).astype(float)
    return stiffness, mass


def floating_sun_eigenvalues(
    m2: float, m3: float, k_c: float, k3: float, k_r: float
) -> tuple[float, float]:
    """(W1^2, W2^2), ascending, roots of the pust2016 determinant equation (rad/s)^2.

    Uses the cancellation-free quadratic formula (W2^2 ~ 2e6 and W1^2 ~ 1e2 differ by
    four orders of magnitude in the pust2016 example).
    """
    a = m2 * m3
    b = -(m3 * k_c + m2 * (k3 - k_r))
    c = k_c * k3 - k_r * (k_c + k_r)
    q = -0.5 * (b + math.copysign(math.sqrt(b * b - 4.0 * a * c), b))
    r1, r2 = q / a, c / q
    return (min(r1, r2), max(r1, r2))


def stability_threshold(k_c: float, k_r: float) -> float:
    """Sun support stiffness k3 at which W1^2 = 0: k_r (k_c + k_r) / k_c."""
    return k_r * (k_c + k_r) / k_c


def mass_m3_from_eigenvalue(w_sq: float, m2: float, k_c: float, k3: float, k_r: float) -> float:
    """The sun mass m3 for which ``w_sq`` is a root of the determinant (it is linear in m3)::

    m3 = (W^2 m2 (k3 - k_r) - k_c k3 + k_r (k_c + k_r)) / (W^4 m2 - W^2 k_c)
    """
    c = k_c * k3 - k_r * (k_c + k_r)
    return (w_sq * m2 * (k3 - k_r) - c) / (w_sq**2 * m2 - w_sq * k_c)


def k_r_from_eigenvalue(w_sq: float, m2: float, m3: float, k_c: float, k3: float) -> float:
    """The radial stiffness k_r (the root nearest zero) for which ``w_sq`` is a root of the
    determinant; it is quadratic in k_r::

    k_r^2 + k_r (k_c - W^2 m2) - (m2 m3 W^4 - W^2 (m3 k_c + m2 k3) + k_c k3) = 0
    """
    b = k_c - w_sq * m2
    c = -(m2 * m3 * w_sq**2 - w_sq * (m3 * k_c + m2 * k3) + k_c * k3)
    q = -0.5 * (b + math.copysign(math.sqrt(b * b - 4.0 * c), b))
    roots = (q, c / q)
    return min(roots, key=abs)


# pust2016 stated parameters of the 2-DOF example (SI).
PUST_M2 = 50.0  # kg, planet
PUST_M3 = 100.0  # kg, sun
PUST_KC = 1.0e8  # N/m, planet pin
PUST_KR = 13_000.0  # N/m, |k_r,ext|
PUST_K3 = (0.0, 5_000.0, 10_000.0, 15_000.0, 20_000.0)  # N/m, sun support
# pust2016 stated inputs of the radial stiffness example (SI).
PUST_EXAMPLE = {"force": 1000.0, "alpha_deg": 25.0, "r_sun": 0.05, "r_planet": 0.1}


def table1(
    m2: float = PUST_M2,
    m3: float = PUST_M3,
    k_c: float = PUST_KC,
    k_r: float = PUST_KR,
    k3_values: Sequence[float] = PUST_K3,
) -> list[dict[str, float]]:
    """pust2016 Table 1 rows {k3, omega1_sq, omega2_sq} (SI) from the stated equations."""
    rows = []
    for k3 in k3_values:
        w1, w2 = floating_sun_eigenvalues(m2, m3, k_c, k3, k_r)
        rows.append({"k3": k3, "omega1_sq": w1, "omega2_sq": w2})
    return rows
