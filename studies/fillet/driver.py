"""Fillet-only refinement of the FE root stress: the flank and body sizes of one level held,
the fillet size of the active teeth refined (:func:`meshing.sizing.with_fillet`).

    python -m studies.fillet 1-GB [--level 1] [--fillets 0.45 0.35 0.3 0.25]
        [--p2 0.3 ...] [--roll 0] [--loaded-only] [--out results/fillet] [--timeout 3600]

The scenes refine the tension fillets of the teeth loaded anywhere in the mesh cycle
(``GearBody.fine_fillets``, :func:`meshing.scenes.tension_fillets`; the other fillets of the
active teeth get ``fillet_far``); ``--loaded-only`` narrows them to the teeth loaded at that
position (:func:`loaded_fillets_only`). Case 1 at level 1 peaks at 6.7 GB with the cycle's
fillets at 0.15 mm and 8.7 GB at 0.12 mm (meshing/sizing.py docstring): run finer sizes
under the heavy-job lock, or not at all.

Every (fillet size, degree) run solves one mesh position (sun angle ``--roll``, rad) in a
fresh child process (:func:`studies.convergence.position_runs.run_child`), so its wall time and peak
memory are its own, and records the DOFs, the wall-time split, the peak resident memory and
the root stresses (:func:`solvers.root_stress.root_stress`: surface maximum, ISO tangent
line, largest fillet cell). The table and the Richardson extrapolation over the three
finest P1 runs are :mod:`studies.fillet.report`. Meshes go to the cache folder of
``PLANETARY_CACHE`` (set it to keep experimental meshes apart). Writes
``<out>/<case>/fillet_L<level>.json`` and ``.md``.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
from mpi4py import MPI

from cases.study_case import load_study_case
from meshing import sizing
from meshing.scene_bodies import load_body_meshes
from meshing.scenes import build_scene, tension_fillets
from solvers.body_store import BodyStore
from solvers.gear_train import build_gear_train
from solvers.root_stress import root_stress
from studies.cli import InputError, guarded
from studies.convergence.position_runs import print_row, run_child
from studies.files import write_json
from studies.fillet.report import fillet_table
from studies.memory import peak_rss_mb
from studies.position import train_inputs


def loaded_fillets_only(scene):
    """``scene`` with every gear body's fine fillets limited to the fillets under the loaded
    flanks of this position (the driver and driven tooth of every contact line of every
    zone, on the zone's drive sides: the tension fillets the root stress is read on), where
    the scene names those of the whole mesh cycle (:func:`meshing.scenes.tension_fillets`)."""
    fine = tension_fillets(scene.zones)
    gears = tuple(
        replace(g, body=replace(g.body, fine_fillets=tuple(sorted(fine.get(g.name, ())))))
        for g in scene.gears
    )
    return replace(scene, gears=gears)


def solve_one(
    case: str, level: int, fillet: float, degree: int, roll: float, loaded_only: bool = False
) -> dict:
    """One position of ``case`` at ``level`` with fillet size ``fillet`` (serial): the steps
    of :func:`studies.position.solve_position` up to the root stress (moments and contact
    stresses are not needed here), each timed."""
    study = load_study_case(case)
    lv = sizing.with_fillet(level, fillet)
    comm = MPI.COMM_SELF
    t0 = time.perf_counter()
    scene = build_scene(study.model.scene, study.gearset, roll)
    if loaded_only:
        scene = loaded_fillets_only(scene)
    meshes = load_body_meshes(scene, lv, comm, {})
    t_mesh = time.perf_counter()
    model = build_gear_train(
        scene,
        meshes,
        train_inputs(study),
        degree=degree,
        spacing=lv.fine,
        penalty_factor=study.numerics.penalty_factor,
        store=BodyStore(),
    )
    result = model.problem.solve()
    t_solve = time.perf_counter()
    bs = root_stress(model, result)
    t_post = time.perf_counter() - t_solve
    keys = list(bs["locations"])
    row = {
        "level": level,
        "fillet_mm": fillet,
        "degree": degree,
        "roll": roll,
        "loaded_only": loaded_only,
        "fine_fillets": {g.name: len(g.body.fine_fillets or ()) for g in scene.gears},
        "sizes": vars(lv),
        "dofs": int(model.dofs),
        "elements": {n: int(m.bundle.meta.get("elements", 0)) for n, m in meshes.items()},
        "time_s": {
            "meshes": t_mesh - t0,
            "factorization": float({**model.timings, **result.timings}.get("factorize", 0.0)),
            "solve": t_solve - t_mesh,
            "root_stress": t_post,
            "total": t_solve - t0 + t_post,
        },
        "surface": {k: bs[k] for k in keys},
        "tangent": bs["tangent"],
        "cell_max": bs["cell_max"],
        "fillet_h_mm": {k: bs["locations"][k]["fillet_h_mm"] for k in keys},
        "surface_points": {k: bs["locations"][k]["surface_points"] for k in keys},
        "at": {
            k: {
                q: bs["locations"][k][q]
                for q in ("tooth", "side", "z_mm", "radius_mm", "tangent_z_mm")
            }
            for k in keys
        },
    }
    row["peak_rss_mb"] = peak_rss_mb()
    return row


def study(args) -> Path:
    load_study_case(args.case)  # a bad case name fails here, before any child
    try:
        sizing.check_level(args.level)
        for h in (*args.fillets, *args.p2):
            sizing.with_fillet(args.level, h)
    except sizing.MeshingError as exc:
        raise InputError(f"--level/--fillets/--p2: {exc}") from exc
    runs = [(h, 1) for h in args.fillets] + [(h, 2) for h in args.p2]
    folder = args.out / args.case
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    tag = "_loaded" if args.loaded_only else ""
    for h, deg in runs:
        child = [
            "--one",
            args.case,
            str(args.level),
            repr(h),
            str(deg),
            repr(args.roll),
            str(int(args.loaded_only)),
        ]
        row = run_child("studies.fillet.driver", child, args.level, deg, args.timeout)
        row.setdefault("fillet_mm", h)
        rows.append(row)
        print(
            f"fillet {h:g} mm P{deg}: "
            + (
                row.get("error")
                or (
                    f"{row['dofs']} DOFs, {row['time_s']['total']:.1f} s, "
                    f"{row['peak_rss_mb'] / 1024:.2f} GB, surface {row['surface']}"
                )
            ),
            flush=True,
        )
        write_json(folder / f"fillet_L{args.level}{tag}.json", {"case": args.case, "runs": rows})
    text = fillet_table(args.case, args.level, rows)
    md = folder / f"fillet_L{args.level}{tag}.md"
    md.write_text(text)
    print(text)
    return md


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.fillet", description=__doc__.splitlines()[0]
    )
    ap.add_argument("case", nargs="?", help="case name (cases/<name>.toml) or case file path")
    ap.add_argument("--level", type=int, default=1, help="flank and body sizes of this level")
    ap.add_argument(
        "--fillets",
        type=float,
        nargs="+",
        default=[0.45, 0.35, 0.3, 0.25],
        help="fillet sizes (mm) of the P1 runs",
    )
    ap.add_argument("--p2", type=float, nargs="*", default=[], help="fillet sizes of P2 runs")
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad)")
    ap.add_argument("--out", type=Path, default=Path("results/fillet"))
    ap.add_argument("--timeout", type=float, default=3600.0, help="per run (s)")
    ap.add_argument(
        "--loaded-only",
        action="store_true",
        help="refine only the tension fillets of the teeth loaded at --roll (default: the "
        "mesh cycle's, as the scenes)",
    )
    ap.add_argument("--one", nargs=6, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        case, level, h, deg, roll, loaded = args.one
        return guarded(
            lambda: print_row(
                solve_one(case, int(level), float(h), int(deg), float(roll), bool(int(loaded)))
            ),
            traceback=True,
        )
    if not args.case:
        ap.error("give the case: python -m studies.fillet 1-GB")
    return guarded(lambda: study(args), traceback=False)


if __name__ == "__main__":
    sys.exit(main())
