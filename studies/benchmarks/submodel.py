"""Root-stress submodel solver benchmark: the CG tolerance of the P2 sectors against what it
costs and what it moves (:class:`solvers.root_submodel.SubmodelBody`).

    python -m studies.benchmarks.submodel [--case 1-GB] [--level 1] [--roll 0]
        [--rtols 1e-10 1e-8 1e-6 1e-5] [--out results/bench]
    python -m studies.benchmarks.submodel --thresholds 0 0.02 0 0.02 [--repeats 2] [...]

One mesh position of the case is solved once per tolerance in one process (the bodies and
the sectors are set up by the first solve and reused, so each row is the same global
solution and the same AMG hierarchies, and only the CG stopping point differs). Per
tolerance and output key (sun, pinion_sun_side, ...): CG iterations, the sector's solve
time (loads, cut values, CG, read-out), the surface root stress and the value on ISO's
line, and their change relative to the tightest tolerance. The ratios come from one run.

With ``--thresholds`` it measures GAMG's graph threshold instead (at the pipeline's
tolerance): per threshold, in the order given (repeat one to interleave them), a fresh store
solves the position once (the sectors' set-up: assembly and AMG hierarchy) and then
``--repeats`` times more (a case run's reuse: CG only). Per sector: set-up, CG time,
iterations and the values, against the first threshold's first pass. A case run of ``n``
reuses costs about set-up + n x CG per sector; the report gives the break-even ``n``.
Writes ``submodel_threshold.json`` / ``.md`` then.

Writes ``<out>/submodel_solver.json`` and ``submodel_solver.md``. Serial. Exit status 0,
2 invalid input, 3 a file could not be written. A benchmark measures; it asserts nothing.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import argparse
import gc
import sys
import time
from pathlib import Path

from mpi4py import MPI

import solvers.root_submodel as root_submodel
from cases.study_case import load_study_case
from solvers.body_store import BodyStore
from solvers.root_submodel import SubmodelBody
from studies.cli import InputError, guarded
from studies.files import atomic_write_text, write_json
from studies.position import solve_position
from studies.settings import RunSettings


def _rows(bs: dict) -> dict[str, dict]:
    """Per output key what a row reports of one position's ``bending_stress``."""
    out = {}
    for key, loc in bs["locations"].items():
        sm = loc["submodel"]
        out[key] = {
            "iterations": sm["iterations"],
            "solve_s": sm["solve_s"],
            **{k: sm[k] for k in ("cut_s", "loads_s", "krylov_s", "read_s")},
            "surface_MPa": bs[key],
            "tangent_MPa": bs["tangent"][key],
        }
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
    solve_position(study, args.roll, comm, RunSettings(level=args.level), store=store)
    setup_s = time.perf_counter() - t0
    runs = []
    for rtol in rtols:  # tightest first: the reference
        for obj in store.objects():
            if isinstance(obj, SubmodelBody):
                obj.ksp.setTolerances(rtol=rtol)
        t0 = time.perf_counter()
        out = solve_position(study, args.roll, comm, RunSettings(level=args.level), store=store)
        runs.append(
            {"rtol": rtol, "wall_s": time.perf_counter() - t0, "keys": _rows(out["bending_stress"])}
        )
    ref = runs[0]["keys"]
    for run in runs:
        for key, row in run["keys"].items():
            for q in ("surface_MPa", "tangent_MPa"):
                a, b = row[q], ref[key][q]
                row[f"{q}_change"] = None if a is None or not b else abs(a - b) / abs(b)
    data = {
        "case": args.case,
        "level": args.level,
        "roll": args.roll,
        "first_solve_s": setup_s,
        "reference_rtol": rtols[0],
        "runs": runs,
    }
    if comm.rank == 0:
        args.out.mkdir(parents=True, exist_ok=True)
        write_json(args.out / "submodel_solver.json", data)
        atomic_write_text(args.out / "submodel_solver.md", _report(data))
        print(_report(data))


def bench_thresholds(args) -> None:
    """GAMG's graph threshold of the sectors: set-up once, then CG per reuse (module doc)."""
    if any(t < -1.0 or t >= 1.0 for t in args.thresholds):
        raise InputError(f"--thresholds: give thresholds in [-1, 1), got {args.thresholds}")
    if args.repeats < 1:
        raise InputError(f"--repeats: give at least 1, got {args.repeats}")
    study = load_study_case(args.case)
    if study.numerics.root_stress != "submodel":
        raise InputError(f"--case {args.case}: numerics.root_stress must be 'submodel'")
    comm = MPI.COMM_WORLD
    default = root_submodel.SUBMODEL_GAMG_THRESHOLD
    passes = []
    try:
        for thr in args.thresholds:
            root_submodel.SUBMODEL_GAMG_THRESHOLD = thr  # read when a sector is set up
            store = BodyStore()
            solves = []
            for _ in range(1 + args.repeats):
                t0 = time.perf_counter()
                out = solve_position(
                    study, args.roll, comm, RunSettings(level=args.level), store=store
                )
                wall = time.perf_counter() - t0
                bs = out["bending_stress"]
                keys = {}
                for key, loc in bs["locations"].items():
                    sm = loc["submodel"]
                    keys[key] = {
                        **{k: sm[k] for k in ("setup_s", "set_up_here", "krylov_s", "iterations")},
                        "surface_MPa": bs[key],
                        "tangent_MPa": bs["tangent"][key],
                    }
                solves.append({"wall_s": wall, "keys": keys})
            passes.append({"threshold": thr, "solves": solves})
            del store, out
            gc.collect()  # the pass's bodies and sectors are freed before the next is built
    finally:
        root_submodel.SUBMODEL_GAMG_THRESHOLD = default
    ref = passes[0]["solves"][0]["keys"]
    for p in passes:
        for s in p["solves"]:
            for key, row in s["keys"].items():
                for q in ("surface_MPa", "tangent_MPa"):
                    a, b = row[q], ref[key][q]
                    row[f"{q}_change"] = None if a is None or not b else abs(a - b) / abs(b)
    data = {
        "case": args.case,
        "level": args.level,
        "roll": args.roll,
        "rtol": root_submodel.SUBMODEL_CG_RTOL,
        "pipeline_threshold": default,
        "repeats": args.repeats,
        "passes": passes,
    }
    if comm.rank == 0:
        args.out.mkdir(parents=True, exist_ok=True)
        write_json(args.out / "submodel_threshold.json", data)
        atomic_write_text(args.out / "submodel_threshold.md", _threshold_report(data))
        print(_threshold_report(data))


def _threshold_report(data: dict) -> str:
    """Per pass and sector: set-up, mean CG over the reuses, iterations, largest change."""
    lines = [
        f"# Submodel GAMG threshold: {data['case']}, level {data['level']}, roll "
        f"{data['roll']}, CG rtol {data['rtol']:g} (the pipeline's threshold: "
        f"{data['pipeline_threshold']:g})",
        "",
        "Per pass (a fresh store, in the order run): the sector's set-up (assembly and AMG "
        f"hierarchy, first solve), its CG time averaged over the {data['repeats']} reuse "
        "solves, CG iterations (first solve / reuses), and the largest change of its two "
        "values over the pass against the first pass's first solve.",
        "",
        "| pass | threshold | key | set-up (s) | CG per reuse (s) | iterations | change |",
        "|---|---|---|---|---|---|---|",
    ]
    totals = []
    for i, p in enumerate(data["passes"]):
        first, reuses = p["solves"][0], p["solves"][1:]
        setup = cg = 0.0
        for key, row in first["keys"].items():
            kcg = sum(s["keys"][key]["krylov_s"] for s in reuses) / len(reuses)
            its = "/".join(str(s["keys"][key]["iterations"]) for s in p["solves"])
            ch = [
                s["keys"][key][f"{q}_change"]
                for s in p["solves"]
                for q in ("surface_MPa", "tangent_MPa")
            ]
            ch = [c for c in ch if c is not None]
            setup += row["setup_s"]
            cg += kcg
            lines.append(
                f"| {i + 1} | {p['threshold']:g} | {key} | {row['setup_s']:.1f} | "
                f"{kcg:.1f} | {its} | {max(ch, default=0.0):.1e} |"
            )
        totals.append((p["threshold"], setup, cg))
    lines += [
        "",
        "| pass | threshold | sum of set-ups (s) | sum of CG per reuse (s) |",
        "|---|---|---|---|",
    ]
    for i, (thr, setup, cg) in enumerate(totals):
        lines.append(f"| {i + 1} | {thr:g} | {setup:.1f} | {cg:.1f} |")
    by = {}
    for thr, setup, cg in totals:
        by.setdefault(thr, []).append((setup, cg))
    if len(by) == 2:
        (ta, a), (tb, b) = by.items()
        sa, ca = (sum(x) / len(x) for x in zip(*a, strict=True))
        sb, cb = (sum(x) / len(x) for x in zip(*b, strict=True))
        lines.append("")
        if ca == cb:
            lines.append(f"Threshold {ta:g} against {tb:g}: the same CG time per reuse.")
        else:
            n = (sb - sa) / (ca - cb)  # set-up + n CG equal
            lines.append(
                f"Threshold {ta:g} against {tb:g} (means over their passes): set-up "
                f"{sa:.1f} / {sb:.1f} s, CG per reuse {ca:.1f} / {cb:.1f} s; a run reusing "
                f"the sectors n times costs the same at n = {n:.1f}"
                + (" (never: one is cheaper at every n)" if n < 0 else "")
                + "."
            )
    return "\n".join(lines) + "\n"


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
        prog="python -m studies.benchmarks.submodel", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--level", type=int, default=1)
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad)")
    ap.add_argument("--rtols", type=float, nargs="+", default=[1e-10, 1e-8, 1e-6, 1e-5])
    ap.add_argument(
        "--thresholds",
        type=float,
        nargs="+",
        help="measure GAMG's graph threshold instead of the tolerance",
    )
    ap.add_argument(
        "--repeats", type=int, default=2, help="with --thresholds: reuse solves after the set-up"
    )
    ap.add_argument("--out", type=Path, default=Path("results/bench"))
    args = ap.parse_args(argv)
    run = bench_thresholds if args.thresholds else bench
    return guarded(lambda: run(args), traceback=False)


if __name__ == "__main__":
    sys.exit(main())
