"""What a solved gear train carries: per pinion and per gear mesh, in the paper's frames.

From a solved :class:`solvers.gear_train.GearTrainModel` (replicated on every rank; N, N m,
mm). Per pinion p (its frame Q_p, rows e_X, e_Y, e_Z, :func:`solvers.gear_train.
pinion_frame`):

* ``Mx``, ``My``, ``Mz`` (N m): the moment of the contact forces on the pinion about its
  centre, M = sum (x_k - c) x f_k, which the bearing carries; also read back from the
  assembled residual (``moment_residual_Nm``), the support reaction (``support_moment_Nm``)
  and the bearing springs k q (``bearing_spring_moment_Nm``);
* ``force_N``: the contact force on the pinion (= the bearing load); ``tilt_rad``.

Per mesh m (a contact grid "driver-driven"): the normal force, the grid points with their
forces and line loads, and for each pinion in the mesh the mesh force on it (+n if the pinion
is driven, -n if it drives: n points from driver to driven), the load-centroid axial offset
Z = sum F_k Z_k / sum F_k (mm from mid face width, Z along e_Z of that pinion) and the
centroid vector from the pinion centre.

Coast flanks (``coast``, per mesh "driver-driven", from its grid "driver-driven/coast"; kept
apart so that no drive-flank number or key changes): the normal force and active points on
the coast flanks, the initial gap (the normal backlash, plus modifications), the smallest
final gap ``min_gap_mm`` (negative: closed, the penalty penetration of a loaded point) and
the points with their forces and final gaps. ``coast_min_gap_mm`` and ``coast_force_N`` sum
them up over the meshes; :func:`coast_summary` over the positions of a study.

Torques about the scene axis: applied sun torque, sun and ring contact torques, ring support
reaction (their balance is a check the solver does not impose).
"""

from __future__ import annotations

import numpy as np

from gears.units import n_m
from solvers.flank_grid import is_coast, mesh_name
from solvers.gear_train import BEARING_DOFS
from solvers.results import contact_resultant, line_load, residual_resultant


def body_resultants(problem, result) -> tuple[dict, float]:
    """Per body (contact force, contact moment, residual resultants) and the largest relative
    mismatch between the contact and residual resultants over every body."""
    res = {}
    for name in problem.bodies:
        fc, mc = contact_resultant(problem, result, name)
        res[name] = (fc, mc, residual_resultant(problem, result, name))
    agree = 0.0
    for f1, m1, r1 in res.values():
        agree = max(
            agree,
            np.linalg.norm(f1 - r1["contact"][0]) / max(np.linalg.norm(f1), 1e-30),
            np.linalg.norm(m1 - r1["contact"][1]) / max(np.linalg.norm(m1), 1e-30),
        )
    return res, float(agree)


def _pinion(model, result, name: str, res) -> dict:
    Q = model.frames[name]
    fc, mc, rr = res[name]
    # the bore's six rigid motions (scene axes) and the bearing's spring load on the pin
    q = np.array([result.rigid[f"{name}_{d}"] for d in BEARING_DOFS])
    kq = model.bearing_load(name, result.rigid)
    mx, my, mz = (float(v) for v in n_m(Q @ mc))
    return {
        "centre_mm": np.asarray(model.centres[name], float).tolist(),
        "frame": Q.tolist(),
        "Mx": mx,
        "My": my,
        "Mz": mz,
        "force_N": (Q @ fc).tolist(),
        "moment_residual_Nm": n_m(Q @ rr["contact"][1]).tolist(),
        "support_moment_Nm": n_m(Q @ rr["support"][1]).tolist(),
        "bearing_spring_force_N": (Q @ kq[:3]).tolist(),
        "bearing_spring_moment_Nm": n_m(Q @ kq[3:]).tolist(),
        "tilt_rad": (Q @ np.array([q[3], q[4], 0.0])).tolist(),  # about the pinion's X, Y
        "spin_rad": float(q[5]),
        "spin_moment_Nm": float(n_m(mc[2])),
    }


def _mesh(model, result, index: int, zone) -> dict:
    p = model.problem
    sl = slice(p.offsets[index], p.offsets[index + 1])
    F = result.forces[sl]
    g = model.grids[p.pairs[index].grid.name][0]
    tot = float(F.sum())
    out = {
        "driver": zone.driver,
        "driven": zone.driven,
        "gears": [model.scene.gear(zone.driver).gear_name, model.scene.gear(zone.driven).gear_name],
        "normal_force_N": tot,
        "active_points": int(np.count_nonzero(F > 0)),
        "grid_points": g.n,
        "normal": np.asarray(g.normals[0], float).tolist(),  # driver -> driven, scene frame
        "points": {
            "x_mm": g.x_a.tolist(),
            "force_N": F.tolist(),
            "line_load_N_per_mm": line_load(p, result, index).tolist(),
        },
        "on": {},
    }
    for pn, sgn in ((zone.driver, -1.0), (zone.driven, +1.0)):
        if pn not in model.frames:
            continue
        Q = model.frames[pn]
        rel = g.x_a - model.centres[pn]
        Z = rel @ Q[2]
        out["on"][pn] = {
            "force_N": (sgn * tot * (Q @ g.normals[0])).tolist(),
            "Z_mm": float((F * Z).sum() / tot) if tot > 0 else float("nan"),
            "centroid_mm": ((F @ rel) / tot).tolist() if tot > 0 else None,
        }
    return out


def _coast(model, result, index: int, zone) -> dict:
    """The coast-flank grid of a mesh after the solve (see the module docstring)."""
    p = model.problem
    sl = slice(p.offsets[index], p.offsets[index + 1])
    F = result.forces[sl]
    gap = np.asarray(result.gaps[sl], float)
    g = p.pairs[index].grid
    return {
        "driver": zone.driver,
        "driven": zone.driven,
        "normal_force_N": float(F.sum()),
        "active_points": int(np.count_nonzero(F > 0)),
        "grid_points": g.n,
        "loaded": bool(np.any(F > 0)),
        "initial_gap_min_mm": float(np.min(g.gap0)),
        "min_gap_mm": float(gap.min()),
        "normal": np.asarray(g.normals[0], float).tolist(),  # out of the driver's coast flank
        "points": {
            "x_mm": g.x_a.tolist(),
            "force_N": F.tolist(),
            "gap_mm": gap.tolist(),
            "line_load_N_per_mm": line_load(p, result, index).tolist(),
        },
    }


def coast_summary(positions: list[dict]) -> dict | None:
    """The coast flanks over the positions of a study: per mesh and overall, the smallest
    final gap (mm; negative: closed) and the largest coast force (N), and whether any coast
    point carried load. None when the positions have no coast grids."""
    with_coast = [p for p in positions if p.get("coast")]
    if not with_coast:
        return None
    meshes = {}
    for name in with_coast[0]["coast"]:
        rows = [p["coast"][name] for p in with_coast if name in p["coast"]]
        meshes[name] = {
            "min_gap_mm": float(min(r["min_gap_mm"] for r in rows)),
            "max_force_N": float(max(r["normal_force_N"] for r in rows)),
            "loaded_positions": int(sum(r["loaded"] for r in rows)),
        }
    return {
        "min_gap_mm": float(min(m["min_gap_mm"] for m in meshes.values())),
        "loaded": any(m["loaded_positions"] for m in meshes.values()),
        "meshes": meshes,
    }


def _carrier(model, result) -> dict:
    """The carrier of a system scene: the bearing loads on its pins, its reaction torque at
    the hub, the displacement and wind-up (mean rotation about z) of the pins."""
    rigid = result.rigid
    torque, windup, pins = 0.0, [], {}
    for p in model.pinions:
        pin = model.pins[p]
        load = model.bearing_load(p, rigid)  # on the pin, scene axes
        c = model.centres[p]
        torque += c[0] * load[1] - c[1] * load[0] + load[5]
        q = np.array([rigid[f"{pin}_{d}"] for d in BEARING_DOFS])
        r = float(np.hypot(c[0], c[1]))
        windup.append((c[0] * q[1] - c[1] * q[0]) / (r * r))
        pins[pin] = {"pinion": p, "load_N_Nmm": load.tolist(), "displacement": q.tolist()}
    return {
        # the hub holds the carrier against the bearing loads on its pins
        "support_torque_Nm": float(n_m(-torque)),
        "windup_rad": float(np.mean(windup)),
        "pins": pins,
    }


def train_results(model, result) -> dict:
    """The summary of a solved gear train (see the module docstring)."""
    p = model.problem
    res, mismatch = body_resultants(p, result)
    sun, ring = model.scene.sun_name, model.scene.ring_name
    zones = {f"{z.driver}-{z.driven}": z for z in model.scene.zones}
    meshes, coast = {}, {}
    for i, pair in enumerate(p.pairs):
        name = pair.grid.name
        if is_coast(name):
            coast[mesh_name(name)] = _coast(model, result, i, zones[mesh_name(name)])
        else:
            meshes[name] = _mesh(model, result, i, zones[name])
    out = {
        "pinions": {pn: _pinion(model, result, pn, res) for pn in model.pinions},
        "meshes": meshes,
        "resultant_mismatch_rel": mismatch,
        "sun_torque_applied_Nm": float(n_m(model.torque)),
        "sun_contact_torque_Nm": float(n_m(res[sun][1][2])),
        "ring_contact_torque_Nm": float(n_m(res[ring][1][2])),
        "ring_support_torque_Nm": float(n_m(res[ring][2]["support"][1][2])),
        "rigid": dict(result.rigid),
        "active_set_iterations": len(result.history),
    }
    if coast:
        out["coast"] = coast
        out["coast_min_gap_mm"] = float(min(c["min_gap_mm"] for c in coast.values()))
        out["coast_force_N"] = float(sum(c["normal_force_N"] for c in coast.values()))
    if model.carrier is not None:
        out["carrier"] = _carrier(model, result)
        out["sun_centre_displacement_mm"] = [result.rigid[f"{sun}_{d}"] for d in ("x", "y")]
        tot = out["sun_torque_applied_Nm"] + out["ring_support_torque_Nm"]
        tot += out["carrier"]["support_torque_Nm"]
        out["torque_balance_rel"] = abs(tot) / out["sun_torque_applied_Nm"]
    return out
