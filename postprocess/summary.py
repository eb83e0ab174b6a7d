"""``summary.json`` of a study: the solved mesh positions reduced to what a report reads.

Per position (:func:`position_record`): the paper's scalars of the gear-set kind
(:data:`postprocess.paper_moments.MEAN_KEYS`), the peak, the interior peak and the
mean-over-loaded-points Hertz contact stress of every mesh (:func:`postprocess.mesh_stress.
contact_stress_at_points`; the peak sits at line ends: tip and face corners, no relief;
interior: :func:`postprocess.mesh_stress.edge_points`), the active points, the FE root stress
and the wall time. The summary (:func:`summarise`) holds the means over the positions at the
top level, the FE root stress as the maximum over the mesh cycle (:func:`cycle_bending`),
the closed-form reference of the kind, the ISO 6336-3 nominal root stress, the
per-position records, the failed positions, and ``inputs`` / ``provenance``: everything that
produced it, so a report never re-reads a case file.

Double pinion (:func:`double_pinion_reference`, :func:`double_pinion_means`): ``analytic``
holds singh2007 Table 5 (2-B, the set's own triangle; 2-A, the collinear limit theta = 180
deg, phi = 0) and the closed form at the FE's own load centroids (mean over the positions);
the summary also holds the mean bearing forces and tilts of SP and RP, the centroid offset
and line-of-action offset of every mesh on every pinion, and the SP-RP differential split
over the load centroids (``sp_rp_differential``, :func:`postprocess.paper_moments.
_sp_rp_differential`).

Contact stress: ``contact_stress`` and ``contact_stress_mean_loaded`` are kept as before (the
means over the positions of each position's peak and of the mean over its loaded stations
(a line grid's points, a zone grid's sections) of each station's peak); the
numbers to quote are in ``contact_stress_cycle`` (per mesh, :func:`postprocess.mesh_stress.
contact_stress_cycle`): the maximum over the mesh cycle at interior points, the edge maximum
as an edge-load indicator, K_Hbeta = w_max / w_mean and ISO 6336-2 sigma_H0 sqrt(K_Hbeta).
"""

from __future__ import annotations

import math

import numpy as np

from gears.analytic import double_pinion as dp
from gears.analytic import single_pinion as sp
from gears.analytic.planetary import (
    double_pinion_axial_forces,
    double_pinion_geometry,
    single_pinion_geometry,
)
from postprocess.mesh_stress import (
    contact_stress_at_points,
    contact_stress_cycle,
    edge_points,
    iso_root_stress_factors,
)
from postprocess.paper_moments import MEAN_KEYS, with_loa_aliases
from postprocess.train_results import coast_summary


def mesh_key(mesh: str) -> str:
    """Summary key of a mesh grid name ("sun-pinion" -> "sun_pinion")."""
    return mesh.replace("-", "_")


def set_mesh(mesh: str, gears) -> str:
    """The gear set's mesh of a scene's mesh grid name: a planet body is its gear's name and
    its index (``sun-pinion2`` -> ``sun_pinion``, :func:`meshing.scenes.planetary_scene`)."""

    def gear(body: str) -> str:
        return next(
            (g for g in gears if body == g or (body.startswith(g) and body[len(g) :].isdigit())),
            body,
        )

    return "_".join(gear(b) for b in mesh.split("-"))


#: the contact stresses of :func:`contact_stress_cycle` reduced over the planets' meshes
CYCLE_SET_QUANTITIES = ("interior_p_max_MPa", "sigma_H_MPa", "w_max_N_per_mm")


def cycle_set(cycle: dict, gears) -> dict:
    """Per mesh of the gear set the largest of :data:`CYCLE_SET_QUANTITIES` over the planets'
    meshes (``cycle``: per mesh grid name, :func:`postprocess.mesh_stress.
    contact_stress_cycle`), and the mesh (summary key) of the largest interior pressure."""
    out: dict = {}
    for m, v in cycle.items():
        rec = out.setdefault(set_mesh(m, gears), {"mesh": None})
        for q in CYCLE_SET_QUANTITIES:
            if v.get(q) is not None and (rec.get(q) is None or v[q] > rec[q]):
                rec[q] = v[q]
                if q == CYCLE_SET_QUANTITIES[0]:
                    rec["mesh"] = mesh_key(m)
    return out


def position_record(study, pos: dict, index: int) -> dict:
    """What summary.json keeps of one position (scalars, per-mesh contact stress);
    ``index``: the position's index in the mesh cycle (0-based, as ``failed_positions``)."""
    hz = contact_stress_at_points(study.gearset, study.material, pos)
    edges = edge_points(study.gearset, pos)
    rec = {k: pos[k] for k in MEAN_KEYS[study.gearset.kind]}
    # per station (a line grid's point, a zone grid's section): the mean of the peaks
    loaded = {m: v["station_p_max"][v["station_p_max"] > 0] for m, v in hz.items()}
    interior = {m: v["p_max"][~edges[m]["edge"]] for m, v in hz.items()}
    rec.update(
        position=index,
        roll=pos["roll"],
        contact_stress_mean_loaded={
            mesh_key(m): float(v.mean()) if v.size else 0.0 for m, v in loaded.items()
        },
        contact_stress={mesh_key(m): float(v["p_max"].max()) for m, v in hz.items()},
        contact_stress_interior={
            mesh_key(m): float(v.max()) if v.size else None for m, v in interior.items()
        },
        active_points={mesh_key(m): pos["meshes"][m]["active_points"] for m in hz},
        bending_stress=pos.get("bending_stress"),
        wall_time_s=pos["timings"]["wall"],
        reused=bool(pos.get("reused", False)),
    )
    if study.gearset.kind == "double_pinion":
        rec["sp_rp_differential"] = _mean_tree([r["sp_rp_differential"] for r in _branch_rows(pos)])
    return rec


def cycle_bending(records: list[dict]) -> dict:
    """FE root stress over the mesh cycle: per key the maximum over the positions of the
    surface value (``bending_stress``), of the value on ISO's 30 / 60 deg line
    (``bending_stress_tangent``), of the largest P1 cell value (``bending_stress_cell``) and
    of the surface value within the face-end band (``bending_stress_face_end``), of the
    value kept apart beside a contact point force (``bending_stress_near_load``), of the
    surface and ISO-line values of the moving least-squares recovery
    (``bending_stress_recovered``, ``bending_stress_tangent_recovered``,
    :mod:`solvers.surface_recovery`; older position files have none), with
    submodels (:mod:`solvers.root_submodel`) also of the global model's own surface value
    (``bending_stress_global``, a check), the method in words (``bending_stress_method``),
    and where the surface maximum sits (``bending_stress_at``: position index, roll, tooth,
    side, z; ``bending_stress_recovered_at`` for the recovered one, where runs have it);
    scenes with several planets also ``<name>_set`` for the four surface and ISO-line
    readings, the largest value per gear-set key (the keys of ISO's nominal stress), and
    ``bending_stress_set_key`` / ``bending_stress_recovered_set_key``, the output key the
    surface ones are of.
    An entry missing at a position (no fillet, or a planet's mesh not read) is left out of
    its maximum; None where no position has it (:mod:`solvers.root_stress`)."""
    recs = [(j, r) for j, r in enumerate(records) if r.get("bending_stress")]
    out: dict = {
        "bending_stress": None,
        "bending_stress_tangent": None,
        "bending_stress_cell": None,
        "bending_stress_face_end": None,
        "bending_stress_near_load": None,
        "bending_stress_at": None,
    }
    if not recs:
        out["bending_stress_note"] = (
            "not read (numerics.root_stress 'none', or 'global' on coarse root fillets)"
        )
        return out
    keys = [k for k, v in recs[0][1]["bending_stress"].items() if not isinstance(v, (dict, str))]

    def best(get):
        vals = {
            k: [(v, j) for j, r in recs if (v := get(r["bending_stress"], k)) is not None]
            for k in keys
        }
        return {k: max(v)[0] if v else None for k, v in vals.items()}, {
            k: max(v)[1] if v else None for k, v in vals.items()
        }

    out["bending_stress"], where = best(lambda b, k: b.get(k))
    out["bending_stress_tangent"], _ = best(lambda b, k: (b.get("tangent") or {}).get(k))
    out["bending_stress_cell"], _ = best(lambda b, k: (b.get("cell_max") or {}).get(k))
    out["bending_stress_face_end"], _ = best(lambda b, k: (b.get("face_end") or {}).get(k))
    out["bending_stress_near_load"], _ = best(
        lambda b, k: ((b.get("locations") or {}).get(k) or {}).get("near_load")
    )

    def recovered(b, k, q):
        return (((b.get("locations") or {}).get(k) or {}).get("recovered") or {}).get(q)

    out["bending_stress_recovered"], where_rec = best(lambda b, k: recovered(b, k, "value"))
    out["bending_stress_tangent_recovered"], _ = best(lambda b, k: recovered(b, k, "tangent"))
    out["bending_stress_method"] = recs[0][1]["bending_stress"].get("method")
    if any(r["bending_stress"].get("global") for _, r in recs):  # read on submodels
        out["bending_stress_global"], _ = best(lambda b, k: (b.get("global") or {}).get(k))

    def at(where, loc_of):
        out = {}
        for k, j in where.items():
            if j is None:
                out[k] = None
                continue
            loc = loc_of((records[j]["bending_stress"].get("locations") or {}).get(k) or {})
            out[k] = {"position": records[j]["position"], "roll": records[j].get("roll")}
            out[k].update({q: loc.get(q) for q in ("tooth", "side", "z_mm")})
        return out

    out["bending_stress_at"] = at(where, lambda loc: loc)
    if any(v is not None for v in where_rec.values()):
        out["bending_stress_recovered_at"] = at(where_rec, lambda loc: loc.get("recovered") or {})
    locs = recs[0][1]["bending_stress"].get("locations") or {}
    to_set = {k: (locs.get(k) or {}).get("set_key", k) for k in keys}
    if any(k != v for k, v in to_set.items()):  # several planets: the largest per gear-set key
        for name in (
            "bending_stress",
            "bending_stress_tangent",
            "bending_stress_recovered",
            "bending_stress_tangent_recovered",
        ):
            by_set: dict = {}
            for k, v in out[name].items():
                if v is not None and (to_set[k] not in by_set or v > by_set[to_set[k]][0]):
                    by_set[to_set[k]] = (v, k)
            out[f"{name}_set"] = {s: v for s, (v, _) in by_set.items()}
            if name in ("bending_stress", "bending_stress_recovered"):
                out[f"{name}_set_key"] = {s: k for s, (_, k) in by_set.items()}
    return out


def analytic_reference(study, fe: dict) -> dict:
    """The closed form of the kind beside the FE means: single pinion, singh2007 Table 3
    (concentrated load) and Table 7 at the FE's own ZS, ZR (N m); double pinion, Table 5."""
    if study.gearset.kind != "single_pinion":
        return {}
    inp = study.gearset.planetary_input()
    geo = single_pinion_geometry(inp)
    f = sp.mesh_forces(inp.torque_per_branch, geo)
    out = {}
    for name, (a, b) in (("concentrated", (0.0, 0.0)), ("at_fe_ZS_ZR", (fe["ZS"], fe["ZR"]))):
        mx, my, _mz = sp.pinion_moments(f, geo, a, b)
        la_s, la_r = sp.loa_moments(mx, my, geo.alpha1, geo.alpha2)
        out[name] = {"Mx_pin": mx, "My_pin": my, "M_LOA_sun": la_s, "M_LOA_ring": la_r}
    return out


def _branch_rows(pos: dict) -> list[dict]:
    """The branch records of a position: its ``branches`` (all-planet scenes) or itself."""
    return pos["branches"] if "branches" in pos else [pos]


def _mean_tree(trees: list):
    """The mean of same-shaped JSON trees: numbers and lists of numbers element-wise, dicts
    key by key (keys of the first tree); anything else is taken from the first tree."""
    first = trees[0]
    if isinstance(first, dict):
        return {k: _mean_tree([t[k] for t in trees]) for k in first}
    if isinstance(first, bool) or not isinstance(first, (int, float, list)):
        return first
    return np.mean(np.asarray(trees, float), axis=0).tolist()


def double_pinion_reference(study, solved: list[dict]) -> dict:
    """singh2007 Table 5 from the gear set: ``table5`` (case 2-B, the set's own sun / SP / RP
    triangle) and ``table5_2A`` (the collinear limit theta = 180 deg, phi = 0, case 2-A);
    ``at_fe_centroids``: the same closed form with each mesh force moved to the FE's load
    centroid, mean over the positions (and branches). N m; angles deg."""
    inp = study.gearset.planetary_input()
    fz = double_pinion_axial_forces(inp)
    out = {}
    for name, kw in (("table5", {}), ("table5_2A", {"theta": math.pi, "phi": 0.0})):
        geo = double_pinion_geometry(inp, **kw)
        out[name] = with_loa_aliases(dp.double_pinion_moments(fz, geo))
        out[name].update(theta_deg=math.degrees(geo.theta), phi_deg=math.degrees(geo.phi))
    rows = [r for p in solved for r in _branch_rows(p)]
    out["at_fe_centroids"] = _mean_tree([r["analytic"]["at_fe_centroids"] for r in rows])
    return out


def double_pinion_means(solved: list[dict]) -> dict:
    """Means over the positions (and branches) of what a double-pinion report quotes beside
    :data:`MEAN_KEYS`: the bearing force (= the contact force on the pinion, N) and tilt (rad)
    of SP and RP in their frames, the normal force of each mesh, the centroid offset Z and the
    offset along the line of action of every mesh on every pinion (mm), and the SP-RP
    differential split over the load centroids."""
    rows = [r for p in solved for r in _branch_rows(p)]
    first = rows[0]
    mean = lambda key: _mean_tree([r[key] for r in rows])  # noqa: E731
    offsets = [k for k in first if k.startswith(("Z_", "loa_offset_"))]
    return {
        "bearing_force_N": {pn: mean(f"{pn}_force_N") for pn in ("SP", "RP")},
        "bearing_tilt_rad": {pn: mean(f"{pn}_tilt_rad") for pn in ("SP", "RP")},
        "normal_force_N": {
            k.removeprefix("normal_force_").removesuffix("_N"): mean(k)
            for k in first
            if k.startswith("normal_force_")
        },
        "mesh_offsets_mm": {k: mean(k) for k in offsets},
        "sp_rp_differential": mean("sp_rp_differential"),
    }


def _system_means(study, solved: list[dict]) -> dict:
    """Per branch (pinion) the means over the positions of its scalars and load share, the
    load-sharing factor K_gamma (the largest share at any position) and, with a carrier body,
    the torque balance, the sun centre displacement and the carrier wind-up."""
    keys = (*MEAN_KEYS[study.gearset.kind], "load_share")
    n = len(solved[0]["branches"])
    pinions = []
    for i in range(n):
        rows = [p["branches"][i] for p in solved]
        rec = {"angle_deg": rows[0]["angle_deg"]}
        rec.update({k: float(np.mean([r[k] for r in rows])) for k in keys})
        pinions.append(rec)
    out: dict = {"pinions": pinions, "K_gamma": float(max(p["K_gamma"] for p in solved))}
    if "carrier" in solved[0]:
        out["torque_balance_rel"] = float(max(p["torque_balance_rel"] for p in solved))
        out["sun_centre_displacement_mm"] = np.mean(
            [p["sun_centre_displacement_mm"] for p in solved], axis=0
        ).tolist()
        out["carrier_windup_rad"] = float(np.mean([p["carrier"]["windup_rad"] for p in solved]))
    return out


def summarise(study, solved: list[dict], failed: list, meta: dict) -> dict:
    """The summary of a study's positions; ``meta``: level, degree, inputs, provenance,
    wall time (copied in as they are)."""
    if failed and any("position" not in p for p in solved):
        raise ValueError(
            "summarise: with failed positions every solved one must carry its "
            "index in the mesh cycle ('position')"
        )
    records = [position_record(study, p, p.get("position", j)) for j, p in enumerate(solved)]
    summary: dict = {"case": study.name, "description": study.description, **meta}
    if records:
        for k in MEAN_KEYS[study.gearset.kind]:
            summary[k] = float(np.mean([r[k] for r in records]))
        for key in ("contact_stress", "contact_stress_mean_loaded"):
            summary[key] = {
                m: float(np.mean([r[key][m] for r in records])) for m in records[0][key]
            }
        cycle = contact_stress_cycle(study.gearset, study.material, solved)
        summary["contact_stress_cycle"] = {mesh_key(m): v for m, v in cycle.items()}
        if "branches" in solved[0]:  # several planets: the largest per mesh of the gear set
            summary["contact_stress_cycle_set"] = cycle_set(cycle, study.gearset.power_path)
        summary["analytic"] = analytic_reference(study, summary)
        if study.gearset.kind == "double_pinion":
            summary["analytic"] = double_pinion_reference(study, solved)
            summary.update(double_pinion_means(solved))
        summary["dofs"] = solved[0]["dofs"]
        # the global model's root fillets, as the scene meshed them (numerics.root_fillets)
        summary["root_fillets"] = solved[0].get("root_fillets")
        # zone model: the largest clipped share of the FE body correction (contact.py eq. (6))
        clipped = [c for p in solved if (c := p["timings"].get("correction_clipped")) is not None]
        zone = study.numerics.contact_model == "zone"
        summary["contact_correction_clipped"] = max(clipped) if zone and clipped else None
        moved = [e for p in solved if (e := p["timings"].get("correction_clip_effect")) is not None]
        summary["contact_correction_clip_effect"] = max(moved) if zone and moved else None
        if "branches" in solved[0]:
            summary.update(_system_means(study, solved))
    summary["coast"] = coast_summary(solved)  # smallest coast gap, coast load (None: no grids)
    summary.update(cycle_bending(records))  # FE fillet stress, maximum over the mesh cycle
    iso = iso_root_stress_factors(study.gearset)
    summary["bending_stress_iso6336_nominal"] = {k: v and v["sigma_F0"] for k, v in iso.items()}
    summary["bending_stress_iso6336"] = iso
    summary["positions"] = records
    summary["failed_positions"] = failed
    return summary
