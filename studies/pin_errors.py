"""Planet load sharing under a pin-hole position error: K_gamma against the error.

    python -m studies.pin_errors 1-GB --errors 0 10 25 50 --out results/case1-system
        [--level 0] [--direction tangential|radial] [--sun-stiffness 0 1e6]

The study case is solved in the system scene (every pinion on the elastic carrier, sun
floating) at one mesh position with the pin of pinion 1 displaced in the carrier by each
error (um, tangential along the sun's rotation or radial; the other pins exact). The error
enters as the rest offset of that pinion's bearing springs (:mod:`solvers.gear_train`), so
every solve reuses the same body factorizations. Each sun radial support stiffness given is
a series of its own (0: floating; a floating sun with three planets shares the load by
statics, so a pin error barely changes the shares, exactly not for forces on the planes of
action; a supported sun does not). Writes
``pin_errors.json`` (per support and error: the load shares, K_gamma = largest share, the
moments of each pinion) and ``pin_errors.png``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from mpi4py import MPI

from cases.study_case import load_study_case
from solvers.body_store import BodyStore
from studies.case_variants import no_root_stress
from studies.position import solve_position


def _with_error(study, error_um: float, direction: str, k_sun: float):
    n = study.gearset.planets
    pair = (error_um, 0.0) if direction == "tangential" else (0.0, error_um)
    errors = (pair,) + ((0.0, 0.0),) * (n - 1)
    system = dataclasses.replace(study.system, pin_position_errors_um=errors,
                                 sun_radial_stiffness=k_sun)  # fmt: skip
    model = dataclasses.replace(study.model, scene="system")
    # the load shares only: no root stress (its submodels would be most of every solve)
    return no_root_stress(dataclasses.replace(study, system=system, model=model))


def run(case: str, errors: list[float], out: Path, level: int, direction: str,
        sun_stiffness: list[float], comm) -> dict:  # fmt: skip
    base = load_study_case(case)
    store = BodyStore()
    rows = []
    for k_sun in sun_stiffness:
        for e in errors:
            study = _with_error(base, e, direction, k_sun)
            pos = solve_position(study, 0.0, comm, level=level, store=store)
            rows.append(_row(pos, e, k_sun))
    result = {"case": case, "level": level, "direction": direction, "roll": 0.0,
              "pinion_with_error": 1, "rows": rows}  # fmt: skip
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
        (out / "pin_errors.json").write_text(json.dumps(result, indent=1) + "\n")
        _plot(result, out / "pin_errors.png")
    return result


def _row(pos: dict, e: float, k_sun: float) -> dict:
    return {
        "sun_radial_stiffness": k_sun,
        "error_um": e,
        "K_gamma": pos["K_gamma"],
        "load_shares": [b["load_share"] for b in pos["branches"]],
        "angles_deg": [b["angle_deg"] for b in pos["branches"]],
        "My_pin": [b["My_pin"] for b in pos["branches"]],
        "Mx_pin": [b["Mx_pin"] for b in pos["branches"]],
        "torque_balance_rel": pos["torque_balance_rel"],
    }


def _plot(result: dict, path: Path) -> None:
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    supports = sorted({r["sun_radial_stiffness"] for r in result["rows"]})
    for k_sun, style in zip(supports, ("-", "--", ":", "-."), strict=False):
        rows = [r for r in result["rows"] if r["sun_radial_stiffness"] == k_sun]
        e = [r["error_um"] for r in rows]
        sun = "floating sun" if k_sun == 0 else f"sun on {k_sun:.3g} N/mm"
        ax.plot(e, [r["K_gamma"] for r in rows], "k" + style, marker="o",
                label=f"K_gamma, {sun}")  # fmt: skip
        ax.plot(e, [r["load_shares"][0] for r in rows], "C3" + style, marker="s",
                label=f"pinion 1 share, {sun}")  # fmt: skip
    ax.axhline(1.0, color="0.6", lw=0.8)
    ax.set_xlabel(f"{result['direction']} pin-hole error of pinion 1 (um)")
    ax.set_ylabel("load share (sun-mesh force / mean)")
    ax.set_title(f"{result['case']}, system scene, level {result['level']}: load sharing")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m studies.pin_errors", description=__doc__)
    ap.add_argument("case")
    ap.add_argument("--errors", type=float, nargs="+", default=[0.0, 10.0, 25.0, 50.0])
    ap.add_argument("--direction", choices=("tangential", "radial"), default="tangential")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--sun-stiffness", type=float, nargs="+", default=[0.0, 1.0e6],
                    help="sun radial support stiffness per series, N/mm; 0: floating")  # fmt: skip
    ap.add_argument("--out", type=Path, default=Path("results/case1-system"))
    args = ap.parse_args(argv)
    res = run(args.case, args.errors, args.out, args.level, args.direction, args.sun_stiffness,
              MPI.COMM_WORLD)  # fmt: skip
    if MPI.COMM_WORLD.rank == 0:
        for r in res["rows"]:
            print(f"sun {r['sun_radial_stiffness']:.3g} N/mm, error {r['error_um']:6.1f} um: "
                  f"K_gamma {r['K_gamma']:.4f}, shares "
                  + ", ".join(f"{s:.4f}" for s in r["load_shares"]))  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
