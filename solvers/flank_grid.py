"""Contact grids on the exact theoretical contact lines of a gear scene's mesh zones, on the
drive flanks and on the coast flanks.

Grid (:func:`flank_grid`). For one mesh zone of a scene (:mod:`meshing.mesh_zones`) and every
tooth pair in contact, the theoretical contact line is the intersection of the driver's
drive-flank helicoid with the plane of action. With the driver's base-circle tangency T, the
transverse line-of-action direction d (the driver's push, ``zone.direction``), the driver
unwinding sense s and the helix rotation rate k = d(helix_rotation)/dz (rad/mm), the flank
of tooth j touches the plane of action at roll

    t(z) = s (tau - theta0_j - k z),      p(z) = T + r_b t(z) d + z e_z,                (1)

a straight line (t is linear in z). Spur gear (k = 0, beta_b = 0): t(z) = s (tau - theta0_j)
is constant, the line is parallel to the axis at that roll and lies in the window over the
whole face or not at all,

    p(z) = T + r_b t d + z e_z (|z| <= b/2)  if t_lo <= t <= t_hi,  n = d,            (1a)

the limit k -> 0 of (1) and of the normal below. It is clipped to the common face width
|z| <= b/2 and to the zone's contact window (driver roll length between the driven gear's
tip / the driver's form circle and the driver's tip, ``zone.window``), then split into
n = round(L / h) equal segments (L its length, h the flank element size of the level); a
grid point sits at each segment's midpoint and stands for the patch (segment length) x
(width across, default h), spread over that patch by the gap operator (patch-averaged rows, see
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
stay open. :func:`flank_contact_pairs` puts the coast pairs after all drive pairs; under the
zone model the coast flanks get a zone grid of their own (below).

Zone grid (``[numerics] contact_model = "zone"``, :func:`zone_grid`). Instead of one row on
the theoretical lines, the flanks get a grid over the whole potential contact zone: per
transverse section and tooth pair within reach, cells across the contact line graded from
half the Hertz semi-width (the pair's contact modulus E*) to h / 2, wherever the unloaded
separation is within ``[numerics] zone_gap_limit_um`` of its reference, the section's
smallest separation over the tooth pairs in reach (on the drive flanks 0 on perfect
involutes, the modifications where there are any; on the coast flanks the backlash, plus
modifications; :func:`flank_contact_pairs` says why). How far the solved load reaches into
that band is checked after the solve (:mod:`solvers.zone_reach`). Its FE compliance comes from one
coarse point per section and its near field from the half-space (eq. (5) of
:mod:`solvers.contact`). Each zone point carries its own contact normal (n on the contact
line; off it the driven flank's normal where the driver's tip corner touches, the driver's
where the driven tip does, the bisector of the two elsewhere: :func:`contact_normals`);
every grid keeps the plane of action's n as its ``nominal_normal``, and the force a grid
transmits is sum_k F_k n_k.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from numbers import Real

import numpy as np

from gears.microgeometry import flank_modification
from gears.profile import involute_deviation, involute_normal
from meshing.mesh_zones import coast_zone, flank_of
from solvers.contact import ContactPair
from solvers.contact_grid import ContactGrid, ZoneLink

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
    fallback: str | None = None  # why a coast view got its line grid under the zone model
    corner: np.ndarray | None = None  # zone grids: per point CORNER_A / CORNER_B bit flags
    reference: np.ndarray | None = None  # zone grids: per point its section's smallest g0 (mm)
    gap_limit: float | None = None  # zone grids: cells kept where g0 < reference + this (mm)


def _helix_rate(gear) -> float:
    """k = d(helix_rotation)/dz (rad/mm); helix_rotation is linear in z."""
    return float(gear.helix_rotation(np.array([1.0]))[0] - gear.helix_rotation(np.array([0.0]))[0])


#: the spreading patch stays this far (mm) inside the tip / form circles of both gears
EDGE_MARGIN = 0.02


def _room(x: np.ndarray, u: np.ndarray, pg, half, n: int = 41) -> np.ndarray:
    """Largest S <= half with x + s u (|s| <= S) between the form and tip circles of ``pg``
    (``half`` one value, or one per point).

    The spreading patch runs across the contact line along the flank profile, and along the
    line obliquely across it (by tan(beta_b) per unit of face width); near a tip (or the
    form circle) a full patch would leave the tooth, and the gap operator would find no cell
    (at a 45 deg helix or the largest grid spacing the along-line half reached 0.1 mm past a
    tip). The patch is then narrowed symmetrically (its weight, the area the point stands
    for, is unchanged); a floor of half / 20, at most EDGE_MARGIN / 2, keeps it a patch that
    stays on the tooth from a point at a tip corner (half / 20 alone took a 5 mm grid's
    corner patches 0.066 mm past a tip).
    """
    g = pg.gear
    r_lo, r_hi = sorted((g.form_radius, g.tip_radius))
    r_lo, r_hi = r_lo + EDGE_MARGIN, r_hi - EDGE_MARGIN
    c = np.array([*pg.placement.centre])
    half = np.broadcast_to(np.asarray(half, dtype=float), (len(x),))
    s = np.linspace(-1.0, 1.0, n)[None, :] * half[:, None]  # (m, n)
    u = np.broadcast_to(u, np.shape(x))  # one direction, or one per point
    q = x[:, None, :2] - c + s[:, :, None] * u[:, None, :2]
    r = np.linalg.norm(q, axis=2)
    bad = (r < r_lo) | (r > r_hi)  # (m, n)
    dist = np.where(bad, np.abs(s), np.inf).min(axis=1)
    step = 2.0 * half / (n - 1)
    return np.clip(dist - step, np.minimum(half / 20, 0.5 * EDGE_MARGIN), half)


def _on_flank(x: np.ndarray, pg) -> np.ndarray:
    """Whether points x lie between the form and tip circles of ``pg`` (EDGE_MARGIN inside)."""
    g = pg.gear
    r_lo, r_hi = sorted((g.form_radius, g.tip_radius))
    r = np.hypot(x[:, 0] - pg.placement.centre[0], x[:, 1] - pg.placement.centre[1])
    return (r >= r_lo + EDGE_MARGIN) & (r <= r_hi - EDGE_MARGIN)


def _patch_halves(x_a, x_b, along, across, drv, dvn, half_along, half_across) -> np.ndarray:
    """(m, 2) half sizes of the spreading patches at x_a (driver) and x_b (driven), along
    the contact line and across it, each narrowed to stay on both flanks (:func:`_room`);
    then both are shrunk together (by 0.7, at most 6 times) where a corner of the patch
    still leaves a flank: the line runs obliquely over the flank, so a patch whose two axes
    each stay on it can still reach past a tip with a corner."""
    h = np.c_[
        np.minimum(_room(x_a, along, drv, half_along), _room(x_b, along, dvn, half_along)),
        np.minimum(_room(x_a, across, drv, half_across), _room(x_b, across, dvn, half_across)),
    ]
    u, v = np.broadcast_to(along, np.shape(x_a)), np.broadcast_to(across, np.shape(x_a))
    floor = np.minimum(h / 20, 0.5 * EDGE_MARGIN)
    for _ in range(6):
        off = [sa * h[:, :1] * u + sc * h[:, 1:] * v for sa in (-1, 1) for sc in (-1, 1)]
        out = ~np.all([_on_flank(x_a + d, drv) & _on_flank(x_b + d, dvn) for d in off], axis=0)
        out &= np.all(h > floor, axis=1)
        if not out.any():
            break
        h[out] = np.maximum(0.7 * h[out], floor[out])
    return h


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
        if c == 0.0:  # spur, eq. (1a): the whole face or nothing
            za, zb = (-math.inf, math.inf) if t_lo <= t0 <= t_hi else (0.0, 0.0)
        else:
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
    # along the line each patch stays within its segment of the line, which ends inside both
    # tip circles: only the width across is narrowed
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
        nominal_normal=n,
    )
    info = FlankGridInfo(lines, dev_a, dev_b, mic, mod_a, mod_b, zone.flanks)
    return grid, info


#: contact stress (MPa) whose Hertz semi-width the zone grid resolves near the contact line
DESIGN_CONTACT_STRESS = 1500.0
#: growth ratio of the zone grid's cells across the contact line, away from it
ZONE_GROWTH = 1.3
#: profile samples per section when searching the closest point of a tooth pair
ZONE_SAMPLES = 400
#: fixed-point steps (at most) and step size (mm) at which the ray to the driven flank stops
RAY_STEPS, RAY_TOL = 20, 1e-13
#: zone cells whose patch reaches a tip circle (bit flags): the driver's, the driven gear's
CORNER_A, CORNER_B = 1, 2


def _rotate(xy: np.ndarray, c: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Points or vectors xy (..., 2) turned by phi (...) about c (c = 0 for vectors)."""
    cs, sn = np.cos(phi), np.sin(phi)
    x, y = xy[..., 0] - c[0], xy[..., 1] - c[1]
    return np.stack([cs * x - sn * y + c[0], sn * x + cs * y + c[1]], axis=-1)


#: matching depth of the zone grid's FE far field below a coarse point, in coarse widths
MATCHING_DEPTH = 1.0


def _matching_depth(pg, other_side: str, x: np.ndarray, inward: np.ndarray, width: float):
    """Depth d (mm) below flank points x along ``inward`` (unit, into the tooth) where the
    FE and the half-space are matched: MATCHING_DEPTH x the coarse patch width, halved
    (at most 6 times) while the point would come closer than d / 4 to the tooth's other
    flank (``other_side``) or below the base circle, i.e. near a thin tip, or would leave the
    face width: the inward normal of a helical flank has an axial part (sin beta_b), which at
    a large helix angle carries a face-end row's point out of the body."""
    g = pg.gear
    d = np.full(len(x), MATCHING_DEPTH * width)
    for _ in range(6):
        y = pg.placement.inverse(x + d[:, None] * inward)
        ok = np.hypot(y[:, 0], y[:, 1]) > g.base_radius * (1 + 1e-9)
        dev = np.full(len(x), np.inf)
        dev[ok] = involute_deviation(g, y[ok], other_side)
        bad = (dev > -0.25 * d) | (np.abs(y[:, 2]) > 0.5 * g.face_width)
        if not bad.any():
            break
        d[bad] *= 0.5
    return d


def _vertex(v: np.ndarray, g: np.ndarray) -> float:
    """Abscissa of the vertex of the parabola through three points (v, g), kept within
    the outer two (the sampled minimum refined to below the sample spacing)."""
    d1, d2 = v[1] - v[0], v[1] - v[2]
    num = d1 * d1 * (g[1] - g[2]) - d2 * d2 * (g[1] - g[0])
    den = d1 * (g[1] - g[2]) - d2 * (g[1] - g[0])
    if den == 0.0:
        return float(v[1])
    return float(np.clip(v[1] - 0.5 * num / den, v[0], v[2]))


def _cells(v_c: float, d0: float, dmax: float, lo: float, hi: float) -> np.ndarray:
    """Cell boundaries across the line: a cell of width d0 centred on v_c, then cells growing
    by ZONE_GROWTH up to dmax on both sides, clipped to [lo, hi]."""
    right, left = [v_c + d0 / 2], [v_c - d0 / 2]
    w = d0
    while right[-1] < hi or left[-1] > lo:
        w = min(w * ZONE_GROWTH, dmax)
        right.append(right[-1] + w)
        left.append(left[-1] - w)
    e = np.clip(np.array(left[::-1] + right), lo, hi)
    return np.unique(e)


def contact_normals(dvn, driven_side: str, x: np.ndarray, n_a: np.ndarray, corner) -> np.ndarray:
    """The contact normal n_k of zone cells at driver flank points x (scene frame), from the
    driver's flank normal n_a there (out of the driver) and the driven flank's n_b: minus
    the driven gear's outward flank normal (:func:`gears.profile.involute_normal`) at x,
    which is its normal at x's nearest point on the driven flank (the distance is exact),
    so n_b, like n_a, points from the driver to the driven gear. Per cell (``corner``, bit
    flags of :func:`zone_grid`):

        CORNER_A (the cell reaches the driver's tip circle):    n_k = n_b
        CORNER_B (it reaches the driven gear's tip circle):     n_k = n_a
        otherwise (both flanks smooth; or both tips):         n_k = (cos(beta_b) u, n_z),
                                       u = (n_a,xy + n_b,xy) / |n_a,xy + n_b,xy|,

    the last the bisector of the two normals on their common cone: both flanks are
    helicoids of the base helix angle beta_b, every normal of either has the axial part
    n_z of the plane of action's n (asserted to 1e-12), so the half turn about the axis
    from n_a to n_b keeps n_z (the plain normalised sum n_a + n_b differs from it by
    O(theta^2), theta the angle between them)."""
    g = dvn.gear
    c, sn = math.cos(dvn.placement.angle), math.sin(dvn.placement.angle)
    loc = involute_normal(g, dvn.placement.inverse(x), driven_side)
    n_b = -np.c_[c * loc[:, 0] - sn * loc[:, 1], sn * loc[:, 0] + c * loc[:, 1], loc[:, 2]]
    if np.abs(n_b[:, 2] - n_a[:, 2]).max(initial=0.0) > 1e-12:
        raise RuntimeError("zone grid: the two flanks' normals differ in their axial part")
    u = n_a[:, :2] + n_b[:, :2]
    u *= (np.hypot(n_a[:, 0], n_a[:, 1]) / np.hypot(u[:, 0], u[:, 1]))[:, None]
    out = np.c_[u, n_a[:, 2]]
    corner = np.asarray(corner)
    out[corner == CORNER_A] = n_b[corner == CORNER_A]
    out[corner == CORNER_B] = n_a[corner == CORNER_B]
    return out


def zone_grid(
    zone,
    drv,
    dvn,
    spacing: float,
    width: float | None = None,
    micro: Callable | None = None,
    n_spread: int = 2,
    modifications: Mapping | None = None,
    gap_limit: float = 0.04,
    *,
    e_star: float,
) -> tuple[ContactGrid, FlankGridInfo, ZoneLink]:
    """Contact grid over the whole potential contact zone of a mesh zone (drive or coast view).

    Flank parameters. The driver's flank point that reaches the plane of action after the
    driver turns on by a roll Delta = t' - t(z) lies now at

        q(z, t') = Rot_z(s (t' - t(z))) (T + r_b t' d) + z e_z,   n_q = Rot_z(s (t' - t(z))) n,

    the rotation about the driver's axis, t(z) of eq. (1), t' the driver's roll from its form
    to its tip circle (0.02 mm margin): a transverse section z is the exact involute, and
    n_q the exact flank normal (the helicoid's normals lie in the turned plane of action).
    The separation is the distance along n_q to the driven flank, x_b = q + dev_B n_q on it
    (the root of dev_B(q + s n_q) = 0 by fixed-point steps s <- s + dev_B, which converge
    like 1 - cos of the angle between n_q and the driven flank's normal, to 1e-13 mm), only
    where q lies between the driven gear's form and tip circles (margins as in
    :func:`flank_grid`).

    Normals. Every grid point carries its own contact normal n_k (driver -> driven): the
    gap, the gap operator's rows, the rigid columns and the force F_k n_k all act along it
    (:func:`contact_normals`). On the contact line the two flank normals coincide (n, the
    plane of action's); off it the driver's n_q turns by about v / rho_a and the driven
    flank's n_b (at the nearest driven flank point) by about -v / rho_b (v the profile
    distance from the line), so they differ by about v / R (R the relative radius of
    curvature): several degrees at the band's edge (~0.7 mm at the 40 um limit), where a
    tilted pinion's face-end load sits. The rule, from the mechanics of the contact there:

    * a cell whose patch reaches the driver's tip circle (``CORNER_A``): the driver touches
      with its tip corner, which has no normal, the driven flank is smooth there: the
      traction of an edge on a smooth face acts along the face's normal, n_k = n_b;
    * a cell reaching the driven gear's tip circle (``CORNER_B``): likewise n_k = n_q;
    * elsewhere both flanks are smooth and nearly conformal (angle theta ~ v / R between
      them): under load they deform into one interface whose normal lies between the two;
      for equal elastic half-spaces (same material, Hertz: both surfaces displace equally
      and oppositely) it is turned half-way, n_k = the bisector of n_q and n_b on their
      common cone (equal n_z, the half turn about the axis: :func:`contact_normals`); with
      unequal moduli the interface would turn towards the stiffer body's normal (not
      modelled: the bisector is kept for every pair).

    The gap is the distance from q along n_k to the driven flank (the fixed-point steps of
    ``separation``); at a driver tip corner it is exactly dev_B (q's distance from the
    driven flank). Every point force acts on one line through x_a and x_b, so the forces of
    a mesh balance both gears exactly; but off the line the arm of F_k n_k about a gear's
    axis is not exactly its r_b cos(beta_b) (that holds only along that gear's own flank
    normal): with the bisector the driver's and the driven gear's arms are each off by about
    theta / 2 times rho / r_b. The mesh force is sum_k F_k n_k; the plane of action's n is
    kept as the grid's ``nominal_normal`` (:class:`solvers.contact_grid.ContactGrid`), the
    direction readers project on.

    The choice of normal is a model uncertainty of about +-1.2 % on the moments where tip
    corners carry load (1-GC, an overturned pinion; this rule sits between the two
    single-flank choices) and none where the load sits on the contact line (1-GA)
    (``studies.benchmarks.contact``; measured: docs/validation.md).

    Grid. Per tooth pair within reach (every driver tooth whose roll t(z) lies within one
    base pitch of the contact window somewhere on the face, so at least one pair beyond the
    theoretical path each side) and per transverse section z_i (b / dz = round(b N / h)
    sections across the common face width b, where both flanks exist; the wider gear's
    overhang acts through its FE body; N = sqrt(1 + (k r_b)^2), each standing for the
    length seg = dz N along the contact line): g0(t') = dev_A + dev_B + mod_A + mod_B
    (+ micro) on ZONE_SAMPLES points; the section is centred on its smallest g0, and cut
    across the line (along the profile arc v = r_b (t'^2 - t(z)^2) / 2, the distance from
    the contact line on the developed flank) into cells of width d0 at the centre growing by
    ZONE_GROWTH to h / 2. d0 = a_H / 2 with the Hertz semi-width at the design contact
    stress p_d = DESIGN_CONTACT_STRESS,

        a_H = 2 R p_d / E*,   d0 = R p_d / E*   (clipped to [0.01 mm, h / 2]),          (2)

    (from a_H = sqrt(4 w R / (pi E*)) and p_d = sqrt(w E* / (pi R)): at a given stress the
    band widens as 1 / E*), R the relative radius of curvature there (1/R = 1/rho_a +-
    1/rho_b, rho the roll lengths), ``e_star`` the pair's contact modulus (MPa), 1/E* =
    (1 - nu_A^2)/E_A + (1 - nu_B^2)/E_B of the study's material, the one the penalty and the
    half-space use (:mod:`solvers.contact`). A cell is kept where g0 at its centre is below
    g_ref(z_i) + ``gap_limit`` (mm), g_ref(z_i) the smallest g0 of the section over every
    tooth pair in reach (:func:`flank_contact_pairs` says why; ``FlankGridInfo.reference``
    holds it per cell, for :mod:`solvers.zone_reach`). It stands for
    the patch seg x (cell width) and is
    spread over it by the gap operator as the line grid's points are. The cells end 0.02 mm
    inside the tip and form circles of both gears (the tooth models have sharp tips, no tip
    rounding), so tip and corner contact beyond the path is caught by the last cells there.

    Coarse grid (FE far field, :class:`solvers.contact_grid.ZoneLink`): one point per kept
    section and tooth pair at the section's centre (the theoretical contact line on pairs in
    the path, where n_q = n up to the vertex refinement; the closest corner beyond the path),
    with the flank normal n_q there, patch seg x ``width`` (default h) along the turned line
    and across, narrowed at tips as in :func:`flank_grid`; every fine point of the section
    takes its column (the fine normals differ from the coarse one by the turn across the
    section, the far field is taken along the coarse one). The
    matching depth below it in each tooth (:func:`_matching_depth`): one coarse width, less
    near a thin tip.
    Independent of the FE mesh: h only sets the coarse spacing.
    """
    w_across = spacing if width is None else width
    ga, gb = drv.gear, dvn.gear
    fa = flank_of(ga, zone.driver_side)
    s, rb = fa.s, fa.rb
    k = _helix_rate(ga)
    nn = math.sqrt(1.0 + (k * rb) ** 2)
    d = np.array([*zone.direction, 0.0])
    ez = np.array([0.0, 0.0, 1.0])
    T0 = np.array([*zone.tangency, 0.0])
    n = (d + s * k * rb * ez) / nn
    tline = (-s * k * rb * d + ez) / nn
    t2 = np.cross(n, tline)
    ca = np.array([*drv.placement.centre])
    cb = np.array([*dvn.placement.centre])
    b = min(ga.face_width, gb.face_width)
    m_z = max(1, round(b * nn / spacing))
    dz = b / m_z
    zc = -0.5 * b + (np.arange(m_z) + 0.5) * dz
    seg = dz * nn
    ra = (ga.form_radius + EDGE_MARGIN, ga.tip_radius - EDGE_MARGIN)
    rb_lo, rb_hi = sorted((gb.form_radius, gb.tip_radius))
    rb_lo, rb_hi = rb_lo + EDGE_MARGIN, rb_hi - EDGE_MARGIN
    # samples uniform in the involute arc sigma = r_b t^2 / 2
    sig = np.linspace(*(0.5 * (r * r - rb * rb) / rb for r in ra), ZONE_SAMPLES)
    t_s = np.sqrt(2.0 * sig / rb)
    t_lo, t_hi = (w / rb for w in zone.window)
    pitch = 2 * math.pi / ga.teeth
    c_dt = -s * k  # dt/dz
    g_len = zone.centre_distance * math.sin(zone.pressure_angle)
    if isinstance(e_star, bool) or not isinstance(e_star, Real) or not 0 < e_star < math.inf:
        raise ValueError(f"zone {zone.name}: e_star = {e_star!r} must be a finite number > 0 MPa")
    e_star = float(e_star)
    mods = modifications or {}
    dmax = 0.5 * spacing

    def flank_points(z, tp, tz):
        """q, n_q, tangents (tline, t2) turned, at sections z (m,) and rolls tp (m,)."""
        phi = s * (tp - tz)
        p2 = T0[None, :2] + (rb * tp)[:, None] * d[None, :2]
        q = np.c_[_rotate(p2, ca[:2], phi), z]

        def turn(vec):
            xy = _rotate(np.broadcast_to(vec[:2], (len(phi), 2)), (0.0, 0.0), phi)
            return np.c_[xy, np.full(len(phi), vec[2])]

        return q, turn(n), turn(tline), turn(t2)

    def separation(q, nq):
        """dev_A, the ray distance from q along n_q to the driven flank (fixed-point steps
        on the normal distance until a step is below RAY_TOL; the normals differ by about
        v / R off the line), the modifications and their sum with micro."""
        la, lb = drv.placement.inverse(q), dvn.placement.inverse(q)
        dev_a = involute_deviation(ga, la, zone.driver_side)
        dev_b = involute_deviation(gb, lb, zone.driven_side)
        for _ in range(RAY_STEPS):
            xb = dvn.placement.inverse(q + dev_b[:, None] * nq)
            # mm; the rest lies far beyond any gap limit (or off the helicoid)
            near = (np.abs(dev_b) < 0.5) & (np.hypot(xb[:, 0], xb[:, 1]) > gb.base_radius)
            step = involute_deviation(gb, xb[near], zone.driven_side)
            dev_b[near] += step
            if not np.abs(step).max(initial=0.0) > RAY_TOL:
                break
        mod_a = flank_modification(ga, mods.get(drv.gear_name), zone.driver_side, la)
        mod_b = flank_modification(gb, mods.get(dvn.gear_name), zone.driven_side, lb)
        mic = mod_a + mod_b
        if micro is not None:
            mic = mic + np.asarray(micro(zone, q), float).reshape(len(q))
        return dev_a, dev_b, mod_a, mod_b, mic

    # pass 1: the unloaded separation g0(t') of every section of every tooth pair in reach
    sampled = []
    for j_a in range(ga.teeth):
        theta0 = fa.theta0 + j_a * pitch + drv.placement.angle
        t0 = s * ((((zone.tau - theta0) + math.pi) % (2 * math.pi)) - math.pi)
        tz = t0 + c_dt * zc
        if tz.max() < t_lo - pitch or tz.min() > t_hi + pitch:
            continue  # beyond reach: more than a base pitch outside the window
        Z = np.repeat(zc, ZONE_SAMPLES)
        TP = np.tile(t_s, m_z)
        TZ = np.repeat(tz, ZONE_SAMPLES)
        q, nq_s, _, _ = flank_points(Z, TP, TZ)
        rad_b = np.hypot(q[:, 0] - cb[0], q[:, 1] - cb[1])
        okf = (rad_b >= rb_lo) & (rad_b <= rb_hi)
        if not okf.any():
            continue
        g = np.full(len(q), np.inf)
        dev_a, dev_b, _, _, mic = separation(q[okf], nq_s[okf])
        g[okf] = dev_a + dev_b + mic
        sampled.append(
            (
                j_a,
                tz,
                okf.reshape(m_z, ZONE_SAMPLES),
                g.reshape(m_z, ZONE_SAMPLES),
                rad_b.reshape(m_z, ZONE_SAMPLES),
            )
        )
    # the reference each cell's g0 is held against: per section the smallest g0 over every
    # tooth pair in reach (inf where no pair has flank there)
    g_ref = np.min(
        [np.where(ok, g, np.inf).min(axis=1) for _, _, ok, g, _ in sampled]
        or [np.full(m_z, np.inf)],
        axis=0,
    )
    limit = g_ref + gap_limit
    # pass 2: cells of each section where g0 < limit
    keys = ("z", "t", "tz", "dv", "v", "sec", "grp", "corner", "ref")
    fine: dict[str, list] = {key: [] for key in keys}
    coarse: dict[str, list] = {key: [] for key in ("z", "t", "tz", "v", "grp")}
    lines = []
    n_fine = 0
    for j_a, tz, ok, g, rad in sampled:
        v = 0.5 * rb * (t_s[None, :] ** 2 - tz[:, None] ** 2)
        grp = len(lines)
        first = n_fine
        z_used = []
        for i in range(m_z):
            if not ok[i].any():
                continue
            gi = np.where(ok[i], g[i], np.inf)
            c_i = int(np.argmin(gi))
            if not gi[c_i] < limit[i]:
                continue
            vi = v[i, ok[i]]
            v_c = v[i, c_i]
            if 0 < c_i < ZONE_SAMPLES - 1 and np.isfinite(gi[c_i - 1 : c_i + 2]).all():
                v_c = _vertex(v[i, c_i - 1 : c_i + 2], gi[c_i - 1 : c_i + 2])
            t_c = math.sqrt(2.0 * v_c / rb + tz[i] ** 2)
            rho_a = rb * t_c
            rho_b = g_len + rho_a if zone.internal else max(g_len - rho_a, 0.1 * rho_a)
            curv = 1.0 / rho_a + (-1.0 if zone.internal else 1.0) / rho_b
            d0 = float(np.clip(DESIGN_CONTACT_STRESS / (e_star * curv), 0.01, dmax))
            edges = _cells(v_c, d0, dmax, vi.min(), vi.max())
            vc = 0.5 * (edges[1:] + edges[:-1])
            # which tip corner the section's first and last cells reach (their patch ends
            # on the section's end, the last sample where both flanks exist)
            corner = np.zeros(len(vc), dtype=int)
            idx = np.flatnonzero(ok[i])
            for end, j in ((0, idx[0]), (-1, idx[-1])):
                if j == ZONE_SAMPLES - 1:
                    corner[end] |= CORNER_A  # ends on the driver's tip circle
                elif j > 0 and abs(rad[i, j] - gb.tip_radius) < abs(rad[i, j] - gb.form_radius):
                    corner[end] |= CORNER_B  # ends on the driven gear's tip circle
            dv = np.diff(edges)
            gc = np.interp(vc, vi, g[i, ok[i]])
            keep = (gc < limit[i]) & (dv > 0.05 * d0)
            if not keep.any():
                continue
            sec = len(coarse["z"])
            coarse["z"].append(zc[i])
            coarse["t"].append(t_c)
            coarse["tz"].append(tz[i])
            coarse["v"].append(v_c)
            coarse["grp"].append(grp)
            m = int(keep.sum())
            fine["z"].append(np.full(m, zc[i]))
            fine["t"].append(np.sqrt(2.0 * vc[keep] / rb + tz[i] ** 2))  # v -> t'
            fine["tz"].append(np.full(m, tz[i]))
            fine["dv"].append(dv[keep])
            fine["v"].append(vc[keep])
            fine["sec"].append(np.full(m, sec))
            fine["grp"].append(np.full(m, grp))
            fine["corner"].append(corner[keep])
            fine["ref"].append(np.full(m, g_ref[i]))
            n_fine += m
            z_used.append(zc[i])
        if n_fine == first:
            continue
        lines.append(
            {
                "driver_tooth": int(j_a),
                "driven_tooth": -1,  # set below from the points
                "rows": (first, n_fine),
                "length": float(len(z_used) * seg),
                "spacing": float(seg),
                "z_range": (float(min(z_used) - dz / 2), float(max(z_used) + dz / 2)),
            }
        )
    if not lines:
        raise ValueError(
            f"zone {zone.name}: no flank point within {gap_limit * 1e3:g} um of the smallest "
            "separation"
        )
    F = {key: np.concatenate(val) for key, val in fine.items()}
    x, nq, tl, tt = flank_points(F["z"], F["t"], F["tz"])  # n_q: the flank normal per point
    nk = contact_normals(dvn, zone.driven_side, x, nq, F["corner"])
    dev_a, dev_b, mod_a, mod_b, mic = separation(x, nk)
    m = len(x)
    C = {key: np.asarray(val) for key, val in coarse.items()}
    xc, nc, tlc, ttc = flank_points(C["z"], C["t"], C["tz"])
    dva_c, dvb_c, _, _, mic_c = separation(xc, nc)
    pitch_b = 2 * math.pi / gb.teeth
    sb = 1 if zone.driven_side == "pos" else -1
    for ln in lines:
        a, e = ln["rows"]
        local = dvn.placement.inverse(x[a:e])
        th = np.arctan2(local[:, 1], local[:, 0]) - gb.helix_rotation(local[:, 2])
        ln["driven_tooth"] = int(np.round(np.median(th) / pitch_b - 0.25 * sb)) % gb.teeth
    mc = len(xc)
    depth_a = _matching_depth(drv, zone.coast_sides[0], xc, -nc, w_across)
    xbc = xc + dvb_c[:, None] * nc
    depth_b = _matching_depth(dvn, zone.coast_sides[1], xbc, nc, w_across)
    halves_c = _patch_halves(xc, xbc, tlc, ttc, drv, dvn, 0.5 * seg, 0.5 * w_across)
    half_c = halves_c[:, 1]
    # a fine cell's patch: its section's length along the line, its width dv across it
    x_b = x + dev_b[:, None] * nk
    half_fine = _patch_halves(x, x_b, tl, tt, drv, dvn, 0.5 * seg, 0.5 * F["dv"])
    coarse_grid = ContactGrid(
        f"{zone.name}#coarse",
        xc,
        xbc,
        nc,
        dva_c + dvb_c + mic_c,
        np.full(mc, seg * w_across),
        tangents=np.stack([tlc, ttc], axis=1),
        half_sizes=halves_c,
        stations=np.arange(mc),
        station_length=np.full(mc, seg),
        n_spread=n_spread,
        nominal_normal=n,
    )
    grid = ContactGrid(
        zone.name,
        x,
        x_b,
        nk,
        dev_a + dev_b + mic,
        seg * F["dv"],
        tangents=np.stack([tl, tt], axis=1),
        half_sizes=half_fine,
        stations=F["sec"].astype(int),
        station_length=np.full(mc, seg),
        n_spread=n_spread,
        nominal_normal=n,
    )
    link = ZoneLink(
        coarse_grid,
        F["sec"].astype(int),
        np.c_[nn * F["z"], F["v"]],
        np.c_[np.full(m, 0.5 * seg), 0.5 * F["dv"]],
        np.c_[nn * C["z"], C["v"]],
        np.c_[np.full(mc, 0.5 * seg), half_c],
        F["grp"].astype(int),
        C["grp"].astype(int),
        depth_a,
        depth_b,
    )
    info = FlankGridInfo(
        lines,
        dev_a,
        dev_b,
        mic,
        mod_a,
        mod_b,
        zone.flanks,
        corner=F["corner"].astype(int),
        reference=F["ref"],
        gap_limit=float(gap_limit),
    )
    return grid, info, link


def flank_contact_pairs(
    scene,
    spacing: float,
    width,
    micro,
    *,
    modifications: Mapping | None = None,
    coast: bool = True,
    contact_model: str = "line",
    gap_limit: float = 0.04,
    e_plane: Mapping[str, float] | None = None,
):
    """Contact grids on the exact theoretical contact lines of every mesh zone of the scene,
    and the contact pairs (driver, driven) that carry them: the drive-flank pairs of every
    zone first, then (``coast``) the coast-flank pairs, ``standby`` (open by the backlash).

    Returns ``(grids, pairs)``, ``grids`` by grid name: ``driver-driven`` (drive flanks) and
    ``driver-driven/coast`` (coast flanks), each (grid, :class:`FlankGridInfo`).
    ``modifications``: the gear set's flank modifications by gear name
    (:attr:`cases.gearset.GearSet.modifications`).

    ``contact_model`` "zone" (:attr:`cases.study_case.Numerics.contact_model`): every flank
    pair gets :func:`zone_grid` with its FE link, graded with the pair's contact modulus
    1/E* = 1/E'_driver + 1/E'_driven from ``e_plane`` (plane-strain modulus E / (1 - nu^2)
    by body name, required; as :mod:`solvers.contact` forms it for the penalty and the
    half-space). Drive and coast flanks alike: points where g0 < g_ref(z) + ``gap_limit``,
    g_ref(z) the smallest separation of the transverse section z over every tooth pair in
    reach. Why per section: the flanks close under a rigid tilt or misalignment of a body
    (an overturned pinion), which changes the gap linearly along the face, and under lead
    modifications, which vary along the face; a reference per section keeps every
    section's closest band, so the face ends, where a tilt closes the backlash first or a
    crown opens the drive flanks, are always on the grid (with one reference per zone, a
    lead crown of more than ``gap_limit`` would drop them and a tilt that closes them again
    would not be seen).
    Why over the tooth pairs of the section, not per pair: within a section the pairs see
    about the same body motion, so a pair whose separation exceeds the section's smallest by
    more than ``gap_limit`` (the corners of the pairs beyond the path) cannot close first;
    a reference per pair would lay a band at every such corner. On perfect involutes g_ref
    is 0 on the drive flanks and the normal backlash j_n on the coast flanks, on every
    section; the contact lines carry the smallest cells, and the coast grid is the drive
    grid's mirror image. Whether the band was wide enough is checked on the solved loads
    (:func:`solvers.zone_reach.check_zone_reach`).
    Fallback: a coast view where :func:`zone_grid` finds no cell (no tooth pair in reach;
    its ``ValueError``) gets its contact-line grid (:func:`flank_grid`, penalty contact as
    in the line model) and ``FlankGridInfo.fallback`` says so, with a warning; the coast
    flanks are never dropped. The drive flanks have no fallback: no drive cell within the
    limit is an error."""
    views = list(scene.zones)
    if coast:
        views += [coast_zone(zn, scene.gear(zn.driver), scene.gear(zn.driven)) for zn in views]
    grids, pairs = {}, []
    if contact_model not in ("line", "zone"):
        raise ValueError(f"contact_model = {contact_model!r}: must be 'line' or 'zone'")
    for zn in views:
        drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
        link, note = None, None
        if contact_model == "zone":
            e_star = pair_contact_modulus(e_plane, zn.driver, zn.driven)
            try:
                g, info, link = zone_grid(
                    zn,
                    drv,
                    dvn,
                    spacing,
                    width,
                    micro,
                    modifications=modifications,
                    gap_limit=gap_limit,
                    e_star=e_star,
                )
            except ValueError as err:
                if zn.flanks != "coast":
                    raise
                note = f"{err}; the coast flanks keep their contact-line grid"
                warnings.warn(note, stacklevel=2)
        if link is None:
            g, info = flank_grid(zn, drv, dvn, spacing, width, micro, modifications=modifications)
            info.fallback = note
        grids[g.name] = (g, info)
        pairs.append(ContactPair(g, zn.driver, zn.driven, standby=zn.flanks == "coast", link=link))
    return grids, pairs


def pair_contact_modulus(e_plane: Mapping[str, float] | None, a: str, b: str) -> float:
    """E* (MPa) of the bodies ``a`` and ``b``: 1/E* = sum 1/E'_i over those in ``e_plane``
    (plane-strain modulus E / (1 - nu^2) by body name; a rigid obstacle is not in it)."""
    if not e_plane:
        raise ValueError("contact_model = 'zone' needs e_plane (E / (1 - nu^2) by body name)")
    e = [float(e_plane[nm]) for nm in (a, b) if nm in e_plane]
    if not e or not all(math.isfinite(v) and v > 0 for v in e):
        raise ValueError(f"pair {a}-{b}: no finite plane-strain modulus > 0 in e_plane")
    return 1.0 / sum(1.0 / v for v in e)


def is_coast(grid_name: str) -> bool:
    """True for the name of a coast-flank grid (``driver-driven/coast``)."""
    return grid_name.endswith(COAST)


def mesh_name(grid_name: str) -> str:
    """The mesh (``driver-driven``) a drive or coast grid belongs to."""
    return grid_name.removesuffix(COAST)
