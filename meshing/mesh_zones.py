"""Gear meshes on exact geometry: involute flank parameters, the placement that puts two
gears in mesh, the mesh zone (line of action, contact window, drive and coast flanks) and the
theoretical contact lines.

Frames and senses. Scene frame: the sun (and ring) axis is the z axis, z = 0 at mid face
width of every body. A body is turned about its own axis by its placement angle and moved
to its centre (:class:`meshing.assemble.Placement`). The mesh position is the sun's roll
angle ``roll`` (rad, its placement angle). Under load the sun turns counter-clockwise
(omega = +1) with the carrier held: in a single-pinion set the pinions and the ring turn
clockwise; in a double-pinion set the sun pinion (SP) clockwise, the ring pinion (RP) and the
ring counter-clockwise.

Drive and coast flanks. The drive flank of a driving gear is the flank that faces its
direction of rotation: ``pos`` for omega = +1, ``neg`` for omega = -1 (external gears). On
an involute mesh the driven gear's drive flank is its flank with the same sense of
unwinding as the driver's (for external and internal meshes alike), so the sun's ``pos``
flank drives the pinion's ``pos`` flank, and the pinion's ``neg`` flank the ring's ``neg``
flank. Each :class:`MeshZone` states these sides; the other flanks are the coast flanks.

Phase. Derived from the involute geometry, not by search: with the line of action tangent
to both base circles at angle tau (external: tau = gamma + s alpha_w from the driver centre
towards the driven one; internal: from the ring centre towards the pinion), a driver flank
whose base-circle start angle is theta0 touches the line of action at roll t = s (tau -
theta0), the point T + r_b t d. The driven flank through that point with normal -d (the same
line) has roll t' from its own tangency point (external: r_b1 t + r_b2 t' = a sin alpha_w;
internal: r_b2 t' = r_b1 t + a sin alpha_w), which fixes its theta0 and hence its placement
angle. With the base helix angles equal the contact stays on the line of action across the
face width, so the drive flanks touch along the theoretical contact lines; the coast flanks
are then apart by the pair's normal backlash (the tooth thickness allowances of the gear set,
:func:`gears.pair.assign_chain_backlash`; zero for zero allowances).

Coast flanks. :func:`coast_zone` is the same mesh seen from its coast flanks: the sides
swapped, the line of action mirrored about the centre line (tau_c = gamma + s_c alpha_w with
the coast flanks' unwinding sense s_c = -s), its direction -s_c perp(tau_c) (out of the
driver's coast flank, towards the driven gear), and the contact lines there. Everything that
works on the drive flanks of a zone (contact lines, contact grids) works on this view
unchanged; the driven coast flank is then the normal backlash away from the lines.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from gears.pair import GearPair
from gears.profile import involute_deviation, tooth_profile
from meshing.assemble import Placement
from meshing.gear_body import GearBody
from meshing.sizing import MeshingError


def unit(a):
    return np.array([math.cos(a), math.sin(a)])


def unit_perp(a):
    return np.array([-math.sin(a), math.cos(a)])


@dataclass(frozen=True)
class Flank:
    """Involute of tooth 0's ``side`` at z = 0 in the gear frame: polar angle
    theta0 + s inv(alpha(r)); roll t = tan(alpha) runs from ``t_form`` to ``t_tip``."""

    side: str
    s: int  # +1: polar angle grows with radius, -1: falls
    theta0: float
    rb: float
    t_form: float
    t_tip: float


def flank_of(gear, side: str) -> Flank:
    """The involute parameters of ``side`` of ``gear`` from its exact profile points."""
    prof = tooth_profile(gear, 20, 4)
    pts = np.asarray(prof.flank_pos if side == "pos" else prof.flank_neg)
    r = np.hypot(pts[:, 0], pts[:, 1])
    th = np.arctan2(pts[:, 1], pts[:, 0])
    rb = gear.base_radius
    alpha = np.arccos(np.minimum(rb / r, 1.0))
    inv = np.tan(alpha) - alpha
    s = 1 if (th[-1] - th[0]) * (r[-1] - r[0]) > 0 else -1
    theta0 = th - s * inv
    if np.ptp(theta0) > 1e-9:
        raise RuntimeError(f"{gear.name}.{side}: flank is not an involute of the base circle")
    t = np.tan(alpha)
    return Flank(side, s, float(theta0.mean()), rb, float(t[0]), float(t[-1]))


def flank_sides(gear) -> dict[int, str]:
    """Map unwinding sense s -> side name for ``gear``."""
    return {flank_of(gear, side).s: side for side in ("pos", "neg")}


@dataclass(frozen=True)
class PlacedGear:
    body: GearBody
    placement: Placement
    omega: int  # sense of rotation under load (+1 counter-clockwise)
    active_teeth: tuple[int, ...] = ()  # refined teeth (flanks and fillets fine)
    contact_teeth: tuple[int, ...] = ()  # teeth in contact at this mesh position
    set_gear: str = ""  # the gear of the gear set this body is ("pinion" for "pinion2")

    @property
    def name(self) -> str:
        return self.body.body

    @property
    def gear_name(self) -> str:
        """Name of the gear in the gear set (the body name unless the set has several)."""
        return self.set_gear or self.name

    @property
    def gear(self):
        return self.body.gear


@dataclass(frozen=True)
class MeshZone:
    """One gear mesh at the scene's mesh position (scene frame, transverse plane z = 0)."""

    driver: str
    driven: str
    internal: bool
    driver_side: str  # drive flanks
    driven_side: str
    centre_distance: float
    pressure_angle: float  # operating transverse, rad
    gamma: float  # polar angle of the centre line (driver -> driven; ring -> pinion)
    tau: float  # polar angle of the base-circle tangency, about the driver (ext) / ring (int)
    direction: tuple[float, float]  # unit direction of the line of action (driver push)
    tangency: tuple[float, float]  # driver's base-circle tangency point T (scene frame)
    window: tuple[float, float]  # driver roll length range in contact (from T), mm
    backlash: float  # circumferential backlash of the pair, mm (coast side)
    contact_lines: tuple = ()  # ((driver tooth, driven tooth, points (N, 3)), ...)
    flanks: str = "drive"  # which flanks the sides, tau, direction, lines are: drive / coast

    @property
    def coast_sides(self) -> tuple[str, str]:
        """The other flanks of this view: the coast flanks of a drive view, and vice versa."""
        other = {"pos": "neg", "neg": "pos"}
        return other[self.driver_side], other[self.driven_side]

    @property
    def name(self) -> str:
        """``driver-driven``, ``driver-driven/coast`` for the coast view."""
        base = f"{self.driver}-{self.driven}"
        return base if self.flanks == "drive" else f"{base}/{self.flanks}"


# --------------------------------------------------------------------------------------
# mesh geometry
# --------------------------------------------------------------------------------------


def _roll_at(r: float, rb: float) -> float:
    return math.sqrt(max(r * r - rb * rb, 0.0))


def solve_mesh(
    drv_gear, drv_pl: Placement, drv_omega: int, dvn_gear, dvn_centre, check_pair=True
) -> tuple[float, MeshZone]:
    """Placement angle of the driven gear that puts its drive flank on the driver's at the
    line of action, and the mesh zone. The driver is external; the driven gear external or
    internal (ring, coaxial with the scene axis)."""

    internal = bool(dvn_gear.internal)
    ca = np.asarray(drv_pl.centre, float)
    cb = np.asarray(dvn_centre, float)
    a = float(np.linalg.norm(cb - ca))
    pair = GearPair(drv_gear, dvn_gear, a)
    backlash = pair.backlash
    if check_pair and backlash < -1e-9:
        raise MeshingError(
            f"{drv_gear.name}/{dvn_gear.name}: centre distance {a:.4f} mm gives backlash "
            f"{backlash * 1e3:.2f} um < 0: the teeth interpenetrate (the shifts and tooth "
            f"thickness allowances of the gears need a {'smaller' if internal else 'larger'} "
            "centre distance)"
        )
    s = -drv_omega  # drive flank of an external driver faces its rotation
    fa = flank_of(drv_gear, flank_sides(drv_gear)[s])
    fb = flank_of(dvn_gear, flank_sides(dvn_gear)[s])
    rba, rbb = fa.rb, fb.rb
    if internal:
        gamma = math.atan2(*(ca - cb)[::-1])
        alpha_w = math.acos((rbb - rba) / a)
    else:
        gamma = math.atan2(*(cb - ca)[::-1])
        alpha_w = math.acos((rba + rbb) / a)
    if not math.isclose(alpha_w, pair.operating_pressure_angle, abs_tol=1e-9):
        raise RuntimeError("operating pressure angle disagrees with GearPair")
    tau = gamma + s * alpha_w
    d = -s * unit_perp(tau)
    g_len = a * math.sin(alpha_w)
    ta = s * (tau - (fa.theta0 + drv_pl.angle))  # driver tooth 0 at z = 0
    if internal:
        tb = (rba * ta + g_len) / rbb
        tau_b = tau
    else:
        tb = (g_len - rba * ta) / rbb
        tau_b = tau + math.pi
    theta0_b = tau_b - s * tb
    pitch_b = 2 * math.pi / dvn_gear.teeth
    angle_b = (theta0_b - fb.theta0) % pitch_b
    # Contact window on the driver's roll length (from its tangency point T).
    la_a = _roll_at(drv_gear.tip_radius, rba)
    la_b = _roll_at(dvn_gear.tip_radius, rbb)
    lo = (la_b - g_len) if internal else (g_len - la_b)
    lo = max(lo, _roll_at(drv_gear.form_radius, rba))
    zone = MeshZone(
        driver=drv_gear.name,
        driven=dvn_gear.name,
        internal=internal,
        driver_side=fa.side,
        driven_side=fb.side,
        centre_distance=a,
        pressure_angle=alpha_w,
        gamma=gamma,
        tau=tau,
        direction=(float(d[0]), float(d[1])),
        tangency=tuple(float(v) for v in ca + rba * unit(tau)),
        window=(float(lo), float(la_a)),
        backlash=float(backlash),
    )
    return float(angle_b), zone


def coast_zone(zone: MeshZone, drv: PlacedGear, dvn: PlacedGear) -> MeshZone:
    """The mesh zone seen from its coast flanks (module docstring), with its contact lines;
    ``zone`` must be a drive view."""
    if zone.flanks != "drive":
        raise ValueError(f"{zone.name}: coast_zone needs the drive view of the zone")
    side_a, side_b = zone.coast_sides
    fa = flank_of(drv.gear, side_a)
    tau = zone.gamma + fa.s * zone.pressure_angle
    d = -fa.s * unit_perp(tau)
    ca = np.asarray(drv.placement.centre, float)
    view = MeshZone(
        driver=zone.driver,
        driven=zone.driven,
        internal=zone.internal,
        driver_side=side_a,
        driven_side=side_b,
        centre_distance=zone.centre_distance,
        pressure_angle=zone.pressure_angle,
        gamma=zone.gamma,
        tau=tau,
        direction=(float(d[0]), float(d[1])),
        tangency=tuple(float(v) for v in ca + fa.rb * unit(tau)),
        window=zone.window,  # the zone is symmetric about the centre line
        backlash=zone.backlash,
        flanks="coast",
    )
    return replace(view, contact_lines=contact_lines(view, drv, dvn))


def contact_lines(zone: MeshZone, drv: PlacedGear, dvn: PlacedGear, n=41, coast=False):
    """Theoretical contact lines of the zone: per driver tooth in contact, the points
    (scene frame) of its flank (``zone.driver_side``) on the zone's line of action within
    the contact window and the common face width, with the index of the driven tooth they
    touch.

    ``coast=True``: the same for the coast flanks of a drive view (the lines of
    ``coast_zone``); the driven coast flank is then the normal backlash away from the points.
    """
    if coast:
        return coast_zone(zone, drv, dvn).contact_lines
    ga, gb = drv.gear, dvn.gear
    side_b = zone.driven_side
    fa = flank_of(ga, zone.driver_side)
    s = fa.s
    tau = zone.tau
    ca = np.asarray(drv.placement.centre, float)
    T0 = ca + fa.rb * unit(tau)
    d = -s * unit_perp(tau)
    b = min(ga.face_width, gb.face_width)
    zs = np.linspace(-0.5 * b, 0.5 * b, n)
    pitch_a = 2 * math.pi / ga.teeth
    t_lo, t_hi = (w / fa.rb for w in zone.window)
    sb = 1 if side_b == "pos" else -1
    pitch_b = 2 * math.pi / gb.teeth
    out = []
    for k in range(ga.teeth):
        theta0 = fa.theta0 + k * pitch_a + drv.placement.angle + ga.helix_rotation(zs)
        t = s * (((tau - theta0) + math.pi) % (2 * math.pi) - math.pi)
        inside = (t >= t_lo - 1e-12) & (t <= t_hi + 1e-12)
        if not inside.any():
            continue
        p2 = T0[None, :] + (fa.rb * t[inside])[:, None] * d[None, :]
        pts = np.c_[p2, zs[inside]]
        local = dvn.placement.inverse(pts)
        th = np.arctan2(local[:, 1], local[:, 0]) - gb.helix_rotation(local[:, 2])
        # circular mean: the angles of one line can straddle the +-pi cut of arctan2, where
        # their median (used before) named a tooth on the far side of the gear
        th_c = float(np.angle(np.mean(np.exp(1j * th))))
        j = int(np.round(th_c / pitch_b - 0.25 * sb)) % gb.teeth
        out.append((k, j, pts))
    return tuple(out)


def normal_backlash(zone: MeshZone, drv: PlacedGear) -> float:
    """Backlash of the zone normal to the flanks: j_wt cos(alpha_wt) cos(beta_b) (mm)."""
    return zone.backlash * math.cos(zone.pressure_angle) * math.cos(drv.gear.base_helix_angle)


def flank_separation(zone: MeshZone, drv: PlacedGear, dvn: PlacedGear, n_r=15, n_z=15):
    """Separations (mm, exact geometry) of the driver's flanks from the driven gear's: the
    drive (and coast) flank surfaces of the driver's teeth near the zone are sampled on an
    (n_r x n_z) grid per tooth, and on the theoretical drive (coast) contact lines, where
    perfect involutes come closest, and measured with ``involute_deviation`` of the driven
    gear's drive (coast) flank, where they lie within the driven gear's involute radii.
    ``min_coast`` is then the normal backlash (to round-off) and ``min_drive`` zero."""

    ga, gb = drv.gear, dvn.gear
    b = min(ga.face_width, gb.face_width)
    zs = np.linspace(-0.5 * b, 0.5 * b, n_z)
    r_lo_b, r_hi_b = sorted((gb.form_radius, gb.tip_radius))
    res = {}
    on_lines = {"drive": zone.contact_lines, "coast": contact_lines(zone, drv, dvn, coast=True)}
    for label, side_a, side_b in (
        ("drive", zone.driver_side, zone.driven_side),
        ("coast", zone.coast_sides[0], zone.coast_sides[1]),
    ):
        fa = flank_of(ga, side_a)
        t = np.linspace(fa.t_form, fa.t_tip, n_r)
        r = fa.rb * np.sqrt(1 + t * t)
        polar = fa.theta0 + fa.s * (t - np.arctan(t))
        teeth = set()
        for k, _, _ in zone.contact_lines:
            teeth.update({k - 1, k, k + 1})
        vals = []
        for k in sorted(teeth):
            ang = polar[:, None] + ga.helix_rotation(zs)[None, :] + k * 2 * math.pi / ga.teeth
            x = r[:, None] * np.cos(ang)
            y = r[:, None] * np.sin(ang)
            pts = np.stack([x, y, np.broadcast_to(zs, x.shape)], -1).reshape(-1, 3)
            scene_pts = drv.placement.apply(pts)
            local = dvn.placement.inverse(scene_pts)
            rb_ = np.hypot(local[:, 0], local[:, 1])
            keep = (rb_ >= r_lo_b) & (rb_ <= r_hi_b)
            if keep.any():
                vals.append(involute_deviation(gb, local[keep], side_b))
        for _, _, pts in on_lines[label]:
            vals.append(involute_deviation(gb, dvn.placement.inverse(pts), side_b))
        v = np.concatenate(vals) if vals else np.array([np.inf])
        res[f"min_{label}"] = float(v.min())
    return res


# --------------------------------------------------------------------------------------
# case scenes
# --------------------------------------------------------------------------------------
