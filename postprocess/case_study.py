"""One finite element study case end to end: mesh positions -> summary, contact patterns.

    python -m postprocess.case_study 1-GA [--level L] [--positions N] [--out results]
    mpiexec -n 2 python -m postprocess.case_study 1-GA

The case (``cases/<name>.toml``) is solved at N mesh positions over one base pitch: sun
angles k (2 pi / Z_sun) / N, k = 0..N-1, with the carrier fixed. Each position is written to
``results/<case>/positions/<k>.json`` as soon as it is solved and reused by a later run of
the same level and degree, so a study that fails part way keeps what it finished.
The displacement of every body at the first position is written as VTX to
``results/<case>/fields/<body>.bp`` (open in ParaView). ``summary.json`` holds the means
over the positions at the top level (Mx_pin, My_pin, Mz_pin, ZS, ZR, M_LOA_sun, M_LOA_ring;
N m, mm, paper's pinion frame of singh2007 section 3), the per-position values, the
analytical model (Table 3 concentrated load, and Table 7 at the FE's own ZS, ZR), and the
contact stress from Hertz line contact with the exact local curvatures and the FE line load
at every grid point (``postprocess.contact_stress``).
Root stress from the FE field (``bending_stress``, MPa): per position the largest maximum
principal stress in the cells at the root fillets of the loaded teeth (sun, pinion on the
sun side and on the ring side, ring; :mod:`solvers.root_stress`), the mean over the
positions here (per-position values and locations in ``positions``);
``bending_stress_iso6336_nominal`` holds the ISO 6336-3 method B values for reference.
P1 cell stresses at a coarse fillet underestimate the peak: a mesh-dependent lower estimate.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import traceback
from pathlib import Path

import numpy as np
from mpi4py import MPI

from cases.study_case import StudyCase, load_study_case
from postprocess import contact_stress
from postprocess.analytic import single_pinion as sp
from postprocess.analytic import study as analytic_study
from postprocess.root_stress_iso6336 import nominal_root_stress

MEAN_KEYS = ("Mx_pin", "My_pin", "Mz_pin", "ZS", "ZR", "M_LOA_sun", "M_LOA_ring")
DEGREE = 1  # element degree of the case runs (P1: see solvers/README.md for the ladder)


def roll_angles(case: StudyCase, positions: int) -> list[float]:
    """Sun angles (rad) of ``positions`` equally spaced mesh positions over one base pitch."""
    z_sun = case.gearset.gears["sun"].teeth
    return [2.0 * math.pi / z_sun * k / positions for k in range(positions)]


def _pairs(case: StudyCase):
    return {"S": case.gearset.pair("sun", "pinion"), "R": case.gearset.pair("pinion", "ring")}


def contact_stress_at_points(case: StudyCase, pos: dict) -> dict:
    """Hertz p_max (MPa) and half-width b (mm) at every grid point of both meshes, from the
    FE line load w and the exact normal-plane curvatures at the point's roll position s
    (distance from the pitch point along the line of action, from its radius on gear 1)."""
    e_gear = case.material.gear_youngs_modulus
    steel = (e_gear, case.material.poisson_ratio)
    centres = {"S": np.zeros(2), "R": np.asarray(pos["pinion_centre_mm"][:2])}
    out = {}
    for key, pair in _pairs(case).items():
        pts = pos[f"points_{key}"]
        x = np.asarray(pts["x_mm"])
        w = np.clip(np.asarray(pts["line_load_N_per_mm"]), 0.0, None)
        r1 = np.linalg.norm(x[:, :2] - centres[key], axis=1)
        s = contact_stress.position_from_radius(pair, r1)
        hz = contact_stress.mesh_contact(pair, s, w, steel, steel)
        out[key] = {"s_mm": np.atleast_1d(s), "p_max": np.atleast_1d(hz.p_max)}
    return out


def analytic_reference(case: StudyCase, zs: float, zr: float) -> dict:
    """singh2007 Table 3 (concentrated load) and Table 7 at the FE's own ZS, ZR (N m)."""
    geo = analytic_study.single_pinion_geometry(analytic_study.from_gearset(case.gearset))
    f = sp.mesh_forces(case.gearset.torque_per_branch, geo)
    out = {}
    for name, (a, b) in (("concentrated", (0.0, 0.0)), ("at_fe_ZS_ZR", (zs, zr))):
        mx, my, _mz = sp.pinion_moments(f, geo, a, b)
        la_s, la_r = sp.loa_moments(mx, my, geo.alpha1, geo.alpha2)
        out[name] = {"Mx_pin": mx, "My_pin": my, "M_LOA_sun": la_s, "M_LOA_ring": la_r}
    return out


def iso_nominal_root_stress(case: StudyCase) -> dict:
    """ISO 6336-3 method B nominal root stress (MPa, all K factors 1) of the external gears;
    the ring is not covered by our ISO implementation (internal gear)."""
    torque = case.gearset.torque_per_branch * 1e3  # N mm on the sun
    pairs = _pairs(case)
    sun_pair, ring_pair = pairs["S"], pairs["R"]
    pinion_torque = torque * sun_pair.gear2.teeth / sun_pair.gear1.teeth
    return {
        "sun": nominal_root_stress(sun_pair, 1, torque)["sigma_F0"],
        "pinion_sun_side": nominal_root_stress(sun_pair, 2, torque)["sigma_F0"],
        "pinion_ring_side": nominal_root_stress(ring_pair, 1, pinion_torque)["sigma_F0"],
        "ring": None,
    }


def _position_record(case: StudyCase, pos: dict) -> dict:
    """What summary.json keeps of one position (scalars, per-mesh peak contact stress)."""
    hz = contact_stress_at_points(case, pos)
    rec = {k: pos[k] for k in MEAN_KEYS}
    loaded = {k: hz[k]["p_max"][hz[k]["p_max"] > 0] for k in hz}
    rec.update(
        roll=pos["roll"],
        # Mean over the loaded points: the peak sits at line ends (tip and face corners, no
        # relief) where a single grid point carries the end of a contact line.
        contact_stress_mean_loaded={
            "sun_pinion": float(loaded["S"].mean()) if loaded["S"].size else 0.0,
            "pinion_ring": float(loaded["R"].mean()) if loaded["R"].size else 0.0,
        },
        contact_stress={
            "sun_pinion": float(hz["S"]["p_max"].max()),
            "pinion_ring": float(hz["R"]["p_max"].max()),
        },
        active_points={"S": pos["active_points_S"], "R": pos["active_points_R"]},
        bending_stress=pos.get("bending_stress"),
        wall_time_s=pos["timings"]["wall"],
    )
    return rec


def run_case(
    name: str,
    out_root: Path = Path("results"),
    level: int | None = None,
    positions: int | None = None,
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> dict:
    """Solve every position (reusing finished ones), then write summary.json and the pictures.
    Returns the summary (on every rank). Raises after writing what finished if a position
    failed."""
    from solvers.gear_contact import run_position  # DOLFINx only when a case runs

    case = load_study_case(name)
    level = case.model.level if level is None else level
    n_pos = case.model.positions if positions is None else positions
    out = out_root / case.name
    pos_dir = out / "positions"
    if comm.rank == 0:
        pos_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    solved, failed = [], []
    for k, roll in enumerate(roll_angles(case, n_pos)):
        path = pos_dir / f"{k}.json"
        pos = None
        if path.is_file():
            old = json.loads(path.read_text())
            same = (old.get("level"), old.get("degree"), old.get("roll")) == (level, DEGREE, roll)
            # positions solved before the FE root stress existed are solved again
            pos = old if same and "bending_stress" in old else None
        if pos is None:
            try:
                # displacement fields (VTX, for ParaView) of the first position only
                vtx = out / "fields" if k == 0 else None
                pos = run_position(case, roll, comm, vtx_dir=vtx, level=level, degree=DEGREE)
            except Exception as exc:  # keep going: finished positions stay on disk
                failed.append({"position": k, "roll": roll, "error": repr(exc)})
                if comm.rank == 0:
                    traceback.print_exc()
                continue
            if comm.rank == 0:
                path.write_text(json.dumps(pos))
        solved.append(pos)
        if comm.rank == 0:
            print(f"{case.name}: position {k + 1}/{n_pos} (roll {roll:.5f} rad) "
                  f"My_pin {pos['My_pin']:.2f} N m, ZS {pos['ZS']:+.2f}, ZR {pos['ZR']:+.2f} mm, "
                  f"{pos['timings']['wall']:.1f} s", flush=True)  # fmt: skip
    summary = summarise(case, solved, failed, level, time.perf_counter() - t0)
    if comm.rank == 0:
        (out / "summary.json").write_text(json.dumps(summary, indent=1))
        if solved:
            from postprocess.contact_pattern import draw_contact_patterns
            from postprocess.loaded_scene import loaded_scene_picture

            draw_contact_patterns(case, solved, out)
            title = f"{case.name}: loaded scene, roll {solved[0]['roll']:.4f} rad"
            loaded_scene_picture(solved[0], out / "loaded_scene.png", title)
    if failed:
        raise RuntimeError(f"{case.name}: {len(failed)} of {n_pos} positions failed: {failed}")
    return summary


BENDING_KEYS = ("sun", "pinion_sun_side", "pinion_ring_side", "ring")


def _mean_bending(records: list[dict]) -> dict | None:
    """Mean over the positions of each FE root stress entry (MPa); None without any (e.g.
    positions solved before the root stress existed). An entry missing at a position (no
    fillet cell) is left out of its mean."""
    recs = [r["bending_stress"] for r in records if r.get("bending_stress")]
    if not recs:
        return None
    out = {}
    for k in BENDING_KEYS:
        vals = [r[k] for r in recs if r.get(k) is not None]
        out[k] = float(np.mean(vals)) if vals else None
    return out


def summarise(case: StudyCase, solved: list[dict], failed: list, level: int, wall: float):
    records = [_position_record(case, p) for p in solved]
    summary: dict = {"case": case.name, "description": case.description, "level": level,
                     "degree": DEGREE}  # fmt: skip
    if records:
        for k in MEAN_KEYS:
            summary[k] = float(np.mean([r[k] for r in records]))
        summary["contact_stress"] = {
            m: float(np.mean([r["contact_stress"][m] for r in records]))
            for m in ("sun_pinion", "pinion_ring")
        }
        summary["contact_stress_mean_loaded"] = {
            m: float(np.mean([r["contact_stress_mean_loaded"][m] for r in records]))
            for m in ("sun_pinion", "pinion_ring")
        }
        summary["analytic"] = analytic_reference(case, summary["ZS"], summary["ZR"])
        summary["dofs"] = solved[0]["dofs"]
    summary["bending_stress"] = _mean_bending(records)  # FE fillet stress, mean over positions
    summary["bending_stress_iso6336_nominal"] = iso_nominal_root_stress(case)
    summary["positions"] = records
    summary["failed_positions"] = failed
    summary["wall_time_s"] = wall
    return summary


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="+", help="case names, e.g. 1-GA 1-GB")
    ap.add_argument("--level", type=int, default=None, help="mesh level (default: the case's)")
    ap.add_argument("--positions", type=int, default=None, help="positions per base pitch")
    ap.add_argument("--out", type=Path, default=Path("results"))
    args = ap.parse_args(argv)
    status = 0
    for name in args.cases:  # a failed case does not stop the others
        try:
            run_case(name, args.out, args.level, args.positions)
        except Exception as exc:
            if MPI.COMM_WORLD.rank == 0:
                print(f"error: {exc}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
