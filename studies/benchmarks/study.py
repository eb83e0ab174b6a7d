"""Study benchmark: what reuse of body factorizations and MPI buy, measured in one run.

    python -m studies.benchmarks.study --out results/bench [--level 1] [--cases 1-GA 1-GB ...]

Each measurement is a fresh ``python -m studies.run`` process (its own results folder, the
shared mesh cache warmed first so no run builds a mesh):

* the case-1 study in the one-branch scene (the cases x their positions) with reuse (one
  process, bodies factorized once per mesh and material) and with ``--no-reuse`` (every
  position assembles and factorizes every body): ``wall_s_reuse``, ``wall_s_no_reuse``,
  ``speedup_reuse``;
* one position of the system scene (every pinion on the elastic carrier) serial and under
  ``mpiexec -n 2``: ``system_position_wall_s_serial``, ``..._mpi2``, ``mpi2_speedup`` (the
  solve's own wall time from the position file, without interpreter start-up);
* the peak resident memory of each run (``ru_maxrss`` of that run's largest process).

Targets of issue 10: ``speedup_reuse`` >= 4 at level 1, ``mpi2_speedup`` >= 1.6 on the
system scene; the figures are written whether they are met or not. Writes ``study.json``.
A benchmark measures; it asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CASES = ("1-GA", "1-GB", "1-GC", "1-GB-R")
TARGET_REUSE = 4.0
TARGET_MPI2 = 1.6


def _run(args: list[str], ranks: int = 1) -> tuple[float, float]:
    """(wall seconds, peak RSS MB of this run's largest process) of one study run.

    ``os.wait4`` gives the rusage of this child and its waited-for descendants only (under
    mpiexec: the largest rank), not the running maximum over every earlier child.
    """
    cmd = [sys.executable, "-m", "studies.run", *args, "--quiet"]
    if ranks > 1:
        mpiexec = Path(sys.executable).with_name("mpiexec")
        cmd = [str(mpiexec), "-n", str(ranks), *cmd]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    return wall, usage.ru_maxrss / 1024.0


def _position_wall(folder: Path, case: str) -> float:
    return json.loads((folder / case / "positions" / "0.json").read_text())["timings"]["wall"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m studies.benchmarks.study", description=__doc__)
    ap.add_argument("--out", type=Path, default=Path("results/bench"))
    ap.add_argument("--level", type=int, default=1)
    ap.add_argument("--cases", nargs="+", default=list(CASES))
    ap.add_argument("--positions", type=int, default=5)
    args = ap.parse_args(argv)
    lv = ["--level", str(args.level)]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        # warm the mesh cache: one position of each scene builds every body mesh
        _run([args.cases[0], *lv, "--positions", "1", "--out", str(tmp / "warm")])
        _run(
            [
                args.cases[0],
                *lv,
                "--positions",
                "1",
                "--scene",
                "system",
                "--out",
                str(tmp / "warm-system"),
            ]
        )
        study = [*args.cases, *lv, "--positions", str(args.positions)]
        wall_reuse, mem_reuse = _run([*study, "--out", str(tmp / "reuse")])
        wall_fresh, mem_fresh = _run([*study, "--no-reuse", "--out", str(tmp / "fresh")])
        one = [args.cases[1 % len(args.cases)], *lv, "--positions", "1", "--scene", "system"]
        _, mem_sys = _run([*one, "--out", str(tmp / "sys1")])
        _, mem_sys2 = _run([*one, "--out", str(tmp / "sys2")], ranks=2)
        case = one[0]
        sys1, sys2 = _position_wall(tmp / "sys1", case), _position_wall(tmp / "sys2", case)
    out = {
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
        },
        "level": args.level,
        "cases": args.cases,
        "positions": args.positions,
        "wall_s_reuse": wall_reuse,
        "wall_s_no_reuse": wall_fresh,
        "speedup_reuse": wall_fresh / wall_reuse,
        "system_case": case,
        "system_position_wall_s_serial": sys1,
        "system_position_wall_s_mpi2": sys2,
        "mpi2_speedup": sys1 / sys2,
        "peak_rss_mb": {
            "branch_study_reuse": mem_reuse,
            "branch_study_no_reuse": mem_fresh,
            "system_serial": mem_sys,
            "system_mpi2": mem_sys2,
        },
        "targets": {
            "speedup_reuse": TARGET_REUSE,
            "speedup_reuse_met": wall_fresh / wall_reuse >= TARGET_REUSE,
            "mpi2_speedup": TARGET_MPI2,
            "mpi2_speedup_met": sys1 / sys2 >= TARGET_MPI2,
        },
        "notes": "wall_s_*: whole processes (start-up, meshes from the warm cache, solves, "
        "summaries, pictures); system_position_wall_s_*: the position's own solve wall time; "
        "peak_rss_mb: the largest process of that run (for mpi2 the largest rank)",
    }
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "study.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps({k: v for k, v in out.items() if k != "machine"}, indent=1))
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
