"""``python -m studies.phasing --case parker2000-3 --case parker2000-4 0 91.4 180 271.4
--out results/phasing``: planet phasing (parker2000) from the all-planet quasi-static FE.

Each ``--case NAME [ANGLE ...]`` is a study case (its gear set, bearing, level and number of
positions); the angles (deg, one per planet of its gear set) place the planets instead of the
assemblable angles nearest to equal spacing, each snapped to the nearest assemblable angle (a
multiple of 360 / (Zs + Zr) deg; the snap is reported). The scene is ``all_planets``. The
sun steps through one tooth pitch in ``model.positions`` equal steps (``--positions``
overrides), every position of the cycle sharing the bodies (one
:class:`solvers.body_store.BodyStore`). Spur gear sets are solved as spur (axial contact
lines, :mod:`solvers.flank_grid` eq. (1a)).

Writes ``phasing.json`` (the per-position records and the harmonic tables), ``report.md``,
``<case>_histories.png`` and ``<case>_harmonics.png`` (:mod:`studies.phasing.fe`).
``--report-only`` rewrites the report and figures from an existing ``phasing.json``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

import numpy as np
from mpi4py import MPI

from cases.gearset import CaseError
from cases.study_case import case_sizes, load_study_case
from gears.analytic import phasing
from postprocess.run_scalars import sizes_in_words
from solvers.body_store import BodyStore
from studies.cli import guarded
from studies.files import atomic_write_text, read_json, write_json
from studies.phasing import fe as pf
from studies.position import PositionExtras, solve_position
from studies.settings import RunSettings


def planet_angles(study, angles_deg) -> tuple[list[float], float]:
    """Given angles snapped to the assemblable ones (deg) and the largest snap (deg)."""
    gs = study.gearset
    zs, zr = gs.gears[gs.power_path[0]].teeth, gs.gears[gs.power_path[-1]].teeth
    if len(angles_deg) != gs.planets:
        raise CaseError(
            f"{study.name}: {len(angles_deg)} planet angles for the {gs.planets} planets of "
            f"gear set {gs.name}"
        )
    snapped = np.degrees(
        phasing.snap_to_assemblable(np.radians(angles_deg), zs, zr, gs.kind == "double_pinion")
    )
    snap = float(np.max(np.abs(snapped - np.asarray(angles_deg, float))))
    return [float(a) for a in snapped], snap


def run_case(name: str, angles, args, comm, store, say) -> tuple[dict, dict, list]:
    study = load_study_case(name)
    study = dataclasses.replace(study, model=dataclasses.replace(study.model, scene="all_planets"))
    gs = study.gearset
    sun, ring = gs.gears[gs.power_path[0]], gs.gears[gs.power_path[-1]]
    opts, snap = {}, 0.0
    if angles:
        psi, snap = planet_angles(study, angles)
        opts["planet_angles_deg"] = tuple(psi)
    else:
        psi = [
            math.degrees(a) for a in phasing.assemblable_angles(sun.teeth, ring.teeth, gs.planets)
        ]
    m = args.positions or study.model.positions
    level, variant = case_sizes(study, args.level)
    pitch = 2 * math.pi / sun.teeth
    records = []
    say(
        f"{name}: {gs.planets} planets at {', '.join(f'{a:.3f}' for a in psi)} deg, "
        f"{m} positions, {sizes_in_words(level, variant)}"
    )
    for k in range(m):
        t0 = time.perf_counter()
        pos = solve_position(
            study,
            k * pitch / m,
            comm,
            RunSettings(level=level, **variant),
            store=store,
            extras=PositionExtras(scene_options=opts),
        )
        rec = pf.position_record(pos, gs)
        records.append(rec)
        forces = ", ".join(f"{p['sun']['transverse_force_N']:.2f}" for p in rec["planets"])
        say(
            f"  position {k + 1}/{m}: sun-mesh forces {forces} N, TE {rec['te_um']:.4f} um "
            f"({time.perf_counter() - t0:.0f} s)"
        )
    inp = {
        "description": study.description,
        "gearset": gs.name,
        "zs": sun.teeth,
        "positions": m,
        "level": level,
        **variant,
        "dofs": records[0]["dofs"],
        "wall_s": float(np.median([r["wall_s"] for r in records])),
        "planet_angles_given_deg": list(angles) if angles else None,
        "planet_angles_deg": psi,
        "largest_snap_deg": snap,
        "r_b_sun_mm": sun.base_radius,
    }
    return inp, records


def run(args, comm=MPI.COMM_WORLD) -> dict:
    say = print if comm.rank == 0 else (lambda *_: None)
    store = BodyStore()
    data = {"case_inputs": {}, "records": {}}
    for spec in args.case:
        name, angles = spec[0], [float(a) for a in spec[1:]]
        data["case_inputs"][name], data["records"][name] = run_case(
            name, angles, args, comm, store, say
        )
    first = load_study_case(args.case[0][0])
    gs = first.gearset
    sun, pin, ring = (gs.gears[g] for g in gs.power_path)
    data["inputs"] = {
        "gearset": gs.name,
        "zs": sun.teeth,
        "zp": pin.teeth,
        "zr": ring.teeth,
        "module": sun.normal_module,
        "pressure_angle": sun.normal_pressure_angle,
        "face_width": sun.face_width,
        "torque_Nm": gs.input_torque,
        "argv": sys.argv[1:],
    }
    return data


def parse_args(argv=None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(
        prog="python -m studies.phasing",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument(
        "--case",
        action="append",
        nargs="+",
        required=True,
        metavar="NAME [DEG]",
        help="a study case and optionally its planet angles in deg",
    )
    ap.add_argument("--out", type=Path, default=Path("results/phasing"))
    ap.add_argument("--level", type=int, default=None, help="mesh level (default: the case's)")
    ap.add_argument(
        "--positions",
        type=int,
        default=None,
        help="positions over one mesh cycle (default: the case's)",
    )
    ap.add_argument(
        "--report-only", action="store_true", help="rewrite report and figures from phasing.json"
    )
    ap.add_argument("--traceback", action="store_true", help="print tracebacks (bug reports)")
    args = ap.parse_args(argv)
    if args.positions is not None and args.positions < 3:
        ap.error("--positions: at least 3 (the first harmonic needs 3 samples)")
    return args


def analyse(data: dict) -> dict:
    """The harmonic tables of every case from its records (in place; :func:`postprocess.
    phasing_fe.analyse`), up to the highest harmonic below M / 2."""
    data["vanish_tol"] = pf.VANISH_TOL
    data["cases"] = {}
    for name, inp in data["case_inputs"].items():
        recs = data["records"][name]
        l_max = (len(recs) - 1) // 2
        data["cases"][name] = pf.analyse(
            recs, inp["zs"], inp["planet_angles_deg"], inp["r_b_sun_mm"], l_max
        )
    data["discussion"] = pf.discussion(data)
    return data


def write_outputs(data: dict, out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    analyse(data)
    write_json(out / "phasing.json", data)
    atomic_write_text(out / "report.md", pf.report(data))
    paths = [out / "phasing.json", out / "report.md"]
    for name, res in data["cases"].items():
        paths.append(pf.figure_histories(res, name, out / f"{name}_histories.png"))
        paths.append(pf.figure_harmonics(res, name, out / f"{name}_harmonics.png"))
    return paths


def main(argv=None) -> int:
    args = parse_args(argv)
    comm = MPI.COMM_WORLD

    def body():
        data = read_json(args.out / "phasing.json") if args.report_only else run(args, comm)
        if comm.rank == 0:
            for p in write_outputs(data, args.out):
                print(p)

    return guarded(body, traceback=args.traceback)


if __name__ == "__main__":
    sys.exit(main())
