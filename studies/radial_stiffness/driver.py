"""``python -m studies.radial_stiffness --case 1-GB --out results/radial_stiffness``: the
radial mesh stiffness of the sun-pinion (external) and pinion-ring (internal) meshes from the
FE contact solve, against pust2016's closed form, and the floating-sun threshold it implies.

The one-branch scene of the case is solved with the pinion moved radially by d (scene option
``pinion_radial_offset``: both centre distances change by +d) at constant sun torque, for
the offsets 0, +-h of every step h and a wider sweep (+-30 um), at several torques
(``--torque-factors`` times the case's) and at a second mesh position. k_r is the slope of
the least-squares straight line through F_rad over all offsets (on a zone grid a few-um
central difference measures the discrete cell set as much as the stiffness: about 1 N of a
6 kN force); the central differences are kept beside it. The meshes
need backlash for the pinion to move radially (the coast flanks of one mesh close by about
0.87 um per um of offset); a set built with too little can have its pinion's teeth thinned
(``--backlash-shift``: profile shift -x, addendum +x, dedendum -x coefficients, tip and root
circles kept; default 0): the operating pressure angle, hence k_r, does not depend on tooth
thickness. Every offset and torque shares the bodies (one
:class:`solvers.body_store.BodyStore`). ``--contact-model line|zone`` overrides the case's
``numerics.contact_model``: the closed form's premise (every mesh force on the plane of
action) is the line model's; the zone model's cells carry their own contact normals.

Writes ``radial_stiffness.json`` (every record and derived number), ``report.md``,
``radial_force.png``, ``load_dependence.png`` and ``stability.png``
(:mod:`studies.radial_stiffness.fe`). ``--report-only`` rewrites the report and figures
from an existing ``radial_stiffness.json``.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import math
import sys
import time
from pathlib import Path

from mpi4py import MPI

from cases.gearset import CaseError
from cases.study_case import load_study_case
from gears.units import n_m
from solvers.body_store import BodyStore
from studies.case_variants import global_root_stress
from studies.cli import guarded
from studies.files import ResultFileError, atomic_write_text, read_json, write_json
from studies.position import PositionExtras, solve_position
from studies.radial_stiffness import fe as rf
from studies.settings import RunSettings

#: how k_r is taken (``inputs.k_r_from``); a radial_stiffness.json without it took k_r from
#: 5 um central differences (before 2026-11-29) and is not rewritten by ``--report-only``
K_R_FROM = "least-squares line over the sweep"


def read_study(path: Path) -> dict:
    """A radial_stiffness.json this code can report."""
    data = read_json(path)
    if data.get("inputs", {}).get("k_r_from") != K_R_FROM:
        raise ResultFileError(
            f"{path}: written before k_r was taken from the {K_R_FROM} (its k_r are 5 um "
            "central differences); solve the study again instead of --report-only"
        )
    return data


def with_backlash(study, shift: float):
    """``study`` with its pinion's teeth thinned by the profile shift ``shift`` (tip and root
    circles kept): a backlash allowance on both meshes."""
    gs = study.gearset
    if gs.kind != "single_pinion":
        raise CaseError(f"{study.name}: the radial-stiffness study needs a single-pinion set")
    name = gs.power_path[1]
    p = gs.gears[name]
    thin = dataclasses.replace(
        p,
        profile_shift=p.profile_shift - shift,
        addendum_coef=p.addendum_coef + shift,
        dedendum_coef=p.dedendum_coef - shift,
    )
    return dataclasses.replace(
        study, gearset=dataclasses.replace(gs, gears={**gs.gears, name: thin})
    )


def with_torque(study, factor: float):
    gs = study.gearset
    return dataclasses.replace(
        study, gearset=dataclasses.replace(gs, input_torque=gs.input_torque * factor)
    )


def normal_backlash_um(study) -> float:
    """The smaller normal backlash of the two meshes (um): j_n = j_wt cos(alpha_wt) cos(beta_b)."""
    gs = study.gearset
    path = gs.power_path
    out = []
    for a, b in itertools.pairwise(path):
        pair = gs.pair(a, b)
        jn = pair.backlash * math.cos(pair.operating_pressure_angle)
        out.append(jn * math.cos(gs.gears[path[1]].base_helix_angle) * 1e3)
    return min(out)


def solve_offsets(study, offsets, roll, comm, level, store, say) -> dict[float, dict]:
    """The radial records (:func:`studies.radial_stiffness.fe.radial_record`) of the
    one-branch scene at each pinion radial offset (mm)."""
    out = {}
    for d in offsets:
        t0 = time.perf_counter()
        pos = solve_position(
            study,
            roll,
            comm,
            RunSettings(level=level),
            store=store,
            extras=PositionExtras(scene_options={"pinion_radial_offset": float(d)}),
        )
        rec = rf.radial_record(pos, study.gearset)
        rec["dofs"] = pos["dofs"]
        out[float(d)] = rec
        say(
            f"  d = {d * 1e3:+6.1f} um: F_rad sun {rec['external']['radial_force_N']:+10.3f} N, "
            f"ring {rec['internal']['radial_force_N']:+10.3f} N ({time.perf_counter() - t0:.1f} s)"
        )
    return out


def _k_steps(records, steps) -> dict:
    return {k: {str(h): rf.central_difference(records, k, h) for h in steps} for k in rf.KINDS}


def run(args, comm=MPI.COMM_WORLD) -> dict:
    say = print if comm.rank == 0 else (lambda *_: None)
    base = load_study_case(args.case)
    if base.model.scene != "one_branch":
        base = dataclasses.replace(base, model=dataclasses.replace(base.model, scene="one_branch"))
    if base.gearset.kind != "single_pinion":
        raise CaseError(f"{base.name}: the radial-stiffness study needs a single-pinion set")
    # the stiffness reads no root stress: on the global model, without the submodels that
    # would be most of every solve (the meshes and the solution are the same)
    base = global_root_stress(base)
    if args.contact_model is not None:
        num = dataclasses.replace(base.numerics, contact_model=args.contact_model)
        base = dataclasses.replace(base, numerics=num)
    say(f"{base.name}: contact model {base.numerics.contact_model}")
    study = with_backlash(base, args.backlash_shift) if args.backlash_shift else base
    steps = sorted(args.steps)
    sweep = sorted({0.0, *(s * h for h in steps + list(args.sweep) for s in (-1, 1))})
    pitch = 2 * math.pi / study.gearset.gears[study.gearset.power_path[0]].teeth
    rolls = [f * pitch for f in args.rolls]
    store = BodyStore()
    runs = []
    nominal = None
    for factor in args.torque_factors:
        st = with_torque(study, factor)
        t_sun = rf.sun_torque_nmm(st.gearset)
        say(f"{base.name}: sun torque {n_m(t_sun):.1f} N m on the branch ({factor:g} x)")
        recs = solve_offsets(st, sweep, rolls[0], comm, args.level, store, say)
        run = {
            "torque_factor": factor,
            "sun_torque_Nm": n_m(t_sun),
            "analytic": rf.analytic_stiffness(st.gearset, t_sun),
            "records": {str(d): r for d, r in recs.items()},
            "k_r_steps": _k_steps(recs, steps),
            "k_r": {k: rf.fit_stiffness(recs, k) for k in rf.KINDS},
        }
        runs.append(run)
        if factor == 1.0:
            nominal = run
    say(f"second mesh position, {args.rolls[-1]:g} pitch")
    recs2 = solve_offsets(study, sweep, rolls[-1], comm, args.level, store, say)
    data = {
        "inputs": {},
        "nominal": nominal,
        "torque_runs": runs,
        "second_roll": {k: rf.fit_stiffness(recs2, k) for k in rf.KINDS},
        "second_roll_records": {str(d): r for d, r in recs2.items()},
    }
    data["inputs"] = {
        "case": base.name,
        "gearset": base.gearset.name,
        "contact_model": base.numerics.contact_model,
        "level": args.level,
        "degree": base.numerics.degree,
        "dofs": nominal["records"]["0.0"]["dofs"],
        "bearing_radial_N_per_mm": base.bearing.radial_stiffness,
        "backlash_shift": args.backlash_shift,
        "backlash_normal_um": normal_backlash_um(study),
        "steps_mm": steps,
        "sweep_mm": sorted(set(args.sweep) | set(steps)),
        "torque_factors": list(args.torque_factors),
        "k_r_from": K_R_FROM,
        "rolls_pitch": list(args.rolls),
    }
    derive(data, base, args.branches)
    return data


def derive(data: dict, base, branches) -> None:
    """The coast flanks' state, the pinion's deflection, the mesh stiffness and the stability
    models (in place; the agreements are :func:`studies.radial_stiffness.fe.checks`)."""
    nom = data["nominal"]
    recs = [r for run in data["torque_runs"] for r in run["records"].values()]
    recs += list(data["second_roll_records"].values())
    gaps = [r["coast_min_gap_mm"] for r in recs if r.get("coast_min_gap_mm") is not None]
    data["coast_min_gap_um"] = min(gaps) * 1e3 if gaps else None
    data["coast_force_max_N"] = max(r.get("coast_force_N", 0.0) for r in recs)
    r0 = nom["records"]["0.0"]
    pin = base.gearset.power_path[1]
    rig = r0["rigid"]
    c = r0["pinion_centre_mm"]
    e_r = [c[0] / math.hypot(c[0], c[1]), c[1] / math.hypot(c[0], c[1])]
    ux, uy = rig[f"{pin}_x"], rig[f"{pin}_y"]
    data["pinion_radial_deflection_um"] = abs(ux * e_r[0] + uy * e_r[1]) * 1e3
    data["pinion_tangential_deflection_um"] = abs(-ux * e_r[1] + uy * e_r[0]) * 1e3
    ms = {
        "k_r_external": nom["k_r"]["external"],  # the fits over the sweep
        "k_r_internal": nom["k_r"]["internal"],
        "k_ms": r0["external"]["transverse_force_N"] / r0["external"]["approach_mm"],
        "k_mr": r0["internal"]["transverse_force_N"] / r0["internal"]["approach_mm"],
        "k_c": base.bearing.radial_stiffness,
    }
    data["mesh_stiffness"] = ms
    a = nom["analytic"]
    data["stability"] = rf.stability(
        ms["k_r_external"],
        ms["k_r_internal"],
        ms["k_ms"],
        ms["k_mr"],
        ms["k_c"],
        math.radians(a["external"]["alpha_wt_deg"]),
        math.radians(a["internal"]["alpha_wt_deg"]),
        rf.body_masses(base.gearset),
        branches,
    )


def write_outputs(data: dict, out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    data["checks"] = rf.checks(data)  # every agreement the report states (also --report-only)
    write_json(out / "radial_stiffness.json", data)
    atomic_write_text(out / "report.md", rf.report(data))
    return [
        out / "radial_stiffness.json",
        out / "report.md",
        rf.figure_radial_force(data, out / "radial_force.png"),
        rf.figure_load(data, out / "load_dependence.png"),
        rf.figure_stability(data, out / "stability.png"),
    ]


def parse_args(argv=None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(
        prog="python -m studies.radial_stiffness",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("--case", required=True, help="a single-pinion study case (name or path)")
    ap.add_argument("--out", type=Path, default=Path("results/radial_stiffness"))
    ap.add_argument("--level", type=int, default=0, help="mesh level (default 0)")
    ap.add_argument(
        "--contact-model",
        choices=("line", "zone"),
        default=None,
        help="contact grid model (default: the case file's numerics.contact_model)",
    )
    ap.add_argument(
        "--steps",
        type=float,
        nargs="+",
        default=[0.005, 0.01],
        help="central-difference steps h, mm (default 0.005 0.01)",
    )
    ap.add_argument(
        "--sweep",
        type=float,
        nargs="*",
        default=[0.02, 0.03],
        help="further offsets at the nominal torque, mm (default 0.02 0.03)",
    )
    ap.add_argument(
        "--torque-factors",
        type=float,
        nargs="+",
        default=[0.25, 0.5, 1.0, 1.5],
        help="sun torques as multiples of the case's (must hold 1)",
    )
    ap.add_argument(
        "--rolls",
        type=float,
        nargs=2,
        default=[0.0, 0.5],
        help="two mesh positions, in sun tooth pitches (default 0 0.5)",
    )
    ap.add_argument(
        "--backlash-shift",
        type=float,
        default=0.0,
        help="pinion tooth thinning as a profile shift, for a set without backlash (default 0)",
    )
    ap.add_argument(
        "--branches",
        type=int,
        nargs="+",
        default=[1, 2, 3, 4],
        help="branch numbers of the floating-sun model (default 1 2 3 4)",
    )
    ap.add_argument(
        "--report-only",
        action="store_true",
        help="rewrite report and figures from radial_stiffness.json",
    )
    ap.add_argument("--traceback", action="store_true", help="print tracebacks (bug reports)")
    args = ap.parse_args(argv)
    if 1.0 not in args.torque_factors or any(f <= 0 for f in args.torque_factors):
        ap.error("--torque-factors: positive numbers, one of them 1 (the case's torque)")
    if any(h <= 0 for h in args.steps + args.sweep) or args.backlash_shift < 0:
        ap.error("--steps, --sweep must be > 0 mm and --backlash-shift >= 0")
    return args


def main(argv=None) -> int:
    args = parse_args(argv)
    comm = MPI.COMM_WORLD

    def body():
        data = (
            read_study(args.out / "radial_stiffness.json") if args.report_only else run(args, comm)
        )
        if comm.rank == 0:
            for p in write_outputs(data, args.out):
                print(p)

    return guarded(body, traceback=args.traceback)


if __name__ == "__main__":
    sys.exit(main())
