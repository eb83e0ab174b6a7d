"""Transverse tooth profiles (involute flanks, trochoidal fillets, root and tip arcs) and
signed deviations of 3D points from the exact flank and fillet surfaces of a :class:`GearSpec`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gears.involute import roll_length, rotate2d
from gears.spec import GearSpec, GeometryError

# --------------------------------------------------------------------------------------
# tooth profile (transverse section at z = 0)
# --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ToothProfile:
    """Transverse section (z = 0) of tooth 0, symmetric about +x; arrays (N, 2) in mm, each
    ordered from the root towards the tip. The fillet's last point is the flank's first
    point (same values). ``fillet_*[0]`` is where the fillet leaves the root circle; the root
    arc from there to the mid-space (at +-pi/z) and the tip arc between the flank ends are
    circles about the origin."""

    teeth: int
    internal: bool
    root_radius: float
    tip_radius: float
    flank_pos: np.ndarray  # involute, counter-clockwise (+theta) side of the tooth
    flank_neg: np.ndarray  # involute, clockwise (-theta) side
    fillet_pos: np.ndarray  # generated fillet, root circle -> form circle, C1 with the flank
    fillet_neg: np.ndarray

    @property
    def pitch_angle(self) -> float:
        """2 pi / z, rad."""
        return 2.0 * math.pi / self.teeth

    def outline(self, n_arc: int = 8) -> np.ndarray:
        """Polyline (M, 2) of one pitch, counter-clockwise from the root circle at -pi/z
        (mid-space) to the root circle at +pi/z: root arc, fillet, flank, tip arc, flank,
        fillet, root arc; circular arcs with n_arc points each."""
        half = 0.5 * self.pitch_angle

        def arc(p0, p1, radius):
            a0, a1 = math.atan2(p0[1], p0[0]), math.atan2(p1[1], p1[0])
            a = np.linspace(a0, a1, max(n_arc, 2))[1:-1]
            return np.vstack([p0, radius * np.c_[np.cos(a), np.sin(a)], p1])

        def polar(a):
            return self.root_radius * np.array([math.cos(a), math.sin(a)])

        pieces = [
            arc(polar(-half), self.fillet_neg[0], self.root_radius),
            self.fillet_neg,
            self.flank_neg,
            arc(self.flank_neg[-1], self.flank_pos[-1], self.tip_radius),
            self.flank_pos[::-1],
            self.fillet_pos[::-1],
            arc(self.fillet_pos[0], polar(half), self.root_radius),
        ]
        pts = np.vstack(pieces)
        keep = np.r_[True, np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-12]
        return pts[keep]


def tooth_profile(gear: GearSpec, n_involute: int = 20, n_fillet: int = 12) -> ToothProfile:
    """Exact transverse profile of tooth 0: involute points evenly spaced in roll length
    (equal turns of the tangent) from the form to the tip circle, fillet points evenly spaced
    in the tool's rounding parameter."""
    if n_involute < 2 or n_fillet < 2:
        raise GeometryError(f"n_involute = {n_involute}, n_fillet = {n_fillet}: must be >= 2")
    r_b = gear.base_radius
    roll = np.linspace(
        roll_length(gear.form_radius, r_b), roll_length(gear.tip_radius, r_b), n_involute
    )
    r = np.hypot(r_b, roll)
    r[[0, -1]] = gear.form_radius, gear.tip_radius
    psi = gear.half_angle(r)
    mirror = np.array([1.0, -1.0])
    flank_pos = np.c_[r * np.cos(psi), r * np.sin(psi)]
    fillet_neg = gear.fillet_envelope(np.linspace(0.0, gear.fillet_end, n_fillet))
    fillet_neg[-1] = flank_pos[0] * mirror
    arrays = flank_pos, flank_pos * mirror, fillet_neg * mirror, fillet_neg
    for arr in arrays:
        arr.flags.writeable = False
    return ToothProfile(gear.teeth, gear.internal, gear.root_radius, gear.tip_radius, *arrays)


def gear_outline(profile: ToothProfile, n_arc: int = 8) -> np.ndarray:
    """Closed outline (M, 2) of the whole gear at z = 0: ``profile.outline`` turned by
    k 2 pi / z for every tooth k, counter-clockwise, the first point not repeated."""
    one = profile.outline(n_arc)[:-1]
    k = np.arange(profile.teeth)[:, None]
    return rotate2d(one[None, :, :], k * profile.pitch_angle).reshape(-1, 2)


# --------------------------------------------------------------------------------------
# deviations of 3D points from the exact flank and fillet surfaces
# --------------------------------------------------------------------------------------


def _side_sign(side: str) -> int:
    if side not in ("pos", "neg"):
        raise GeometryError(f"side = {side!r}: must be 'pos' or 'neg'")
    return 1 if side == "pos" else -1


def _untwist(gear: GearSpec, xyz, s: int) -> tuple[np.ndarray, np.ndarray]:
    """Radius and polar angle of points xyz (..., 3) screwed back to z = 0 along the helix,
    the angle taken from the centre line of the tooth whose side s (+1 pos, -1 neg) is
    nearest (window of one pitch centred on that side)."""
    p = np.asarray(xyz, dtype=float)
    theta = np.arctan2(p[..., 1], p[..., 0]) - gear.helix_rotation(p[..., 2])
    pitch = 2.0 * math.pi / gear.teeth
    return np.hypot(p[..., 0], p[..., 1]), theta - pitch * np.round(theta / pitch - 0.25 * s)


def involute_deviation(gear: GearSpec, xyz, side: str) -> np.ndarray:
    """Signed normal distance (mm, + outside the material) of points xyz (..., 3), gear frame
    with z = 0 at mid face width, from the exact involute helicoid of the nearest tooth's
    ``side`` ("pos" / "neg") flank:

        d = r_b cos(beta_b) (s theta - psi(rho)),  s = +1 pos / -1 neg,

    with (rho, theta) the point's radius and polar angle turned back to z = 0 by
    ``helix_rotation`` and taken from the tooth's centre line, psi the half tooth angle.

    Derivation. The flank is invariant under the screw motion that defines
    ``helix_rotation``, so the point may be moved along it to z = 0. Involutes of one base
    circle that differ by a turn delta are parallel curves a distance r_b delta apart along
    their common normals (tangents to the base circle); the involute through the point is
    turned by s theta - psi(rho) from the flank, so its transverse distance is exact. In 3D,
    an involute helicoid is swept by the straight generators of a plane tangent to the base
    cylinder, inclined at beta_b to the axis, and its normals lie in that plane. Helicoids of
    one base cylinder turned by delta cut the plane in parallel generators a distance r_b
    delta apart across the axis, hence r_b delta cos(beta_b) apart along their common normal:
    the normal distance is exact too (for rho >= r_b).
    """
    s = _side_sign(side)
    rho, theta = _untwist(gear, xyz, s)
    if np.any(rho < gear.base_radius * (1.0 - 1e-12)):
        raise GeometryError(
            f"{gear.name}: points at radius {float(np.min(rho)):.6g} mm: must be >= the base "
            f"radius {gear.base_radius:.6g} mm (the involute helicoid ends there)"
        )
    rho = np.maximum(rho, gear.base_radius)
    return gear.base_radius * math.cos(gear.base_helix_angle) * (s * theta - gear.half_angle(rho))


def involute_normal(gear: GearSpec, xyz, side: str) -> np.ndarray:
    """Unit normal (..., 3), out of the material, of the exact involute helicoid of the
    nearest tooth's ``side`` flank through the parallel surface at points xyz (gear frame):
    the gradient of :func:`involute_deviation`'s d = C (s theta_u - psi(rho)), C = r_b
    cos(beta_b), theta_u = atan2(y, x) - k z (k = d(helix_rotation)/dz), and with
    d psi / d rho = -sigma tan(alpha) / rho (d inv(alpha(rho)) / d rho = tan(alpha) / rho,
    cos(alpha) = r_b / rho):

        grad d = C ( s (-y, x) / rho^2 + sigma tan(alpha) (x, y) / rho^2,  -s k ).

    Its transverse part has length C / (rho cos(alpha)) = cos(beta_b), its axial one
    |k| r_b cos(beta_b) = sin(beta_b): unit. d is an exact distance (see
    :func:`involute_deviation`), so this is also the flank's normal at the point's foot on
    the flank (the nearest flank point), for rho >= r_b."""
    s = _side_sign(side)
    p = np.asarray(xyz, dtype=float)
    x, y = p[..., 0], p[..., 1]
    rho2 = x * x + y * y
    rb = gear.base_radius
    if np.any(rho2 < (rb * (1.0 - 1e-12)) ** 2):
        raise GeometryError(f"{gear.name}: points inside the base circle have no involute normal")
    tan_a = np.sqrt(np.maximum(rho2 - rb * rb, 0.0)) / rb
    c = rb * math.cos(gear.base_helix_angle)
    k = float(gear.helix_rotation(1.0)) - float(gear.helix_rotation(0.0))
    sig = gear.sigma * tan_a
    out = np.stack(
        [c * (-s * y + sig * x) / rho2, c * (s * x + sig * y) / rho2, np.full(x.shape, -c * s * k)],
        axis=-1,
    )
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def polyline_foot(curve: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Foot points of the points q (n, 2) on the polyline ``curve`` (m, 2): for each point
    the index j of the nearest segment and the parameter w in [0, 1] along it, the foot
    being curve[j] + w (curve[j + 1] - curve[j]). Segments of zero length are skipped;
    the points go in chunks of about 2e6 point-segment pairs."""
    curve = np.asarray(curve, float)
    seg = np.diff(curve, axis=0)
    seg_len2 = np.einsum("ij,ij->i", seg, seg)
    index = np.flatnonzero(seg_len2 > 0.0)
    a, seg, seg_len2 = curve[index], seg[index], seg_len2[index]
    q = np.asarray(q, float).reshape(-1, 2)
    j, w = np.empty(len(q), np.int64), np.empty(len(q))
    chunk = max(1, 2_000_000 // len(seg))
    for i in range(0, len(q), chunk):
        d = q[i : i + chunk, None, :] - a
        dot = np.einsum("pij,ij->pi", d, seg)
        t = np.clip(dot / seg_len2, 0.0, 1.0)
        dist2 = np.einsum("pij,pij->pi", d, d) - t * (2.0 * dot - t * seg_len2)
        k = np.argmin(dist2, axis=1)
        j[i : i + chunk], w[i : i + chunk] = index[k], t[np.arange(len(k)), k]
    return j, w


def fillet_deviation(gear: GearSpec, xyz, side: str, n_samples: int = 2000) -> np.ndarray:
    """Signed normal distance (mm, + outside the material) of points xyz (..., 3) from the
    root surface on the ``side`` of the nearest tooth: its generated fillet and the half root
    land from the fillet to the mid-space.

    The points are screwed back to z = 0 (as in ``involute_deviation``) and measured against
    the exact fillet trochoid sampled at ``n_samples`` points (chord error about
    L^2 / (8 R n^2), below 1e-7 mm for real fillets). The transverse distance d_t becomes
    the normal distance d_t / sqrt(1 + (k c x n_t)^2), k = d(helix_rotation)/dz, c the foot
    point and n_t the transverse unit normal, because the surface normal of a screw surface
    is (n_t, -k c x n_t) normalised; exact to first order in d_t.
    """
    s = _side_sign(side)
    rho, theta = _untwist(gear, xyz, s)
    angle = -s * theta  # the pos side is the mirror image of the neg side
    q = np.stack([rho * np.cos(angle), rho * np.sin(angle)], axis=-1).reshape(-1, 2)
    fillet = gear.fillet_envelope(np.linspace(0.0, gear.fillet_end, n_samples))
    land = np.linspace(-math.pi / gear.teeth, math.atan2(fillet[0, 1], fillet[0, 0]), 64)[:-1]
    curve = np.vstack([gear.root_radius * np.c_[np.cos(land), np.sin(land)], fillet])
    j, w = polyline_foot(curve, q)
    seg = np.diff(curve, axis=0)[j]
    foot = curve[j] + w[:, None] * seg
    tangent = seg / np.linalg.norm(seg, axis=1)[:, None]
    # Outward normal: the body lies left of the root -> form direction on the neg side
    # of an external gear, right of it on an internal gear.
    n_t = gear.sigma * np.c_[tangent[:, 1], -tangent[:, 0]]
    d_t = np.einsum("ij,ij->i", q - foot, n_t)
    c_cross_n = foot[:, 0] * n_t[:, 1] - foot[:, 1] * n_t[:, 0]
    k = float(gear.helix_rotation(1.0))
    out = d_t / np.sqrt(1.0 + (k * c_cross_n) ** 2)
    return out.reshape(rho.shape)
