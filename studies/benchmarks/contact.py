"""Contact model benchmark (issue 11 items 2-3): the line grid against the zone grid.

    python -m studies.benchmarks.contact [--out results/bench] [--level 0] [--cases 1-GA 1-GC]
        [--factors 10 100 1000 10000] [--roll 0] [--models line zone]

Per case and contact model (``[numerics] contact_model``, :mod:`solvers.flank_grid`): one
mesh position (sun angle ``roll``) of the case's scene at mesh ``level``, the contact
problem built once and solved for every penalty factor (the compliance columns are reused,
so the sweep isolates the penalty). Recorded:

* cost: contact grid points, FE points (the coarse grid of "zone"), FE compliance columns
  formed, seconds in the compliance, the active set and the whole position (model + solve,
  body factorizations included; meshes from the cache);
* the coast flanks: their grid points and FE points, whether every coast pair is on a zone
  grid (``coast_zoned``; "zone" lays them over the coast contact zone, exact contact, so
  no pair of the zone model then carries a penalty) or on its contact lines (penalty), and
  per penalty factor the coast force;
* the paper's moments My_pin, M_LOA_sun, M_LOA_ring and the load centroids ZS, ZR per
  penalty factor, and their spread over the sweep, (max - min) / |value at the case's
  penalty factor| (ZS, ZR also in mm);
* per penalty factor and grid (drive and coast), the force on each pinion in it, in the
  pinion's frame: sum_k F_k n_k over the points (``mesh_force_on_pinion_N``, each point
  along its own normal), and (sum_k F_k) times the grid's nominal normal (the plane of
  action's, ``..._nominal_N``), which differ where a zone grid's points lie off the line;
* line loads: per contact line with at least 6 stations, the end stations' line load over
  the interior mean (stations 3 .. n-2), the end labelled ``face_end`` (within one station
  of a face end) or ``path_end`` (where the line leaves the path of contact);
* contact pressure: per loaded interior station (line load above half the largest), the
  largest grid pressure F_k / w_k against Hertz at the station's line load
  (:func:`gears.contact_stress.hertz_line_contact`, relative radius of the normal section
  R_n = R_t / cos(beta_b), 1/R_t = 1/rho_a +- 1/rho_b from the roll lengths at the point,
  E* of the case's gear material). The line model's pressure is a patch mean (line load /
  patch width), not a contact pressure.

Writes ``<out>/contact_grid.json``. A benchmark measures; it asserts nothing. Collective:
under ``mpiexec -n 2`` the numbers must equal the serial ones (rank 0 writes).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from mpi4py import MPI

from cases.study_case import load_study_case
from gears.contact_stress import hertz_line_contact
from meshing import sizing
from meshing.scene_bodies import load_body_meshes
from meshing.scenes import build_scene
from postprocess.paper_moments import paper_moments
from postprocess.train_results import train_results
from solvers.body_store import BodyStore
from solvers.flank_grid import is_coast
from solvers.gear_train import build_gear_train
from studies.position import train_inputs

MOMENTS = ("My_pin", "M_LOA_sun", "M_LOA_ring", "ZS", "ZR")


def _drive_pairs(model):
    p = model.problem
    return [(i, pr) for i, pr in enumerate(p.pairs) if not is_coast(pr.grid.name)]


def _stations(model, result, i):
    """Per station of drive pair i: line load (N/mm), largest grid pressure (MPa), the
    point of the largest force (mm)."""
    p = model.problem
    pr = p.pairs[i]
    g = pr.grid
    F = result.forces[p.offsets[i] : p.offsets[i + 1]]
    st = np.asarray(g.stations)
    ns = len(g.station_length)
    q = np.zeros(ns)
    np.add.at(q, st, F)
    q /= np.asarray(g.station_length, float)
    pres = F / np.asarray(g.weights, float)
    pmax = np.zeros(ns)
    np.maximum.at(pmax, st, pres)
    # the point of the largest force (the first point of an unloaded station)
    where = np.zeros((ns, 3))
    best = np.full(ns, -1.0)
    for k in range(g.n):
        if F[k] > best[st[k]]:
            best[st[k]] = F[k]
            where[st[k]] = g.x_a[k]
    return q, pmax, where


def _mesh_forces(model, result) -> dict:
    """Per grid and pinion in it: the force on the pinion (pinion frame, N), sum_k F_k n_k
    (per point) and (sum_k F_k) n_nominal (the grid's nominal normal)."""
    p = model.problem
    out = {}
    for i, pr in enumerate(p.pairs):
        F = result.forces[p.offsets[i] : p.offsets[i + 1]]
        g = pr.grid
        for pn, sgn in ((pr.body_a, -1.0), (pr.body_b, +1.0)):
            if pn not in model.frames:
                continue
            Q = model.frames[pn]
            out[f"{g.name} on {pn}"] = {
                "per_point_N": (sgn * (Q @ (F @ np.asarray(g.normals, float)))).tolist(),
                "nominal_N": (sgn * F.sum() * (Q @ np.asarray(g.nominal_normal))).tolist(),
            }
    return out


def _hertz(study, scene, zone_name, x, q):
    drv_name, dvn_name = zone_name.split("-")
    E = study.material.gear_youngs_modulus
    nu = study.material.poisson_ratio
    e_star = E / (2.0 * (1.0 - nu * nu))
    inv = 0.0
    for nm, sign in ((drv_name, 1.0), (dvn_name, 1.0)):
        pg = scene.gear(nm)
        c = np.asarray(pg.placement.centre, float)
        r = float(np.hypot(*(x[:2] - c)))
        rho = math.sqrt(max(r * r - pg.gear.base_radius**2, 1e-12))
        inv += (-1.0 if pg.gear.internal else sign) / rho
    beta_b = scene.gear(drv_name).gear.base_helix_angle
    r_n = (1.0 / inv) / math.cos(beta_b)
    return float(hertz_line_contact(q, r_n, e_star)[1])


def _line_ends(model, result, grids_info, scene):
    out = []
    for i, pr in _drive_pairs(model):
        name = pr.grid.name
        q, _, where = _stations(model, result, i)
        info = grids_info[name][1]
        b = min(scene.gear(nm).gear.face_width for nm in name.split("-"))
        st0 = 0
        for ln in info.lines:
            m = max(1, round(ln["length"] / ln["spacing"]))
            ql = q[st0 : st0 + m]
            zl = where[st0 : st0 + m, 2]
            st0 += m
            if m < 6 or ql[2:-2].mean() <= 0:
                continue
            mean = float(ql[2:-2].mean())
            for end, k in (("first", 0), ("last", m - 1)):
                at_face = abs(abs(zl[k]) - b / 2) < 1.01 * ln["spacing"]
                out.append(
                    {
                        "mesh": name,
                        "driver_tooth": ln["driver_tooth"],
                        "end": end,
                        "where": "face_end" if at_face else "path_end",
                        "ratio_end_to_interior": float(ql[k] / mean),
                        "interior_line_load_N_per_mm": mean,
                    }
                )
    return out


def _pressure(model, result, study, scene):
    problem, res = model.problem, result
    out = {}
    for i, pr in _drive_pairs(model):
        q, pmax, where = _stations(model, result, i)
        loaded = np.flatnonzero(q > 0.5 * q.max())
        ratios = [pmax[k] / _hertz(study, scene, pr.grid.name, where[k], q[k]) for k in loaded]
        if not ratios:
            continue
        # where the largest pressure sits: mm from the face end and from each tip circle
        g = pr.grid
        F = res.forces[problem.offsets[i] : problem.offsets[i + 1]]
        k = int(np.argmax(F / np.asarray(g.weights, float)))
        x = np.asarray(g.x_a[k], float)
        b = min(scene.gear(nm).gear.face_width for nm in pr.grid.name.split("-"))
        tips = {}
        for nm in pr.grid.name.split("-"):
            pg = scene.gear(nm)
            r = float(np.hypot(*(x[:2] - np.asarray(pg.placement.centre, float))))
            tips[nm] = abs(r - pg.gear.tip_radius)
        out[pr.grid.name] = {
            "stations": len(ratios),
            "p_max_at": {"from_face_end_mm": float(b / 2 - abs(x[2])), "from_tip_mm": tips},
            "p_max_MPa": float(pmax.max()),
            "p_over_hertz_median": float(np.median(ratios)),
            "p_over_hertz_min": float(np.min(ratios)),
            "p_over_hertz_max": float(np.max(ratios)),
        }
    return out


def run_case(case, model_name, level, roll, factors, comm, store) -> dict:
    study = load_study_case(case)
    study = replace(study, numerics=replace(study.numerics, contact_model=model_name))
    num = study.numerics
    spacing = num.grid_spacing or sizing.check_level(level).fine
    t0 = time.perf_counter()
    store.begin_position()
    scene = build_scene(study.model.scene, study.gearset, roll)
    meshes = load_body_meshes(scene, level, comm, store.mesh_memo)
    t1 = time.perf_counter()
    model = build_gear_train(
        scene,
        meshes,
        train_inputs(study),
        degree=num.degree,
        spacing=spacing,
        penalty_factor=num.penalty_factor,
        store=store,
    )
    p = model.problem
    rows, first = {}, None
    # the case's factor first: its columns and seconds are the cost of a position
    for f in [num.penalty_factor, *sorted(set(factors) - {num.penalty_factor})]:
        ts = time.perf_counter()
        res = p.solve(penalty_factor=f)
        te = time.perf_counter()
        train = train_results(model, res)
        pm = paper_moments(train, scene, study.gearset)
        rows[f] = {k: float(pm[k]) for k in MOMENTS}
        rows[f]["active_points"] = int(np.count_nonzero(res.forces > 0))
        rows[f]["coast_force_N"] = float(train.get("coast_force_N", 0.0))
        rows[f]["solve_s"] = te - ts
        rows[f]["resultant_mismatch_rel"] = train["resultant_mismatch_rel"]
        rows[f]["mesh_force_on_pinion_N"] = _mesh_forces(model, res)
        if f == num.penalty_factor:
            cost = {
                "columns": int(p.timings["compliance_columns"]),
                "compliance_s": float(p.timings["compliance"]),
            }
            first = (res, te - t1, dict(res.timings))
    res, wall, timings = first
    coast = [pr for pr in p.pairs if is_coast(pr.grid.name)]
    ref = rows[num.penalty_factor]
    spread = {}
    for k in MOMENTS:
        vals = np.array([r[k] for r in rows.values()])
        spread[k] = float(np.ptp(vals) / max(abs(ref[k]), 1e-30))
        if k in ("ZS", "ZR"):
            spread[f"{k}_mm"] = float(np.ptp(vals))
    return {
        "case": case,
        "contact_model": model_name,
        "level": level,
        "roll": roll,
        "ranks": comm.size,
        "grid_spacing_mm": spacing,
        "zone_gap_limit_um": num.zone_gap_limit_um,
        "grid_points": int(p.n),
        "fe_points": int(p.n_fe),
        "coast_grid_points": int(sum(pr.grid.n for pr in coast)),
        "coast_fe_points": int(
            sum(pr.grid.n if pr.link is None else pr.link.coarse.n for pr in coast)
        ),
        "coast_zoned": bool(coast) and all(pr.link is not None for pr in coast),
        "compliance_columns": cost["columns"],
        "compliance_s": cost["compliance_s"],
        "compliance_columns_whole_sweep": int(p.timings["compliance_columns"]),
        "position_s": float(wall),
        "meshes_s": float(t1 - t0),
        "timings": {k: float(v) for k, v in timings.items()},
        "penalty_factor": num.penalty_factor,
        "sweep": {f"{f:g}": rows[f] for f in sorted(rows)},
        "spread_over_sweep": spread,
        "line_ends": _line_ends(model, res, model.grids, scene),
        "pressure": _pressure(model, res, study, scene),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.benchmarks.contact", description=__doc__.split("\n")[0]
    )
    ap.add_argument("--out", default="results/bench")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--roll", type=float, default=0.0)
    ap.add_argument("--cases", nargs="+", default=["1-GA", "1-GC"])
    ap.add_argument("--models", nargs="+", default=["line", "zone"], choices=["line", "zone"])
    ap.add_argument("--factors", nargs="+", type=float, default=[10.0, 100.0, 1000.0, 10000.0])
    a = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    store = BodyStore()
    runs = []
    for case in a.cases:
        for m in a.models:
            r = run_case(case, m, a.level, a.roll, a.factors, comm, store)
            runs.append(r)
            if comm.rank == 0:
                sp = r["spread_over_sweep"]
                print(
                    f"{case} {m}: {r['grid_points']} points ({r['coast_grid_points']} coast, "
                    f"zoned {r['coast_zoned']}), {r['compliance_columns']} FE "
                    f"columns, {r['position_s']:.1f} s; spread over the sweep "
                    + ", ".join(f"{k} {100 * sp[k]:.2f} %" for k in MOMENTS),
                    flush=True,
                )
    if comm.rank == 0:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        path = out / "contact_grid.json"
        path.write_text(json.dumps({"runs": runs, "factors": a.factors}, indent=1))
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
