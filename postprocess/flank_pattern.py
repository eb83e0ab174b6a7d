"""Contact patterns on the exact flanks: the Hertz pressure of every solved mesh position
mapped onto one representative tooth of each gear and accumulated over the mesh cycle.

Flank coordinates
-----------------
A drive flank (side s = +1 ``pos`` / -1 ``neg``) of a gear is an involute helicoid. In the
gear's own frame (:mod:`gears.spec`: z = 0 at mid face width, tooth 0 symmetric about +x)
the flank of tooth k is, with roll length u (mm) and axial position z (mm),

    r = sqrt(r_b^2 + u^2),   theta = k 2 pi / z_teeth + s psi(r) + h(z),

psi the half tooth angle (``GearSpec.half_angle``) and h(z) the helix rotation
(``GearSpec.helix_rotation``). Turning a point by -k 2 pi / z_teeth (the tooth pitch) moves
it onto the same (u, z) of tooth 0, so every loaded tooth maps onto one representative tooth
(:func:`to_flank`); the distance of a mapped point from the exact flank
(:func:`gears.profile.involute_deviation`) checks the mapping.

Contact lines and the mesh cycle
--------------------------------
A theoretical contact line lies in the plane of action, tangent to the base cylinder at one
angle phi_T. The flank's polar angle is theta0(z) + q inv(alpha(r)), q = -s sigma its sense
of unwinding (sigma = +1 external, -1 internal), so its base-circle tangency lies at
theta0(z) + q u / r_b = phi_T with theta0(z) = theta0 + h(z): the contact phase

    c = u + q r_b h(z)        (mm of roll length)

is constant along a contact line and grows by r_b times the gear's turn as the mesh rolls.
All gears of a set share the transverse base pitch p_bt = 2 pi r_b / z, so N mesh positions
over one base pitch put the contact lines of every tooth, mapped onto tooth 0, at N phases
per p_bt, a phase step dc = p_bt / N apart (:func:`phase_step`).

The pattern (:func:`cycle_maximum`) is the largest pressure a flank point sees over the
mesh cycle: the pressure at the instant the contact line passes over it (the Hertz maximum
p_max lies on the line; across it the pressure falls off over the half-width b, well below
dc). Between two sampled phases it is interpolated linearly in phase at the same z; where
several sampled lines fall on one phase (positions that repeat a phase) it takes their
maximum. Every line covers half its point spacing beyond its end points in z. The pattern is
clipped to the active profile (the theoretical path of contact, widened to any sampled point
beyond it, :func:`active_profile`); inside it a line with no sampled neighbour within 1.5 dc
on one side (the neighbour left the path of contact there) covers up to 1.5 dc on that side,
outside it half a step. Flank points no sampled contact line reaches have no value (NaN).

Grid points farther than ``ON_FLANK`` from the flank (e.g. on a coast flank) are left out.

Zone grids (:func:`zone_flank_pattern`)
---------------------------------------
A zone grid's cells cover the contact zone around each line with the solved pressure (the
Hertz band, 0.3-0.6 mm across in case 1, resolved by cells down to a few hundredths of a mm), and
beyond the path of contact the corner contact at the tips. Between two sampled positions
the band moves a phase step dc (1.0 mm of roll length for case 1 with five positions),
several times its width, so the cells of the sampled positions alone would leave stripes: a flank
point between two sampled bands did see the band pass over it, at a peak like theirs. The
pattern is therefore the larger of

* the envelope of the passing band: per section of every sampled position, its largest
  cell pressure at the section's contact-line point, interpolated in phase as the line
  grid's points are (:func:`cycle_maximum`), from the sections whose point is not at a tip
  or form circle (``station_tip_form`` of :func:`postprocess.mesh_stress.edge_points`;
  those are the corner contacts of tooth pairs beyond the path, not a band that moves with
  the mesh; a band that reaches a tip from a line inside the path is kept); and
* every cell's own pressure on its own patch (profile arc sigma = u^2 / (2 r_b) +- half its
  width, z +- half its section, a cell narrower than the flank sampling on the nearest
  sample), the largest over the positions, not moved in phase: a sharp tip's corner
  contact stays at that tip while the mesh rolls, so only the sampled instants are drawn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gears import contact_stress
from gears.involute import roll_length
from gears.profile import involute_deviation
from meshing.scenes import build_scene
from postprocess.mesh_stress import contact_stress_at_points, edge_points
from postprocess.train_results import mesh_stations

N_U, N_Z = 49, 161  # flank samples: roll length (profile) x face width
SAME_PHASE = 0.05  # lines closer than this many phase steps are the same phase
NEIGHBOUR_GAP = 1.5  # phase steps across which two lines are interpolated
ON_FLANK = 0.2  # mm: grid points farther from the drive flank belong to another flank


def side_sign(side: str) -> int:
    """s = +1 for the ``pos`` flank, -1 for ``neg``."""
    if side not in ("pos", "neg"):
        raise ValueError(f"side = {side!r}: must be 'pos' or 'neg'")
    return 1 if side == "pos" else -1


def flank_point(gear, side: str, u, z) -> np.ndarray:
    """Points (..., 3) of tooth 0's ``side`` flank at roll length u and axial position z
    (broadcast), gear frame: r = sqrt(r_b^2 + u^2), theta = s psi(r) + h(z)."""
    u, z = np.broadcast_arrays(np.asarray(u, float), np.asarray(z, float))
    r = np.hypot(gear.base_radius, u)
    theta = side_sign(side) * gear.half_angle(r) + gear.helix_rotation(z)
    return np.stack([r * np.cos(theta), r * np.sin(theta), z], axis=-1)


def unwinding_sense(gear, side: str) -> int:
    """q = +1 if the flank's polar angle grows with the radius, -1 if it falls: -s sigma
    (psi(r) falls with r on an external gear, grows on an internal one)."""
    return -side_sign(side) * gear.sigma


def contact_phase(gear, side: str, u, z):
    """Contact phase c = u + q r_b h(z) (mm), constant along a theoretical contact line."""
    q = unwinding_sense(gear, side)
    return np.asarray(u, float) + q * gear.base_radius * gear.helix_rotation(z)


def phase_step(gear, phases) -> float:
    """Phase step dc (mm) of the sampled mesh cycle: p_bt / N with N the number of distinct
    phases modulo the transverse base pitch p_bt = 2 pi r_b / z among ``phases``."""
    p_bt = 2.0 * math.pi * gear.base_radius / gear.teeth
    m = np.sort(np.mod(np.asarray(phases, float), p_bt))
    if m.size == 0:
        return p_bt
    gaps = np.diff(np.r_[m, m[0] + p_bt])
    n = max(int(np.count_nonzero(gaps > SAME_PHASE * p_bt / max(m.size, 1))), 1)
    return p_bt / n


def active_profile(pair, i: int) -> tuple[float, float]:
    """Roll lengths (u_low, u_high) of gear i (1 driver, 2 driven) of ``pair`` on the
    theoretical path of contact (:func:`gears.contact_stress.path_of_contact`, s from the
    pitch point towards gear1's tip): u1 = r_b1 tan(alpha_wt) + s; external
    u2 = r_b2 tan(alpha_wt) - s, internal u2 = r_b2 tan(alpha_wt) + s; clipped to the
    gear's involute between its form and tip circles."""
    s = np.asarray(contact_stress.path_of_contact(pair), float)
    sign = 1.0 if i == 1 or pair.internal else -1.0
    u = contact_stress.pitch_roll(pair, i) + sign * s
    g = pair.gear(i)
    ends = roll_length(np.array([g.form_radius, g.tip_radius]), g.base_radius)
    return float(max(u.min(), ends.min())), float(min(u.max(), ends.max()))


def to_flank(gear, side: str, xyz) -> dict:
    """Points ``xyz`` (N, 3, gear frame) on the ``side`` flanks of any teeth, mapped onto
    tooth 0: ``u`` roll length, ``z``, ``tooth`` k (the tooth they lie on), ``xyz`` on tooth 0
    (turned by -k 2 pi / z_teeth), ``deviation`` from the exact flank (mm, + outside)."""
    p = np.atleast_2d(np.asarray(xyz, float))
    s = side_sign(side)
    r = np.hypot(p[:, 0], p[:, 1])
    theta = np.arctan2(p[:, 1], p[:, 0]) - gear.helix_rotation(p[:, 2])
    pitch = 2.0 * math.pi / gear.teeth
    psi = gear.half_angle(np.maximum(r, gear.base_radius))
    k = np.round((theta - s * psi) / pitch).astype(int)
    c, sn = np.cos(-k * pitch), np.sin(-k * pitch)
    q = np.c_[c * p[:, 0] - sn * p[:, 1], sn * p[:, 0] + c * p[:, 1], p[:, 2]]
    return {
        "u": roll_length(r, gear.base_radius),
        "z": p[:, 2],
        "tooth": np.mod(k, gear.teeth),
        "xyz": q,
        "deviation": involute_deviation(gear, q, side),
    }


@dataclass(frozen=True, eq=False)
class FlankGrid:
    """Tooth 0's ``side`` flank sampled on a (roll length u, axial z) grid from the form to
    the tip circle across the face width: ``xyz`` (n_u, n_z, 3), gear frame."""

    gear: object  # gears.spec.GearSpec
    side: str
    u: np.ndarray  # (n_u,), form -> tip
    z: np.ndarray  # (n_z,)
    xyz: np.ndarray

    @property
    def u_form(self) -> float:
        return float(self.u[0])

    @property
    def u_tip(self) -> float:
        return float(self.u[-1])

    @property
    def phase(self) -> np.ndarray:
        """Contact phase c (n_u, n_z) of every sample."""
        return contact_phase(self.gear, self.side, self.u[:, None], self.z[None, :])

    def outward_normal(self, iu: int, iz: int) -> np.ndarray:
        """Unit normal at sample (iu, iz) pointing out of the material (the side the mate
        is on), from the sign of ``involute_deviation``."""
        du = self.xyz[min(iu + 1, len(self.u) - 1), iz] - self.xyz[max(iu - 1, 0), iz]
        dz = self.xyz[iu, min(iz + 1, len(self.z) - 1)] - self.xyz[iu, max(iz - 1, 0)]
        n = np.cross(du, dz)
        n /= np.linalg.norm(n)
        probe = self.xyz[iu, iz] + 1e-3 * n
        if involute_deviation(self.gear, probe[None, :], self.side)[0] < 0.0:
            n = -n
        return n


def flank_grid(gear, side: str, n_u: int = N_U, n_z: int = N_Z) -> FlankGrid:
    """The exact flank of tooth 0 (:func:`flank_point`) between the form and tip circles."""
    u = np.linspace(
        float(roll_length(gear.form_radius, gear.base_radius)),
        float(roll_length(gear.tip_radius, gear.base_radius)),
        n_u,
    )
    z = np.linspace(-0.5 * gear.face_width, 0.5 * gear.face_width, n_z)
    return FlankGrid(gear, side, u, z, flank_point(gear, side, u[:, None], z[None, :]))


@dataclass(frozen=True, eq=False)
class SampledLine:
    """One contact line of one position on the representative flank: its phase ``c`` (mm),
    the axial positions ``z`` (sorted) and pressures ``p`` (MPa) of its points, and how far
    it covers beyond its end points (``half_spacing``, mm)."""

    c: float
    z: np.ndarray
    p: np.ndarray
    half_spacing: float

    def at(self, z) -> np.ndarray:
        """Pressure at axial positions z (linear along the line); NaN beyond its reach."""
        z = np.asarray(z, float)
        out = np.interp(z, self.z, self.p)
        reach = (z >= self.z[0] - self.half_spacing) & (z <= self.z[-1] + self.half_spacing)
        return np.where(reach, out, np.nan)


def split_lines(gear, side: str, u, z, p, gap: float) -> list[SampledLine]:
    """The points (u, z, p) of one position grouped into contact lines by their phase: a
    jump of more than ``gap`` (mm) between sorted phases starts a new line (the lines of one
    position lie a base pitch apart). A line covers half its median point spacing in z
    beyond its end points (a one-point line: half the median spacing of the others)."""
    c = contact_phase(gear, side, u, z)
    order = np.argsort(c)
    groups = np.split(order, np.flatnonzero(np.diff(c[order]) > gap) + 1)
    z, p = np.asarray(z, float), np.asarray(p, float)
    spacing = []
    for idx in groups:
        dz = np.diff(np.sort(z[idx]))
        spacing.append(float(np.median(dz[dz > 1e-9])) if np.any(dz > 1e-9) else np.nan)
    known = [h for h in spacing if np.isfinite(h)]
    default = float(np.median(known)) if known else 0.5
    lines = []
    for idx, h in zip(groups, spacing, strict=True):
        zo = np.argsort(z[idx])
        half = 0.5 * (h if np.isfinite(h) else default)
        lines.append(SampledLine(float(np.median(c[idx])), z[idx][zo], p[idx][zo], half))
    return lines


def cycle_maximum(lines: list[SampledLine], step: float, c, z, u=None, u_range=None):
    """Pressure (MPa, shaped like c) over the mesh cycle at flank points of contact phase c,
    axial position z and roll length u, from the sampled contact ``lines`` a phase ``step``
    apart (see the module docstring); NaN where no line reaches. ``u_range`` (u_min, u_max):
    the active profile (the path of contact and any sampled point beyond it); the pattern is
    clipped to it, and inside it a line with no neighbour on one side covers up to 1.5 steps
    on that side (where its neighbour ended at the path of contact), not only half a step."""
    c, z = np.broadcast_arrays(np.asarray(c, float), np.asarray(z, float))
    shape = c.shape
    if not lines:
        return np.full(shape, np.nan)
    cv, zv = c.ravel(), z.ravel()
    c_l = np.array([ln.c for ln in lines])
    vals = np.vstack([ln.at(zv) for ln in lines])  # (L, V)
    cover = ~np.isnan(vals)
    dc = cv[None, :] - c_l[:, None]  # >= 0: the line lies at or below the point's phase
    tol = SAME_PHASE * step

    below = dc >= -1e-9  # the line lies at (to round-off) or below the point's phase

    def side(d, mask):  # nearest covering line on one side and the max over its phase
        d = np.where(cover & mask, np.maximum(d, 0.0), np.inf)
        d_near = d.min(axis=0)
        same = cover & (d <= d_near[None, :] + tol)
        return d_near, np.where(same, vals, -np.inf).max(axis=0)

    d_lo, p_lo = side(dc, below)
    d_hi, p_hi = side(-dc, ~below)
    out = np.full(cv.shape, np.nan)
    both = np.isfinite(d_lo) & np.isfinite(d_hi) & (d_lo + d_hi <= NEIGHBOUR_GAP * step)
    t = d_lo[both] / np.maximum(d_lo[both] + d_hi[both], 1e-300)
    out[both] = (1.0 - t) * p_lo[both] + t * p_hi[both]
    reach = np.full(cv.shape, 0.5 * step + tol)
    active = np.ones(cv.shape, bool)
    if u_range is not None:
        uv = np.broadcast_to(np.asarray(u, float), shape).ravel()
        active = (uv >= min(u_range) - 1e-9) & (uv <= max(u_range) + 1e-9)
        reach[active] = NEIGHBOUR_GAP * step
    near_lo = ~both & (d_lo <= reach)
    near_hi = ~both & ~near_lo & (d_hi <= reach)
    out[near_lo] = p_lo[near_lo]
    out[near_hi] = p_hi[near_hi]
    out[~active] = np.nan
    return out.reshape(shape)


@dataclass(frozen=True, eq=False)
class CycleSamples:
    """The contact lines of one flank sampled over the mesh cycle: what
    :func:`cycle_maximum` needs to give the pattern anywhere on the flank."""

    gear: object  # gears.spec.GearSpec
    side: str
    lines: list[SampledLine]
    step: float  # phase step, mm
    u_range: tuple[float, float]  # active profile, roll length mm

    def pressure(self, u, z):
        """The pattern (MPa, NaN where no line reaches) at roll length u, axial z."""
        c = contact_phase(self.gear, self.side, u, z)
        return cycle_maximum(self.lines, self.step, c, z, u, self.u_range)


@dataclass(frozen=True, eq=False)
class FlankPattern:
    """The contact pattern of one gear's drive flank in one mesh, over the mesh cycle."""

    mesh: str  # grid name "driver-driven"
    body: str  # the body (scene name) whose flank this is
    role: str  # "driver" | "driven"
    pinion: str  # the pinion whose frame Z is reported in (first pinion of the mesh)
    z_sign: float  # +1 if the pinion's e_Z is the gear's +z, -1 if opposite
    flank: FlankGrid
    pressure: np.ndarray  # (n_u, n_z) MPa, max over the cycle; NaN where no line reaches
    samples: CycleSamples  # the pattern anywhere on the flank: samples.pressure(u, z)
    centroid_z: float  # load centroid, gear z (mm), mean over the positions
    points_u: np.ndarray  # the mapped grid points of every position (u, z, p), for checks
    points_z: np.ndarray
    points_p: np.ndarray
    max_deviation: float  # largest |distance| of a mapped grid point from the exact flank, mm
    positions: int
    grid_model: str = "line"  # "line" or "zone" (points_p: Hertz at points / cell pressures)
    interior_max: float = float("nan")  # largest pressure of a non-edge point (MPa)
    edge_max: float = float("nan")  # largest pressure of an edge point (MPa; NaN: none)

    @property
    def gear(self):
        return self.flank.gear

    @property
    def face_width(self) -> float:
        return self.flank.gear.face_width


def _pinion_of(pos: dict, mesh: str) -> str:
    """The pinion whose frame the mesh's pattern is reported in (the first pinion in it)."""
    return next(iter(pos["meshes"][mesh]["on"]))


def mesh_flank_patterns(study, positions: list[dict], scenes=None) -> list[FlankPattern]:
    """Per mesh of the study's solved ``positions``, the patterns of its two drive flanks
    (the first pinion's first, then its mate's). ``scenes``: the scene of each position
    (rebuilt from ``study`` and the position's roll if None). The pressure at the grid points
    is :func:`postprocess.mesh_stress.contact_stress_at_points`' (Hertz p_max on a line grid,
    the solved cell pressure on a zone grid, :func:`zone_flank_pattern`)."""
    if scenes is None:
        scenes = [build_scene(study.model.scene, study.gearset, p["roll"]) for p in positions]
    hz = [contact_stress_at_points(study.gearset, study.material, p) for p in positions]
    edges = [edge_points(study.gearset, p) for p in positions]
    out = []
    zones = {f"{zn.driver}-{zn.driven}": zn for zn in scenes[0].zones}
    for mesh in positions[0]["meshes"]:
        if mesh not in zones:  # not a drive-flank grid of a mesh zone
            continue
        m0 = positions[0]["meshes"][mesh]
        pinion = _pinion_of(positions[0], mesh)
        e_z = np.asarray(positions[0]["pinions"][pinion]["frame"])[2]
        z_sign = 1.0 if e_z[2] >= 0.0 else -1.0
        pair = study.gearset.pair(*m0["gears"])
        roles = [(m0["driver"], "driver", 1), (m0["driven"], "driven", 2)]
        roles.sort(key=lambda r: r[0] != pinion)
        zoned = m0.get("grid_model", "line") == "zone"
        for body, role, i in roles:
            zone = zones[mesh]
            side = zone.driver_side if role == "driver" else zone.driven_side
            gear, path = scenes[0].gear(body).gear, active_profile(pair, i)
            if zoned:
                runs = zip(positions, scenes, hz, edges, strict=True)
                data = [
                    (p["meshes"][mesh], sc.gear(body).placement, h[mesh], e[mesh])
                    for p, sc, h, e in runs
                ]
                pattern = zone_flank_pattern(gear, side, data, path)
            else:
                data = [
                    (p["meshes"][mesh], sc.gear(body).placement, h[mesh]["p_max"])
                    for p, sc, h in zip(positions, scenes, hz, strict=True)
                ]
                pattern = flank_pattern(gear, side, data, path)
                e_all = np.concatenate([e[mesh]["edge"] for e in edges])
                p_all = np.concatenate([h[mesh]["p_max"] for h in hz])
                pattern["interior_max"] = float(p_all[~e_all].max()) if (~e_all).any() else 0.0
                pattern["edge_max"] = float(p_all[e_all].max()) if e_all.any() else float("nan")
            out.append(FlankPattern(mesh, body, role, pinion, z_sign, **pattern))
    return out


def flank_pattern(gear, side: str, data, path: tuple[float, float]) -> dict:
    """The pattern of one flank from ``data``: per position (mesh dict of the position, the
    gear's placement, Hertz p_max at the mesh's grid points); ``path``: the active profile
    (u range) of the gear on the theoretical path of contact. Returns the :class:`FlankPattern`
    fields from ``flank`` on."""
    flank = flank_grid(gear, side)
    p_bt = 2.0 * math.pi * gear.base_radius / gear.teeth
    lines, us, zs, ps, dev, centroids = [], [], [], [], [], []
    for m, placement, p_max in data:
        x = np.asarray(m["points"]["x_mm"], float).reshape(-1, 3)
        if x.size == 0:
            continue
        f = m["points"].get("force_N", m["points"]["line_load_N_per_mm"])  # centroid weights
        f = np.clip(np.asarray(f, float), 0.0, None)
        if f.sum() > 0.0:
            centroids.append(float((f * x[:, 2]).sum() / f.sum()))
        q = to_flank(gear, side, placement.inverse(x))
        on = np.abs(q["deviation"]) <= ON_FLANK
        if not on.any():
            continue
        p = np.asarray(p_max, float)[on]
        lines += split_lines(gear, side, q["u"][on], q["z"][on], p, 0.25 * p_bt)
        us.append(q["u"][on])
        zs.append(q["z"][on])
        ps.append(p)
        dev.append(np.abs(q["deviation"][on]))
    u = np.concatenate(us) if us else np.zeros(0)
    u_range = (min(path[0], float(u.min())), max(path[1], float(u.max()))) if us else path
    samples = CycleSamples(gear, side, lines, phase_step(gear, [ln.c for ln in lines]), u_range)
    return {
        "flank": flank,
        "pressure": samples.pressure(flank.u[:, None], flank.z[None, :]),
        "samples": samples,
        "centroid_z": float(np.mean(centroids)) if centroids else float("nan"),
        "points_u": u,
        "points_z": np.concatenate(zs) if us else np.zeros(0),
        "points_p": np.concatenate(ps) if us else np.zeros(0),
        "max_deviation": float(np.concatenate(dev).max()) if us else 0.0,
        "positions": len(data),
    }


def _cell_patches(gear, side: str, mesh: dict, placement):
    """The cells of one position of a zone grid on tooth 0's flank: (u, z, u_lo, u_hi,
    z_lo, z_hi, on, deviation) per cell, the patch profile arc sigma +- width / 2 (width =
    area / segment, along the profile) and z +- half the section (segment cos(beta_b))."""
    pts = mesh["points"]
    x = np.asarray(pts["x_mm"], float).reshape(-1, 3)
    q = to_flank(gear, side, placement.inverse(x))
    seg = np.asarray(mesh_stations(mesh)["length_mm"], float)[np.asarray(pts["station"], int)]
    width = np.asarray(pts["area_mm2"], float) / seg
    rb = gear.base_radius
    sig = 0.5 * q["u"] ** 2 / rb
    u_lo = np.sqrt(2.0 * rb * np.maximum(sig - 0.5 * width, 0.0))
    u_hi = np.sqrt(2.0 * rb * (sig + 0.5 * width))
    half_z = 0.5 * seg * math.cos(gear.base_helix_angle)
    on = np.abs(q["deviation"]) <= ON_FLANK
    return q, u_lo, u_hi, q["z"] - half_z, q["z"] + half_z, on


def _splat(flank: FlankGrid, p, u_lo, u_hi, z_lo, z_hi) -> np.ndarray:
    """(n_u, n_z) the largest p of the patches covering each flank sample (NaN: none); a
    patch between two samples covers the sample nearest its centre."""
    out = np.full((len(flank.u), len(flank.z)), np.nan)
    for k in range(len(p)):
        bounds = []
        for axis, lo, hi in ((flank.u, u_lo[k], u_hi[k]), (flank.z, z_lo[k], z_hi[k])):
            i0, i1 = np.searchsorted(axis, lo), np.searchsorted(axis, hi, side="right")
            if i1 <= i0:  # narrower than the sampling: the nearest sample
                i0 = int(np.argmin(np.abs(axis - 0.5 * (lo + hi))))
                i1 = i0 + 1
            bounds.append(slice(i0, i1))
        out[bounds[0], bounds[1]] = np.fmax(out[bounds[0], bounds[1]], p[k])
    return out


def zone_flank_pattern(gear, side: str, data, path: tuple[float, float]) -> dict:
    """The pattern of one flank from a zone grid (module docstring, "Zone grids"): ``data``
    per position (mesh dict of the position, the gear's placement, its
    :func:`postprocess.mesh_stress.contact_stress_at_points` and
    :func:`postprocess.mesh_stress.edge_points` entries of the mesh); ``path``: the active
    profile (u range) of the gear on the theoretical path of contact. Returns the
    :class:`FlankPattern` fields from ``flank`` on."""
    flank = flank_grid(gear, side)
    p_bt = 2.0 * math.pi * gear.base_radius / gear.teeth
    lines, us, zs, ps, dev, centroids, edge_p = [], [], [], [], [], [], []
    cells = np.full((len(flank.u), len(flank.z)), np.nan)
    for m, placement, h, e in data:
        x = np.asarray(m["points"]["x_mm"], float).reshape(-1, 3)
        f = np.clip(np.asarray(m["points"]["force_N"], float), 0.0, None)
        if f.sum() > 0.0:
            centroids.append(float((f * x[:, 2]).sum() / f.sum()))
        p = np.asarray(h["p_max"], float)
        q, u_lo, u_hi, z_lo, z_hi, on = _cell_patches(gear, side, m, placement)
        if not on.any():
            continue
        patch = _splat(flank, p[on], u_lo[on], u_hi[on], z_lo[on], z_hi[on])
        cells = np.fmax(cells, patch)
        # the band's envelope: per section its largest cell pressure, at the section's point
        st = mesh_stations(m)
        sec = np.asarray(m["points"]["station"], int)
        peak = np.zeros(len(st["x_mm"]))
        np.maximum.at(peak, sec, p)
        qs = to_flank(gear, side, placement.inverse(np.asarray(st["x_mm"], float).reshape(-1, 3)))
        keep = (np.abs(qs["deviation"]) <= ON_FLANK) & ~np.asarray(e["station_tip_form"], bool)
        if keep.any():
            lines += split_lines(gear, side, qs["u"][keep], qs["z"][keep], peak[keep], 0.25 * p_bt)
        us.append(q["u"][on])
        zs.append(q["z"][on])
        ps.append(p[on])
        edge_p.append(np.asarray(e["edge"], bool)[on])
        dev.append(np.abs(q["deviation"][on]))
    u = np.concatenate(us) if us else np.zeros(0)
    u_range = (min(path[0], float(u.min())), max(path[1], float(u.max()))) if us else path
    samples = CycleSamples(gear, side, lines, phase_step(gear, [ln.c for ln in lines]), u_range)
    envelope = samples.pressure(flank.u[:, None], flank.z[None, :])
    p_all = np.concatenate(ps) if us else np.zeros(0)
    e_all = np.concatenate(edge_p) if us else np.zeros(0, bool)
    return {
        "flank": flank,
        "pressure": np.fmax(envelope, cells),
        "samples": samples,
        "centroid_z": float(np.mean(centroids)) if centroids else float("nan"),
        "points_u": u,
        "points_z": np.concatenate(zs) if us else np.zeros(0),
        "points_p": p_all,
        "max_deviation": float(np.concatenate(dev).max()) if us else 0.0,
        "positions": len(data),
        "grid_model": "zone",
        "interior_max": float(p_all[~e_all].max()) if (~e_all).any() else 0.0,
        "edge_max": float(p_all[e_all].max()) if e_all.any() else float("nan"),
    }
