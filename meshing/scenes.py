"""Scenes: the bodies of a gear set placed at one mesh position, in phase, teeth in mesh.

A scene is built from a gear set it is handed (:class:`cases.gearset.GearSet`, never loaded
by name here) and the sun's roll angle. The power path sun -> pinion(s) -> ring gives one
branch: a single pinion at the sun-pinion centre distance, or a sun pinion (SP) and a ring
pinion (RP) at the triangle the three centre distances fix (the RP axis lies on the RP-ring
centre distance from the sun axis). Each gear is placed by :func:`meshing.mesh_zones.
solve_mesh` so its drive flank touches its driver's on the line of action.

The registry :data:`SCENES` holds the scenes a study case may name (``model.scene``):

* ``one_branch``: one branch on the +x axis; sectors of sun and ring around the mesh zones
  (the teeth in contact, one more refined tooth each side, one more unrefined) and the full
  pinion(s). Three equal branches on a rigid carrier share the torque equally.
* ``all_planets``: every branch at the carrier angles nearest to equal spacing that the
  assembly condition allows, in diametrically opposed pairs where the tooth numbers allow
  (:func:`gears.analytic.phasing.assemblable_angles`), with the full sun and ring; the pins
  are rigid.
* ``system``: ``all_planets`` with the carrier as a body: two plates joined by posts, one
  pin per pinion (single pinion) or an SP and an RP pin per branch (double pinion), in the
  order of the scene's pinions (:mod:`meshing.carrier`).

``Scene.report()`` lists what each scene leaves out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from cases.gearset import first_overlap
from cases.study_case import SCENES as SCENE_NAMES
from gears.analytic.phasing import assemblable_angles, planet_layout
from gears.layout import pinion_centres
from meshing.assemble import Placement
from meshing.carrier import carrier_spec
from meshing.gear_body import RIM_MODULES, GearBody
from meshing.mesh_zones import (
    MeshZone,
    PlacedGear,
    contact_lines,
    flank_separation,
    solve_mesh,
)
from meshing.sizing import MeshingError

# Body dimensions the gear data do not give (mm). Bores carry the needle bearings: pin
# diameter + 2 needle diameters; rim of the ring about 3 modules outside its root circle.
PIN_DIAMETER = 16.0
NEEDLE_DIAMETER = 3.0
SUN_BORE_RADIUS = 15.0  # largest sun bore; smaller suns get sun_bore_radius()
# Rim under the sun's root circle, in normal modules: a rim backup ratio t_R / h_t of about
# 1.5 (h_t = 2.25 m), above the 1.2 from which ISO 6336-3 takes the rim as stiff (Y_B = 1).
SUN_RIM_MODULES = 3.5
RING_RIM_THICKNESS = 5.0  # outer radius = root radius + this
SECTOR_MARGIN = 1  # unrefined teeth added each side of the refined teeth in a sector
ACTIVE_MARGIN = 1  # refined teeth added each side of the teeth in contact
# Sun angles sampled per mesh cycle for the bodies of the cycle (``cycle_bodies``): a tooth
# can be in contact for a tenth of a pitch only, between two of five samples (1-GA: a pinion
# tooth at 0.55-0.65 p), so 5 samples gave bodies that changed from one position to the
# next; 60 hits every position of a study with 1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30 or 60
# positions exactly.
CYCLE_SAMPLES = 60
_CYCLE_MEMO: dict[str, tuple[dict, dict]] = {}  # see _cycle_cover


def sun_bore_radius(sun) -> float:
    """The sun's bore radius (mm): SUN_BORE_RADIUS, or less where the rim under the root
    circle would be thinner than SUN_RIM_MODULES normal modules (a small sun). A sun too
    small for any bore gets a radius <= 0, which :class:`meshing.gear_body.GearBody` refuses
    with a message naming ``inner_radius``."""
    return min(SUN_BORE_RADIUS, sun.root_radius - SUN_RIM_MODULES * sun.normal_module)


def pinion_bore_radius(pin_diameter: float = PIN_DIAMETER) -> float:
    return 0.5 * pin_diameter + NEEDLE_DIAMETER


def _check_bores(gearset, sun_bore: float, pin_bore: float, pin_diameter: float) -> None:
    """MeshingError, in a gear engineer's terms, for a gear whose bore does not fit under its
    root circle with a rim of RIM_MODULES (:meth:`meshing.gear_body.GearBody.validate`): a
    planet too small for the pin and its needle bearing, a sun too small for a rim of
    SUN_RIM_MODULES modules. A gear-set file cannot set either bore."""
    path = gearset.power_path
    for name in path[:-1]:
        g = gearset.gears[name]
        bore = sun_bore if name == path[0] else pin_bore
        need = bore + RIM_MODULES * g.normal_module
        if 0.0 < bore and g.root_radius >= need:
            continue
        if name == path[0]:
            why = f"a rim of {SUN_RIM_MODULES:g} normal modules under its root circle"
        else:
            why = (
                f"its pin ({pin_diameter:g} mm) and needle bearing ({NEEDLE_DIAMETER:g} mm "
                f"needles): a bore of {bore:g} mm radius and a rim of {RIM_MODULES:g} normal "
                "module, so a "
                f"root radius of at least {need:.3f} mm"
            )
        raise MeshingError(
            f"gears.{name}: teeth = {g.teeth} at normal_module = {g.normal_module:g} mm gives "
            f"a root radius of {g.root_radius:.3f} mm, too small for {why}: more teeth or a "
            "larger module"
        )


@dataclass(frozen=True)
class Scene:
    name: str
    gearset: str  # name of the gear set
    roll: float
    gears: tuple[PlacedGear, ...]
    zones: tuple[MeshZone, ...]
    left_out: tuple[str, ...] = ()
    carrier: object | None = None  # meshing.carrier.CarrierSpec
    notes: tuple[str, ...] = field(default=())
    branches: int = 1  # branches (pinion or pinion pair) of the set this scene holds

    @property
    def sun_name(self) -> str:
        """The sun: first of :attr:`gears`."""
        return self.gears[0].name

    @property
    def ring_name(self) -> str:
        """The ring: last of :attr:`gears`."""
        return self.gears[-1].name

    @property
    def pinion_names(self) -> tuple[str, ...]:
        """The pinions, branch by branch along the power path."""
        return tuple(g.name for g in self.gears[1:-1])

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

    def report(self) -> dict:
        return {
            "scene": self.name,
            "gearset": self.gearset,
            "roll_rad": self.roll,
            "bodies": {
                g.name: {
                    "teeth": g.body.teeth if not g.body.full else "full",
                    "placement_angle_rad": g.placement.angle,
                    "centre_mm": list(g.placement.centre),
                    "omega": g.omega,
                    "refined_teeth": list(g.active_teeth),
                    "fine_fillets": [list(f) for f in g.body.fine_fillets or ()],
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
            "branches": self.branches,
            "left_out": list(self.left_out),
            "notes": list(self.notes),
        }


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


def tension_fillets(zones) -> dict[str, set[tuple[int, str]]]:
    """Body -> the (tooth, side) fillets in tension under load at one mesh position: of every
    contact line of every zone (with ``contact_lines``), the driver tooth's fillet on the
    zone's driver side and the driven tooth's on its driven side (the fillet under the loaded
    flank; :mod:`solvers.root_stress` reads the root stress on these teeth)."""
    out: dict[str, set[tuple[int, str]]] = {}
    for zn in zones:
        for k, j, _ in zn.contact_lines:
            out.setdefault(zn.driver, set()).add((int(k), zn.driver_side))
            out.setdefault(zn.driven, set()).add((int(j), zn.driven_side))
    return out


def _finish_gear(
    pg: PlacedGear,
    contact: list[int],
    cover: set[int],
    full: bool,
    radius_kw: dict,
    fine: set[tuple[int, str]],
) -> PlacedGear:
    """The body of a placed gear: refined around the teeth in ``cover`` (the teeth in contact
    anywhere in the mesh cycle) and, for a sector, cut around them; the fillets in ``fine``
    (the tension fillets of those teeth, :func:`tension_fillets`) get the level's ``fillet``
    size, the other fillets ``fillet_far`` (``GearBody.fine_fillets``)."""
    g = pg.gear
    teeth = sorted(set(contact) | set(cover))
    active = _widen(teeth, g.teeth, ACTIVE_MARGIN)
    kw = {**radius_kw, "fine_fillets": tuple(sorted(fine))}
    if full:
        body = GearBody(g, **kw)
    else:
        body = _sector(g, _teeth_around(teeth, g.teeth, ACTIVE_MARGIN + SECTOR_MARGIN), kw)
    return replace(
        pg, body=body, active_teeth=tuple(sorted(active)), contact_teeth=tuple(sorted(contact))
    )


def branch_centres(gearset, psi: float, rp_side: int = +1, radial_offset: float = 0.0):
    """Centres (scene frame, mm) of the pinions of the branch at carrier angle ``psi``.

    Single pinion: at the sun-pinion centre distance a1 (+ ``radial_offset``). Double
    pinion: SP at a1 (+ ``radial_offset``) on the angle ``psi``, RP at the RP-ring centre
    distance a3 on ``psi + rp_side psi_t``, psi_t = acos((a1^2 + a3^2 - a2^2) / (2 a1 a3))
    the triangle's angle at the sun (``rp_side`` +1: RP counter-clockwise of SP); the
    geometry is :func:`gears.layout.pinion_centres`, which the gear set's clearance check uses.
    """
    pinions = gearset.power_path[1:-1]
    if len(pinions) == 2 and rp_side not in (1, -1):
        raise MeshingError(f"rp_side = {rp_side!r}: must be +1 or -1")
    if len(pinions) in (1, 2):  # the carrier's pins: meshing.carrier.sun_rp_angle
        a = [m.centre_distance for m in gearset.meshes]
        return [np.array(c) for c in pinion_centres(a, psi, rp_side, radial_offset)]
    raise MeshingError(
        f"{gearset.name}: power path {gearset.power_path}: scenes hold one or two pinions per "
        "branch"
    )


def _unwrap(angle: float, ref: float | None, teeth: int, omega: int) -> float:
    """``angle`` moved by whole tooth pitches to lie within one pitch of ``ref`` in the sense
    of rotation ``omega`` (from ``ref`` on): the placement of a gear at the sun angles of one
    mesh cycle, measured from its placement at the cycle start, never wraps (a wrap relabels
    the teeth in contact, so the cycle's refined teeth would differ from gear to gear)."""
    if ref is None:
        return angle
    pitch = 2 * math.pi / teeth
    slack = 1e-9 * pitch
    return ref + omega * ((omega * (angle - ref) + slack) % pitch - slack)


def _place_branch(
    gearset, sun, sun_pl, psi, names, offsets, pin_kw, rp_side, radial_offset, angle_ref
):
    """Pinions of one branch placed in mesh along the power path, their zones, and the ring
    placement angle the branch asks for. The sun turns counter-clockwise (omega = +1); each
    external mesh reverses the sense, the internal mesh keeps it. ``angle_ref``: body ->
    placement at the cycle start (:func:`_unwrap`), or empty."""
    centres = branch_centres(gearset, psi, rp_side, radial_offset)
    drv, drv_pl, omega = sun, sun_pl, +1
    placed, zones = [], []
    for pname, gname, c in zip(names, gearset.power_path[1:-1], centres, strict=True):
        p_gear = replace(gearset.gears[gname], name=pname)
        ang, zone = solve_mesh(drv, drv_pl, omega, p_gear, c)
        p_ang = _unwrap(ang + offsets.pop(pname, 0.0), angle_ref.get(pname), p_gear.teeth, -omega)
        p_pl = Placement(p_ang, (float(c[0]), float(c[1])))
        placed.append(PlacedGear(GearBody(p_gear, **pin_kw), p_pl, -omega, set_gear=gname))
        zones.append(zone)
        drv, drv_pl, omega = p_gear, p_pl, -omega
    ring = gearset.gears[gearset.power_path[-1]]
    ang_r, zone = solve_mesh(drv, drv_pl, omega, ring, (0.0, 0.0))
    zones.append(zone)
    return placed, zones, ang_r, omega


def cycle_angles(gearset, roll: float) -> tuple[int, list[float]]:
    """The mesh cycle that holds ``roll`` (sun angles k p .. (k + 1) p, p = 2 pi / Z_sun): k,
    and its :data:`CYCLE_SAMPLES` equally spaced sun angles from its start (rad)."""
    pitch = 2 * math.pi / gearset.gears[gearset.power_path[0]].teeth
    cycle = math.floor(roll / pitch + 1e-9)
    return cycle, [(cycle + j / CYCLE_SAMPLES) * pitch for j in range(CYCLE_SAMPLES)]


def _cycle_cover(gearset, roll: float, all_planets: bool, options: dict):
    """The mesh cycle that holds ``roll`` (sun angles k p .. (k + 1) p, p = 2 pi / Z_sun):
    per body its placement at the cycle start (the reference of :func:`_unwrap`), and the
    teeth in contact and their tension fillets (:func:`tension_fillets`) anywhere in the
    cycle, the union over :data:`CYCLE_SAMPLES` equally spaced sun angles from its start
    (memoized per gear set, scene options and cycle)."""
    cycle, angles = cycle_angles(gearset, roll)
    key = repr((gearset, cycle, all_planets, sorted(options.items())))
    if key not in _CYCLE_MEMO:
        first = planetary_scene(gearset, angles[0], all_planets, cycle_bodies=False, **options)
        ref = {g.name: g.placement.angle for g in first.gears}
        cover: dict[str, set[int]] = {}
        fine: dict[str, set[tuple[int, str]]] = {}
        for angle in angles:
            sc = planetary_scene(
                gearset, angle, all_planets, cycle_bodies=False, _angle_ref=ref, **options
            )
            for g in sc.gears:
                cover.setdefault(g.name, set()).update(g.contact_teeth)
            for name, fl in tension_fillets(sc.zones).items():
                fine.setdefault(name, set()).update(fl)
        if len(_CYCLE_MEMO) >= 64:
            _CYCLE_MEMO.pop(next(iter(_CYCLE_MEMO)))
        _CYCLE_MEMO[key] = (
            ref,
            {n: frozenset(v) for n, v in cover.items()},
            {n: frozenset(v) for n, v in fine.items()},
        )
    return _CYCLE_MEMO[key]


def planetary_scene(
    gearset,
    roll: float = 0.0,
    all_planets: bool = False,
    phase_offsets: dict | None = None,
    pinion_radial_offset: float = 0.0,
    pin_diameter: float = PIN_DIAMETER,
    carrier: bool = False,
    rp_side: int = +1,
    cycle_bodies: bool = True,
    planet_angles_deg: tuple | None = None,
    fine_fillets: bool | None = None,
    _angle_ref: dict | None = None,
) -> Scene:
    """The gear set at sun angle ``roll`` (rad): one branch on +x, or every branch.

    ``phase_offsets`` (body -> rad) turns bodies away from the theoretical phase and
    ``pinion_radial_offset`` (mm) moves the first pinion of each branch off its centre
    distance; both are checked on exact geometry and a scene that interpenetrates raises
    :class:`MeshingError` before any meshing. ``carrier`` adds the carrier body.

    ``cycle_bodies``: every body covers (sector) and refines the teeth in contact anywhere in
    the mesh cycle that holds ``roll`` (sun angles k p .. (k + 1) p, p = 2 pi / Z_sun; sampled
    at :data:`CYCLE_SAMPLES` angles), so all the positions of a cycle share the same
    bodies and a body's stiffness and factorization serve them all. Off: the teeth in contact
    at ``roll`` only. Over a cycle the placement of every gear turns on from its placement
    at the cycle start without wrapping into one tooth pitch (:func:`_unwrap`): a wrap
    relabels the teeth, so the cycle's refined teeth and fillets held both labels of a tooth
    and differed between planets in phase (parker2000-3: 4 or 5 fine fillets, the net sun
    force no longer cancelling).
    The same way every body's ``fine_fillets`` (the fillets meshed at the level's ``fillet``
    size, where the root stress is read) are the tension fillets of the teeth loaded anywhere
    in the cycle (:func:`tension_fillets`, union over the sampled angles and ``roll``), not only
    at ``roll``: a per-position set would change the body meshes from one position to the
    next; the other fillets of the refined teeth get ``fillet_far``. ``fine_fillets`` False
    names none (every fillet at ``fillet_far``; :func:`refines_root_fillets` is then False);
    None: True for one branch, False with all planets, where the loaded fillets of every
    planet at 0.15 mm (level 1) would about double the DOFs (numerics.root_fillets).

    ``planet_angles_deg`` (all planets, no carrier body): the carrier angles of the branches
    (deg, one per planet of the set) instead of the assemblable angles nearest to equal
    spacing; a branch out of phase with the ring raises (assembly condition).
    """
    roll = _validate_roll(roll)
    options = {
        "phase_offsets": phase_offsets,
        "pinion_radial_offset": pinion_radial_offset,
        "pin_diameter": pin_diameter,
        "carrier": carrier,
        "rp_side": rp_side,
        "planet_angles_deg": planet_angles_deg,
    }
    cover: dict[str, frozenset[int]] = {}
    fine: dict[str, frozenset[tuple[int, str]]] = {}
    angle_ref = dict(_angle_ref or {})
    if cycle_bodies:
        angle_ref, cover, fine = _cycle_cover(gearset, roll, all_planets, options)
    refine = (not all_planets) if fine_fillets is None else bool(fine_fillets)
    path = gearset.power_path
    sun, ring = gearset.gears[path[0]], gearset.gears[path[-1]]
    pinions = path[1:-1]
    double = len(pinions) == 2
    offsets = dict(phase_offsets or {})
    sun_pl = Placement(roll + offsets.pop(path[0], 0.0))
    sun_kw = {"inner_radius": sun_bore_radius(sun)}
    pin_kw = {"inner_radius": pinion_bore_radius(pin_diameter)}
    _check_bores(gearset, sun_kw["inner_radius"], pin_kw["inner_radius"], pin_diameter)
    ring_kw = {"outer_radius": ring.root_radius + RING_RIM_THICKNESS}
    if all_planets:
        n = gearset.planets
        if planet_angles_deg is None:
            angles = [float(x) for x in assemblable_angles(sun.teeth, ring.teeth, n, double)]
        else:
            angles = _given_planet_angles(planet_angles_deg, n, carrier)
            _check_given_layout(gearset, angles, planet_angles_deg)
        branch_names = [[f"{p}{k + 1}" for p in pinions] for k in range(n)]
    else:
        if planet_angles_deg is not None:
            raise MeshingError("planet_angles_deg: only for the all-planet scenes")
        angles = [0.0]
        branch_names = [list(pinions)]
    placed, zones, ring_angles = [], [], []
    for psi, names in zip(angles, branch_names, strict=True):
        pg, zn, ang_r, ring_omega = _place_branch(
            gearset,
            sun,
            sun_pl,
            psi,
            names,
            offsets,
            pin_kw,
            rp_side,
            pinion_radial_offset,
            angle_ref,
        )
        placed += pg
        zones += zn
        ring_angles.append(ang_r)
    pitch_r = 2 * math.pi / ring.teeth
    for k, ang in enumerate(ring_angles):
        mis = ((ang - ring_angles[0] + 0.5 * pitch_r) % pitch_r) - 0.5 * pitch_r
        if abs(mis) * ring.base_radius > 1e-6:
            raise MeshingError(
                f"{gearset.name}: branch {k + 1} at carrier angle {math.degrees(angles[k]):.3f} "
                f"deg is out of phase with the ring by {mis * ring.base_radius * 1e3:.2f} um "
                "(assembly condition)"
            )
    ring_pl = Placement(
        _unwrap(
            ring_angles[0] + offsets.pop(path[-1], 0.0),
            angle_ref.get(path[-1]),
            ring.teeth,
            ring_omega,
        )
    )
    if offsets:
        raise MeshingError(f"phase_offsets: unknown bodies {sorted(offsets)}")
    gears = [
        PlacedGear(GearBody(sun, **sun_kw), sun_pl, +1),
        *placed,
        PlacedGear(GearBody(ring, **ring_kw), ring_pl, ring_omega),
    ]
    pinion_names = [g.name for g in placed]
    left_out = [] if carrier else ["carrier (rigid)"]
    notes = []
    if all_planets:
        a_deg = [round(math.degrees(x), 4) for x in angles]
        rule = "z_ring - z_sun" if double else "z_sun + z_ring"
        steps = ring.teeth - sun.teeth if double else ring.teeth + sun.teeth
        spacing = planet_layout(sun.teeth, ring.teeth, gearset.planets, double)
        spacing = "given" if planet_angles_deg is not None else spacing
        notes.append(
            f"planet angles (deg): {a_deg}; {rule} = {steps}, {gearset.planets} branches: "
            f"{spacing} (assembly condition)"
        )
    else:
        left_out = [
            f"the other {gearset.planets - 1} branches (equal load sharing: one branch)",
            "sun and ring outside the sectors (rigid there)",
            *left_out,
        ]
    if double:
        psi_t = math.atan2(*branch_centres(gearset, 0.0, rp_side)[1][::-1])
        notes.append(f"triangle angle at the sun between SP and RP: {math.degrees(psi_t):.3f} deg")
    full = {path[0]: all_planets, path[-1]: all_planets, **{n: True for n in pinion_names}}
    radius_kw = {path[0]: sun_kw, path[-1]: ring_kw, **{n: pin_kw for n in pinion_names}}
    kind = ("all" if all_planets else "branch") + ("-carrier" if carrier else "")
    return _assemble_scene(
        f"{gearset.name}-{kind}",
        gearset.name,
        roll,
        gears,
        zones,
        full=full,
        radius_kw=radius_kw,
        left_out=left_out,
        carrier=carrier_spec(gearset, pin_diameter, rp_side) if carrier else None,
        notes=notes,
        branches=len(angles),
        cover=cover,
        fine=fine if refine else None,
    )


def _given_planet_angles(angles_deg, n: int, carrier: bool) -> list[float]:
    """``planet_angles_deg`` checked (n finite, distinct carrier angles in degrees) -> rad."""
    ok = isinstance(angles_deg, (tuple, list)) and len(angles_deg) == n
    ok = ok and all(isinstance(a, (int, float)) and not isinstance(a, bool) for a in angles_deg)
    ok = ok and all(math.isfinite(a) for a in angles_deg)
    if not ok:
        raise MeshingError(
            f"planet_angles_deg = {angles_deg!r}: must be {n} finite numbers (deg), one per "
            "planet of the gear set"
        )
    rad = [math.radians(float(a)) for a in angles_deg]
    gaps = [abs(math.remainder(a - b, 2 * math.pi)) for i, a in enumerate(rad) for b in rad[:i]]
    if gaps and min(gaps) < 1e-9:
        raise MeshingError(f"planet_angles_deg = {angles_deg!r}: two planets at one angle")
    if carrier:
        raise MeshingError("planet_angles_deg: the carrier body has its pins at equal spacing")
    return rad


def _check_given_layout(gearset, angles: list[float], angles_deg) -> None:
    """Given carrier angles: the gears clear each other there too (the gear set's own check,
    :func:`cases.gearset.parse_gearset`, holds at its default angles)."""
    hit = first_overlap(gearset, angles)
    if hit is not None:
        raise MeshingError(
            f"planet_angles_deg = {list(angles_deg)!r}: the tip circles of {hit[0]} overlap "
            f"by {hit[1]:.3f} mm"
        )


def branch_scene(gearset, roll: float = 0.0, **options) -> Scene:
    """``one_branch``: one branch on +x (see :func:`planetary_scene`)."""
    return planetary_scene(gearset, roll, all_planets=False, **options)


def all_planets_scene(gearset, roll: float = 0.0, **options) -> Scene:
    """``all_planets``: every branch, full sun and ring, pins rigid (see
    :func:`planetary_scene`)."""
    return planetary_scene(gearset, roll, all_planets=True, **options)


def system_scene(gearset, roll: float = 0.0, **options) -> Scene:
    """``system``: every branch, full sun and ring, and the elastic carrier with one pin per
    pinion (see :func:`planetary_scene`)."""
    return planetary_scene(gearset, roll, all_planets=True, carrier=True, **options)


def _assemble_scene(
    name,
    gearset,
    roll,
    gears,
    zones,
    full,
    radius_kw,
    left_out,
    carrier,
    notes,
    branches,
    cover,
    fine,
):
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
    # Bodies: sectors / full, refined teeth, fine fillets (the cycle's and this position's
    # tension fillets: the same set at every position of a cycle).
    here = tension_fillets(zones_done) if fine is not None else {}
    if fine is None:  # no fine fillets: every fillet at fillet_far
        fine = {}
        notes = (*notes, "root fillets coarse (fillet_far): the root stress only on submodels")
    placed = [
        _finish_gear(
            g,
            sorted(contact[g.name]),
            cover.get(g.name, set()),
            full[g.name],
            radius_kw[g.name],
            fine.get(g.name, set()) | here.get(g.name, set()),
        )
        for g in gears
    ]
    by_name = {g.name: g for g in placed}
    for zn in zones_done:
        _check_phase(name, zn, by_name[zn.driver], by_name[zn.driven])
    return Scene(
        name=name,
        gearset=gearset,
        roll=roll,
        gears=tuple(placed),
        zones=tuple(zones_done),
        left_out=tuple(left_out),
        carrier=carrier,
        notes=tuple(notes),
        branches=branches,
    )


def refines_root_fillets(scene) -> bool:
    """Whether ``scene`` refines root fillets of the global model (some body names fine
    fillets, :func:`planetary_scene`): where the global model's own root stress is read
    (``numerics.root_stress = "global"``, and the check beside a submodel's)."""
    return any(g.body.fine_fillets for g in scene.gears)


#: The scenes a study case may name (``model.scene``), each ``builder(gearset, roll, **opts)``.
SCENES = {"one_branch": branch_scene, "all_planets": all_planets_scene, "system": system_scene}
if set(SCENES) != set(SCENE_NAMES):  # the case-file vocabulary and this registry are one list
    raise ImportError(f"meshing.scenes.SCENES {sorted(SCENES)} != cases SCENES {SCENE_NAMES}")


def build_scene(kind: str, gearset, roll: float = 0.0, **options) -> Scene:
    """The scene ``kind`` (a key of :data:`SCENES`) of ``gearset`` at sun angle ``roll``."""
    if kind not in SCENES:
        raise MeshingError(f"scene = {kind!r}: must be one of {', '.join(SCENES)}")
    return SCENES[kind](gearset, roll, **options)
