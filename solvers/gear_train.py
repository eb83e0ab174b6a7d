"""The contact model of a gear scene: any number of pinions and meshes, one builder.

Handed a scene (:mod:`meshing.scenes`: the sun first, the pinions, the ring last, one mesh
zone per gear mesh, and possibly the carrier) and the body meshes in their own frames
(:func:`meshing.scene_bodies.load_body_meshes`), :func:`build_gear_train` places each body
by its gear's placement (a rigid map: the body's stiffness and factorization, kept in a
:class:`solvers.body_store.BodyStore`, serve every mesh position) and sets up:

* the sun: its bore rigidly coupled to the axis point, the rotation about z an explicit
  rigid unknown balanced by the sun torque of the scene (the input torque times the share of
  the branches the scene holds). Without a carrier body the other five DOFs are fixed; with
  one (the ``system`` scene) the sun floats radially: its x and y translations are rigid
  unknowns on the case's radial support springs (0: floating). A sun sector's cut faces
  are free;
* every pinion (full): its bore rigidly coupled to the pin centre and clamped there in the
  FE system; the six rigid motions of the bore (x, y, z translations, tilts about x and y,
  spin about z; scene axes) are explicit rigid unknowns ``<pinion>_x`` ... ``<pinion>_spin``
  held by the study's needle bearing, a 6x6 diagonal spring (radial x and y, axial, tilting
  about x and y, spin free: a zero-moment equation) to its pin: a rigid, fixed pin, or the
  pin of the elastic carrier. The springs live outside the body's factorization;
* the carrier (``system`` scene): an elastic steel body (the gears' modulus factor does not
  apply) held at the hub of its -z plate, condensed onto its pins (each pin surface a rigid
  ring on a reference point at the pin centre; :class:`solvers.superelement.Superelement`):
  rigid unknowns ``carrier_pin<k>_<dof>`` with the carrier's condensed stiffness, pin k
  under the scene's k-th pinion (double pinion: SP1, RP1, SP2, ..., each SP and each RP on
  its own pin). A pin-hole position error e (tangential along the sun's rotation, radial)
  offsets the bearing spring's rest position, k (q_pinion - q_pin - e)
  (:func:`branch_pin_errors`: per pinion, or per branch on the SP pin);
* the ring: held at its outer rim (homogeneous Dirichlet on ``<ring>/rim``), so the ring
  reaction torque is the rim support reaction;
* two contact pairs per mesh zone, on the exact contact-line grids of
  :func:`solvers.flank_grid.flank_grid` (driver on side A, driven on side B): the drive
  flanks, and after every drive pair the coast flanks, whose initial gap is the mesh's normal
  backlash (they carry load only where a large tilt closes it). The gear set's flank
  modifications enter both as initial gaps.

Gears take E = E_case * gear_modulus_factor and nu from the case (:class:`TrainInputs`).

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
from dataclasses import dataclass, field

import numpy as np

from gears.units import n_mm
from meshing import tags as T
from solvers.body_store import BodyStore
from solvers.contact import ContactProblem, RigidUnknown, Spring, StiffnessBlock
from solvers.contact_grid import ContactGrid
from solvers.elastic_body import Dirichlet, ElasticBody, Material
from solvers.flank_grid import FlankGridInfo, flank_contact_pairs, is_coast, mesh_name
from solvers.modulus_scaling import ScaledBody, with_material
from solvers.rigid_coupling import RigidCoupling
from solvers.superelement import Superelement
from solvers.train_inputs import TrainInputs

#: the six bore DOFs of a pinion (and of a carrier pin), as rigid unknowns <name>_<dof>
BEARING_DOFS = ("x", "y", "z", "rx", "ry", "spin")
CARRIER = T.CARRIER
UM = 1e-3  # mm per um


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
    bearings: dict[str, np.ndarray]  # pinion -> the 6 bearing stiffnesses (scene axes)
    dofs: int
    timings: dict
    pins: dict[str, str | None] = field(default_factory=dict)  # pinion -> carrier pin prefix
    pin_errors: dict[str, np.ndarray] = field(default_factory=dict)  # pinion -> 6 offsets
    carrier: Superelement | None = None
    # coast-flank grids per mesh zone "driver-driven" (grid "driver-driven/coast")
    coast_grids: dict[str, tuple[ContactGrid, FlankGridInfo]] = field(default_factory=dict)

    @property
    def pinions(self) -> tuple[str, ...]:
        return tuple(self.centres)

    def bearing_load(self, pinion: str, rigid: dict[str, float]) -> np.ndarray:
        """The bearing's spring load on the pin (6: N along x, y, z, N mm about x, y, z;
        scene axes): k (q_pinion - q_pin - e)."""
        q = np.array([rigid[f"{pinion}_{d}"] for d in BEARING_DOFS])
        pin = self.pins.get(pinion)
        if pin is not None:
            q = q - np.array([rigid[f"{pin}_{d}"] for d in BEARING_DOFS])
        q = q - self.pin_errors.get(pinion, np.zeros(6))
        return self.bearings[pinion] * q


def sun_torque(gearset, branches: int) -> float:
    """Sun torque (N mm) carried by ``branches`` of the set's branches (equal sharing)."""
    return n_mm(gearset.input_torque / gearset.planets * branches)


def total_dofs(bodies) -> int:
    return sum(b.V.dofmap.index_map.size_global * b.V.dofmap.index_map_bs for b in bodies)


def _rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def bearing_stiffness(bearing) -> np.ndarray:
    """The 6 diagonal needle-bearing stiffnesses along :data:`BEARING_DOFS` (N/mm, N mm/rad):
    radial x and y, axial, tilting about x and y, spin free."""
    b = bearing
    return np.array(
        [
            b.radial_stiffness,
            b.radial_stiffness,
            b.axial_stiffness,
            b.tilting_stiffness,
            b.tilting_stiffness,
            0.0,
        ]
    )


def _held_body(store, key, make, held):
    def made():
        b = make()
        for coupling, dof in held:
            b.hold(coupling, dof)
        return b

    return store.body(key, made)


def gear_bodies(
    scene, meshes: dict, inputs: TrainInputs, degree: int, store: BodyStore
) -> list[ElasticBody]:
    """The elastic bodies of the scene's gears, each in its own frame and placed in the scene:
    the sun bore slaved to its axis, every pinion bore slaved to its centre (all six DOFs
    held as rigid unknowns), the ring held at its rim. Kept in ``store`` by (mesh, degree,
    Poisson ratio, supports): a body of another Young's modulus is a
    :class:`solvers.modulus_scaling.ScaledBody` of the stored one."""
    mat = Material(inputs.gear_youngs_modulus, inputs.poisson_ratio)
    ls = inputs.linear_solver
    origin = (0.0, 0.0, 0.0)
    sun, ring = scene.sun_name, scene.ring_name
    floating = scene.carrier is not None
    bodies = []
    for g in scene.gears:
        nm = g.name
        bm = meshes[nm]
        kw: dict = {"centre": origin}
        held: list[tuple[str, int]] = []  # reference DOFs left to rigid unknowns
        if nm == sun:
            inf = math.inf
            fixed = (0.0, 0.0, inf, inf, inf, 0.0) if floating else (inf,) * 5 + (0.0,)
            kw["couplings"] = [RigidCoupling("axis", f"{nm}/bore", origin, fixed)]
            held = [("axis", 0), ("axis", 1), ("axis", 5)] if floating else [("axis", 5)]
            role = "sun-floating" if floating else "sun"
        elif nm == ring:
            kw["dirichlet"] = [Dirichlet(f"{nm}/rim")]
            role = "ring"
        else:
            kw["couplings"] = [RigidCoupling("bearing", f"{nm}/bore", origin, (0.0,) * 6)]
            held = [("bearing", j) for j in range(len(BEARING_DOFS))]
            role = "pinion"

        def make(bm=bm, nm=nm, kw=kw):
            return ElasticBody(
                nm,
                bm.bundle.mesh,
                bm.bundle.facet_tags,
                bm.tags,
                mat,
                degree,
                linear_solver=ls,
                **kw,
            )

        # keyed without E: a gear set of another modulus solves on the same factors
        base = _held_body(store, (bm.key, degree, mat.nu, role, ls), make, held)
        b = with_material(base, mat, ScaledBody)
        b.place(_rotation_z(g.placement.angle), (*g.placement.centre, 0.0))
        bodies.append(b)
    return bodies


def carrier_superelement(
    scene, meshes: dict, inputs: TrainInputs, degree: int, store
) -> Superelement:
    """The carrier condensed onto its pins: steel (no gear modulus factor), held at the hub
    of its -z plate, each pin surface a rigid ring on a reference point at the pin centre."""
    spec = scene.carrier
    mat = Material(inputs.youngs_modulus, inputs.poisson_ratio)
    bm = meshes[CARRIER]
    couplings = [
        RigidCoupling(f"pin{k}", T.pin(k), (float(c[0]), float(c[1]), 0.0), (0.0,) * 6)
        for k, c in enumerate(spec.pin_centres())
    ]
    hub = Dirichlet(T.carrier_surface(T.HUB_ZNEG))

    def make():
        mb = bm.bundle
        kw = {"couplings": couplings, "dirichlet": [hub], "centre": (0.0, 0.0, 0.0)}
        body = ElasticBody(
            CARRIER, mb.mesh, mb.facet_tags, bm.tags, mat, degree, linear_solver=ls, **kw
        )
        return Superelement(body)

    ls = inputs.linear_solver
    return store.keep((bm.key, degree, mat.E, mat.nu, "carrier-superelement", ls), make)


def bearing_unknowns(pinion: str, k: np.ndarray, pin: str | None, offset: np.ndarray):
    """The six rigid unknowns of a pinion's bore (scene axes) and the bearing springs that
    hold them to the pin: ``pin`` (the prefix of a carrier pin's unknowns) or, if None, a
    rigid pin fixed in space. ``offset``: the springs' rest offsets (pin-hole error)."""
    unknowns = [
        RigidUnknown(f"{pinion}_{d}", pinion, coupling="bearing", dof=j, axes=np.eye(3))
        for j, d in enumerate(BEARING_DOFS)
    ]
    springs = [
        Spring(f"{pinion}_{d}", None if pin is None else f"{pin}_{d}", float(kj), float(o))
        for d, kj, o in zip(BEARING_DOFS, k, offset, strict=True)
        if kj > 0
    ]
    return unknowns, springs


def _pin_unknowns(se: Superelement) -> tuple[list[RigidUnknown], StiffnessBlock, list[str]]:
    """Rigid unknowns of the carrier's pin reference DOFs (scene axes: the carrier is not
    turned) and the carrier's condensed stiffness on them."""
    body = se.body
    names, unknowns, prefixes = [], [], []
    for cname, c in body.couplings.items():
        prefix = f"{CARRIER}_{cname}"
        prefixes.append(prefix)
        for j, d in enumerate(BEARING_DOFS):
            e = np.eye(3)[j % 3]
            kw = {"direction": e} if j < 3 else {"axis": e}
            unknowns.append(RigidUnknown(f"{prefix}_{d}", CARRIER, x_ref=c.x_ref, **kw))
            names.append(f"{prefix}_{d}")
    if [f"{CARRIER}_{c}_{BEARING_DOFS[j]}" for c, j in se.dofs] != names:
        raise RuntimeError("carrier superelement DOFs out of order")
    return unknowns, StiffnessBlock(tuple(names), se.S), prefixes


def pin_error_offsets(error_um, angle: float) -> np.ndarray:
    """Bearing-spring rest offsets (6, mm) of a pin-hole error [tangential, radial] (um) at
    carrier angle ``angle``: tangential along the sun's (counter-clockwise) rotation."""
    e_t, e_r = (v * UM for v in error_um)
    radial = np.array([math.cos(angle), math.sin(angle)])
    tangential = np.array([-math.sin(angle), math.cos(angle)])
    xy = e_r * radial + e_t * tangential
    return np.array([xy[0], xy[1], 0.0, 0.0, 0.0, 0.0])


def branch_pin_errors(errors, pinions: int, branches: int) -> list[tuple[float, float]]:
    """Pin-hole errors [tangential, radial] (um) per pinion in carrier order from the case
    file's list: none (all exact), one per pinion, or one per branch (the case file's
    ``system.pin_position_errors_um`` has one per planet); a double-pinion branch's error is
    its SP pin's (the pin on the sun-pinion centre distance, as a single pinion's), its RP
    pin exact."""
    if not errors:
        return [(0.0, 0.0)] * pinions
    if len(errors) == pinions:
        return [tuple(e) for e in errors]
    per = pinions // branches if branches else 0
    if per * branches != pinions or len(errors) != branches:
        raise ValueError(
            f"system.pin_position_errors_um: {len(errors)} errors for {pinions} pinions in "
            f"{branches} branches: give one per branch or one per pinion"
        )
    return [tuple(e) if j == 0 else (0.0, 0.0) for e in errors for j in range(per)]


def contact_grids(
    scene,
    inputs: TrainInputs,
    spacing: float,
    width=None,
    micro=None,
    e_plane=None,
    coast: bool = True,
):
    """The contact grids and pairs of ``scene`` with the contact settings and flank
    modifications of ``inputs`` (:func:`solvers.flank_grid.flank_contact_pairs`); ``e_plane``
    by body name, default the gears' plane-strain modulus (:func:`gear_bodies`'s material)."""
    if e_plane is None:
        e = Material(inputs.gear_youngs_modulus, inputs.poisson_ratio).e_plane
        e_plane = {g.name: e for g in scene.gears}
    return flank_contact_pairs(
        scene,
        spacing,
        width,
        micro,
        modifications=inputs.modifications,
        coast=coast,
        contact_model=inputs.contact_model,
        gap_limit=inputs.zone_gap_limit_mm,
        e_plane=e_plane,
    )


def build_gear_train(
    scene,
    meshes: dict,
    inputs: TrainInputs,
    *,
    degree: int,
    spacing: float,
    penalty_factor: float,
    width: float | None = None,
    micro: Callable | None = None,
    store: BodyStore | None = None,
) -> GearTrainModel:
    """The contact problem of ``scene`` (see the module docstring).

    Args:
        scene: :class:`meshing.scenes.Scene`.
        meshes: body name -> :class:`meshing.scene_bodies.BodyMesh` (body frame).
        inputs: what the model takes of the case (:class:`solvers.train_inputs.TrainInputs`).
        degree: Lagrange degree of the bodies.
        spacing: contact grid point spacing along the contact lines (mm).
        penalty_factor: contact penalty scale (see :class:`solvers.contact.ContactProblem`).
        width: grid patch width across the lines (mm; default ``spacing``).
        micro: optional ``micro(zone, points) -> (n,)`` added to the initial gap (mm).
        store: where set-up bodies are kept across positions and cases (default: a new one).
    """
    t0 = time.perf_counter()
    store = BodyStore() if store is None else store
    bodies = gear_bodies(scene, meshes, inputs, degree, store)
    every, pairs = contact_grids(
        scene, inputs, spacing, width, micro, {b.name: b.material.e_plane for b in bodies}
    )
    grids = {k: v for k, v in every.items() if not is_coast(k)}
    coast_grids = {mesh_name(k): v for k, v in every.items() if is_coast(k)}
    torque = n_mm(inputs.torque_per_branch_Nm * scene.branches)
    sun = scene.sun_name
    centres = {p: np.array([*scene.gear(p).placement.centre, 0.0]) for p in scene.pinion_names}
    k = np.array(inputs.bearing_stiffness, dtype=float)
    unknowns = [RigidUnknown(f"{sun}_rotation", sun, coupling="axis", dof=5, load=torque)]
    springs, blocks, obstacles = [], [], []
    pins: dict[str, str | None] = dict.fromkeys(centres)
    errors = {p: np.zeros(6) for p in centres}
    carrier = None
    if scene.carrier is not None:
        k_sun = inputs.sun_radial_stiffness
        for j, d in ((0, "x"), (1, "y")):
            unknowns.append(RigidUnknown(f"{sun}_{d}", sun, coupling="axis", dof=j, axes=np.eye(3)))
            if k_sun > 0:
                springs.append(Spring(f"{sun}_{d}", None, k_sun))
        carrier = carrier_superelement(scene, meshes, inputs, degree, store)
        pin_unknowns, block, prefixes = _pin_unknowns(carrier)
        unknowns += pin_unknowns
        blocks.append(block)
        obstacles.append(CARRIER)
        angles = scene.carrier.pin_angles
        if len(prefixes) != len(centres):
            raise ValueError(f"{len(prefixes)} carrier pins for {len(centres)} pinions")
        pin_err = branch_pin_errors(inputs.pin_position_errors_um, len(centres), scene.branches)
        for p, prefix, a, e in zip(centres, prefixes, angles, pin_err, strict=True):
            pins[p] = prefix
            errors[p] = pin_error_offsets(e, a)
    for p in centres:
        u, s = bearing_unknowns(p, k, pins[p], errors[p])
        unknowns += u
        springs += s
    problem = ContactProblem(
        bodies,
        pairs,
        unknowns,
        springs,
        obstacles=obstacles,
        blocks=blocks,
        penalty_factor=penalty_factor,
    )
    frames = {p: pinion_frame(c) for p, c in centres.items()}
    bearings = {p: k.copy() for p in centres}
    dofs = total_dofs(bodies) + (total_dofs([carrier.body]) if carrier else 0)
    timings = {"model": time.perf_counter() - t0}
    return GearTrainModel(
        problem,
        scene,
        grids,
        torque,
        centres,
        frames,
        bearings,
        dofs,
        timings,
        pins,
        errors,
        carrier,
        coast_grids,
    )
