"""Root-stress submodel solver benchmark: the CG tolerance of the P2 sectors against what it
costs and what it moves (:class:`solvers.root_submodel.SubmodelBody`).

    python -m studies.bench_submodel [--case 1-GB] [--level 1] [--roll 0]
        [--rtols 1e-10 1e-8 1e-6 1e-5] [--out results/bench]

One mesh position of the case is solved once per tolerance in one process (the bodies and
the sectors are set up by the first solve and reused, so each row is the same global
solution and the same AMG hierarchies, and only the CG stopping point differs). Per
tolerance and output key (sun, pinion_sun_side, ...): CG iterations, the sector's solve
time (loads, cut values, CG, read-out), the surface root stress and the value on ISO's
line, and their change relative to the tightest tolerance. The ratios come from one run.

Writes ``<out>/submodel_solver.json`` and ``submodel_solver.md``. Serial. Exit status 0,
2 invalid input, 3 a file could not be written. A benchmark measures; it asserts nothing.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import argparse
import sys
import time
from pathlib import Path

from mpi4py import MPI

from cases.study_case import load_study_case
from solvers.body_store import BodyStore
from solvers.root_submodel import SubmodelBody
from studies.cli import InputError, guarded
from studies.files import atomic_write_text, write_json
from studies.position import solve_position


def _rows(bs: dict) -> dict[str, dict]:
    """Per output key what a row reports of one position's ``bending_stress``."""
    out = {}
    for key, loc in bs["locations"].items():
        sm = loc["submodel"]
        out[key] = {"iterations": sm["iterations"], "solve_s": sm["solve_s"],
                    **{k: sm[k] for k in ("cut_s", "loads_s", "krylov_s", "read_s")},
                    "surface_MPa": bs[key], "tangent_MPa": bs["tangent"][key]}  # fmt: skip
    return out


def bench(args) -> None:
    rtols = sorted(set(args.rtols))
    if not rtols or min(rtols) <= 0.0 or max(rtols) >= 1.0:
        raise InputError(f"--rtols: give tolerances in (0, 1), got {args.rtols}")
    study = load_study_case(args.case)
    if study.numerics.root_stress != "submodel":
        raise InputError(f"--case {args.case}: numerics.root_stress must be 'submodel'")
    comm = MPI.COMM_WORLD
    store = BodyStore()
    # a first solve sets up the bodies and the sectors (at the default tolerance); every row
    # after it reuses them
    t0 = time.perf_counter()
    solve_position(study, args.roll, comm, level=args.level, store=store)
    setup_s = time.perf_counter() - t0
    runs = []
    for rtol in rtols:  # tightest first: the reference
        for obj in store.objects():
            if isinstance(obj, SubmodelBody):
                obj.ksp.setTolerances(rtol=rtol)
        t0 = time.perf_counter()
        out = solve_position(study, args.roll, comm, level=args.level, store=store)
        runs.append({"rtol": rtol, "wall_s": time.perf_counter() - t0,
                     "keys": _rows(out["bending_stress"])})  # fmt: skip
    ref = runs[0]["keys"]
    for run in runs:
        for key, row in run["keys"].items():
            for q in ("surface_MPa", "tangent_MPa"):
                a, b = row[q], ref[key][q]
                row[f"{q}_change"] = None if a is None or not b else abs(a - b) / abs(b)
    data = {"case": args.case, "level": args.level, "roll": args.roll,
            "first_solve_s": setup_s, "reference_rtol": rtols[0], "runs": runs}  # fmt: skip
    if comm.rank == 0:
        args.out.mkdir(parents=True, exist_ok=True)
        write_json(args.out / "submodel_solver.json", data)
        atomic_write_text(args.out / "submodel_solver.md", _report(data))
        print(_report(data))


def _report(data: dict) -> str:
    lines = [
        f"# Submodel CG tolerance: {data['case']}, level {data['level']}, roll {data['roll']}",
        "",
        "Each row: one key's sector at one tolerance, the same global solution; change "
        f"relative to rtol {data['reference_rtol']:g} (the first row of each key). No row "
        f"includes a set-up: a first solve ({data['first_solve_s']:.0f} s) set up the "
        "bodies and the sectors.",
        "",
        "| key | rtol | CG iterations | sector solve (s): all / cut / loads / CG / read | "
        "surface (MPa) | change | ISO line (MPa) | change |",
        "|---|---|---|---|---|---|---|---|",
    ]
    keys = list(data["runs"][0]["keys"])
    for key in keys:
        for run in data["runs"]:
            r = run["keys"][key]

            def ch(x):
                return "-" if x is None else f"{x:.1e}"

            tan = "-" if r["tangent_MPa"] is None else f"{r['tangent_MPa']:.2f}"
            lines.append(
                f"| {key} | {run['rtol']:g} | {r['iterations']} | {r['solve_s']:.1f} / "
                f"{r['cut_s']:.1f} / {r['loads_s']:.1f} / {r['krylov_s']:.1f} / "
                f"{r['read_s']:.1f} | "
                f"{r['surface_MPa']:.2f} | {ch(r['surface_MPa_change'])} | {tan} | "
                f"{ch(r['tangent_MPa_change'])} |"
            )
    lines += ["", "| rtol | position wall (s) | sum of sector solves (s) |", "|---|---|---|"]
    for run in data["runs"]:
        tot = sum(r["solve_s"] for r in run["keys"].values())
        lines.append(f"| {run['rtol']:g} | {run['wall_s']:.1f} | {tot:.1f} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.bench_submodel", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--level", type=int, default=1)
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad)")
    ap.add_argument("--rtols", type=float, nargs="+", default=[1e-10, 1e-8, 1e-6, 1e-5])
    ap.add_argument("--out", type=Path, default=Path("results/bench"))
    args = ap.parse_args(argv)
    return guarded(lambda: bench(args), traceback=False)


if __name__ == "__main__":
    sys.exit(main())
