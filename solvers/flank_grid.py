"""Contact grids on the exact theoretical contact lines of a gear scene's mesh zones, on the
drive flanks and on the coast flanks.

Grid (:func:`flank_grid`). For one mesh zone of a scene (:mod:`meshing.mesh_zones`) and every
tooth pair in contact, the theoretical contact line is the intersection of the driver's
drive-flank helicoid with the plane of action. With the driver's base-circle tangency T, the
transverse line-of-action direction d (the driver's push, ``zone.direction``), the driver
unwinding sense s and the helix rotation rate k = d(helix_rotation)/dz (rad/mm), the flank
of tooth j touches the plane of action at roll

    t(z) = s (tau - theta0_j - k z),      p(z) = T + r_b t(z) d + z e_z,                (1)

a straight line (t is linear in z). It is clipped to the common face width |z| <= b/2 and to
the zone's contact window (driver roll length between the driven gear's tip / the driver's
form circle and the driver's tip, ``zone.window``), then split into n = round(L / h)
equal segments (L its length, h the flank element size of the level); a grid point sits at
each segment's midpoint and stands for the patch (segment length) x (width across, default
h), spread over that patch by the gap operator (patch-averaged rows, see
:mod:`solvers.contact_grid`).

Normal (derivation and sign). The involute helicoid's normals lie in the plane of action
and are perpendicular to its straight generators, the contact lines. From (1) the line
direction is dp/dz = -s k r_b d + e_z, so the unit normal in the plane of action is

    n = (d + s k r_b e_z) / sqrt(1 + (k r_b)^2) = cos(beta_b) d + s k r_b cos(beta_b) e_z,

since |k| r_b = tan(beta_b) (base helix angle): the transverse line of action inclined by
beta_b out of the transverse plane. n points from the driver (side A) to the driven gear
(side B) because d is the driver's push; the z sign is s sign(k) (case 1: n_z < 0 at both
meshes, the sun pushes the pinion towards -z). A test checks n against the gradient of the
exact flank distance.

Initial gap. g0 = dev_A(p) + dev_B(p) + mod_A(p) + mod_B(p) (+ micro), dev the signed normal
distance outside the material from :func:`gears.profile.involute_deviation` of each exact
flank: for two flanks with common normal at p the separation along n is the sum of the two
distances, and it is 0 (to ~1e-13 mm) on the theoretical drive lines of perfect involutes.
mod the material the flank modifications of each gear remove there
(:func:`gears.microgeometry.flank_modification`, ``modifications`` by gear-set gear name:
lead crown, lead slope, tip and end relief; the FE meshes keep the exact flanks), and
``micro(zone, points) -> (n,) mm`` any further gap (misalignment; default none). The point
on side B is moved onto the exact driven flank, x_b = p + dev_B n (dev_B is the backlash on
a coast line, ~1e-13 mm on a drive line); the modifications move no point.

Coast flanks. The same construction on :func:`meshing.mesh_zones.coast_zone`, the zone seen
from its coast flanks (sides swapped, the mirrored plane of action, its own contact lines):
the coast grid (``<driver>-<driven>/coast``) has the driver's coast flank on side A, the
normal out of it towards the driven gear, and g0 = the exact coast separation, the normal
backlash j_n (plus the modifications of the coast flanks). It carries force only where its
gap closes (penalty contact with an active set, :mod:`solvers.contact`): an overturned
pinion whose tilt across the face exceeds the backlash loads its coast flanks; otherwise they
stay open. :func:`flank_contact_pairs` puts the coast pairs after all drive pairs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from gears.microgeometry import flank_modification
from gears.profile import involute_deviation
from meshing.mesh_zones import coast_zone, flank_of
from solvers.contact import ContactPair
from solvers.contact_grid import ContactGrid

#: grid-name suffix of the coast-flank grids ("sun-pinion/coast", ``MeshZone.name``)
COAST = "/coast"


@dataclass
class FlankGridInfo:
    """What :func:`flank_grid` laid out, beyond the :class:`ContactGrid` arrays."""

    lines: list[dict]  # per tooth pair: driver tooth, driven tooth, rows, length, spacing
    dev_a: np.ndarray  # involute_deviation of the driver's flank at the points (mm)
    dev_b: np.ndarray  # the same for the driven gear's flank
    micro: np.ndarray  # microgeometry / misalignment part of g0 (mm): mod_a + mod_b + micro
    mod_a: np.ndarray | None = None  # flank modifications of the driver at the points (mm)
    mod_b: np.ndarray | None = None  # the same for the driven gear
    flanks: str = "drive"  # "drive" or "coast"


def _helix_rate(gear) -> float:
    """k = d(helix_rotation)/dz (rad/mm); helix_rotation is linear in z."""
    return float(gear.helix_rotation(np.array([1.0]))[0] - gear.helix_rotation(np.array([0.0]))[0])


#: the spreading patch stays this far (mm) inside the tip / form circles of both gears
EDGE_MARGIN = 0.02


def _room(x: np.ndarray, u: np.ndarray, pg, half: float, n: int = 41) -> np.ndarray:
    """Largest S <= half with x + s u (|s| <= S) between the form and tip circles of ``pg``.

    Across the contact line the spreading patch runs along the flank profile; near a tip
    (or the form circle) a full patch would leave the tooth, and the gap operator would find
    no cell. The patch is then narrowed symmetrically (its weight, the area the point stands
    for, is unchanged); a floor of half / 20 keeps it a patch.
    """
    g = pg.gear
    r_lo, r_hi = sorted((g.form_radius, g.tip_radius))
    r_lo, r_hi = r_lo + EDGE_MARGIN, r_hi - EDGE_MARGIN
    c = np.array([*pg.placement.centre])
    s = np.linspace(-half, half, n)
    q = x[:, None, :2] - c + s[None, :, None] * u[None, None, :2]
    r = np.linalg.norm(q, axis=2)
    bad = (r < r_lo) | (r > r_hi)  # (m, n)
    dist = np.where(bad, np.abs(s)[None, :], np.inf).min(axis=1)
    step = s[1] - s[0]
    return np.clip(dist - step, half / 20, half)


def flank_grid(
    zone,
    drv,
    dvn,
    spacing: float,
    width: float | None = None,
    micro: Callable | None = None,
    n_spread: int = 2,
    modifications: Mapping | None = None,
) -> tuple[ContactGrid, FlankGridInfo]:
    """Contact grid of one mesh zone on the theoretical contact lines, eq. (1).

    Args:
        zone: :class:`meshing.mesh_zones.MeshZone` (with ``contact_lines``: the tooth pairs),
            the drive view or the coast view (:func:`meshing.mesh_zones.coast_zone`): the
            grid lies on the flanks ``zone.driver_side`` / ``zone.driven_side``.
        drv, dvn: the driver and driven :class:`meshing.mesh_zones.PlacedGear`.
        spacing: target point spacing along the line (mm), ~ the flank element size.
        width: patch width across the line (mm); default ``spacing``.
        micro: optional ``micro(zone, points (n, 3)) -> (n,)`` added to g0 (mm).
        modifications: flank modifications (:class:`gears.microgeometry.FlankModifications`)
            by gear-set gear name (``PlacedGear.gear_name``); a gear not in it has none.
    """
    w_across = spacing if width is None else width
    ga, gb = drv.gear, dvn.gear
    fa = flank_of(ga, zone.driver_side)
    s, rb = fa.s, fa.rb
    k = _helix_rate(ga)
    d = np.array([*zone.direction, 0.0])
    ez = np.array([0.0, 0.0, 1.0])
    T0 = np.array([*zone.tangency, 0.0])
    n = (d + s * k * rb * ez) / math.sqrt(1.0 + (k * rb) ** 2)
    tline = (-s * k * rb * d + ez) / math.sqrt(1.0 + (k * rb) ** 2)
    t2 = np.cross(n, tline)
    b = min(ga.face_width, gb.face_width)
    t_lo, t_hi = (w / rb for w in zone.window)
    pitch = 2 * math.pi / ga.teeth
    pts, sp, lines = [], [], []
    for j_a, j_b, _ in zone.contact_lines:
        theta0 = fa.theta0 + j_a * pitch + drv.placement.angle
        t0 = s * ((((zone.tau - theta0) + math.pi) % (2 * math.pi)) - math.pi)
        c = -s * k  # dt/dz
        za, zb = sorted(((t_lo - t0) / c, (t_hi - t0) / c))
        z0, z1 = max(za, -0.5 * b), min(zb, 0.5 * b)
        if z1 - z0 <= 1e-9:
            continue
        length = (z1 - z0) * math.sqrt(1.0 + (k * rb) ** 2)
        m = max(1, round(length / spacing))
        z = z0 + (np.arange(m) + 0.5) * (z1 - z0) / m
        t = t0 + c * z
        p = T0[None, :] + (rb * t)[:, None] * d[None, :] + z[:, None] * ez[None, :]
        lines.append(
            {
                "driver_tooth": int(j_a),
                "driven_tooth": int(j_b),
                "rows": (sum(len(q) for q in pts), sum(len(q) for q in pts) + m),
                "length": float(length),
                "spacing": float(length / m),
                "z_range": (float(z0), float(z1)),
            }
        )
        pts.append(p)
        sp.append(np.full(m, length / m))
    if not pts:
        raise ValueError(f"zone {zone.driver}/{zone.driven}: no contact line in the face width")
    x = np.vstack(pts)
    seg = np.concatenate(sp)
    m = len(x)
    local_a, local_b = drv.placement.inverse(x), dvn.placement.inverse(x)
    dev_a = involute_deviation(ga, local_a, zone.driver_side)
    dev_b = involute_deviation(gb, local_b, zone.driven_side)
    mods = modifications or {}
    mod_a = flank_modification(ga, mods.get(drv.gear_name), zone.driver_side, local_a)
    mod_b = flank_modification(gb, mods.get(dvn.gear_name), zone.driven_side, local_b)
    mic = mod_a + mod_b
    if micro is not None:
        mic = mic + np.asarray(micro(zone, x), float).reshape(m)
    tangents = np.broadcast_to(np.stack([tline, t2]), (m, 2, 3)).copy()
    half_across = np.minimum(_room(x, t2, drv, 0.5 * w_across), _room(x, t2, dvn, 0.5 * w_across))
    grid = ContactGrid(
        zone.name,
        x.copy(),
        x + dev_b[:, None] * n[None, :],
        np.tile(n, (m, 1)),
        dev_a + dev_b + mic,
        seg * w_across,
        tangents=tangents,
        half_sizes=np.c_[0.5 * seg, half_across],
        stations=np.arange(m),
        station_length=seg.copy(),
        n_spread=n_spread,
    )
    info = FlankGridInfo(lines, dev_a, dev_b, mic, mod_a, mod_b, zone.flanks)
    return grid, info


def flank_contact_pairs(
    scene, spacing: float, width, micro, *, modifications: Mapping | None = None,
    coast: bool = True,
):  # fmt: skip
    """Contact grids on the exact theoretical contact lines of every mesh zone of the scene,
    and the contact pairs (driver, driven) that carry them: the drive-flank pairs of every
    zone first, then (``coast``) the coast-flank pairs.

    Returns ``(grids, pairs)``, ``grids`` by grid name: ``driver-driven`` (drive flanks) and
    ``driver-driven/coast`` (coast flanks), each (grid, :class:`FlankGridInfo`).
    ``modifications``: the gear set's flank modifications by gear name
    (:attr:`cases.gearset.GearSet.modifications`)."""
    views = list(scene.zones)
    if coast:
        views += [coast_zone(zn, scene.gear(zn.driver), scene.gear(zn.driven)) for zn in views]
    grids, pairs = {}, []
    for zn in views:
        g, info = flank_grid(zn, scene.gear(zn.driver), scene.gear(zn.driven), spacing, width,
                             micro, modifications=modifications)  # fmt: skip
        grids[g.name] = (g, info)
        pairs.append(ContactPair(g, zn.driver, zn.driven, standby=zn.flanks == "coast"))
    return grids, pairs


def is_coast(grid_name: str) -> bool:
    """True for the name of a coast-flank grid (``driver-driven/coast``)."""
    return grid_name.endswith(COAST)


def mesh_name(grid_name: str) -> str:
    """The mesh (``driver-driven``) a drive or coast grid belongs to."""
    return grid_name.removesuffix(COAST)
