"""Scenes: the bodies of a case placed at one mesh position, in phase, with the teeth in mesh.

Frames and senses. Scene frame: the sun (and ring) axis is the z axis, z = 0 at mid face
width of every body. A body is turned about its own axis by its placement angle and moved
to its centre (:class:`meshing.assemble.Placement`). The mesh position is the sun's roll
angle ``roll`` (rad, its placement angle). Under load the sun turns counter-clockwise
(omega = +1) with the carrier held: case 1 pinions turn clockwise and the ring clockwise;
case 2 SP clockwise, RP and ring counter-clockwise.

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
are then apart by the pair's backlash (zero for the cases' zero-backlash shifts).

What is modelled. A one-branch scene meshes sectors of the sun and ring around the mesh
zones (the teeth in contact, one more tooth each side refined, one more unrefined) and the
full pinion(s); ``report()`` lists what is left out (other pinions, the rest of sun and
ring, carrier unless asked for).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from meshing import tags as T
from meshing.assemble import Placement
from meshing.gear_body import GearBody
from meshing.sizing import MeshingError

# Body dimensions the gear data do not give (mm). Bores carry the needle bearings: pin
# diameter + 2 needle diameters; rim of the ring about 3 modules outside its root circle.
PIN_DIAMETER = 16.0
NEEDLE_DIAMETER = 3.0
SUN_BORE_RADIUS = 15.0
RING_RIM_THICKNESS = 5.0  # outer radius = root radius + this
SECTOR_MARGIN = 1  # unrefined teeth added each side of the refined teeth in a sector
ACTIVE_MARGIN = 1  # refined teeth added each side of the teeth in contact


def pinion_bore_radius(pin_diameter: float = PIN_DIAMETER) -> float:
    return 0.5 * pin_diameter + NEEDLE_DIAMETER


def _e(a):
    return np.array([math.cos(a), math.sin(a)])


def _eperp(a):
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
    from meshing.gear_geometry import tooth_profile

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

    @property
    def name(self) -> str:
        return self.body.body

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

    @property
    def coast_sides(self) -> tuple[str, str]:
        other = {"pos": "neg", "neg": "pos"}
        return other[self.driver_side], other[self.driven_side]


@dataclass(frozen=True)
class Scene:
    name: str
    case: str
    roll: float
    gears: tuple[PlacedGear, ...]
    zones: tuple[MeshZone, ...]
    left_out: tuple[str, ...] = ()
    carrier: object | None = None  # meshing.carrier.CarrierSpec
    notes: tuple[str, ...] = field(default=())

    def gear(self, name: str) -> PlacedGear:
        for g in self.gears:
            if g.name == name:
                return g
        raise KeyError(f"{self.name}: no body {name!r}; bodies are {[g.name for g in self.gears]}")

    def params(self) -> dict:
        """Canonical description (cache key of the merged scene mesh)."""
        return {
            "name": self.name,
            "gears": [
                {"body": g.body.params(), "placement": g.placement, "active": g.active_teeth}
                for g in self.gears
            ],
            "carrier": self.carrier,
        }

    def drive_flank_names(self) -> dict[str, list[str]]:
        """Tag names of the drive flanks of the teeth in contact, per body."""
        out: dict[str, list[str]] = {}
        for zn in self.zones:
            for body, side in ((zn.driver, zn.driver_side), (zn.driven, zn.driven_side)):
                g = self.gear(body)
                out.setdefault(body, []).extend(T.flank(body, k, side) for k in g.contact_teeth)
        return out

    def report(self) -> dict:
        return {
            "scene": self.name,
            "case": self.case,
            "roll_rad": self.roll,
            "bodies": {
                g.name: {
                    "teeth": g.body.teeth if not g.body.full else "full",
                    "placement_angle_rad": g.placement.angle,
                    "centre_mm": list(g.placement.centre),
                    "omega": g.omega,
                    "refined_teeth": list(g.active_teeth),
                    "teeth_in_contact": list(g.contact_teeth),
                }
                for g in self.gears
            },
            "mesh_zones": [
                {
                    "driver": z.driver,
                    "driven": z.driven,
                    "drive_flanks": {z.driver: z.driver_side, z.driven: z.driven_side},
                    "coast_flanks": dict(zip((z.driver, z.driven), z.coast_sides, strict=True)),
                    "operating_pressure_angle_deg": math.degrees(z.pressure_angle),
                    "backlash_mm": z.backlash,
                    "tooth_pairs_in_contact": [(a, b) for a, b, _ in z.contact_lines],
                }
                for z in self.zones
            ],
            "left_out": list(self.left_out),
            "notes": list(self.notes),
        }


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
    from meshing.gear_geometry import GearPair

    internal = bool(dvn_gear.internal)
    ca = np.asarray(drv_pl.centre, float)
    cb = np.asarray(dvn_centre, float)
    a = float(np.linalg.norm(cb - ca))
    pair = GearPair(drv_gear, dvn_gear, a)
    backlash = pair.backlash
    if check_pair and backlash < -1e-9:
        raise MeshingError(
            f"{drv_gear.name}/{dvn_gear.name}: centre distance {a:.4f} mm gives backlash "
            f"{backlash * 1e3:.2f} um < 0: the teeth interpenetrate (the shifts of the gears "
            "need a larger distance for an external mesh)"
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
    d = -s * _eperp(tau)
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
        tangency=tuple(float(v) for v in ca + rba * _e(tau)),
        window=(float(lo), float(la_a)),
        backlash=float(backlash),
    )
    return float(angle_b), zone


def contact_lines(zone: MeshZone, drv: PlacedGear, dvn: PlacedGear, n=41, coast=False):
    """Theoretical contact lines of the zone: per driver tooth in contact, the points
    (scene frame) of its drive flank on the line of action within the contact window and
    the common face width, with the index of the driven tooth they touch.

    ``coast=True``: the same for the coast flanks (the line of action mirrored about the
    centre line); the driven coast flank is then the normal backlash away from the points.
    """
    ga, gb = drv.gear, dvn.gear
    side_a, side_b = zone.coast_sides if coast else (zone.driver_side, zone.driven_side)
    fa = flank_of(ga, side_a)
    s = fa.s
    tau = zone.gamma + s * zone.pressure_angle if coast else zone.tau
    ca = np.asarray(drv.placement.centre, float)
    T0 = ca + fa.rb * _e(tau)
    d = -s * _eperp(tau)
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
        j = int(np.round(np.median(th) / pitch_b - 0.25 * sb)) % gb.teeth
        out.append((k, j, pts))
    return tuple(out)


def normal_backlash(zone: MeshZone, drv: PlacedGear) -> float:
    """Backlash of the zone normal to the flanks: j_wt cos(alpha_wt) cos(beta_b) (mm)."""
    return zone.backlash * math.cos(zone.pressure_angle) * math.cos(drv.gear.base_helix_angle)


def _widen(contact, z: int, margin: int) -> set[int]:
    """Teeth within ``margin`` of a contact tooth (cyclic)."""
    return {(k + i) % z for k in contact for i in range(-margin, margin + 1)}


def _teeth_around(contact: list[int], z: int, margin: int) -> list[int]:
    """Contact teeth widened by ``margin`` each side (cyclic) as one CCW run (for sectors:
    everything between the first and the last tooth across the largest gap)."""
    if not contact:
        return []
    cs = sorted(set(contact))
    gaps = [((cs[(i + 1) % len(cs)] - cs[i]) % z, i) for i in range(len(cs))]
    _, i_max = max(gaps)
    start = cs[(i_max + 1) % len(cs)]
    span = (cs[i_max] - start) % z + 1
    return [(start - margin + i) % z for i in range(span + 2 * margin)]


def _sector(gear, teeth_ccw: list[int], radius_kw: dict, name: str | None = None) -> GearBody:
    z = gear.teeth
    if len(teeth_ccw) > z // 2:
        raise MeshingError(
            f"{gear.name}: the mesh zones need {len(teeth_ccw)} teeth, more than a sector "
            f"holds ({z // 2}); use the full gear"
        )
    return GearBody(gear, name=name, first_tooth=teeth_ccw[0], n_teeth=len(teeth_ccw), **radius_kw)


def _validate_roll(roll) -> float:
    if isinstance(roll, bool) or not isinstance(roll, (int, float)) or not math.isfinite(roll):
        raise MeshingError(f"roll = {roll!r}: must be a finite number (sun angle, rad)")
    return float(roll)


def _check_phase(scene_name: str, zone: MeshZone, drv: PlacedGear, dvn: PlacedGear) -> None:
    """Raise if the drive flanks interpenetrate (checked on exact geometry, before gmsh)."""
    sep = flank_separation(zone, drv, dvn, n_r=7, n_z=7)
    if sep["min_drive"] < -1e-6 or sep["min_coast"] < -1e-6:
        raise MeshingError(
            f"{scene_name}: {zone.driver}/{zone.driven} interpenetrate (min drive-flank "
            f"separation {sep['min_drive'] * 1e3:.3f} um, coast {sep['min_coast'] * 1e3:.3f} "
            "um): check the centre distance and the phase offsets"
        )


def flank_separation(zone: MeshZone, drv: PlacedGear, dvn: PlacedGear, n_r=15, n_z=15):
    """Separations (mm, exact geometry) of the driver's flanks from the driven gear's: the
    drive (and coast) flank surfaces of the driver's teeth near the zone are sampled on an
    (n_r x n_z) grid per tooth and measured with ``involute_deviation`` of the driven gear's
    drive (coast) flank, where they lie within the driven gear's involute radii."""
    from meshing.gear_geometry import involute_deviation

    ga, gb = drv.gear, dvn.gear
    b = min(ga.face_width, gb.face_width)
    zs = np.linspace(-0.5 * b, 0.5 * b, n_z)
    r_lo_b, r_hi_b = sorted((gb.form_radius, gb.tip_radius))
    res = {}
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
        v = np.concatenate(vals) if vals else np.array([np.inf])
        res[f"min_{label}"] = float(v.min())
    return res


# --------------------------------------------------------------------------------------
# case scenes
# --------------------------------------------------------------------------------------


def _gearset(case: str):
    from cases.gearset import load_gearset

    return load_gearset(case)


def _finish_gear(pg: PlacedGear, contact: list[int], full: bool, radius_kw: dict) -> PlacedGear:
    g = pg.gear
    active = _widen(contact, g.teeth, ACTIVE_MARGIN)
    if full:
        body = GearBody(g, **radius_kw)
    else:
        body = _sector(g, _teeth_around(contact, g.teeth, ACTIVE_MARGIN + SECTOR_MARGIN), radius_kw)
    return replace(
        pg, body=body, active_teeth=tuple(sorted(active)), contact_teeth=tuple(sorted(contact))
    )


def planet_angles(z_sun: int, z_ring: int, n: int) -> list[float]:
    """Carrier angles of n planets as near equal spacing as the assembly condition allows:
    multiples of 2 pi / (z_sun + z_ring) (a single pinion planetary)."""
    step = 2 * math.pi / (z_sun + z_ring)
    return [round(2 * math.pi * k / n / step) * step for k in range(n)]


def case1_scene(
    roll: float = 0.0,
    branches: int = 1,
    phase_offsets: dict | None = None,
    pinion_radial_offset: float = 0.0,
    pin_diameter: float = PIN_DIAMETER,
    carrier: bool = False,
) -> Scene:
    """Case 1 (sun, pinion(s), ring) at sun angle ``roll``.

    ``branches=1``: one pinion on +x with sectors of sun and ring; ``branches=3``: all
    pinions (at the assembly-condition angles nearest to 120 deg spacing) with full sun and
    ring. ``phase_offsets`` (body -> rad) turns bodies away from the theoretical phase and
    ``pinion_radial_offset`` (mm) moves the pinion(s) off the printed centre distance; both
    are checked on exact geometry and a scene that interpenetrates raises
    :class:`MeshingError` before any meshing.
    """
    roll = _validate_roll(roll)
    if branches not in (1, 3):
        raise MeshingError(f"branches = {branches!r}: must be 1 (one branch) or 3 (all pinions)")
    gs = _gearset("case1")
    sun, pinion, ring = gs.gears["sun"], gs.gears["pinion"], gs.gears["ring"]
    a = gs.meshes[0].centre_distance + pinion_radial_offset
    offsets = dict(phase_offsets or {})
    sun_pl = Placement(roll + offsets.pop("sun", 0.0))
    sun_kw = {"inner_radius": SUN_BORE_RADIUS}
    pin_kw = {"inner_radius": pinion_bore_radius(pin_diameter)}
    ring_kw = {"outer_radius": ring.root_radius + RING_RIM_THICKNESS}
    if branches == 1:
        angles = [0.0]
        names = ["pinion"]
    else:
        angles = planet_angles(sun.teeth, ring.teeth, 3)
        names = ["pinion1", "pinion2", "pinion3"]
    pg_sun = PlacedGear(GearBody(sun, **sun_kw), sun_pl, +1)
    zones, pinions = [], []
    ring_angle = None
    ring_angles = []
    for psi, pname in zip(angles, names, strict=True):
        centre = a * _e(psi)
        p_gear = replace(pinion, name=pname)
        ang_p, z1 = solve_mesh(sun, sun_pl, +1, p_gear, centre)
        p_pl = Placement(ang_p + offsets.pop(pname, 0.0), (float(centre[0]), float(centre[1])))
        ang_r, z2 = solve_mesh(p_gear, p_pl, -1, ring, (0.0, 0.0))
        ring_angles.append(ang_r)
        if ring_angle is None:
            ring_angle = ang_r
        pinions.append(PlacedGear(GearBody(p_gear, **pin_kw), p_pl, -1))
        zones += [z1, z2]
    pitch_r = 2 * math.pi / ring.teeth
    for k, ang in enumerate(ring_angles):
        mis = ((ang - ring_angle + 0.5 * pitch_r) % pitch_r) - 0.5 * pitch_r
        if abs(mis) * ring.base_radius > 1e-6:
            raise MeshingError(
                f"case1: pinion {names[k]} at carrier angle {math.degrees(angles[k]):.3f} deg "
                f"is out of phase with the ring by {mis * ring.base_radius * 1e3:.2f} um "
                "(assembly condition)"
            )
    ring_pl = Placement(ring_angle + offsets.pop("ring", 0.0))
    if offsets:
        raise MeshingError(f"phase_offsets: unknown bodies {sorted(offsets)}")
    pg_ring = PlacedGear(GearBody(ring, **ring_kw), ring_pl, -1)
    return _assemble_scene(
        f"case1-{'branch' if branches == 1 else 'all'}",
        "case1",
        roll,
        [pg_sun, *pinions, pg_ring],
        zones,
        full={"sun": branches > 1, "ring": branches > 1, **{n: True for n in names}},
        radius_kw={"sun": sun_kw, "ring": ring_kw, **{n: pin_kw for n in names}},
        left_out=(
            [
                "pinions 2 and 3 (equal load sharing: one branch)",
                "sun and ring outside the sectors (rigid there)",
            ]
            if branches == 1
            else []
        )
        + ([] if carrier else ["carrier (rigid)"]),
        carrier=_carrier_spec(pin_diameter) if carrier else None,
        notes=[
            f"planet angles (deg): {[round(math.degrees(x), 4) for x in angles]}; "
            f"z_sun + z_ring = {sun.teeth + ring.teeth} is not divisible by 3, so three "
            "pinions cannot be equally spaced"
        ]
        if branches == 3
        else [],
    )


def case2_scene(
    roll: float = 0.0,
    rp_side: int = +1,
    phase_offsets: dict | None = None,
    pin_diameter: float = PIN_DIAMETER,
    carrier: bool = False,
) -> Scene:
    """Case 2-B (sun, SP, RP, ring), one branch: SP on +x, RP on the side ``rp_side`` (+1:
    counter-clockwise of SP about the sun) at the triangle the three centre distances fix."""
    roll = _validate_roll(roll)
    if rp_side not in (1, -1):
        raise MeshingError(f"rp_side = {rp_side!r}: must be +1 or -1")
    gs = _gearset("case2")
    sun, sp, rp, ring = (gs.gears[n] for n in ("sun", "SP", "RP", "ring"))
    a1, a2, a3 = (m.centre_distance for m in gs.meshes)
    psi = math.acos((a1 * a1 + a3 * a3 - a2 * a2) / (2 * a1 * a3))  # angle at the sun centre
    offsets = dict(phase_offsets or {})
    sun_pl = Placement(roll + offsets.pop("sun", 0.0))
    c_sp = a1 * _e(0.0)
    c_rp = a3 * _e(rp_side * psi)
    ang_sp, z1 = solve_mesh(sun, sun_pl, +1, sp, c_sp)
    sp_pl = Placement(ang_sp + offsets.pop("SP", 0.0), tuple(float(v) for v in c_sp))
    ang_rp, z2 = solve_mesh(sp, sp_pl, -1, rp, c_rp)
    rp_pl = Placement(ang_rp + offsets.pop("RP", 0.0), tuple(float(v) for v in c_rp))
    ang_r, z3 = solve_mesh(rp, rp_pl, +1, ring, (0.0, 0.0))
    ring_pl = Placement(ang_r + offsets.pop("ring", 0.0))
    if offsets:
        raise MeshingError(f"phase_offsets: unknown bodies {sorted(offsets)}")
    pin_kw = {"inner_radius": pinion_bore_radius(pin_diameter)}
    sun_kw = {"inner_radius": SUN_BORE_RADIUS}
    ring_kw = {"outer_radius": ring.root_radius + RING_RIM_THICKNESS}
    gears = [
        PlacedGear(GearBody(sun, **sun_kw), sun_pl, +1),
        PlacedGear(GearBody(sp, **pin_kw), sp_pl, -1),
        PlacedGear(GearBody(rp, **pin_kw), rp_pl, +1),
        PlacedGear(GearBody(ring, **ring_kw), ring_pl, +1),
    ]
    theta = math.pi - psi - math.acos((a1 * a1 + a2 * a2 - a3 * a3) / (2 * a1 * a2))
    return _assemble_scene(
        "case2-branch",
        "case2",
        roll,
        gears,
        [z1, z2, z3],
        full={"sun": False, "SP": True, "RP": True, "ring": False},
        radius_kw={"sun": sun_kw, "SP": pin_kw, "RP": pin_kw, "ring": ring_kw},
        left_out=[
            "pinion pairs 2 and 3 (equal load sharing: one branch)",
            "sun and ring outside the sectors",
        ]
        + ([] if carrier else ["carrier (rigid)"]),
        carrier=None,
        notes=[
            f"triangle angles (deg): psi (sun) = {math.degrees(psi):.3f}, theta (SP) = "
            f"{math.degrees(math.pi - theta - psi):.3f}"
        ],
    )


def _carrier_spec(pin_diameter):
    from meshing.carrier import default_carrier

    return default_carrier("case1", pin_diameter)


def _assemble_scene(name, case, roll, gears, zones, full, radius_kw, left_out, carrier, notes):
    by_name = {g.name: g for g in gears}
    # Contact lines and the teeth in contact.
    zones_done = []
    contact: dict[str, set[int]] = {g.name: set() for g in gears}
    for zn in zones:
        drv, dvn = by_name[zn.driver], by_name[zn.driven]
        zn = replace(zn, contact_lines=contact_lines(zn, drv, dvn))
        for k, j, _ in zn.contact_lines:
            contact[zn.driver].add(k)
            contact[zn.driven].add(j)
        zones_done.append(zn)
    # Bodies: sectors / full, refined teeth.
    placed = [
        _finish_gear(g, sorted(contact[g.name]), full[g.name], radius_kw[g.name]) for g in gears
    ]
    by_name = {g.name: g for g in placed}
    for zn in zones_done:
        _check_phase(name, zn, by_name[zn.driver], by_name[zn.driven])
    return Scene(
        name=name,
        case=case,
        roll=roll,
        gears=tuple(placed),
        zones=tuple(zones_done),
        left_out=tuple(left_out),
        carrier=carrier,
        notes=tuple(notes),
    )


SCENES = {
    "case1-branch": lambda **kw: case1_scene(branches=1, **kw),
    "case1-all": lambda **kw: case1_scene(branches=3, **kw),
    "case2-branch": lambda **kw: case2_scene(**kw),
}
