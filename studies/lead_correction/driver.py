"""``python -m studies.lead_correction --case 1-GB [--level L] [--positions N] [--out DIR]``:
the lead slopes of the pinion and the sun that re-centre the contact patterns of a
single-pinion case under its bearing stiffness and torque (|ZS|, |ZR| <= ``--tol``), and the
contact and root stresses before and after (:mod:`studies.lead_correction.report`).

Every evaluation solves the case's scene at its mesh positions with the trial slopes
(:func:`studies.position.solve_position`; the bodies are factorized once and reused, the
slopes only change the initial gaps) and reduces them with
:func:`postprocess.summary.summarise`. The search reads the root stress on the global model
(``numerics.root_stress = "global"``: the same solution, without the P2 submodels, which
feed nothing back and were most of every solve); the slopes as given and the slopes found
are solved with the case's own root-stress reading, which the report compares.
Writes ``<out>/<case>/lead_correction.json`` (every evaluation), ``report.md`` and
``modifications.toml`` (the tables to paste into the gear-set file). Level and positions
default to the case file's.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np
from mpi4py import MPI

from cases.study_case import case_sizes, load_study_case
from meshing import sizing
from postprocess.run_scalars import run_label
from postprocess.summary import summarise
from solvers.body_store import BodyStore
from studies.case_variants import global_root_stress
from studies.cli import InputError, guarded
from studies.files import atomic_write_text, write_json
from studies.lead_correction import report as lc
from studies.position import roll_angles, solve_position
from studies.settings import RunSettings


def evaluate(
    study, slopes: dict, crowns: dict | None, rolls, comm, level, store, variant: dict | None = None
) -> dict:
    """The summary of ``study`` with the lead slopes (and crowns) given, um by gear name, at
    ``level`` with the sizes ``variant`` takes from other levels (``flank_level``,
    ``fillet_level``)."""
    gs = lc.corrected_gearset(study.gearset, slopes, crowns)
    trial = dataclasses.replace(study, gearset=gs)
    variant = variant or {}
    solved = [
        solve_position(trial, r, comm, RunSettings(level=level, **variant), store=store)
        for r in rolls
    ]
    return summarise(trial, solved, [], {"level": level, **variant})


def correct(
    study,
    *,
    level,
    positions,
    tol,
    fd_step,
    max_step,
    max_solves,
    crowns,
    comm,
    say=print,
    variant: dict | None = None,
):
    """Newton / Broyden on (ZS, ZR) over the slopes of (pinion, sun) (module docstring of
    :mod:`studies.lead_correction.report`); the data the report is written from."""
    gs = study.gearset
    if gs.kind != "single_pinion":
        raise InputError(
            f"{study.name}: lead correction is for single-pinion sets (ZS, ZR); "
            f"{gs.name} is {gs.kind}"
        )
    names = [gs.power_path[1], gs.power_path[0]]  # pinion, sun
    rolls = roll_angles(study, positions)
    store = BodyStore()
    history = []
    search = global_root_stress(study)  # the search needs ZS, ZR only: no submodels

    def run(u, kind, case=search):
        slopes = dict(zip(names, (float(x) for x in u), strict=True))
        t0 = time.perf_counter()
        s = evaluate(case, slopes, crowns, rolls, comm, level, store, variant)
        history.append(
            {
                "slopes_um": slopes,
                "kind": kind,
                "ZS": s["ZS"],
                "ZR": s["ZR"],
                "My_pin": s["My_pin"],
                "wall_s": time.perf_counter() - t0,
            }
        )
        say(
            f"  {kind:>10}: "
            + ", ".join(f"{n} {v:+7.2f} um" for n, v in slopes.items())
            + f" -> ZS {s['ZS']:+.3f} mm, ZR {s['ZR']:+.3f} mm ({history[-1]['wall_s']:.0f} s)"
        )
        return s

    u = np.array([gs.modifications.get(n, lc.NONE).lead_slope_um for n in names], float)
    first = run(u, "as given", study)
    best_u, best = u, first
    r = lc.residual(first)
    if not lc.converged(r, tol):
        jac = np.zeros((2, 2))
        for j in range(2):
            du = np.zeros(2)
            du[j] = fd_step
            jac[:, j] = (lc.residual(run(u + du, f"d/d{names[j]}")) - r) / fd_step
        while len(history) < max_solves:
            du = lc.newton_step(jac, r, max_step)
            s = run(u + du, "Newton")
            r_new = lc.residual(s)
            jac = lc.broyden_update(jac, du, r_new - r)
            u, r = u + du, r_new
            if np.abs(r).max() < np.abs(lc.residual(best)).max():
                best_u, best = u, s
            if lc.converged(r, tol):
                break
    if best is not first and study.numerics.root_stress != "global":  # with the case's reading
        best = run(best_u, "final", study)
    slopes = dict(zip(names, (float(x) for x in best_u), strict=True))
    return {
        "inputs": {
            "case": study.name,
            "gearset": gs.name,
            "gearset_path": _shown_path(gs.path) or f"cases/gearsets/{gs.name}.toml",
            "scene": study.model.scene,
            "level": level,
            **(variant or {}),
            "positions": positions,
            "tol_mm": tol,
            "fd_step_um": fd_step,
            "max_step_um": max_step,
            "unknowns": names,
            "crowns_um": crowns,
            "input_torque_Nm": gs.input_torque,
            "bearing_radial_N_per_mm": study.bearing.radial_stiffness,
            "bearing_tilting_Nmm_per_rad": study.bearing.tilting_stiffness,
        },
        "history": history,
        "converged": lc.converged(lc.residual(best), tol),
        "slopes_um": slopes,
        "before": lc.state_row(first),
        "after": lc.state_row(best),
        "toml": lc.modification_toml(gs, slopes, crowns),
    }


def _shown_path(path: str) -> str:
    """``path`` relative to the working directory when it lies below it."""
    if not path:
        return ""
    p = Path(path).resolve()
    return str(p.relative_to(Path.cwd())) if p.is_relative_to(Path.cwd()) else str(p)


def parse_args(argv=None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(
        prog="python -m studies.lead_correction",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("--case", required=True, help="a single-pinion study case (name or path)")
    ap.add_argument("--level", type=int, default=None, help="mesh level (default: the case's)")
    ap.add_argument(
        "--positions",
        type=int,
        default=None,
        help="mesh positions per base pitch (default: the case's)",
    )
    ap.add_argument("--tol", type=float, default=0.5, help="|ZS|, |ZR| target, mm (0.5)")
    ap.add_argument(
        "--fd-step",
        type=float,
        default=10.0,
        help="slope step of the finite-difference Jacobian, um (10)",
    )
    ap.add_argument(
        "--max-step", type=float, default=100.0, help="largest Newton step of a slope, um (100)"
    )
    ap.add_argument(
        "--max-solves",
        type=int,
        default=8,
        help="evaluations of the search at most, the three of the Jacobian "
        "included, and one more of the slopes found with the case's root-stress "
        "submodels (8)",
    )
    ap.add_argument(
        "--pinion-crown",
        type=float,
        default=None,
        help="pinion lead crown, um, kept fixed (default: the file's)",
    )
    ap.add_argument("--out", type=Path, default=Path("results/lead_correction"))
    ap.add_argument("--traceback", action="store_true", help="re-raise errors (bug reports)")
    args = ap.parse_args(argv)
    if not 0 < args.tol <= 5:
        ap.error(f"--tol {args.tol!r}: must be in (0, 5] mm")
    if not 0 < args.fd_step <= 100 or not 0 < args.max_step <= 500:
        ap.error("--fd-step must be in (0, 100] um and --max-step in (0, 500] um")
    if not 4 <= args.max_solves <= 30:
        ap.error(f"--max-solves {args.max_solves!r}: must be an integer from 4 to 30")
    return args


def main(argv=None) -> int:
    args = parse_args(argv)
    comm = MPI.COMM_WORLD
    say = print if comm.rank == 0 else (lambda *_: None)

    def body():
        study = load_study_case(args.case)
        # the case's sizes with its level; a level given is that level's own
        level, variant = case_sizes(study, args.level)
        try:
            sizing.check_level(level)
        except ValueError as exc:
            raise InputError(f"{study.name}: {exc} (option --level)") from exc
        positions = study.model.positions if args.positions is None else args.positions
        if not 1 <= positions <= 50:
            raise InputError(f"--positions {positions!r}: must be an integer from 1 to 50")
        crowns = None
        if args.pinion_crown is not None:
            crowns = {study.gearset.power_path[1]: args.pinion_crown}
        label = run_label(level, study.numerics.degree, **variant)
        say(f"{study.name}: lead correction at {label}, {positions} positions")
        data = correct(
            study,
            level=level,
            positions=positions,
            tol=args.tol,
            fd_step=args.fd_step,
            max_step=args.max_step,
            max_solves=args.max_solves,
            crowns=crowns,
            comm=comm,
            say=say,
            variant=variant,
        )
        if comm.rank == 0:
            out = args.out / study.name
            out.mkdir(parents=True, exist_ok=True)
            write_json(out / "lead_correction.json", data)
            atomic_write_text(out / "report.md", lc.report(data))
            atomic_write_text(out / "modifications.toml", data["toml"])
            for p in ("report.md", "modifications.toml", "lead_correction.json"):
                print(out / p)

    return guarded(body, traceback=args.traceback)


if __name__ == "__main__":
    sys.exit(main())
