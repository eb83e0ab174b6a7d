"""Linear solver benchmark (issue 13 item 5): the bodies' exact MUMPS LU against block
low-rank MUMPS, CG/GAMG and the LU out of core (``[numerics] linear_solver`` and
``out_of_core``, :mod:`solvers.elastic_body`).

    python -m studies.benchmarks.linear [--case 1-GB] [--levels 1 2] [--iterative-max-level 1]
        [--solvers mumps mumps-blr cg-gamg mumps+ooc] [--tolerances mumps-blr:1e-6 ...]
        [--out results/bench]

A solver ``<kind>+ooc`` is the LU ``<kind>`` with its factors on disk.

Per level and solver, one mesh position of the case solved in a fresh child process
(:func:`studies.convergence.position_runs.run_child`, the runs of
:mod:`studies.convergence.driver`), so the peak memory is that run's alone. Reported: DOFs,
factorization (set-up) time, compliance time, total, peak memory, and the change of every moment
and stress against the exact LU of the same level (relative; the effect of the solver's tolerance
on the results). The exact LU is run first at each level; the ratios come from runs of one
invocation.

Writes ``<out>/linear_solver.json`` and ``linear_solver.md``. Exit status 0 (runs may have
failed: see the report), 2 invalid input, 3 a file could not be written.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from cases.study_case import LINEAR_SOLVERS, Numerics, load_study_case
from meshing import sizing
from postprocess.run_scalars import scalar_kind
from solvers.elastic_body import DEFAULT_TOLERANCE
from studies.cli import InputError, guarded
from studies.convergence.position_runs import print_row, run_child, solve_run
from studies.files import atomic_write_text, write_json

#: the solvers a run can be asked for: every linear solver, and the LU ones out of core
SOLVERS = (*LINEAR_SOLVERS, "mumps+ooc", "mumps-blr+ooc")
OOC = "+ooc"

NOISE = 1e-6


def _moments(scalars: dict) -> list[str]:
    """The moment keys of a run's scalars (any gear set kind: My_pin, My_SP, M_LOA_...)."""
    return [k for k in scalars if scalar_kind(k) == "moment"]


def _solver_numerics(solver: str, tolerances: dict[str, float]) -> dict:
    kind = solver.removesuffix(OOC)
    return {
        "linear_solver": kind,
        "linear_tolerance": tolerances.get(kind),
        "out_of_core": solver.endswith(OOC),
    }


def _tolerance(solver: str, given: float | None) -> float | None:
    """The tolerance a run used: the given one, else the solver's default."""
    return given if given is not None else DEFAULT_TOLERANCE[solver.removesuffix(OOC)]


def _changes(row: dict, ref: dict) -> dict[str, float]:
    """Relative change of every scalar of ``row`` against ``ref`` (same level, exact LU).
    Scalars that are zero by construction (the pinion's spin moment Mz_pin: spin free) sit at
    round-off, below NOISE x the largest moment, and are left out."""
    num = {k: v for k, v in ref["scalars"].items() if isinstance(v, (int, float))}
    floor = NOISE * max((abs(num[k]) for k in _moments(num)), default=0.0)
    out = {}
    for k, v in num.items():
        w = row["scalars"].get(k)
        if isinstance(w, (int, float)) and abs(v) > floor:
            out[k] = (w - v) / abs(v)
    return out


def _md(case: str, rows: list[dict]) -> str:
    lines = [
        f"# Linear solvers of the bodies: {case}, one mesh position",
        "",
        "Each run is one child process (its own peak memory). Change: relative to the exact "
        "MUMPS LU of the same level in this run; max |change| over every moment "
        "(pinion and LOA moments) and over every reported scalar (stresses included; "
        "the spin moments Mz, zero by construction, left out). Tolerance: the BLR dropping "
        "threshold (MUMPS CNTL(7)) or the CG relative residual. `+ooc`: the factors on disk "
        "(MUMPS ICNTL(22)).",
        "",
        "| level | solver | tolerance | DOFs | factorization (s) | compliance (s) "
        "| total (s) | peak memory (GB) | max moment change | max scalar change |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        head = f"| {r['level']} | {r['solver']} | {r['tolerance'] or '-'} |"
        if "error" in r:
            lines.append(f"{head} {r['error']} | | | | | | |")
            continue
        t = r["time_s"]
        ch = r.get("change") or {}
        mom = [abs(ch[k]) for k in _moments(ch)]
        allc = [abs(v) for v in ch.values()]
        lines.append(
            f"{head} {r['dofs']} | {t['factorization']:.1f} | {t['compliance']:.1f} | "
            f"{t['total']:.1f} | {r['peak_rss_mb'] / 1024:.2f} | "
            + (f"{max(mom, default=0.0):.1e} | {max(allc):.1e} |" if ch else "(reference) | |")
        )
    return "\n".join(lines) + "\n"


def bench(args) -> Path:
    study = load_study_case(args.case)  # validated before any run
    for lv in args.levels:
        sizing.check_level(lv)
    tolerances = {}
    for item in args.tolerances:
        kind, _, val = item.partition(":")
        try:
            tolerances[kind] = float(val)
        except ValueError:
            raise InputError(
                f"--tolerances {item!r}: give SOLVER:VALUE, e.g. mumps-blr:1e-6"
            ) from None
    for s in args.solvers:
        Numerics(**_solver_numerics(s, tolerances))  # CaseError names the field
    solvers = ["mumps"] + [s for s in args.solvers if s != "mumps"]
    rows = []
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for level in args.levels:
        ref = None
        for s in solvers:
            num = _solver_numerics(s, tolerances)
            if s == "cg-gamg" and level > args.iterative_max_level:
                rows.append(
                    {
                        "level": level,
                        "solver": s,
                        "tolerance": _tolerance(s, None),
                        "error": f"not run: level > --iterative-max-level "
                        f"{args.iterative_max_level} (every column an iterative "
                        "solve, 8-30x the LU's time)",
                    }
                )
                continue
            print(f"level {level}, {s} ...", flush=True)
            cli = ["--one", args.case, str(level), json.dumps(num)]
            row = run_child("studies.benchmarks.linear", cli, level, 1, args.timeout)
            row.update(solver=s, tolerance=_tolerance(s, num["linear_tolerance"]))
            if "error" in row:
                row["error"] = f"failed: {row['error']}"
            else:
                if s == "mumps":
                    ref = row
                elif ref is not None:
                    row["change"] = _changes(row, ref)
            rows.append(row)
            write_json(out / "linear_solver.json", {"case": study.name, "runs": rows})
    atomic_write_text(out / "linear_solver.md", _md(study.name, rows))
    print(f"wrote {out / 'linear_solver.md'}")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.benchmarks.linear", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--levels", type=int, nargs="+", default=[1])
    ap.add_argument("--solvers", nargs="+", default=[*LINEAR_SOLVERS, "mumps+ooc"], choices=SOLVERS)
    ap.add_argument("--tolerances", nargs="*", default=[], metavar="SOLVER:VALUE")
    ap.add_argument("--out", type=Path, default=Path("results/bench"))
    ap.add_argument("--timeout", type=float, default=3600.0, help="per run (s)")
    ap.add_argument(
        "--iterative-max-level", type=int, default=1, help="run cg-gamg up to this level"
    )
    ap.add_argument("--one", nargs=3, metavar=("CASE", "L", "NUMERICS"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        case, level, num = args.one
        return guarded(
            lambda: print_row(solve_run(case, int(level), 1, 1, json.loads(num))), traceback=True
        )
    return guarded(lambda: bench(args), traceback=False)


if __name__ == "__main__":
    sys.exit(main())
