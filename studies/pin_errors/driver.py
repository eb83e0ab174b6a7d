"""Planet load sharing under a pin-hole position error: K_gamma and the root stress of the
most loaded planet against the error.

    python -m studies.pin_errors 1-GB --errors 0 10 25 50 --out results/case1-system
        [--level 0] [--direction tangential|radial] [--sun-stiffness 0 1e6]
        [--root-stress submodel|none]

The study case is solved in the system scene (every pinion on the elastic carrier, sun
floating) at one mesh position with the pin of pinion 1 displaced in the carrier by each
error (um, tangential along the sun's rotation or radial; the other pins exact). The error
enters as the rest offset of that pinion's bearing springs (:mod:`solvers.gear_train`), so
every solve reuses the same body factorizations. With the zone contact model every row is
solved on one band widened for the largest error (:func:`zone_gap_limit_for`). Each sun
radial support stiffness given is a series of its own (0: floating; a floating sun with
three planets shares the load by statics, so a pin error barely changes the shares, exactly
not for forces on the planes of action; a supported sun does not). With ``--root-stress
submodel`` (the default) each solve also reads the root stress on the submodels of each
gear's most loaded planet mesh (:func:`solvers.root_submodel.most_loaded`), the value a pin
error raises. Writes ``pin_errors.json`` (per support and error: the load shares, K_gamma =
largest share, the moments of each pinion, the root stress per gear-set key and the planet
it was read on; rewritten after every solve, so a study that fails part way keeps what it
finished) and ``pin_errors.png``.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from mpi4py import MPI

from cases.study_case import load_study_case
from meshing import sizing
from postprocess.summary import cycle_bending
from solvers.body_store import BodyStore
from solvers.zone_reach import LIMIT_CEILING_UM, REACH_FRACTION
from studies.cli import InputError, StudyFailed, guarded, one_line
from studies.files import on_root, write_json
from studies.paper.system_report import root_stress_ratios
from studies.position import solve_position
from studies.ranks import Ranks
from studies.settings import RunSettings

#: ``--root-stress``: read on the most loaded planet's submodels, or not at all (load shares)
ROOT_STRESS = ("submodel", "none")


def zone_gap_limit_for(numerics, errors_um: list[float]) -> float | None:
    """The zone grids' gap limit (um) a series of pin errors is solved with: the case's
    limit L widened to L + max|e| / REACH_FRACTION (at most LIMIT_CEILING_UM); None for
    a line grid, which has no band.

    A pin error e moves one planet's mesh approaches by at most |e| along their normals,
    and the load it sheds or takes moves the most loaded planet's approach by at most |e|
    (rigid meshes, N planets on one sun rotation: the erroneous planet's approach shifts
    by e (N - 1) / N, the others' by e / N). The reach of the load into the band
    (:mod:`solvers.zone_reach`) grows with the approach, so the band widens by what keeps
    the reach check's margin; one limit for every row, so the rows differ by the error
    only. A reach the widened band does not hold is still refused by the solve."""
    if numerics.contact_model != "zone":
        return None
    widen = max((abs(e) for e in errors_um), default=0.0) / REACH_FRACTION
    return min(LIMIT_CEILING_UM, numerics.zone_gap_limit_um + widen)


def _with_error(
    study,
    error_um: float,
    direction: str,
    k_sun: float,
    root_stress: str,
    gap_limit_um: float | None,
):
    n = study.gearset.planets
    pair = (error_um, 0.0) if direction == "tangential" else (0.0, error_um)
    errors = (pair,) + ((0.0, 0.0),) * (n - 1)
    system = dataclasses.replace(
        study.system, pin_position_errors_um=errors, sun_radial_stiffness=k_sun
    )
    system.check(n, f"{study.name} (options --errors, --sun-stiffness)")
    model = dataclasses.replace(study.model, scene="system")
    numerics = dataclasses.replace(study.numerics, root_stress=root_stress)
    if gap_limit_um is not None:
        numerics = dataclasses.replace(numerics, zone_gap_limit_um=gap_limit_um)
    return dataclasses.replace(study, system=system, model=model, numerics=numerics)


def run(
    case: str,
    errors: list[float],
    out: Path,
    level: int,
    direction: str,
    sun_stiffness: list[float],
    comm,
    root_stress: str = "submodel",
) -> dict:
    """Solve every (support, error) row. The options are checked before any solve (the
    errors and supports by the case file's own check, :meth:`cases.study_case.System.check`);
    ``pin_errors.json`` is rewritten after every row; a row that fails on any rank stops
    every rank (:class:`studies.ranks.Ranks`), the finished rows kept."""
    try:
        sizing.check_level(level)
    except ValueError as exc:
        raise InputError(f"{exc} (option --level)") from exc
    base = load_study_case(case)
    gap_limit = zone_gap_limit_for(base.numerics, errors)
    studies = [
        (k, e, _with_error(base, e, direction, k, root_stress, gap_limit))
        for k in sun_stiffness
        for e in errors
    ]
    store, ranks = BodyStore(), Ranks(comm)
    result = {
        "case": base.name,
        "level": level,
        "direction": direction,
        "roll": 0.0,
        "pinion_with_error": 1,
        "root_stress": root_stress,
        "zone_gap_limit_um": gap_limit,
        "rows": [],
    }
    path = out / "pin_errors.json"
    on_root(comm, lambda: out.mkdir(parents=True, exist_ok=True), f"creating {out}")
    for k_sun, e, study in studies:
        what = f"{base.name}: sun support {k_sun:g} N/mm, pin error {e:g} um"
        failure, pos = None, None
        try:
            pos = solve_position(study, 0.0, comm, RunSettings(level=level), store=store)
        except Exception as exc:  # shared with every rank below
            failure = one_line(exc)
        failed = ranks.agree(failure, what)
        if failed:
            n = len(result["rows"])
            raise StudyFailed(
                f"{what}: rank {failed[0][0]}: {failed[0][1]} ({n} rows before it kept in {path})"
            )
        result["rows"].append(_row(pos, e, k_sun))
        on_root(comm, lambda: write_json(path, result), f"writing {path}")
    on_root(comm, lambda: _plot(result, out / "pin_errors.png"), f"plotting {out}")
    return result


def _row(pos: dict, e: float, k_sun: float) -> dict:
    root = cycle_bending(
        [{"position": 0, "bending_stress": pos.get("bending_stress"), "roll": pos["roll"]}]
    )
    return {
        "sun_radial_stiffness": k_sun,
        "error_um": e,
        "K_gamma": pos["K_gamma"],
        "load_shares": [b["load_share"] for b in pos["branches"]],
        "angles_deg": [b["angle_deg"] for b in pos["branches"]],
        "My_pin": [b["My_pin"] for b in pos["branches"]],
        "Mx_pin": [b["Mx_pin"] for b in pos["branches"]],
        "torque_balance_rel": pos["torque_balance_rel"],
        # per gear-set key (sun, pinion_sun_side, ...) the surface root stress (MPa) on the
        # most loaded planet's mesh, and the output key it was read on; None: not read
        "root_stress": root.get("bending_stress_set"),
        "root_stress_key": root.get("bending_stress_set_key"),
    }


def _plot(result: dict, path: Path) -> None:
    ratios = root_stress_ratios(result["rows"])
    fig, axes = plt.subplots(
        1, 2 if ratios else 1, figsize=(13 if ratios else 7.5, 4.5), squeeze=False
    )
    ax = axes[0, 0]
    supports = sorted({r["sun_radial_stiffness"] for r in result["rows"]})
    styles = dict(zip(supports, ("-", "--", ":", "-."), strict=False))

    def sun(k_sun):
        return "floating sun" if k_sun == 0 else f"sun on {k_sun:.3g} N/mm"

    for k_sun in supports:
        # along the error axis: the rows come in the order the errors were given
        rows = sorted(
            (r for r in result["rows"] if r["sun_radial_stiffness"] == k_sun),
            key=lambda r: r["error_um"],
        )
        e = [r["error_um"] for r in rows]
        ax.plot(
            e,
            [r["K_gamma"] for r in rows],
            "k" + styles[k_sun],
            marker="o",
            label=f"K_gamma, {sun(k_sun)}",
        )
        ax.plot(
            e,
            [r["load_shares"][0] for r in rows],
            "C3" + styles[k_sun],
            marker="s",
            label=f"pinion 1 share, {sun(k_sun)}",
        )
    ax.axhline(1.0, color="0.6", lw=0.8)
    ax.set_xlabel(f"{result['direction']} pin-hole error of pinion 1 (um)")
    ax.set_ylabel("load share (sun-mesh force / mean)")
    ax.set_title(f"{result['case']}, system scene, level {result['level']}: load sharing")
    ax.legend(fontsize=8)
    if ratios:
        ax = axes[0, 1]
        for k_sun, per_key in ratios.items():
            for j, (key, pts) in enumerate(sorted(per_key.items())):
                ax.plot(
                    *zip(*pts, strict=True),
                    f"C{j}" + styles[k_sun],
                    marker="o",
                    label=f"{key}, {sun(k_sun)}",
                )
            rows = [r for r in result["rows"] if r["sun_radial_stiffness"] == k_sun]
            k0 = next(r["K_gamma"] for r in rows if r["error_um"] == 0)
            pts = sorted((r["error_um"], r["K_gamma"] / k0) for r in rows)
            ax.plot(
                *zip(*pts, strict=True),
                "k" + styles[k_sun],
                lw=0.8,
                label=f"K_gamma / K_gamma without error, {sun(k_sun)}",
            )
        ax.axhline(1.0, color="0.6", lw=0.8)
        ax.set_xlabel(f"{result['direction']} pin-hole error of pinion 1 (um)")
        ax.set_ylabel("root stress / root stress without error")
        ax.set_title("root stress of the most loaded planet (surface, submodels)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.pin_errors",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("case")
    ap.add_argument(
        "--errors",
        type=float,
        nargs="+",
        default=[0.0, 10.0, 25.0, 50.0],
        help="pin-hole errors of pinion 1, um",
    )
    ap.add_argument("--direction", choices=("tangential", "radial"), default="tangential")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument(
        "--sun-stiffness",
        type=float,
        nargs="+",
        default=[0.0, 1.0e6],
        help="sun radial support stiffness per series, N/mm; 0: floating",
    )
    ap.add_argument(
        "--root-stress",
        choices=ROOT_STRESS,
        default="submodel",
        help="read the most loaded planet's root stress on submodels (default), "
        "or not (the load shares alone: 1-GB's eight level-0 solves took 2 min "
        "against 6.5)",
    )
    ap.add_argument("--out", type=Path, default=Path("results/case1-system"))
    ap.add_argument("--traceback", action="store_true", help="re-raise errors (bug reports)")
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD

    def body():
        res = run(
            args.case,
            args.errors,
            args.out,
            args.level,
            args.direction,
            args.sun_stiffness,
            comm,
            args.root_stress,
        )
        if comm.rank != 0:
            return
        for r in res["rows"]:
            stress = r["root_stress"] or {}
            print(
                f"sun {r['sun_radial_stiffness']:.3g} N/mm, error {r['error_um']:6.1f} um: "
                f"K_gamma {r['K_gamma']:.4f}, shares "
                + ", ".join(f"{s:.4f}" for s in r["load_shares"])
                + "".join(f", {k} {v:.0f} MPa" for k, v in stress.items())
            )

    return guarded(body, traceback=args.traceback)


if __name__ == "__main__":
    sys.exit(main())
