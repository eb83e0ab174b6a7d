"""One branch of the case-2 double pinion planetary (singh2007 section 5): sun, SP, RP, ring.

Model (:func:`build_double_branch`), following :func:`solvers.gear_contact.build_branch`
and reusing its grid (:func:`solvers.gear_contact.flank_grid`) and body loading. Bodies
from the cached body meshes of :func:`meshing.scenes.case2_scene` (SP on +x, RP counter-
clockwise of it about the sun), scene frame z = 0 at mid face width:

* sun sector: bore rigidly coupled to the axis point, rotation about z an explicit rigid
  unknown balanced by the torque per branch (1378.7 / 3 = 459.57 N m);
* SP and RP (full): bores each on the case's needle bearing (6x6 diagonal about the pin
  centre, spin free), the spin an explicit rigid unknown with a zero-moment equation;
* ring sector: held at its outer rim (its reaction torque is the rim support reaction).

Contact grids on the three meshes sun-SP, SP-RP, RP-ring (the scene's zones, drive flanks
as the scene states them: the sun drives SP, SP drives RP, RP drives the ring).

Pinion frame (section 5, one per pinion). X radial from the sun centre through the pinion
centre, Z = -z (scene), Y = Z x X (right-handed; Y = the clockwise tangential direction).
This is the case-1 frame of :func:`solvers.gear_contact.paper_frame` (a 180 deg turn of
the scene about X), and it puts the meshes where the section-5 formulas have them: in the
SP frame the sun pitch point at -R_SP-SUN X and the RP pitch point at R_SP-RP (-cos theta,
-sin theta) (so Mx-SP = -FzRP R_SP-RP sin theta); in the RP frame the ring pitch point at
+R_RP-RING X and the SP pitch point at R_RP-SP (-cos phi, +sin phi). Moments are
M = sum r x F of the contact forces about the pinion centre (= what the bearing carries).
The axial forces read from the FE (sum of point forces times n_z) are reported in the same
frames and compared in sign with the closed form: FzSUN, FzSP > 0, FzRP, FzRING < 0.

Outputs (:func:`double_branch_results`): per pinion Mx, My, Mz (N m) from the contact
forces, the bearing spring reactions k q, the four section-5 LOA moments from the FE Mx,
My, the load-centroid axial offsets Z (mm, in the frame of the pinion at that mesh: the
SP frame for sun-SP and SP-RP, the RP frame for RP-ring, and for SP-RP also in the RP
frame, which is the same number since both frames have Z = -z), and the analytic Table 5
values (concentrated load at the pitch points) plus the same closed form with the forces
moved to the FE's own centroid offsets.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import numpy as np
from mpi4py import MPI

from solvers.contact import ContactProblem, RigidUnknown
from solvers.contact_grid import ContactGrid
from solvers.gear_contact import (
    FlankGridInfo,
    body_resultants,
    chain_bodies,
    flank_contact_pairs,
    total_dofs,
)

PINIONS = ("SP", "RP")
MESHES = ("sun-SP", "SP-RP", "RP-ring")


def pinion_frame(centre) -> np.ndarray:
    """Rows e_X (radial, sun -> pinion), e_Y = e_Z x e_X, e_Z = -z (scene coordinates)."""
    ex = np.array([centre[0], centre[1], 0.0])
    ex /= np.linalg.norm(ex)
    ez = np.array([0.0, 0.0, -1.0])
    return np.vstack([ex, np.cross(ez, ex), ez])


@dataclass
class DoubleBranchModel:
    problem: ContactProblem
    scene: object
    grids: dict[str, tuple[ContactGrid, FlankGridInfo]]
    torque: float  # N mm on the sun (per branch)
    centres: dict[str, np.ndarray]  # SP, RP centres (scene frame)
    frames: dict[str, np.ndarray]  # SP, RP pinion frames (rows e_X, e_Y, e_Z)
    dofs: int
    timings: dict


def build_double_branch(
    case,
    roll: float = 0.0,
    comm: MPI.Comm = MPI.COMM_WORLD,
    level: int | None = None,
    degree: int = 1,
    spacing: float | None = None,
    width: float | None = None,
    penalty_factor: float = 100.0,
    micro: Callable | None = None,
) -> DoubleBranchModel:
    """The one-branch case-2 contact problem at sun roll angle ``roll`` (see module doc)."""
    from meshing import sizing
    from meshing.scenes import case2_scene

    if case.gearset.name != "case2":
        raise ValueError(f"{case.name}: build_double_branch models case 2 (double pinion) only")
    t0 = time.perf_counter()
    lv = case.model.level if level is None else level
    h = sizing.check_level(lv).fine if spacing is None else spacing
    scene = case2_scene(roll)
    bodies, centres, t_meshes = chain_bodies(case, scene, PINIONS, lv, degree, comm)
    grids, pairs = flank_contact_pairs(scene, h, width, micro)
    if tuple(grids) != MESHES:
        raise ValueError(f"case2 scene zones {tuple(grids)}: expected {MESHES}")
    torque = case.gearset.torque_per_branch * 1e3  # N mm
    problem = ContactProblem(
        bodies,
        pairs,
        [
            RigidUnknown("sun_rotation", "sun", coupling="axis", dof=5, load=torque),
            *(RigidUnknown(f"{p}_spin", p, coupling="bearing", dof=5, load=0.0) for p in PINIONS),
        ],
        penalty_factor=penalty_factor,
    )
    frames = {p: pinion_frame(centres[p]) for p in PINIONS}
    dofs = total_dofs(bodies)
    timings = {"scene_and_meshes": t_meshes, "bodies": time.perf_counter() - t0 - t_meshes}
    return DoubleBranchModel(problem, scene, grids, torque, centres, frames, dofs, timings)


# ---------------------------------------------------------------------------- outputs
def _analytic():
    from postprocess.analytic import double_pinion as dp
    from postprocess.analytic.study import (
        case2_axial_forces,
        default_inputs,
        double_pinion_geometry,
    )

    c2 = default_inputs()[1]
    return dp, double_pinion_geometry(c2), case2_axial_forces(c2)


def _mesh_slice(p: ContactProblem, name: str) -> tuple[int, slice]:
    i = [pp.grid.name for pp in p.pairs].index(name)
    return i, slice(p.offsets[i], p.offsets[i + 1])


def double_branch_results(model: DoubleBranchModel, result) -> dict:
    """The summary of a solved case-2 branch (replicated on every rank; N, N m, mm)."""
    p = model.problem
    out: dict = {
        "centres_mm": {k: v.tolist() for k, v in model.centres.items()},
        "frames": {k: v.tolist() for k, v in model.frames.items()},
    }
    res, out["resultant_mismatch_rel"] = body_resultants(p, result)
    for pn in PINIONS:
        Q = model.frames[pn]
        fc, mc, rr = res[pn]
        m = Q @ mc / 1e3
        out[f"Mx_{pn}"], out[f"My_{pn}"], out[f"Mz_{pn}"] = (float(v) for v in m)
        out[f"{pn}_force_N"] = (Q @ fc).tolist()
        out[f"{pn}_spin_moment_Nm"] = float(mc[2] / 1e3)
        out[f"{pn}_support_moment_Nm"] = (Q @ rr["support"][1] / 1e3).tolist()
        b = p.bodies[pn]
        q = b.reference_dofs(result.reduced[pn])["bearing"]
        c = b.couplings["bearing"]
        kq = c.springs() * q
        a = c.frame(3)
        out[f"{pn}_bearing_spring_force_N"] = (Q @ (a.T @ kq[:3])).tolist()
        out[f"{pn}_bearing_spring_moment_Nm"] = (Q @ (a.T @ kq[3:]) / 1e3).tolist()
        out[f"{pn}_tilt_rad"] = (Q @ (a.T @ q[3:])).tolist()
    out["sun_torque_applied_Nm"] = model.torque / 1e3
    out["sun_contact_torque_Nm"] = float(res["sun"][1][2] / 1e3)
    out["ring_contact_torque_Nm"] = float(res["ring"][1][2] / 1e3)
    out["ring_support_torque_Nm"] = float(res["ring"][2]["support"][1][2] / 1e3)
    # per mesh: normal force, FE axial force on each pinion (its frame), centroid offsets
    dp, geo, fz = _analytic()
    on = {
        "sun-SP": (("SP", +1.0),),
        "SP-RP": (("SP", -1.0), ("RP", +1.0)),
        "RP-ring": (("RP", -1.0),),
    }
    fe_fz, cent = {}, {}
    for mesh in MESHES:
        _, sl = _mesh_slice(p, mesh)
        F = result.forces[sl]
        g = model.grids[mesh][0]
        tot = float(F.sum())
        out[f"normal_force_{mesh}_N"] = tot
        out[f"active_points_{mesh}"] = int(np.count_nonzero(F > 0))
        out[f"grid_points_{mesh}"] = g.n
        for pn, sgn in on[mesh]:
            Q = model.frames[pn]
            f_vec = sgn * tot * (Q @ g.normals[0])  # the mesh force on the pinion
            fe_fz[(mesh, pn)] = float(f_vec[2])
            rel = g.x_a - model.centres[pn]
            Z = rel @ Q[2]
            cent[(mesh, pn)] = ((F @ rel) / tot) if tot > 0 else np.full(3, np.nan)
            out[f"Z_{mesh}_{pn}"] = float((F * Z).sum() / tot) if tot > 0 else float("nan")
            out[f"F_{mesh}_on_{pn}_N"] = f_vec.tolist()
    out["FzSUN_fe"] = fe_fz[("sun-SP", "SP")]
    out["FzRP_fe"] = fe_fz[("SP-RP", "SP")]
    out["FzSP_fe"] = fe_fz[("SP-RP", "RP")]
    out["FzRING_fe"] = fe_fz[("RP-ring", "RP")]
    out["ZS"] = out["Z_sun-SP_SP"]
    out["Z_SPRP"] = out["Z_SP-RP_SP"]
    out["ZR"] = out["Z_RP-ring_RP"]
    out.update(dp.loa_moments(out["Mx_SP"], out["My_SP"], out["Mx_RP"], out["My_RP"], geo))
    # closed form: Table 5 (concentrated load at the pitch points, mid face width)
    table5 = dp.double_pinion_moments(fz, geo)
    # closed form moved to the FE centroid offsets: the analytic mesh forces (axial part
    # from the closed form, direction = the exact plane-of-action normal of the grid) at the
    # pitch point + Z e_Z; the transverse parts then add Z x F_transverse to Mx, My
    shifted = {}
    fz_an = {
        ("sun-SP", "SP"): fz.FzSUN,
        ("SP-RP", "SP"): fz.FzRP,
        ("SP-RP", "RP"): fz.FzSP,
        ("RP-ring", "RP"): fz.FzRING,
    }
    # pitch point: operating pitch radius from the pinion centre towards the mating centre
    pitch = {
        ("sun-SP", "SP"): (geo.r_sp_sun, "sun"),
        ("SP-RP", "SP"): (geo.r_sp_rp, "RP"),
        ("SP-RP", "RP"): (geo.r_rp_sp, "SP"),
        ("RP-ring", "RP"): (geo.r_rp_ring, "out"),
    }
    for pn in PINIONS:
        Q = model.frames[pn]
        m = np.zeros(3)
        for (mesh, who), fza in fz_an.items():
            if who != pn:
                continue
            g = model.grids[mesh][0]
            sgn = dict(on[mesh])[pn]
            n = sgn * (Q @ g.normals[0])
            f_vec = fza / n[2] * n
            r_w, towards = pitch[(mesh, pn)]
            if towards == "sun":
                d = -model.centres[pn]
            elif towards == "out":
                d = model.centres[pn].copy()
            else:
                d = model.centres[towards] - model.centres[pn]
            d = Q @ (d / np.linalg.norm(d))
            r = r_w * d + np.array([0.0, 0.0, out[f"Z_{mesh}_{pn}"]])
            m += np.cross(r, f_vec) / 1e3
            # where the FE centroid sits along the transverse line of action from the pitch
            # point (mm): the closed form has 0; the axial force there adds s x Fz to Mx, My
            t = np.array([n[0], n[1], 0.0]) / math.hypot(n[0], n[1])
            out[f"loa_offset_{mesh}_{pn}_mm"] = float((cent[(mesh, pn)] @ Q.T - r_w * d) @ t)
        shifted[f"Mx_{pn}"], shifted[f"My_{pn}"] = float(m[0]), float(m[1])
    shifted.update(
        dp.loa_moments(shifted["Mx_SP"], shifted["My_SP"], shifted["Mx_RP"], shifted["My_RP"], geo)
    )
    out["analytic"] = {
        "table5": table5,
        "at_fe_centroids": shifted,
        "FzSUN": fz.FzSUN,
        "FzRP": fz.FzRP,
        "FzSP": fz.FzSP,
        "FzRING": fz.FzRING,
        "theta_deg": math.degrees(geo.theta),
        "phi_deg": math.degrees(geo.phi),
    }
    out["rigid"] = dict(result.rigid)
    out["active_set_iterations"] = len(result.history)
    return out


def run_position_double(
    case,
    roll: float = 0.0,
    comm: MPI.Comm = MPI.COMM_WORLD,
    level: int = 0,
    degree: int = 1,
    **kw,
) -> dict:
    """Build, solve and summarise one case-2 mesh position (collective; dict on every rank)."""
    t0 = time.perf_counter()
    model = build_double_branch(case, roll, comm, level=level, degree=degree, **kw)
    result = model.problem.solve()
    out = double_branch_results(model, result)
    out.update(
        case=case.name,
        roll=roll,
        dofs=model.dofs,
        ranks=comm.size,
        level=level,
        degree=degree,
        timings={
            **model.timings,
            **{k: float(v) for k, v in result.timings.items()},
            "wall": time.perf_counter() - t0,
        },
    )
    out["grid_lines"] = {k: v[1].lines for k, v in model.grids.items()}
    out["g0_max_abs_mm"] = float(max(np.abs(v[0].gap0).max() for v in model.grids.values()))
    return out


def main(argv=None) -> None:
    from cases.study_case import load_study_case

    ap = argparse.ArgumentParser(description="one-branch double pinion contact, one position")
    ap.add_argument("--case", default="2B-GA")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--degree", type=int, default=1)
    ap.add_argument("--roll", type=float, default=0.0, help="sun roll angle (rad)")
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    case = load_study_case(args.case)
    out = run_position_double(case, args.roll, comm, level=args.level, degree=args.degree)
    if comm.rank == 0:
        print(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
