"""What a solved gear train carries: per pinion and per gear mesh, in the paper's frames.

From a solved :class:`solvers.gear_train.GearTrainModel` (replicated on every rank; N, N m,
mm). Per pinion p (its frame Q_p, rows e_X, e_Y, e_Z, :func:`solvers.gear_train.
pinion_frame`):

* ``Mx``, ``My``, ``Mz`` (N m): the moment of the contact forces on the pinion about its
  centre, M = sum (x_k - c) x f_k, which the bearing carries; also read back from the
  assembled residual (``moment_residual_Nm``), the support reaction (``support_moment_Nm``)
  and the bearing springs k q (``bearing_spring_moment_Nm``);
* ``force_N``: the contact force on the pinion (= the bearing load); ``tilt_rad``.

Per mesh m (a contact grid "driver-driven"): the normal force, the grid points and the
stations (:func:`grid_record`), and for each pinion in the mesh the mesh force on it,
sum_k F_k n_k over the grid points (+ if the pinion is driven, - if it drives: n_k points
from driver to driven; a zone grid's points carry their own contact normals,
:func:`solvers.flank_grid.contact_normals`, turned off the contact line, so the force is not
(sum F_k) n), the load-centroid
axial offset Z = sum F_k Z_k / sum F_k (mm from mid face width, Z along e_Z of that pinion,
over the grid points: the cells of a zone grid) and the centroid vector from the pinion
centre.

Grid points and stations. ``grid_model`` says what the grid is: "line" (one row of points
on the theoretical contact lines, :func:`solvers.flank_grid.flank_grid`) or "zone" (cells
over the whole potential contact zone, :func:`solvers.flank_grid.zone_grid`). A station is a
segment of a contact line (a transverse section of a tooth pair for a zone grid); the line
load lives there, q_s = sum_{k in s} F_k / L_s. Two blocks, never to be paired across:

* ``points`` (one entry per grid point / cell): ``x_mm`` (on the driver's flank),
  ``force_N``, ``area_mm2`` (w_k), ``pressure_MPa`` = F_k / w_k (the cell-average pressure;
  for a line grid the load spread over its patch, not a contact pressure), ``station`` (the
  station index of the point); a line grid, whose points are its stations, also keeps
  ``line_load_N_per_mm`` here (= ``stations`` entry of the same index), so every reader of
  line grids works unchanged; a zone grid has no per-point line load;
* ``stations`` (one entry per station): ``x_mm`` (the station's point on the contact line:
  the line grid's point, the zone grid's coarse point, where the section is closest),
  ``length_mm`` L_s, ``force_N`` sum F_k, ``line_load_N_per_mm`` q_s, ``peak_pressure_MPa``
  (largest F_k / w_k of the station), ``line`` (index of its tooth pair in
  ``grid_lines[mesh]`` of the position).

:func:`mesh_stations` reads the stations of a mesh record, also of a record written before
this layout (line grids: one station per point, ``line`` unknown).

Coast flanks (``coast``, per mesh "driver-driven", from its grid "driver-driven/coast"; kept
apart so that no drive-flank number or key changes): the normal force and active points on
the coast flanks, the initial gap (the normal backlash, plus modifications), the smallest
final gap ``min_gap_mm`` (negative: closed, the penalty penetration of a loaded point) and
the points with their forces and final gaps. ``coast_min_gap_mm`` and ``coast_force_N`` sum
them up over the meshes; :func:`coast_summary` over the positions of a study.

Per mesh (drive and coast), ``torque_Nm`` and ``transmitted_force_N`` by gear
(:func:`mesh_torques`): the moment of the mesh's point forces about each gear's axis, that
moment over the gear's r_b cos(beta_b), and ``off_line_N``, how far the points' arms depart
from r_b cos(beta_b) (0 on a line grid). Zone grids (drive flanks): ``corner_cells``, the
cells that reach a tip circle (:func:`corner_cells`: count, loaded count, force).

Torques about the scene axis: applied sun torque, sun and ring contact torques, ring support
reaction (their balance is a check the solver does not impose).
"""

from __future__ import annotations

import numpy as np

from gears.units import n_m
from solvers.flank_grid import is_coast, mesh_name
from solvers.gear_train import BEARING_DOFS
from solvers.results import contact_resultant, residual_resultant


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


def grid_record(pair, lines: list[dict], F: np.ndarray) -> dict:
    """``grid_model``, ``points`` and ``stations`` of one solved contact pair (module
    docstring). ``lines``: the :class:`solvers.flank_grid.FlankGridInfo` lines of the grid
    (``rows`` [first, last + 1) of each tooth pair's points)."""
    g = pair.grid
    F = np.asarray(F, float)
    w = np.asarray(g.weights, float)
    zone = pair.link is not None
    if g.stations is None:
        raise ValueError(f"grid '{g.name}': no stations, no line load (a 3D flank grid has them)")
    st = np.asarray(g.stations, int)
    n_st = len(g.station_length)
    if zone:
        x_st = np.asarray(pair.link.coarse.x_a, float)
    elif n_st == g.n and np.array_equal(st, np.arange(g.n)):
        x_st = np.asarray(g.x_a, float)  # a line grid: its points are its stations
    else:
        raise ValueError(f"grid '{g.name}': a line grid must have one station per point")
    if len(x_st) != n_st:
        raise ValueError(f"grid '{g.name}': {len(x_st)} station points for {n_st} stations")
    L = np.asarray(g.station_length, float)
    f_st = np.zeros(n_st)
    np.add.at(f_st, st, F)
    p = F / w
    peak = np.zeros(n_st)
    np.maximum.at(peak, st, p)
    line = np.full(n_st, -1)
    for j, ln in enumerate(lines):
        a, b = ln["rows"]
        line[st[a:b]] = j
    points = {
        "x_mm": g.x_a.tolist(),
        "force_N": F.tolist(),
        "area_mm2": w.tolist(),
        "pressure_MPa": p.tolist(),
        "station": st.tolist(),
    }
    q = f_st / L
    if not zone:
        points["line_load_N_per_mm"] = q.tolist()
    stations = {
        "x_mm": x_st.tolist(),
        "length_mm": L.tolist(),
        "force_N": f_st.tolist(),
        "line_load_N_per_mm": q.tolist(),
        "peak_pressure_MPa": peak.tolist(),
        "line": line.tolist(),
    }
    return {
        "grid_model": "zone" if zone else "line",
        "grid_points": g.n,
        "grid_stations": n_st,
        "points": points,
        "stations": stations,
    }


def mesh_stations(mesh: dict) -> dict:
    """The ``stations`` block of a mesh (or coast) record; for a record without one (written
    before the stations were kept; line grids only) one station per point, from its points:
    ``x_mm``, ``line_load_N_per_mm`` (if the points have it), ``line`` -1 (unknown)."""
    if "stations" in mesh:
        return mesh["stations"]
    if mesh.get("grid_model", "line") != "line":
        name = f"{mesh.get('driver')}-{mesh.get('driven')}"
        raise KeyError(f"mesh {name}: a zone grid record without its stations")
    pts = mesh["points"]
    out = {"x_mm": pts["x_mm"], "line": [-1] * len(pts["x_mm"])}
    if "line_load_N_per_mm" in pts:
        out["line_load_N_per_mm"] = pts["line_load_N_per_mm"]
    return out


def mesh_torques(model, zone, grid, F) -> dict:
    """Per gear of a mesh, the moment about its own axis (scene z through its centre c) of
    the mesh's contact forces on it, T = sum_k ((x_k - c) x s F_k n_k)_z (N m; s = -1 on
    the driver at x_a, +1 on the driven gear at x_b), the force that torque transmits,
    F_tr = |T| / (r_b cos(beta_b)) (N), and the force-weighted departure of the points' arms
    a_k = |((x_k - c) x n_k)_z| from the plane of action's r_b cos(beta_b),

        off_line_N = sum_k F_k |a_k - r_b cos(beta_b)| / (r_b cos(beta_b))  >=  |F_tr - sum_k F_k|.

    On a line grid (every n_k the plane of action's) a_k = r_b cos(beta_b): F_tr = sum F_k at
    both gears and off_line_N = 0 (round-off); off the line of action (a zone grid's cells,
    their own normals) each gear's arms differ, and only the torques are statics."""
    torque, force, off = {}, {}, {}
    nk = np.asarray(grid.normals, float)
    for name, sgn, x in ((zone.driver, -1.0, grid.x_a), (zone.driven, +1.0, grid.x_b)):
        pg = model.scene.gear(name)
        c = np.array([*pg.placement.centre, 0.0])
        arm = np.cross(np.asarray(x, float) - c, nk)[:, 2]  # mm, per unit force along n_k
        t = float(sgn * (F * arm).sum())  # N mm
        r0 = pg.gear.base_radius * np.cos(pg.gear.base_helix_angle)
        torque[name] = float(n_m(t))
        force[name] = float(abs(t) / r0)
        off[name] = float((F * np.abs(np.abs(arm) - r0)).sum() / r0)
    return {"torque_Nm": torque, "transmitted_force_N": force, "off_line_N": off}


def corner_cells(corner, F: np.ndarray) -> dict:
    """The cells of a zone grid that reach a tip circle (``corner``: the
    :class:`solvers.flank_grid.FlankGridInfo` bit flags; their contact normal is the other
    flank's, off the plane of action): how many, how many carry load, and their force (N)."""
    on = np.asarray(corner, int) != 0
    F = np.asarray(F, float)
    return {
        "points": int(on.sum()),
        "active_points": int(np.count_nonzero(F[on] > 0)),
        "force_N": float(F[on].sum()),
    }


def _mesh(model, result, index: int, zone, lines: list[dict], corner=None) -> dict:
    p = model.problem
    sl = slice(p.offsets[index], p.offsets[index + 1])
    F = result.forces[sl]
    g = p.pairs[index].grid
    tot = float(F.sum())
    out = {
        "driver": zone.driver,
        "driven": zone.driven,
        "gears": [model.scene.gear(zone.driver).gear_name, model.scene.gear(zone.driven).gear_name],
        "normal_force_N": tot,
        "active_points": int(np.count_nonzero(F > 0)),
        # the plane of action's normal (driver -> driven, scene frame; ContactGrid.nominal_normal)
        "normal": np.asarray(g.nominal_normal, float).tolist(),
        **grid_record(p.pairs[index], lines, F),
        **mesh_torques(model, zone, g, F),
        "on": {},
    }
    if corner is not None:  # zone grids: the tip-corner cells
        out["corner_cells"] = corner_cells(corner, F)
    for pn, sgn in ((zone.driver, -1.0), (zone.driven, +1.0)):
        if pn not in model.frames:
            continue
        Q = model.frames[pn]
        rel = g.x_a - model.centres[pn]
        Z = rel @ Q[2]
        out["on"][pn] = {
            "force_N": (sgn * (Q @ (F @ np.asarray(g.normals, float)))).tolist(),  # sum F_k n_k
            "Z_mm": float((F * Z).sum() / tot) if tot > 0 else float("nan"),
            "centroid_mm": ((F @ rel) / tot).tolist() if tot > 0 else None,
        }
    return out


def _coast(model, result, index: int, zone, lines: list[dict]) -> dict:
    """The coast-flank grid of a mesh after the solve (see the module docstring)."""
    p = model.problem
    sl = slice(p.offsets[index], p.offsets[index + 1])
    F = result.forces[sl]
    gap = np.asarray(result.gaps[sl], float)
    g = p.pairs[index].grid
    out = {
        "driver": zone.driver,
        "driven": zone.driven,
        "normal_force_N": float(F.sum()),
        "active_points": int(np.count_nonzero(F > 0)),
        "loaded": bool(np.any(F > 0)),
        "initial_gap_min_mm": float(np.min(g.gap0)),
        "min_gap_mm": float(gap.min()),
        "normal": np.asarray(g.nominal_normal, float).tolist(),  # out of the driver's coast flank
    }
    rec = grid_record(p.pairs[index], lines, F)
    rec["points"]["gap_mm"] = gap.tolist()
    out.update(rec)
    out.update(mesh_torques(model, zone, g, F))
    return out


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
            lines = model.coast_grids[mesh_name(name)][1].lines
            coast[mesh_name(name)] = _coast(model, result, i, zones[mesh_name(name)], lines)
        else:
            info = model.grids[name][1]
            meshes[name] = _mesh(model, result, i, zones[name], info.lines, info.corner)
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
