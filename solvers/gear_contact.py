"""Contact on real gear scenes: exact contact-line grids and the one-branch case-1 model.

Grid (:func:`flank_grid`). For one mesh zone of a scene (:mod:`meshing.scenes`) and every
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

Initial gap. g0 = dev_A(p) + dev_B(p) (+ optional microgeometry), dev the signed normal
distance outside the material from :func:`meshing.gear_geometry.involute_deviation` of
each exact flank: for two flanks with common normal at p the separation along n is the sum
of the two distances, and it is 0 (to ~1e-13 mm) on the theoretical lines of perfect
involutes. ``micro(zone, points) -> (n,) mm`` adds crowning / misalignment (default none).

Model (:func:`build_branch`, case 1, one branch). Bodies from the cached body meshes of
the scene, moved to their placements (scene frame, z = 0 mid face width):

* sun sector: bore rigidly coupled to the axis point (all rigid DOFs fixed but rotation
  about z), the rotation an explicit rigid unknown balanced by the torque per branch T/3;
  the sector's cut faces are free;
* pinion (full): bore on the case's needle bearing (6x6 diagonal about its centre: radial
  x and y, axial, tilting about x and y; spin free), the spin an explicit rigid unknown with
  a zero-moment equation;
* ring sector: held at its outer rim (homogeneous Dirichlet on ``ring/rim``; the cut faces
  free), so the ring reaction torque is the rim support reaction.

Gears take E = E_case * gear_modulus_factor, nu from the case.

Outputs (:func:`run_position`), in the paper's pinion frame (singh2007 section 3): X radial
from the sun centre through the pinion centre, Y tangential, Z axial. The scene's sun turns
counter-clockwise, the paper's sense is the opposite: Y is chosen so that the tangential
sun-mesh force on the pinion is negative (as FyS in Table 3) and Z = X x Y (right-handed).
For case 1 this gives Y = -y, Z = -z (a 180 deg turn about X, not a mirror), and then
FzS > 0 as in Table 3 (checked). Mx_pin, My_pin, Mz_pin (N m) = moment of the contact
forces on the pinion about its centre = the moment the bearing carries (also read from the
bearing springs, k q, and from the residual). ZS, ZR = force-weighted Z of the contact
points at each mesh (mm from mid face width). ``bending_stress``: the largest maximum
principal stress (MPa) of the FE field in the cells at the root fillets of the loaded teeth,
per gear (the pinion per mesh), with its location (:mod:`solvers.root_stress`).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import numpy as np
from mpi4py import MPI

from solvers.contact import ContactPair, ContactProblem, RigidUnknown
from solvers.contact_grid import ContactGrid
from solvers.elastic_body import Dirichlet, ElasticBody, Material
from solvers.results import contact_resultant, line_load, residual_resultant, write_vtx
from solvers.rigid_coupling import RigidCoupling, bearing
from solvers.root_stress import root_stress


# ---------------------------------------------------------------------------- grid
@dataclass
class FlankGridInfo:
    """What :func:`flank_grid` laid out, beyond the :class:`ContactGrid` arrays."""

    lines: list[dict]  # per tooth pair: driver tooth, driven tooth, rows, length, spacing
    dev_a: np.ndarray  # involute_deviation of the driver's drive flank at the points (mm)
    dev_b: np.ndarray  # the same for the driven gear's drive flank
    micro: np.ndarray  # microgeometry / misalignment part of g0 (mm)


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
) -> tuple[ContactGrid, FlankGridInfo]:
    """Contact grid of one mesh zone on the theoretical contact lines, eq. (1).

    Args:
        zone: :class:`meshing.scenes.MeshZone` (with ``contact_lines``: the tooth pairs).
        drv, dvn: the driver and driven :class:`meshing.scenes.PlacedGear`.
        spacing: target point spacing along the line (mm), ~ the flank element size.
        width: patch width across the line (mm); default ``spacing``.
        micro: optional ``micro(zone, points (n, 3)) -> (n,)`` added to g0 (mm).
    """
    from meshing.gear_geometry import involute_deviation
    from meshing.scenes import flank_of

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
    dev_a = involute_deviation(ga, drv.placement.inverse(x), zone.driver_side)
    dev_b = involute_deviation(gb, dvn.placement.inverse(x), zone.driven_side)
    mic = np.zeros(m) if micro is None else np.asarray(micro(zone, x), float).reshape(m)
    tangents = np.broadcast_to(np.stack([tline, t2]), (m, 2, 3)).copy()
    half_across = np.minimum(_room(x, t2, drv, 0.5 * w_across), _room(x, t2, dvn, 0.5 * w_across))
    grid = ContactGrid(
        f"{zone.driver}-{zone.driven}",
        x.copy(),
        x.copy(),
        np.tile(n, (m, 1)),
        dev_a + dev_b + mic,
        seg * w_across,
        tangents=tangents,
        half_sizes=np.c_[0.5 * seg, half_across],
        stations=np.arange(m),
        station_length=seg.copy(),
        n_spread=n_spread,
    )
    return grid, FlankGridInfo(lines, dev_a, dev_b, mic)


# ---------------------------------------------------------------------------- model
@dataclass
class BranchModel:
    problem: ContactProblem
    scene: object
    grids: dict[str, tuple[ContactGrid, FlankGridInfo]]
    torque: float  # N mm on the sun (per branch)
    pinion_centre: np.ndarray
    frame: np.ndarray  # rows e_X, e_Y, e_Z of the paper's pinion frame (scene coordinates)
    dofs: int
    timings: dict


def _load_placed(pg, level: int, comm):
    """The body mesh of a placed gear, moved to the scene frame."""
    from meshing.gear_body import load_body

    bundle = load_body(pg.body, level, comm, active_teeth=pg.active_teeth)
    x = bundle.mesh.geometry.x
    x[:] = pg.placement.apply(x)
    tags = {nm: tag for nm, (dim, tag) in bundle.names.items() if dim == 2}
    return bundle, tags


def paper_frame(f_sun_on_pinion: np.ndarray, pinion_centre) -> np.ndarray:
    """Rows e_X (radial, sun -> pinion), e_Y (tangential, FyS < 0), e_Z = e_X x e_Y."""
    ex = np.array([*pinion_centre[:2], 0.0])
    ex /= np.linalg.norm(ex)
    ey = np.cross([0.0, 0.0, 1.0], ex)
    if f_sun_on_pinion @ ey > 0:
        ey = -ey
    return np.vstack([ex, ey, np.cross(ex, ey)])


def chain_bodies(case, scene, pinions: tuple[str, ...], level: int, degree: int, comm):
    """The elastic bodies of one power path sun -> pinions -> ring (scene frame): the sun
    bore slaved to its axis (rotation left to a rigid unknown), each pinion bore on the
    case's 6x6 diagonal needle bearing about its own centre (spin left to a rigid unknown),
    the ring held at its rim. Returns (bodies, pinion centres, mesh-loading seconds)."""
    t0 = time.perf_counter()
    names = ("sun", *pinions, "ring")
    loaded = {nm: _load_placed(scene.gear(nm), level, comm) for nm in names}
    t_meshes = time.perf_counter() - t0
    mat = Material(case.material.gear_youngs_modulus, case.material.poisson_ratio)
    brg, origin = case.bearing, (0.0, 0.0, 0.0)
    centres = {p: np.array([*scene.gear(p).placement.centre, 0.0]) for p in pinions}
    bodies = []
    for nm in names:
        b, tg = loaded[nm]
        kw: dict = {"centre": origin}
        if nm == "sun":
            kw["couplings"] = [RigidCoupling("axis", "sun/bore", origin, (math.inf,) * 5 + (0.0,))]
        elif nm == "ring":
            kw["dirichlet"] = [Dirichlet("ring/rim")]
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
        bodies.append(ElasticBody(nm, b.mesh, b.facet_tags, tg, mat, degree, **kw))
    return bodies, centres, t_meshes


def flank_contact_pairs(scene, spacing: float, width, micro):
    """Contact grids on the exact theoretical contact lines of every mesh zone of the scene,
    and the contact pairs (driver, driven) that carry them."""
    grids, pairs = {}, []
    for zn in scene.zones:
        g, info = flank_grid(
            zn, scene.gear(zn.driver), scene.gear(zn.driven), spacing, width, micro
        )
        grids[g.name] = (g, info)
        pairs.append(ContactPair(g, zn.driver, zn.driven))
    return grids, pairs


def total_dofs(bodies) -> int:
    return sum(b.V.dofmap.index_map.size_global * b.V.dofmap.index_map_bs for b in bodies)


def body_resultants(p: ContactProblem, result) -> tuple[dict, float]:
    """Per body (contact force, contact moment, residual resultants) and the largest relative
    mismatch between the contact and residual resultants over every body."""
    res = {}
    for name in p.bodies:
        fc, mc = contact_resultant(p, result, name)
        res[name] = (fc, mc, residual_resultant(p, result, name))
    agree = 0.0
    for f1, m1, r1 in res.values():
        agree = max(
            agree,
            np.linalg.norm(f1 - r1["contact"][0]) / max(np.linalg.norm(f1), 1e-30),
            np.linalg.norm(m1 - r1["contact"][1]) / max(np.linalg.norm(m1), 1e-30),
        )
    return res, float(agree)


def build_branch(
    case,
    roll: float = 0.0,
    comm: MPI.Comm = MPI.COMM_WORLD,
    level: int | None = None,
    degree: int = 1,
    spacing: float | None = None,
    width: float | None = None,
    penalty_factor: float = 100.0,
    micro: Callable | None = None,
) -> BranchModel:
    """The one-branch case-1 contact problem at sun roll angle ``roll`` (see module doc)."""
    from meshing import sizing
    from meshing.scenes import case1_scene

    if case.gearset.name != "case1":
        raise ValueError(f"{case.name}: build_branch models case 1 (single pinion) only")
    t0 = time.perf_counter()
    lv = case.model.level if level is None else level
    h = sizing.check_level(lv).fine if spacing is None else spacing
    scene = case1_scene(roll)
    bodies, centres, t_meshes = chain_bodies(case, scene, ("pinion",), lv, degree, comm)
    c_pin = centres["pinion"]
    grids, pairs = flank_contact_pairs(scene, h, width, micro)
    torque = case.gearset.torque_per_branch * 1e3  # N mm
    problem = ContactProblem(
        bodies,
        pairs,
        [
            RigidUnknown("sun_rotation", "sun", coupling="axis", dof=5, load=torque),
            RigidUnknown("pinion_spin", "pinion", coupling="bearing", dof=5, load=0.0),
        ],
        penalty_factor=penalty_factor,
    )
    sun_grid = grids["sun-pinion"][0]
    frame = paper_frame(sun_grid.normals[0], c_pin)
    timings = {"scene_and_meshes": t_meshes, "bodies": time.perf_counter() - t0 - t_meshes}
    return BranchModel(problem, scene, grids, torque, c_pin, frame, total_dofs(bodies), timings)


# ---------------------------------------------------------------------------- outputs
def _analytic():
    from postprocess.analytic import single_pinion as sp
    from postprocess.analytic.study import default_inputs, single_pinion_geometry

    c1 = default_inputs()[0]
    g = single_pinion_geometry(c1)
    return sp, g, sp.mesh_forces(c1.torque_per_branch, g)


def branch_results(model: BranchModel, result) -> dict:
    """The summary of a solved branch (replicated on every rank; N, N m, mm)."""
    p = model.problem
    Q = model.frame
    cp = model.pinion_centre
    out: dict = {"pinion_centre_mm": np.asarray(cp, float).tolist(), "frame": Q.tolist()}
    res, mismatch = body_resultants(p, result)
    fc, mc, rr = res["pinion"]
    out["pinion_force_N"] = (Q @ fc).tolist()  # load carried by the bearing
    m_pin = Q @ mc / 1e3
    out["Mx_pin"], out["My_pin"], out["Mz_pin"] = (float(v) for v in m_pin)
    out["pinion_moment_residual_Nm"] = (Q @ rr["contact"][1] / 1e3).tolist()
    out["pinion_support_moment_Nm"] = (Q @ rr["support"][1] / 1e3).tolist()
    # spring reactions k q (bearing frame rows a_1, a_2, a_3 = x, y, z of the scene)
    b_pin = p.bodies["pinion"]
    q = b_pin.reference_dofs(result.reduced["pinion"])["bearing"]
    c = b_pin.couplings["bearing"]
    kq = c.springs() * q
    a = c.frame(3)
    out["bearing_spring_force_N"] = (Q @ (a.T @ kq[:3])).tolist()
    out["bearing_spring_moment_Nm"] = (Q @ (a.T @ kq[3:]) / 1e3).tolist()
    out["pinion_tilt_rad"] = (Q @ (a.T @ q[3:])).tolist()
    out["pinion_spin_moment_Nm"] = float(mc[2] / 1e3)
    out["resultant_mismatch_rel"] = mismatch
    # torques about the scene axis
    out["sun_torque_applied_Nm"] = model.torque / 1e3
    out["sun_contact_torque_Nm"] = float(res["sun"][1][2] / 1e3)
    out["ring_contact_torque_Nm"] = float(res["ring"][1][2] / 1e3)
    out["ring_support_torque_Nm"] = float(res["ring"][2]["support"][1][2] / 1e3)
    # centroids, line loads
    for key, pname in (("S", "sun-pinion"), ("R", "pinion-ring")):
        i = [pp.grid.name for pp in p.pairs].index(pname)
        sl = slice(p.offsets[i], p.offsets[i + 1])
        F = result.forces[sl]
        g = model.grids[pname][0]
        Z = (g.x_a - cp) @ Q[2]
        tot = float(F.sum())
        out[f"Z{key}"] = float((F * Z).sum() / tot) if tot > 0 else float("nan")
        out[f"mesh_normal_force_{key}_N"] = tot
        # the mesh force on the pinion in the paper frame (sun: +n, ring: -n on the pinion)
        sgn = 1.0 if key == "S" else -1.0
        out[f"F{key}_pinion_N"] = (sgn * tot * (Q @ g.normals[0])).tolist()
        out[f"active_points_{key}"] = int(np.count_nonzero(F > 0))
        out[f"grid_points_{key}"] = g.n
        out[f"points_{key}"] = {
            "x_mm": g.x_a.tolist(),
            "force_N": F.tolist(),
            "line_load_N_per_mm": line_load(p, result, i).tolist(),
        }
        # position of the load centroid along the line of action (for the pitch-point check)
        out[f"centroid_{key}_mm"] = ((F @ (g.x_a - cp)) / tot).tolist() if tot > 0 else None
    # LOA moments from the FE moments, and the analytic model at the FE's own ZS, ZR
    sp, geo, f = _analytic()
    out["M_LOA_sun"], out["M_LOA_ring"] = sp.loa_moments(
        out["Mx_pin"], out["My_pin"], geo.alpha1, geo.alpha2
    )
    mx_a, my_a, mz_a = sp.pinion_moments(f, geo, out["ZS"], out["ZR"])
    la_s, la_r = sp.loa_moments(mx_a, my_a, geo.alpha1, geo.alpha2)
    out["analytic"] = {
        "Mx_pin": mx_a,
        "My_pin": my_a,
        "Mz_pin": mz_a,
        "M_LOA_sun": la_s,
        "M_LOA_ring": la_r,
        "FzS": f.FzS,
        "FzR": f.FzR,
        "Fpin": list(f.resultant),
    }
    out["rigid"] = dict(result.rigid)
    out["active_set_iterations"] = len(result.history)
    return out


def run_position(
    case,
    roll_angle: float = 0.0,
    comm: MPI.Comm = MPI.COMM_WORLD,
    vtx_dir: str | Path | None = None,
    **kw,
) -> dict:
    """Build, solve and summarise one mesh position (collective; dict on every rank).
    ``vtx_dir``: also write every body's displacement there as VTX (``<body>.bp``)."""
    t0 = time.perf_counter()
    model = build_branch(case, roll_angle, comm, **kw)
    result = model.problem.solve()
    t1 = time.perf_counter()
    if vtx_dir is not None:
        write_vtx(vtx_dir, model.problem, result)
    out = branch_results(model, result)
    out["bending_stress"] = root_stress(model, result)
    out.update(
        case=case.name,
        roll=roll_angle,
        dofs=model.dofs,
        ranks=comm.size,
        level=kw.get("level", case.model.level),
        degree=kw.get("degree", 1),
        timings={
            **model.timings,
            **{k: float(v) for k, v in result.timings.items()},
            "wall": time.perf_counter() - t0,
            "solve_wall": t1 - t0 - model.timings["scene_and_meshes"] - model.timings["bodies"],
        },
    )
    out["grid_lines"] = {k: v[1].lines for k, v in model.grids.items()}
    out["g0_max_abs_mm"] = float(max(np.abs(v[0].gap0).max() for v in model.grids.values()))
    return out


def main(argv=None) -> None:
    from cases.study_case import load_study_case

    ap = argparse.ArgumentParser(description="one-branch gear contact at one mesh position")
    ap.add_argument("--case", default="1-GA")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--degree", type=int, default=1)
    ap.add_argument("--roll", type=float, default=0.0, help="sun roll angle (rad)")
    ap.add_argument("--points", action="store_true", help="include per-point forces")
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    case = load_study_case(args.case)
    out = run_position(case, args.roll, comm, level=args.level, degree=args.degree)
    if not args.points:
        for key in ("points_S", "points_R"):
            out.pop(key)
    if comm.rank == 0:
        print(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
