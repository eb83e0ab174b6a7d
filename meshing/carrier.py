"""Planet carrier: two annular plates joined by posts, with the pinion pins through them.

Real enough for a carrier wind-up study (plates, posts, pins as one steel body); the case
studies may treat it as rigid. Pins are cylinders of ``pin_diameter`` and ``pin_length``
centred at mid face width; the pin surface between the plates (``carrier/pin<K>``) is where
a pinion's needle bearing acts. Posts sit midway between the pins on the pin circle.
Frame: the scene frame (sun axis = z, z = 0 at mid face width).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import numpy as np

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
        r_pin = 0.5 * self.pin_diameter
        need(
            self.plate_inner_radius + r_pin
            < self.pin_circle_radius
            < self.plate_outer_radius - r_pin,
            "pin_diameter",
            "pins must lie inside the plates (inner radius + pin radius < pin circle radius "
            "< outer radius - pin radius)",
        )
        need(
            self.plate_inner_radius < self.pin_circle_radius - self.post_radius
            and self.pin_circle_radius + self.post_radius < self.plate_outer_radius,
            "post_radius",
            "posts must lie inside the plates",
        )

    def post_angles(self) -> list[float]:
        a = sorted(x % (2 * math.pi) for x in self.pin_angles)
        if len(a) < 2:
            return []
        nxt = [*a[1:], a[0] + 2 * math.pi]
        return [0.5 * (x + y) for x, y in zip(a, nxt, strict=True)]

    def params(self) -> dict:
        return {**asdict(self), "version": MESHER_VERSION}


def build_geometry(gmsh, spec: CarrierSpec) -> int:
    spec.validate()
    occ = gmsh.model.occ
    z_in, z_out = spec.plate_z
    rc = spec.pin_circle_radius
    parts = []
    for sgn in (1, -1):
        z0 = z_in if sgn > 0 else -z_out
        outer = occ.addCylinder(0, 0, z0, 0, 0, spec.plate_thickness, spec.plate_outer_radius)
        inner = occ.addCylinder(0, 0, z0, 0, 0, spec.plate_thickness, spec.plate_inner_radius)
        plate, _ = occ.cut([(3, outer)], [(3, inner)])
        parts += plate
    half = 0.5 * spec.length
    for a in spec.pin_angles:
        c = rc * np.array([math.cos(a), math.sin(a)])
        parts.append(
            (3, occ.addCylinder(c[0], c[1], -half, 0, 0, 2 * half, 0.5 * spec.pin_diameter))
        )
    for a in spec.post_angles():
        c = rc * np.array([math.cos(a), math.sin(a)])
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
    centres = [
        spec.pin_circle_radius * np.array([math.cos(a), math.sin(a)]) for a in spec.pin_angles
    ]
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


def carrier_spec(gearset, pin_diameter: float = 16.0) -> CarrierSpec:
    """The carrier of a single-pinion gear set: one pin per pinion at the carrier angles the
    assembly condition allows nearest to equal spacing, on the sun-pinion centre distance."""
    path = gearset.power_path
    if len(path) != 3:
        raise MeshingError(
            f"{gearset.name}: the carrier is modelled for single-pinion sets only (the "
            "double-pinion carrier with SP and RP pins is not built yet)"
        )
    sun, pinion, ring = (gearset.gears[n] for n in path)
    angles = assemblable_angles(sun.teeth, ring.teeth, gearset.planets)
    return CarrierSpec(
        pin_diameter=pin_diameter,
        pin_circle_radius=gearset.meshes[0].centre_distance,
        pin_angles=tuple(float(a) for a in angles),
        pinion_face_width=pinion.face_width,
        plate_inner_radius=sun.tip_radius + 1.5,
        plate_outer_radius=ring.tip_radius - 2.5,
    )
