"""One study driver for any case file: mesh positions -> summary, contact patterns, pictures.

    python -m studies.run 1-GA [1-GB ...] [--level L] [--positions N] [--out results]
    python -m studies.run path/to/my_case.toml
    mpiexec -n 2 python -m studies.run 1-GA

A case is a study-case file (``cases/<name>.toml`` or any path): a gear set, the pinion
bearing, the material, the scene (``model.scene``) and the numerical settings. It is solved
at N mesh positions over one base pitch of the sun: sun angles k (2 pi / Z_sun) / N, k = 0..
N-1, with the carrier fixed (:func:`studies.position.solve_position`). Each position is
written to ``<out>/<case>/positions/<k>.json`` as soon as it is solved, and reused by a later
run only if it was solved from the same inputs (hash of the resolved case and gear set), the
same settings and the same code (:mod:`studies.provenance`); the run says which positions it
reused and which it computed. A study that fails part way keeps what it finished. The
displacement of every body at the first position is written as VTX to
``<out>/<case>/fields/<body>.bp`` (ParaView). ``summary.json`` (:mod:`postprocess.summary`)
holds the means over the positions, the per-position values, the closed-form reference, the
contact and root stresses, and the inputs and provenance that produced them.

Exit status: 0 all cases finished, 1 a case failed while solving (finished positions kept),
2 a case file is invalid (the message names the file and the field).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import traceback
from pathlib import Path

from mpi4py import MPI

from cases.gearset import CaseError
from cases.study_case import StudyCase, inputs_hash, load_study_case, study_inputs
from meshing.scenes import build_scene
from postprocess.contact_pattern import draw_contact_patterns
from postprocess.loaded_scene import loaded_scene_picture
from postprocess.summary import summarise
from studies.files import ResultFileError, on_root, read_json, write_json
from studies.position import solve_position
from studies.provenance import code_hash, provenance


def roll_angles(study: StudyCase, positions: int) -> list[float]:
    """Sun angles (rad) of ``positions`` equally spaced mesh positions over one base pitch."""
    z_sun = study.gearset.gears[study.gearset.power_path[0]].teeth
    return [2.0 * math.pi / z_sun * k / positions for k in range(positions)]


def reuse_key(study: StudyCase, level: int, degree: int, roll: float) -> dict:
    """What a finished position must match to be reused."""
    return {"inputs_hash": inputs_hash(study), "code_hash": code_hash(), "level": level,
            "degree": degree, "roll": roll}  # fmt: skip


def _finished(path: Path, key: dict) -> dict | None:
    """The position in ``path`` if it was solved with ``key``; None if absent or stale. An
    unreadable file is reported and solved again."""
    if not path.is_file():
        return None
    try:
        old = read_json(path)
    except ResultFileError as exc:
        print(f"warning: {exc}; solving the position again", file=sys.stderr)
        return None
    return old if old.get("reuse_key") == key else None


def run_study(
    name_or_path: str | Path,
    out_root: Path = Path("results"),
    level: int | None = None,
    positions: int | None = None,
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> dict:
    """Solve every position (reusing finished ones), then write summary.json and the pictures.
    Returns the summary (on every rank). Raises after writing what finished if a position
    failed."""
    study = load_study_case(name_or_path)
    level = study.model.level if level is None else level
    n_pos = study.model.positions if positions is None else positions
    if isinstance(n_pos, bool) or not isinstance(n_pos, int) or n_pos < 1:
        raise CaseError(f"{study.name}: positions = {n_pos!r}: must be an integer >= 1")
    degree = study.numerics.degree
    out = out_root / study.name
    pos_dir = out / "positions"
    on_root(comm, lambda: pos_dir.mkdir(parents=True, exist_ok=True), f"creating {pos_dir}")
    t0 = time.perf_counter()
    solved, failed, reused = [], [], []
    for k, roll in enumerate(roll_angles(study, n_pos)):
        path = pos_dir / f"{k}.json"
        key = reuse_key(study, level, degree, roll)
        pos = on_root(comm, lambda path=path, key=key: _finished(path, key), f"reading {path}")
        if pos is not None:
            pos["reused"] = True
            reused.append(k)
        else:
            try:
                vtx = out / "fields" if k == 0 else None  # displacement fields: first position
                pos = solve_position(study, roll, comm, level=level, vtx_dir=vtx)
            except Exception as exc:  # keep going: finished positions stay on disk
                failed.append({"position": k, "roll": roll, "error": repr(exc)})
                if comm.rank == 0:
                    traceback.print_exc()
                continue
            pos["reuse_key"] = key
            on_root(comm, lambda path=path, pos=pos: write_json(path, pos), f"writing {path}")
        solved.append(pos)
        if comm.rank == 0:
            what = "reused" if pos.get("reused") else f"{pos['timings']['wall']:.1f} s"
            print(f"{study.name}: position {k + 1}/{n_pos} (roll {roll:.5f} rad) "
                  f"{_headline(study, pos)}, {what}", flush=True)  # fmt: skip
    meta = {
        "level": level,
        "degree": degree,
        "scene": study.model.scene,
        "inputs": study_inputs(study),
        "inputs_hash": inputs_hash(study),
        "provenance": provenance(),
        "ranks": comm.size,
        "positions_reused": reused,
        "wall_time_s": time.perf_counter() - t0,
    }
    summary = summarise(study, solved, failed, meta)
    on_root(comm, lambda: _write_outputs(study, solved, summary, out, level),
            f"writing the results of {study.name} to {out}")  # fmt: skip
    if failed:
        raise RuntimeError(f"{study.name}: {len(failed)} of {n_pos} positions failed: {failed}")
    return summary


def _headline(study: StudyCase, pos: dict) -> str:
    if study.gearset.kind == "single_pinion":
        return f"My_pin {pos['My_pin']:.2f} N m, ZS {pos['ZS']:+.2f}, ZR {pos['ZR']:+.2f} mm"
    return (f"My_SP {pos['My_SP']:.2f}, My_RP {pos['My_RP']:.2f} N m, "
            f"ZS {pos['ZS']:+.2f}, ZR {pos['ZR']:+.2f} mm")  # fmt: skip


def _write_outputs(study: StudyCase, solved: list[dict], summary: dict, out: Path, level: int):
    write_json(out / "summary.json", summary)
    if solved:
        draw_contact_patterns(study, solved, out)
        first = solved[0]
        scene = build_scene(study.model.scene, study.gearset, first["roll"])
        title = f"{study.name}: loaded scene, roll {first['roll']:.4f} rad"
        loaded_scene_picture(scene, first, level, out / "loaded_scene.png", title)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m studies.run", description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="+", help="case names (cases/<name>.toml) or case file paths")
    ap.add_argument("--level", type=int, default=None, help="mesh level (default: the case's)")
    ap.add_argument("--positions", type=int, default=None, help="positions per base pitch")
    ap.add_argument("--out", type=Path, default=Path("results"))
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    status = 0
    for name in args.cases:  # a failed case does not stop the others
        try:
            run_study(name, args.out, args.level, args.positions, comm)
        except CaseError as exc:
            if comm.rank == 0:
                print(f"error: {exc}", file=sys.stderr)
            status = max(status, 2)
        except Exception as exc:
            if comm.rank == 0:
                print(f"error: {exc}", file=sys.stderr)
            status = max(status, 1)
    return status


if __name__ == "__main__":
    sys.exit(main())
