"""The contact model of a gear scene: any number of pinions and meshes, one builder.

Handed a scene (:mod:`meshing.scenes`: the sun first, the pinions, the ring last, and one
mesh zone per gear mesh) and the body meshes already placed in the scene frame
(:func:`meshing.placed_meshes.load_scene_bodies`), :func:`build_gear_train` sets up:

* the sun: its bore rigidly coupled to the axis point, all rigid DOFs fixed but the rotation
  about z, which is an explicit rigid unknown balanced by the sun torque of the scene (the
  input torque times the share of the branches the scene holds). A sun sector's cut faces
  are free;
* every pinion (full): its bore on the study's needle bearing (6x6 diagonal about the pin
  centre: radial x and y, axial, tilting about x and y, spin free), the spin an explicit
  rigid unknown with a zero-moment equation;
* the ring: held at its outer rim (homogeneous Dirichlet on ``<ring>/rim``), so the ring
  reaction torque is the rim support reaction;
* one contact pair per mesh zone, on the exact contact-line grid of
  :func:`solvers.flank_grid.flank_grid` (driver on side A, driven on side B).

Gears take E = E_case * gear_modulus_factor and nu from the study case.

Pinion frame (singh2007 sections 3 and 5, one per pinion): X radial from the sun centre
through the pinion centre, Z = -z (scene), Y = Z x X (right-handed). The scene's sun turns
counter-clockwise, the paper's clockwise: the frame is the scene turned 180 deg about X (not
a mirror), which gives the paper's signs (case 1: the tangential sun-mesh force on the
pinion FyS < 0 and FzS > 0 as in Table 3).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gears.units import n_mm
from solvers.contact import ContactProblem, RigidUnknown
from solvers.contact_grid import ContactGrid
from solvers.elastic_body import Dirichlet, ElasticBody, Material
from solvers.flank_grid import FlankGridInfo, flank_contact_pairs
from solvers.rigid_coupling import RigidCoupling, bearing


def pinion_frame(centre) -> np.ndarray:
    """Rows e_X (radial, sun -> pinion), e_Y = e_Z x e_X, e_Z = -z (scene coordinates)."""
    ex = np.array([centre[0], centre[1], 0.0])
    ex /= np.linalg.norm(ex)
    ez = np.array([0.0, 0.0, -1.0])
    return np.vstack([ex, np.cross(ez, ex), ez])


@dataclass
class GearTrainModel:
    problem: ContactProblem
    scene: object  # meshing.scenes.Scene
    grids: dict[str, tuple[ContactGrid, FlankGridInfo]]  # per mesh zone "driver-driven"
    torque: float  # N mm on the sun
    centres: dict[str, np.ndarray]  # pinion centres (scene frame, mm)
    frames: dict[str, np.ndarray]  # pinion frames (rows e_X, e_Y, e_Z)
    dofs: int
    timings: dict

    @property
    def pinions(self) -> tuple[str, ...]:
        return tuple(self.centres)


def sun_torque(gearset, branches: int) -> float:
    """Sun torque (N mm) carried by ``branches`` of the set's branches (equal sharing)."""
    return n_mm(gearset.input_torque / gearset.planets * branches)


def total_dofs(bodies) -> int:
    return sum(b.V.dofmap.index_map.size_global * b.V.dofmap.index_map_bs for b in bodies)


def gear_bodies(scene, meshes: dict, study, degree: int) -> tuple[list[ElasticBody], dict]:
    """The elastic bodies of the scene's gears (scene frame) and the pinion centres."""
    mat = Material(study.material.gear_youngs_modulus, study.material.poisson_ratio)
    brg, origin = study.bearing, (0.0, 0.0, 0.0)
    sun, ring = scene.sun_name, scene.ring_name
    centres = {p: np.array([*scene.gear(p).placement.centre, 0.0]) for p in scene.pinion_names}
    bodies = []
    for g in scene.gears:
        nm = g.name
        bundle, tags = meshes[nm]
        kw: dict = {"centre": origin}
        if nm == sun:
            fixed = (math.inf,) * 5 + (0.0,)  # rotation about z left to a rigid unknown
            kw["couplings"] = [RigidCoupling("axis", f"{nm}/bore", origin, fixed)]
        elif nm == ring:
            kw["dirichlet"] = [Dirichlet(f"{nm}/rim")]
        else:
            c = tuple(centres[nm])
            kw["centre"] = c
            kw["couplings"] = [
                bearing(
                    "bearing",
                    f"{nm}/bore",
                    c,
                    (0.0, 0.0, 1.0),
                    brg.radial_stiffness,
                    brg.tilting_stiffness,
                    brg.axial_stiffness,
                )
            ]
        bodies.append(ElasticBody(nm, bundle.mesh, bundle.facet_tags, tags, mat, degree, **kw))
    return bodies, centres


def build_gear_train(
    scene,
    meshes: dict,
    study,
    *,
    degree: int,
    spacing: float,
    penalty_factor: float,
    width: float | None = None,
    micro: Callable | None = None,
) -> GearTrainModel:
    """The contact problem of ``scene`` (see the module docstring).

    Args:
        scene: :class:`meshing.scenes.Scene`.
        meshes: body name -> (mesh bundle, facet tag names) placed in the scene frame.
        study: :class:`cases.study_case.StudyCase` (material, bearing, torque).
        degree: Lagrange degree of the bodies.
        spacing: contact grid point spacing along the contact lines (mm).
        penalty_factor: contact penalty scale (see :class:`solvers.contact.ContactProblem`).
        width: grid patch width across the lines (mm; default ``spacing``).
        micro: optional ``micro(zone, points) -> (n,)`` added to the initial gap (mm).
    """
    t0 = time.perf_counter()
    bodies, centres = gear_bodies(scene, meshes, study, degree)
    grids, pairs = flank_contact_pairs(scene, spacing, width, micro)
    torque = sun_torque(study.gearset, scene.branches)
    sun = scene.sun_name
    problem = ContactProblem(
        bodies,
        pairs,
        [
            RigidUnknown(f"{sun}_rotation", sun, coupling="axis", dof=5, load=torque),
            *(RigidUnknown(f"{p}_spin", p, coupling="bearing", dof=5, load=0.0) for p in centres),
        ],
        penalty_factor=penalty_factor,
    )
    frames = {p: pinion_frame(c) for p, c in centres.items()}
    timings = {"model": time.perf_counter() - t0}
    return GearTrainModel(
        problem, scene, grids, torque, centres, frames, total_dofs(bodies), timings
    )
