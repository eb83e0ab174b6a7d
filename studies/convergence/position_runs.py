"""Mesh positions of a case solved in a fresh child process, one (level, degree) per child, so
the wall time and peak memory measured are those of that run alone.

:func:`solve_run` solves the positions in this process and returns the run's row: the
reported scalars of the summary these positions make (:func:`postprocess.summary.summarise`
reduced by :func:`postprocess.run_scalars.summary_scalars`: means over the positions, cycle
maxima of the stresses, exactly what ``summary.json`` would hold), DOFs, contact grid points,
the wall-time split summed over the positions (scene and meshes / bodies, of which
factorization / gap operator and free solve / compliance / active set / final solve / total),
the element sizes of the level and the peak resident memory (``ru_maxrss`` of the process).
:func:`run_child` runs it in a child (``python -m <module> --one ...``) and reads the row
back; a child that fails (out of memory, timeout, error) gives a row with its ``error``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from dataclasses import asdict, replace
from pathlib import Path

from mpi4py import MPI

from cases.study_case import CaseError, Numerics, load_study_case
from meshing import sizing
from meshing.submodel import submodel_level
from postprocess.run_scalars import summary_scalars
from postprocess.summary import cycle_bending, summarise
from solvers.body_store import BodyStore
from solvers.elastic_body import OOC_DIR_ENV, ooc_folder
from studies.memory import peak_rss_mb
from studies.position import PositionExtras, roll_angles, solve_position
from studies.settings import RunSettings

ROW_MARK = "@@row "  # the line of the child's stdout that holds its row


def _time_split(positions: list[dict]) -> dict[str, float]:
    """The wall-time split of a run, summed over its positions (s). ``bodies``: assembly,
    reduction and factorization of the bodies (the first position; later ones reuse them)
    and the contact grids; ``factorization``: the part of it spent factorizing."""

    def total(*keys):
        return float(sum(p["timings"].get(k, 0.0) for p in positions for k in keys))

    return {
        "scene_meshes": total("scene", "meshes"),
        "bodies": total("model"),
        "factorization": float(positions[0]["timings"].get("factorize", 0.0)),
        "gap_operator_free_solve": total("setup_bodies", "gap_operator", "free_solve"),
        "compliance": total("compliance"),
        "active_set": total("active_set"),
        "final_solve": total("final_solve"),
        "total": total("wall"),
    }


#: the summary's root-stress groups a submodel ladder run keeps per read fillet size
FILLET_SCALARS = (
    "bending_stress",
    "bending_stress_tangent",
    "bending_stress_recovered",
    "bending_stress_tangent_recovered",
)


def fillet_scalars(solved: list[dict]) -> dict[str, dict[str, float]]:
    """Per submodel fillet size of the positions' ``bending_stress_fillets``
    (:func:`studies.position.solve_position`), the root-stress scalars as a summary holds
    them (``bending_stress.<key>``, ``bending_stress_tangent.<key>`` and their recovered
    counterparts: maxima over the positions, :func:`postprocess.summary.cycle_bending`)."""
    sizes = sorted({f for p in solved for f in (p.get("bending_stress_fillets") or {})}, key=float)
    out = {}
    for f in sizes:
        recs = [
            {"position": i, "bending_stress": (p.get("bending_stress_fillets") or {}).get(f)}
            for i, p in enumerate(solved)
        ]
        cyc = cycle_bending(recs)
        out[f] = {
            f"{name}.{k}": float(v)
            for name in FILLET_SCALARS
            for k, v in (cyc.get(name) or {}).items()
            if v is not None
        }
    return out


def solve_run(
    case: str,
    level: int,
    degree: int,
    positions: int,
    numerics: dict | None = None,
    submodel_levels: tuple[int, ...] = (),
    flank_level: int | None = None,
    fillet_level: int | None = None,
    store: BodyStore | None = None,
) -> dict:
    """Solve ``positions`` equally spaced mesh positions of ``case`` (serial, bodies reused
    across them) at ``level``/``degree``; the run's row (see the module docstring).
    ``numerics``: fields of the case's ``[numerics]`` replaced for this run (validated as in
    a case file); ``submodel_levels``: the root stress read also on the submodels of these
    levels at the same global solutions, in the row's ``fillet_scalars`` keyed by their fillet
    (:func:`fillet_scalars`; timed apart, not in the run's time); ``flank_level``: the
    active flanks and contact grid at that level's size, ``fillet_level``: the named fine
    fillets at that level's (:func:`meshing.sizing.with_sizes`; the row keeps them, an
    off-ladder run); ``store``: where the bodies and sectors are kept (default: a new store
    that reuses them only over several positions)."""
    study = load_study_case(case)
    if numerics:
        try:
            num = Numerics(**{**asdict(study.numerics), **numerics})
        except TypeError as exc:  # an unknown field
            raise CaseError(f"numerics: {exc}") from exc
        study = replace(study, numerics=num)
    comm = MPI.COMM_WORLD
    # one position has nothing to reuse: without reuse each root-stress submodel is freed
    # after its solve instead of all being held beside the global factors (level 2: 22.5 GB)
    store = BodyStore(reuse=positions > 1) if store is None else store
    t0 = time.perf_counter()

    def progress(stage: str) -> None:  # the child's log (runs/<run>.log): where time goes
        if comm.rank == 0:
            t, gb = time.perf_counter() - t0, peak_rss_mb() / 1024
            print(f"{t:8.1f} s  {stage} (peak {gb:.1f} GB)", file=sys.stderr, flush=True)

    solved = [
        solve_position(
            study,
            roll,
            comm,
            RunSettings(
                level=level, degree=degree, flank_level=flank_level, fillet_level=fillet_level
            ),
            store=store,
            progress=progress,
            extras=PositionExtras(submodel_levels=tuple(submodel_levels), sector_log=progress),
        )
        for roll in roll_angles(study, positions)
    ]
    summary = summarise(study, solved, [], {"level": level, "degree": degree})
    # the peak before the submodel ladder's extra readings (an upper bound of the run's own
    # over several positions: a later position's peak follows an earlier ladder)
    before = [p["timings"].get("peak_rss_mb_before_ladder") for p in solved]
    peak = max(before) if all(v is not None for v in before) else peak_rss_mb()
    other = {"flank_level": flank_level, "fillet_level": fillet_level}
    other = {k: v for k, v in other.items() if v is not None}
    lv = sizing.with_sizes(level, **other)
    # the fillets the root stress is read on: the submodel's, or the global model's
    sub = study.numerics.root_stress == "submodel"
    read_fillet = submodel_level(level).fillet if sub else lv.fillet
    grid = {m: int(v["grid_points"]) for m, v in solved[0]["meshes"].items()}
    return {
        "level": level,
        "degree": degree,
        **other,
        "positions": positions,
        "rolls": [p["roll"] for p in solved],
        "dofs": int(solved[0]["dofs"]),
        "h_mm": {"fine": lv.fine, "fillet": read_fillet, "global_fillet": lv.fillet},
        "grid_points": grid,
        "grid_points_total": sum(grid.values()),
        "compliance_columns": int(sum(p["timings"].get("compliance_columns", 0) for p in solved)),
        "time_s": _time_split(solved),
        "peak_rss_mb": peak,
        "peak_rss_with_ladder_mb": peak_rss_mb(),
        "numerics": asdict(study.numerics),
        "scalars": summary_scalars(summary, study.gearset.kind),
        "fillet_scalars": fillet_scalars(solved),
        "fillet_ladder_s": float(sum(p["timings"].get("fillet_ladder", 0.0) for p in solved)),
    }


def run_child(
    module: str, args: list[str], level: int, degree: int, timeout: float, log: Path | None = None
) -> dict:
    """``python -m <module> <args>`` in a child process; its row (the last ``@@row`` line of
    its stdout) with ``process_wall_s`` (including interpreter and library start-up), or a
    row with ``error`` (exit code, signal, the tail of stderr). The child's out-of-core
    factor files (``numerics.out_of_core``) go to a folder of its own under
    ``$PLANETARY_OOC_DIR`` (or the temporary folder), removed when it ends, however it ends:
    a child killed out of memory or by the timeout leaves no factor files behind (tens of GB
    at level 2). ``log``: the child's stderr goes to this file as it runs (its progress, e.g.
    a line per submodel), not to memory."""
    cmd = [sys.executable, "-m", module, *args]
    ooc = ooc_folder("ooc-run-")
    env = {**os.environ, OOC_DIR_ENV: ooc}
    t0 = time.perf_counter()
    err = subprocess.PIPE if log is None else open(log, "w")
    try:
        res = subprocess.run(
            cmd, stdout=subprocess.PIPE, stderr=err, text=True, timeout=timeout, env=env
        )
    except subprocess.TimeoutExpired:
        return {"level": level, "degree": degree, "error": f"timeout after {timeout:.0f} s"}
    finally:
        shutil.rmtree(ooc, ignore_errors=True)
        if log is not None:
            err.close()
    stderr = res.stderr if log is None else Path(log).read_text(errors="replace")
    wall = time.perf_counter() - t0
    rows = [ln[len(ROW_MARK) :] for ln in res.stdout.splitlines() if ln.startswith(ROW_MARK)]
    if res.returncode != 0 or not rows:
        sig = -res.returncode if res.returncode < 0 else None
        err = f"exit code {res.returncode}" + (
            f" (signal {sig}, e.g. killed out of memory)" if sig else ""
        )
        return {
            "level": level,
            "degree": degree,
            "error": err,
            "stderr_tail": stderr.strip().splitlines()[-5:],
            "process_wall_s": wall,
        }
    row = json.loads(rows[-1])
    row["process_wall_s"] = wall
    return row


def print_row(row: dict) -> None:
    """What a child prints for :func:`run_child` to read."""
    print(ROW_MARK + json.dumps(row), flush=True)
