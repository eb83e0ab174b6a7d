"""Planet carrier: two annular plates joined by posts, with the pinion pins through them.

Real enough for a carrier wind-up study (plates, posts, pins as one steel body); the case
studies may treat it as rigid. Pins are cylinders of ``pin_diameter`` and ``pin_length``
centred at mid face width; the pin surface between the plates (``carrier/pin<K>``) is where
a pinion's needle bearing acts. Frame: the scene frame (sun axis = z, z = 0 at mid face
width).

Single pinion (:func:`carrier_spec`): one pin per pinion on the sun-pinion centre distance
a1, at the carrier angles the assembly condition allows nearest to equal spacing
(multiples of 2 pi / (Zs + Zr)); posts midway between the pins on the pin circle.

Double pinion (sun -> SP -> RP -> ring): two pins per branch, in the scene's pinion order
(SP1, RP1, SP2, ...): the SP pin at (a1, psi_k), the RP pin at (a3, psi_k + s psi_t), a3 the
RP-ring centre distance (the RP axis is a3 from the sun axis), psi_t the triangle angle at
the sun, cos psi_t = (a1^2 + a3^2 - a2^2) / (2 a1 a3) (a2: SP-RP; case 2: 45.00 deg), s = +1
(RP counter-clockwise of SP, the scenes' default). The branch angles psi_k are multiples of
2 pi / (Zr - Zs) nearest to equal spacing: a branch turned by psi on a fixed sun and ring
turns its SP's sun mesh by Zs psi / 2 pi teeth and its RP's ring mesh by Zr psi / 2 pi teeth,
and with the SP-RP mesh fixed relative to the carrier both are in phase only if
(Zr - Zs) psi / 2 pi is an integer (equally spaced when (Zr - Zs) / N is an integer; case 2:
(92 - 35) / 3 = 19). One post per branch, in the gap between a branch's last pin and the next
branch's first, where it keeps the largest clearance to the tip circles of every pinion
(the envelope of a turning pinion's teeth) inside the plates (:func:`place_posts`); less
than :data:`MIN_POST_CLEARANCE` raises :class:`MeshingError`.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, replace

import numpy as np

from gears.analytic.double_pinion import triangle_angles
from gears.analytic.phasing import assemblable_angles
from meshing import cache, gmsh_util, sizing
from meshing import tags as T
from meshing.gmsh_util import (
    add_physical_groups,
    enforce_quality,
    mesh_options,
    mesh_stats,
    sample_surface,
)
from meshing.sizing import MeshingError

MESHER_VERSION = "carrier-2"  # 2: plate hubs tagged
MIN_POST_CLEARANCE = 1.0  # mm between a post and a pinion's tip circle (as plate_gap)
# mm of plate kept between a post and the plates' inner and outer rims: a post tangent to a
# rim (the best clearance to the pinions often lies there) leaves a knife-edge of plate that
# meshes into slivers (minimum SICN 0.002 on the case-2 carrier, which no optimiser repairs)
POST_RIM_MARGIN = 2.0


@dataclass(frozen=True)
class CarrierSpec:
    pin_diameter: float  # mm
    pin_circle_radius: float  # mm (the sun-pinion centre distance)
    pin_angles: tuple[float, ...]  # rad, carrier angles of the pins
    pinion_face_width: float  # mm
    pin_length: float | None = None  # mm; default: through both plates (flush)
    plate_thickness: float = 8.0
    plate_gap: float = 1.0  # axial clearance pinion end face <-> plate
    plate_inner_radius: float = 33.0  # clears the sun tips (31.4 mm in the cases)
    plate_outer_radius: float = 70.0  # inside the ring tips (72.5 mm in case 1)
    post_radius: float = 7.0
    # per pin, its distance from the sun axis (mm); None: every pin on pin_circle_radius
    pin_radii: tuple[float, ...] | None = None
    # per post, (carrier angle rad, distance from the sun axis mm); None: midway between
    # the pins on the pin circle
    posts: tuple[tuple[float, float], ...] | None = None

    def pin_centres(self) -> list[np.ndarray]:
        """(x, y) of each pin centre (mm), in pin order."""
        radii = self.pin_radii or (self.pin_circle_radius,) * len(self.pin_angles)
        return [
            r * np.array([math.cos(a), math.sin(a)])
            for r, a in zip(radii, self.pin_angles, strict=True)
        ]

    def post_centres(self) -> list[np.ndarray]:
        """(x, y) of each post centre (mm)."""
        if self.posts is not None:
            return [r * np.array([math.cos(a), math.sin(a)]) for a, r in self.posts]
        rc = self.pin_circle_radius
        return [rc * np.array([math.cos(a), math.sin(a)]) for a in self.post_angles()]

    @property
    def plate_z(self) -> tuple[float, float]:
        """Inner and outer z of the +z plate (the -z plate mirrors it)."""
        z0 = 0.5 * self.pinion_face_width + self.plate_gap
        return z0, z0 + self.plate_thickness

    @property
    def length(self) -> float:
        return self.pin_length if self.pin_length is not None else 2 * self.plate_z[1]

    def validate(self) -> None:
        def need(ok, field, rule):
            if not ok:
                raise MeshingError(f"carrier.{field} = {getattr(self, field)!r}: {rule}")

        for f in ("pin_diameter", "pin_circle_radius", "pinion_face_width", "plate_thickness"):
            v = getattr(self, f)
            need(isinstance(v, (int, float)) and v > 0, f, "must be a number > 0 (mm)")
        need(self.plate_gap >= 0, "plate_gap", "must be >= 0")
        need(len(self.pin_angles) >= 1, "pin_angles", "at least one pin")
        z_in, z_out = self.plate_z
        need(
            self.pin_length is None or 2 * z_in < self.pin_length <= 2 * z_out + 1e-9,
            "pin_length",
            f"must be in ({2 * z_in:g}, {2 * z_out:g}] mm (span the pinion and gaps, end "
            "inside or flush with the plates)",
        )
        need(
            self.pin_radii is None or len(self.pin_radii) == len(self.pin_angles),
            "pin_radii",
            f"must be None or {len(self.pin_angles)} radii (one per pin)",
        )
        r_pin = 0.5 * self.pin_diameter
        radii = [float(np.hypot(*c)) for c in self.pin_centres()]
        need(
            all(
                self.plate_inner_radius + r_pin < r < self.plate_outer_radius - r_pin for r in radii
            ),
            "pin_diameter",
            "pins must lie inside the plates (inner radius + pin radius < pin centre radius "
            "< outer radius - pin radius)",
        )
        need(
            all(
                self.plate_inner_radius < float(np.hypot(*c)) - self.post_radius
                and float(np.hypot(*c)) + self.post_radius < self.plate_outer_radius
                for c in self.post_centres()
            ),
            "post_radius",
            "posts must lie inside the plates",
        )

    def post_angles(self) -> list[float]:
        if self.posts is not None:
            return [float(a) for a, _ in self.posts]
        a = sorted(x % (2 * math.pi) for x in self.pin_angles)
        if len(a) < 2:
            return []
        nxt = [*a[1:], a[0] + 2 * math.pi]
        return [0.5 * (x + y) for x, y in zip(a, nxt, strict=True)]

    def params(self) -> dict:
        """Cache key: the fields (the optional per-pin radii and posts only when given, so a
        single-pinion carrier keeps its key) and the mesher version."""
        d = {
            k: v for k, v in asdict(self).items() if not (k in ("pin_radii", "posts") and v is None)
        }
        return {**d, "version": MESHER_VERSION}


def build_geometry(gmsh, spec: CarrierSpec) -> int:
    spec.validate()
    occ = gmsh.model.occ
    z_in, z_out = spec.plate_z
    parts = []
    for sgn in (1, -1):
        z0 = z_in if sgn > 0 else -z_out
        outer = occ.addCylinder(0, 0, z0, 0, 0, spec.plate_thickness, spec.plate_outer_radius)
        inner = occ.addCylinder(0, 0, z0, 0, 0, spec.plate_thickness, spec.plate_inner_radius)
        plate, _ = occ.cut([(3, outer)], [(3, inner)])
        parts += plate
    half = 0.5 * spec.length
    for c in spec.pin_centres():
        parts.append(
            (3, occ.addCylinder(c[0], c[1], -half, 0, 0, 2 * half, 0.5 * spec.pin_diameter))
        )
    for c in spec.post_centres():
        parts.append((3, occ.addCylinder(c[0], c[1], -z_in, 0, 0, 2 * z_in, spec.post_radius)))
    fused, _ = occ.fuse(parts[:1], parts[1:])
    occ.synchronize()
    vols = [t for d, t in fused if d == 3]
    if len(vols) != 1:
        raise RuntimeError(f"carrier: fusion gave {len(vols)} volumes")
    return vols[0]


def classify_surfaces(gmsh, spec: CarrierSpec, vol: int) -> dict[str, list[int]]:
    """Pin surfaces by distance from each pin axis; plate outer faces by z; plate hubs (inner
    cylinders) by radius and side; rest other."""
    z_out = spec.plate_z[1]
    r_pin = 0.5 * spec.pin_diameter
    centres = spec.pin_centres()
    out: dict[str, list[int]] = {}
    for _, s in gmsh.model.getBoundary([(3, vol)], combined=False, oriented=False):
        xyz = sample_surface(gmsh, s)
        name = T.carrier_surface(T.OTHER)
        if np.all(np.abs(xyz[:, 2] - z_out) < 1e-6):
            name = T.carrier_surface(T.PLATE_ZPOS)
        elif np.all(np.abs(xyz[:, 2] + z_out) < 1e-6):
            name = T.carrier_surface(T.PLATE_ZNEG)
        elif np.all(np.abs(np.hypot(xyz[:, 0], xyz[:, 1]) - spec.plate_inner_radius) < 1e-6):
            name = T.carrier_surface(T.HUB_ZPOS if xyz[:, 2].mean() > 0 else T.HUB_ZNEG)
        else:
            for k, c in enumerate(centres):
                if np.all(np.abs(np.hypot(xyz[:, 0] - c[0], xyz[:, 1] - c[1]) - r_pin) < 1e-6):
                    name = T.pin(k)
        out.setdefault(name, []).append(s)
    return out


def build_carrier_mesh(gmsh, spec: CarrierSpec, level: int) -> dict:
    lv = sizing.check_level(level)
    t0 = time.perf_counter()
    vol = build_geometry(gmsh, spec)
    groups = classify_surfaces(gmsh, spec, vol)
    add_physical_groups(gmsh, groups, {T.CARRIER: [vol]})
    t_geo = time.perf_counter() - t0
    r_pin = 0.5 * spec.pin_diameter
    pin_size = min(lv.tooth, 2 * math.pi * r_pin / lv.per_circle * 2)
    sizes = {s: pin_size for n, ss in groups.items() if n.startswith(T.pin(0)[:-1]) for s in ss}
    sizing.apply_sizes(gmsh, level, sizes)
    mesh_options(gmsh)
    t1 = time.perf_counter()
    gmsh.model.mesh.generate(3)
    enforce_quality(gmsh)
    stats = mesh_stats(gmsh)
    stats.update(
        geometry_seconds=t_geo,
        mesh_seconds=time.perf_counter() - t1,
        names=[*sorted(groups), T.CARRIER],
    )
    return stats


def carrier_mesh_file(spec: CarrierSpec, level: int, comm=None, rebuild=False):
    """``(msh_path, meta)`` of the carrier mesh, from the cache or built on rank 0."""
    spec.validate()
    sizing.check_level(level)

    def builder(path):
        with gmsh_util.session("carrier") as gm:
            stats = build_carrier_mesh(gm, spec, level)
            gmsh_util.write_msh(path)
        return stats

    return cache.get_or_build(
        "carrier", {"carrier": spec.params(), "level": level}, builder, comm=comm, rebuild=rebuild
    )


def sun_rp_angle(gearset) -> float:
    """psi_t (rad): the angle at the sun between the SP and RP centres of a double-pinion
    branch, from the three centre distances (law of cosines; see the module docstring)."""
    a1, a2, a3 = (m.centre_distance for m in gearset.meshes)
    return triangle_angles(a1, a2, a3).psi


def place_posts(
    spec: CarrierSpec, branches: list[list[int]], tips: list[float], samples: int = 121
) -> tuple[tuple[float, float], ...]:
    """One post per branch, in the angular gap from the branch's last pin to the next
    branch's first pin: the (angle, radius) inside the plates that maximises the clearance
    c = min_i (|p - c_i| - r_tip,i) - post_radius to every pin's pinion tip circle (sampled
    on a ``samples`` x ``samples`` grid of the gap). ``branches``: pin indices per branch,
    in carrier order; ``tips``: the tip radius of each pin's pinion (mm)."""
    centres = np.array(spec.pin_centres())
    tips_a = np.asarray(tips, float)
    angles = np.array([math.atan2(c[1], c[0]) for c in centres])
    r_lo = spec.plate_inner_radius + spec.post_radius + POST_RIM_MARGIN
    r_hi = spec.plate_outer_radius - spec.post_radius - POST_RIM_MARGIN
    if r_hi <= r_lo:
        raise MeshingError(
            f"carrier.post_radius = {spec.post_radius!r}: a post does not fit between the plates' "
            f"inner ({spec.plate_inner_radius:.2f} mm) and outer ({spec.plate_outer_radius:.2f} "
            f"mm) radii with {POST_RIM_MARGIN:g} mm of plate each side"
        )
    radii = np.linspace(r_lo, r_hi, samples)
    posts = []
    for k, pins in enumerate(branches):
        nxt = branches[(k + 1) % len(branches)]
        a0 = angles[pins[-1]]
        gap = (angles[nxt[0]] - a0) % (2 * math.pi) or 2 * math.pi
        ang = a0 + gap * np.linspace(0.0, 1.0, samples + 2)[1:-1]
        A, R = np.meshgrid(ang, radii, indexing="ij")
        P = np.stack([R * np.cos(A), R * np.sin(A)], axis=-1)
        d = np.linalg.norm(P[:, :, None, :] - centres[None, None, :, :], axis=-1)
        clear = (d - tips_a).min(axis=-1) - spec.post_radius
        i, j = np.unravel_index(int(np.argmax(clear)), clear.shape)
        if clear[i, j] < MIN_POST_CLEARANCE:
            raise MeshingError(
                f"carrier.post_radius = {spec.post_radius!r}: no room for a post between branch "
                f"{k + 1} and branch {(k + 1) % len(branches) + 1}: the best place keeps "
                f"{clear[i, j]:.2f} mm from a pinion's tip circle, at least "
                f"{MIN_POST_CLEARANCE:g} mm needed (smaller posts or larger plates)"
            )
        posts.append((float(A[i, j] % (2 * math.pi)), float(R[i, j])))
    return tuple(posts)


def carrier_spec(gearset, pin_diameter: float = 16.0, rp_side: int = +1) -> CarrierSpec:
    """The carrier of a gear set (see the module docstring): single pinion, one pin per
    pinion on the sun-pinion centre distance at the assemblable angles nearest to equal
    spacing, posts midway; double pinion, an SP and an RP pin per branch at the centres the
    scenes place them (``rp_side`` as :func:`meshing.scenes.branch_centres`), the branches
    at multiples of 2 pi / (Zr - Zs), one post per branch clear of every pinion."""
    path = gearset.power_path
    sun, ring = gearset.gears[path[0]], gearset.gears[path[-1]]
    pinions = [gearset.gears[n] for n in path[1:-1]]
    if len(pinions) not in (1, 2):
        raise MeshingError(
            f"{gearset.name}: power path {list(path)}: the carrier holds one or two pinions per "
            "branch"
        )
    common = {
        "pin_diameter": pin_diameter,
        "pin_circle_radius": gearset.meshes[0].centre_distance,
        "pinion_face_width": max(p.face_width for p in pinions),
        "plate_inner_radius": sun.tip_radius + 1.5,
        "plate_outer_radius": ring.tip_radius - 2.5,
    }
    if len(pinions) == 1:
        angles = assemblable_angles(sun.teeth, ring.teeth, gearset.planets)
        return CarrierSpec(pin_angles=tuple(float(a) for a in angles), **common)
    if rp_side not in (1, -1):
        raise MeshingError(f"rp_side = {rp_side!r}: must be +1 or -1")
    psi = assemblable_angles(sun.teeth, ring.teeth, gearset.planets, double_pinion=True)
    psi_t = rp_side * sun_rp_angle(gearset)
    a1, a3 = gearset.meshes[0].centre_distance, gearset.meshes[-1].centre_distance
    pin_angles = tuple(float(a + d) for a in psi for d in (0.0, psi_t))
    spec = CarrierSpec(pin_angles=pin_angles, pin_radii=(a1, a3) * len(psi), **common)
    spec.validate()
    order = [[2 * k, 2 * k + 1] if rp_side > 0 else [2 * k + 1, 2 * k] for k in range(len(psi))]
    tips = [p.tip_radius for p in pinions] * len(psi)
    return replace(spec, posts=place_posts(spec, order, tips))
