"""Involute functions and small numeric helpers shared by the gear geometry modules.

inv(alpha) = tan(alpha) - alpha; an involute point at radius r of a base circle r_b has the
roll length sqrt(r^2 - r_b^2) and the polar angle inv(acos(r_b / r)) from its cusp.
"""

from __future__ import annotations

import math

import numpy as np


def involute(alpha):
    """inv(alpha) = tan(alpha) - alpha (vectorised, radians)."""
    a = np.asarray(alpha, dtype=float)
    return (np.tan(a) - a)[()]


def inverse_involute(value):
    """alpha with inv(alpha) = value (vectorised, odd in value, radians, to about 1e-15).

    Newton on f(alpha) = tan(alpha) - alpha - v, f' = tan(alpha)^2, started from
    min(cbrt(3 v), atan(v + pi/2)). Both bound the root from above (tan(a) - a >= a^3 / 3 and
    tan(a) = v + a < v + pi/2) and f is convex and increasing on [0, pi/2), so the iterates
    fall monotonically onto the root.
    """
    v = np.asarray(value, dtype=float)
    s = np.abs(v)
    a = np.minimum(np.cbrt(3.0 * s), np.arctan(s + 0.5 * np.pi))
    for _ in range(60):
        t = np.tan(a)
        f = t - a - s
        step = np.divide(f, t * t, out=np.zeros_like(f), where=t != 0.0)
        a = a - step
        if np.all(np.abs(step) <= 1e-16 * np.maximum(a, 1e-300)):
            break
    return np.copysign(a, v)[()]


def roll_length(r, r_b):
    """Roll length sqrt(r^2 - r_b^2) of the involute point at radius r (0 below r_b)."""
    return np.sqrt(np.maximum(np.square(r) - r_b * r_b, 0.0))


def involute_polar(r, r_b):
    """inv(alpha(r)) with cos(alpha(r)) = r_b / r (the involute's polar angle from its cusp)."""
    return involute(np.arccos(np.minimum(r_b / np.asarray(r, dtype=float), 1.0)))


def rotate2d(points: np.ndarray, angle) -> np.ndarray:
    """Rotate (..., 2) points by angle (broadcast) about the origin."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def bisect_last(inside, lo: float, hi: float) -> float:
    """Last point of [lo, hi] where ``inside`` holds, given inside(lo) and not inside(hi)."""
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if inside(mid) else (lo, mid)
    return lo


def tip_interference_margin(z1, r_a1, r_b1, z2, r_a2, r_b2, a, alpha_w) -> float:
    """Tip (trochoid) interference of an internal pair, pinion 1 in ring 2 (rad of ring turn;
    >= 0 is clear). After contact ends at the pinion tip, the pinion's tip corner must leave
    the ring's tooth space (cross the ring tip circle at Q) before the ring tooth tip gets
    there: theta1 z1 / z2 + inv(alpha_w) - inv(alpha_a2) - theta2 >= 0 with
    theta1 = acos((r_a2^2 - r_a1^2 - a^2) / (2 a r_a1)) + inv(alpha_a1) - inv(alpha_w),
    theta2 = acos((a^2 + r_a2^2 - r_a1^2) / (2 a r_a2)) (KHK gear handbook)."""
    c1 = (r_a2**2 - r_a1**2 - a**2) / (2.0 * a * r_a1)
    c2 = (a**2 + r_a2**2 - r_a1**2) / (2.0 * a * r_a2)
    if abs(c1) > 1.0 or abs(c2) > 1.0:  # the tip circles do not cross: the tips never meet
        return math.inf
    inv_w = involute(alpha_w)
    theta1 = math.acos(c1) + involute_polar(r_a1, r_b1) - inv_w
    return float(theta1 * z1 / z2 + inv_w - involute_polar(r_a2, r_b2) - math.acos(c2))
