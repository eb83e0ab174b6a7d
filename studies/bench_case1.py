"""Case 1 benchmark: speed against error of one mesh position over mesh level and degree.

    python -m studies.bench_case1 --out results/bench [--levels 0 1 2] [--degrees 1]
        [--case 1-GB] [--roll 0] [--extra L:D ...]

Every (level, degree) runs one mesh position of the case (``studies.position
.solve_position``, serial) in a fresh subprocess, so the peak resident memory reported by the
child (``ru_maxrss`` of its own process) is that of one run. Meshes come from the shared mesh
cache (as in a case run); ``time_s.meshes_bodies`` shows whether a mesh had to be built. Per run:
DOFs, grid points, the wall time split (meshes + bodies / assembly + reduction /
factorization / gap operator + free solve / compliance / active set / final solve / total),
peak memory, My_pin, M_LOA_sun, M_LOA_ring, ZS, ZR and the peak Hertz contact stress per
mesh (``postprocess.mesh_stress.contact_stress_at_points``). The changes are taken against
the finest run that finished (highest level, then highest degree): relative for My_pin and
the LOA moments, absolute (mm) for ZS and ZR. ``root_stress`` is the FE fillet stress of the
position (:mod:`solvers.root_stress`). A run that fails (out of memory, timeout, error) is
recorded with its error and the benchmark goes on. The goal checked: My_pin and the LOA
moments within 2 % of the finest run in under 60 s per position. Writes
``case1_speed_error.json`` and ``case1_speed_error.png``. A benchmark measures; it asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from mpi4py import MPI

from cases.study_case import load_study_case
from postprocess.mesh_stress import contact_stress_at_points
from studies.position import solve_position

GOAL_REL = 0.02  # My_pin and LOA moments within 2 % of the finest run
GOAL_SECONDS = 60.0  # per position
MOMENTS = ("My_pin", "M_LOA_sun", "M_LOA_ring")
OFFSETS = ("ZS", "ZR")


def _one(case_name: str, level: int, degree: int, roll: float) -> dict:
    """Solve one position in this process; return its row (rank 0 prints it)."""
    study = load_study_case(case_name)
    comm = MPI.COMM_WORLD
    pos = solve_position(study, roll, comm, level=level, degree=degree)
    hz = contact_stress_at_points(study.gearset, study.material, pos)
    t = pos["timings"]
    setup_other = t["setup_bodies"] - t["factorize"]  # assembly, reduction, rigid-mode check
    grid = {m: int(v["grid_points"]) for m, v in pos["meshes"].items()}
    row = {
        "level": level,
        "degree": degree,
        "ranks": comm.size,
        "dofs": int(pos["dofs"]),
        "grid_points": grid,
        "grid_points_total": sum(grid.values()),
        "active_points": {m: v["active_points"] for m, v in pos["meshes"].items()},
        "compliance_columns": int(t["compliance_columns"]),
        "active_set_iterations": pos["active_set_iterations"],
        "time_s": {
            "meshes_bodies": t["scene"] + t["meshes"] + t["model"],
            "assembly_reduction": setup_other,
            "factorization": t["factorize"],
            "gap_operator_free_solve": t["gap_operator"] + t["free_solve"],
            "compliance": t["compliance"],
            "active_set": t["active_set"],
            "final_solve": t["final_solve"],
            "total": t["wall"],
        },
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "contact_stress_peak_MPa": {
            m.replace("-", "_"): float(np.max(v["p_max"])) for m, v in hz.items()
        },
        "root_stress": pos["bending_stress"],
        "resultant_mismatch_rel": pos["resultant_mismatch_rel"],
    }
    row.update({k: float(pos[k]) for k in (*MOMENTS, "Mx_pin", *OFFSETS)})
    return row


def _run_child(args, level: int, degree: int) -> dict:
    cmd = [sys.executable, "-m", "studies.bench_case1", "--one", args.case]
    cmd += [str(level), str(degree), repr(args.roll)]
    t0 = time.perf_counter()
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return {"level": level, "degree": degree, "error": f"timeout after {args.timeout} s"}
    wall = time.perf_counter() - t0
    lines = [ln for ln in res.stdout.strip().splitlines() if ln.startswith("{")]
    if res.returncode != 0 or not lines:
        sig = -res.returncode if res.returncode < 0 else None
        err = f"exit code {res.returncode}" + (f" (signal {sig}, e.g. OOM kill)" if sig else "")
        tail = res.stderr.strip().splitlines()[-5:]
        return {"level": level, "degree": degree, "error": err, "stderr_tail": tail,
                "process_wall_s": wall}  # fmt: skip
    row = json.loads(lines[-1])
    row["process_wall_s"] = wall  # includes Python and DOLFINx start-up
    return row


def _compare(rows: list[dict]) -> dict | None:
    """Changes against the finest finished run (highest level, then degree); the verdict."""
    ok = [r for r in rows if "error" not in r]
    if not ok:
        return None
    ref = max(ok, key=lambda r: (r["level"], r["degree"], r["dofs"]))
    for r in ok:
        r["is_finest"] = r is ref
        r["rel_change_vs_finest"] = {
            k: abs(r[k] / ref[k] - 1.0) if ref[k] != 0 else None for k in MOMENTS
        }
        r["abs_change_vs_finest_mm"] = {k: abs(r[k] - ref[k]) for k in OFFSETS}
        rel = r["rel_change_vs_finest"].values()
        r["meets_goal"] = (
            not r["is_finest"]
            and all(v is not None and v <= GOAL_REL for v in rel)
            and r["time_s"]["total"] < GOAL_SECONDS
        )
    meeting = sorted((r for r in ok if r["meets_goal"]), key=lambda r: r["time_s"]["total"])
    fastest = None
    if meeting:
        m = meeting[0]
        fastest = {"level": m["level"], "degree": m["degree"], "seconds": m["time_s"]["total"]}
    return {
        "what": (
            f"My_pin, M_LOA_sun and M_LOA_ring within {GOAL_REL:.0%} of the finest run, "
            f"in under {GOAL_SECONDS:.0f} s per position (time_s.total)"
        ),
        "finest": {"level": ref["level"], "degree": ref["degree"], "dofs": ref["dofs"]},
        "caveat": (
            "the finest run is itself not converged: 'within 2 % of the finest' measures "
            "the change against it, not the discretization error; the finest run cannot "
            "meet the goal against itself"
        ),
        "runs_meeting_goal": [{"level": r["level"], "degree": r["degree"]} for r in meeting],
        "fastest_meeting_goal": fastest,
        "met": bool(meeting),
    }


def _plot(rows: list[dict], path: Path, case_name: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in rows if "error" not in r]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
    marks = {"My_pin": "o", "M_LOA_sun": "s", "M_LOA_ring": "^"}
    for k, m in marks.items():
        pts = [
            (r["time_s"]["total"], r["rel_change_vs_finest"][k], f"L{r['level']}P{r['degree']}")
            for r in ok
            if not r["is_finest"] and r["rel_change_vs_finest"][k]
        ]
        if pts:
            x, y, _lab = zip(*pts, strict=True)
            a1.loglog(x, y, m, label=k)
            for xi, yi, li in pts:
                a1.annotate(li, (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7)
    a1.axhline(GOAL_REL, color="k", lw=0.8, ls="--", label=f"{GOAL_REL:.0%}")
    a1.axvline(GOAL_SECONDS, color="r", lw=0.8, ls=":", label=f"{GOAL_SECONDS:.0f} s")
    a1.set_xlabel("wall time per position (s)")
    a1.set_ylabel("|relative change vs finest run|")
    a1.set_title(f"{case_name}: moments against wall time")
    a1.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=8)
    for k, m in (("ZS", "o"), ("ZR", "s")):
        pts = sorted((r["dofs"], r[k], f"L{r['level']}P{r['degree']}") for r in ok)
        if pts:
            x, y, _lab = zip(*pts, strict=True)
            a2.semilogx(x, y, m + "-", label=k)
            for xi, yi, li in pts:
                a2.annotate(li, (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7)
    a2.set_xlabel("DOFs")
    a2.set_ylabel("load centre offset (mm)")
    a2.set_title("ZS, ZR against DOFs")
    a2.grid(True, which="both", alpha=0.3)
    a2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m studies.bench_case1")
    ap.add_argument("--out", type=Path, default=Path("results/bench"))
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--degrees", type=int, nargs="+", default=[1])
    ap.add_argument("--extra", nargs="*", default=[], metavar="L:D",
                    help="further (level, degree) runs, e.g. 0:2 3:1")  # fmt: skip
    ap.add_argument("--roll", type=float, default=0.0, help="sun roll angle (rad)")
    ap.add_argument("--timeout", type=float, default=1800.0, help="per run (s)")
    ap.add_argument("--one", nargs=4, metavar=("CASE", "L", "D", "ROLL"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        row = _one(args.one[0], int(args.one[1]), int(args.one[2]), float(args.one[3]))
        print(json.dumps(row))
        return 0

    runs = [(lv, dg) for dg in args.degrees for lv in args.levels]
    runs += [tuple(int(v) for v in e.split(":")) for e in args.extra]
    rows = []
    for level, degree in runs:
        row = _run_child(args, level, degree)
        rows.append(row)
        if "error" in row:
            print(f"L{level} P{degree}: FAILED {row['error']}", flush=True)
            continue
        t = row["time_s"]
        print(
            f"L{level} P{degree} {row['dofs']:8d} DOFs {row['grid_points_total']:5d} pts "
            f"{t['total']:7.1f} s (fact {t['factorization']:.1f}, compl {t['compliance']:.1f}) "
            f"{row['peak_rss_mb']:6.0f} MB  My_pin {row['My_pin']:.2f} "
            f"LOA {row['M_LOA_sun']:.2f} / {row['M_LOA_ring']:.2f} N m  "
            f"ZS {row['ZS']:+.3f} ZR {row['ZR']:+.3f} mm",
            flush=True,
        )
    goal = _compare(rows)
    out = {
        "case": args.case,
        "roll": args.roll,
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
        },
        "units": {"moments": "N m", "ZS_ZR": "mm", "stress": "MPa", "time": "s", "memory": "MB"},
        "notes": {
            "memory": "peak_rss_mb: ru_maxrss of the child process that ran the position",
            "time": "time_s.total = solve_position wall (meshes from the cache, bodies, solve); "
            "process_wall_s adds interpreter and library start-up",
            "root_stress": "FE fillet stress (max tensile principal of the P1/P2 cells on the "
            "loaded fillets, MPa), a mesh-dependent lower estimate",
            "contact_stress": "peak Hertz p_max over the grid points of each mesh, from the "
            "FE line load and exact curvatures; the peak sits at line ends",
        },
        "goal": goal,
        "rows": rows,
    }
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "case1_speed_error.json").write_text(json.dumps(out, indent=1))
    if goal is not None:
        _plot(rows, args.out / "case1_speed_error.png", args.case)
    print(f"wrote {args.out / 'case1_speed_error.json'}")
    if goal:
        print(f"goal met: {goal['met']} {goal['runs_meeting_goal']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
