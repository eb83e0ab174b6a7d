"""Benchmark of the contact solver: time against error, and the cost of contact over one solve.

    .venv/bin/python -m studies.benchmarks.solver [--out results/bench] [--levels ...]
    .venv/bin/mpiexec -n 2 .venv/bin/python -m studies.benchmarks.solver

For each mesh level of the 2D Hertz scene and the 3D roller scene (solvers.verification):
DOFs, grid points, compliance columns formed, and the times of the factorization, one
solve, the compliance columns (MUMPS multi-RHS solves with the one factorization), the
active-set loop and the final solve. The headline number is

    ratio = (contact solve) / (one factorization + one solve)

with contact solve = factorization + gap operator + no-contact solve + compliance +
active set + final solve (assembly excluded on both sides). Errors against Hertz (2D: a,
p_max, approach nonlinearity; 3D: a and p_max at mid-length, where the finite roller is
closest to plane strain) give time against error. Writes ``solver.json`` and ``solver.md``.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import numpy as np
from mpi4py import MPI

from gears.contact_stress import hertz_line_contact
from solvers.verification import hertz_measures, hertz_reference, hertz_scene, roller_scene


def _timed_solves(problem) -> dict[str, float]:
    """Factorization and one-solve times summed over the bodies (the baseline)."""
    one = 0.0
    for b in problem.bodies.values():
        problem.comm.Barrier()
        t0 = MPI.Wtime()
        b.solve(b.f_red)
        one += MPI.Wtime() - t0
    fact = sum(b.timings["factorize"] for b in problem.bodies.values())
    return {"factorize": fact, "one_solve": one}


def _row(problem, res, extra) -> dict:
    t = dict(res.timings)
    base = _timed_solves(problem)
    contact = (
        base["factorize"]
        + t["gap_operator"]
        + t["free_solve"]
        + t["compliance"]
        + t["active_set"]
        + t["final_solve"]
    )
    row = {
        "dofs": int(sum(b.K_red.getSize()[0] for b in problem.bodies.values())),
        "points": int(problem.n),
        "columns": int(t["compliance_columns"]),
        "active": int(res.active.sum()),
        "iterations": int(t["iterations"]),
        "factorize_s": base["factorize"],
        "one_solve_s": base["one_solve"],
        "compliance_s": t["compliance"],
        "active_set_s": t["active_set"],
        "final_solve_s": t["final_solve"],
        "contact_solve_s": contact,
        "ratio": contact / (base["factorize"] + base["one_solve"]),
    }
    row.update(extra)
    return row


def bench_hertz(comm, levels) -> list[dict]:
    rows = []
    for h in levels:
        problem, info = hertz_scene(comm, h_min=h, degree=2)
        r1 = problem.solve()
        r2 = problem.solve(loads={"approach": -2 * info["P"]})
        m1, m2 = hertz_measures(problem, r1, info), hertz_measures(problem, r2, info)
        ref = hertz_reference(info)
        extra = {
            "case": "hertz2d",
            "h": h,
            "err_a": m1["a"] / ref["a"] - 1,
            "err_pmax": m1["p_max"] / ref["p0"] - 1,
            "err_nonlinearity": (m2["approach"] - 2 * m1["approach"]) / ref["nonlinearity"] - 1,
        }
        rows.append(_row(problem, r1, extra))
    return rows


def bench_roller(comm, levels, degree=2, spacing_ratio=1.0) -> list[dict]:
    rows = []
    for h in levels:
        problem, info = roller_scene(comm, h_min=h, degree=degree, spacing=spacing_ratio * h)
        res = problem.solve()
        s, x, z = info["spacing"], info["x"], info["z"]
        mid = np.abs(z - z[np.argmin(np.abs(z))]) < 1e-9  # the station nearest mid-length
        F = res.forces[mid]
        a, p0 = hertz_line_contact(info["q"], info["R"], info["e_star"])
        ref = {"a": float(a), "p0": float(p0)}
        extra = {
            "case": f"roller3d_P{degree}" + ("" if spacing_ratio == 1.0 else "_fine_grid"),
            "h": h,
            "spacing": spacing_ratio * h,
            "err_a": 2 * math.sqrt(float((F * x[mid] ** 2).sum() / F.sum())) / ref["a"] - 1,
            "err_pmax": float((F / problem.weights[mid]).max()) / ref["p0"] - 1,
            "mid_line_load": float(F.sum() / s),
        }
        rows.append(_row(problem, res, extra))
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(
        prog="python -m studies.benchmarks.solver", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--out", default="results/bench")
    ap.add_argument("--hertz", type=float, nargs="*", default=[1.0, 0.5, 0.25])
    ap.add_argument("--roller", type=float, nargs="*", default=[1.0, 0.7, 0.5])
    ap.add_argument(
        "--roller-fine-grid",
        type=float,
        nargs="*",
        default=[0.5],
        help="roller levels rerun with grid spacing h/2 (4x the grid points)",
    )
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    rows = bench_hertz(comm, args.hertz) + bench_roller(comm, args.roller)
    rows += bench_roller(comm, args.roller_fine_grid, spacing_ratio=0.5)
    if comm.rank == 0:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        meta = {"ranks": comm.size, "rows": rows}
        (out / "solver.json").write_text(json.dumps(meta, indent=1))
        cols = [
            "case",
            "h",
            "dofs",
            "points",
            "columns",
            "iterations",
            "factorize_s",
            "one_solve_s",
            "compliance_s",
            "active_set_s",
            "contact_solve_s",
            "ratio",
            "err_a",
            "err_pmax",
        ]
        lines = [
            f"# contact solver benchmark ({comm.size} rank(s))",
            "",
            "| " + " | ".join(cols) + " |",
            "|" + "---|" * len(cols),
        ]
        for r in rows:
            cells = []
            for c in cols:
                v = r.get(c, "")
                if isinstance(v, float):
                    v = f"{v:+.2%}" if c.startswith("err") else f"{v:.3g}"
                cells.append(str(v))
            lines.append("| " + " | ".join(cells) + " |")
        (out / "solver.md").write_text("\n".join(lines) + "\n")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
