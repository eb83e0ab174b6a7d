"""Where a level's root-stress driver error comes from: the global mesh of one level with one
of its sizes set to the next level's, every root stress read on the same sector.

    python -m studies.convergence.driver_sizes [--case 1-GB] [--level 0] [--roll 0]
        [--variants base grid flank ...] [--out results/convergence]

The convergence study splits a root stress's error into the driver's (the global solution
that drives the P2 sector) and the sector's (:mod:`studies.convergence.driver`,
``--split-root-stress``). The driver's ladder refines every size of the global mesh at once;
this study changes one at a time from level ``L`` towards level ``L + 1``:

    base        level L
    grid        the contact grid at level L + 1's flank size
    flank       the active teeth's flank elements at level L + 1's (grid kept)
    flank+grid  both
    tooth       the other teeth's flanks and tips
    fillet_far  the fillets that are not refined
    fillet      the refined (loaded) fillets
    body        rim, web and faces, and the segments per turn
    next        level L + 1

and reads every variant's root stresses on the sector of level 1 (0.15 mm read fillets,
:func:`meshing.submodel.submodel_level`), so only the driver differs. Each variant's change
from ``base`` against ``next``'s says which size the driver's error follows. One process
solves the variants in turn; a finished variant is kept in
``<out>/<case>/driver_sizes_L<L>.json`` (``_roll<roll>`` added off roll 0; written after
each) and not solved again while the case's inputs
(:func:`cases.study_case.inputs_hash`), the source hash (:func:`studies.provenance.code_hash`),
the level and the roll are those it was solved with; otherwise the file starts afresh.
Each variant reads the read sectors only (``own_sectors=False``; before 2026-11-30 it also
read the sectors of its own sizes, 31 s of 1-GB's level-0 base of 436 s, the four 0.15 mm
read sectors 356 s). Serial. Exit status 0, 2 invalid input,
3 a file could not be written. A diagnostic: it asserts nothing.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

from cases.study_case import load_study_case
from meshing.sizing import LEVELS, Level
from postprocess.paper_moments import LOA_ALIASES
from solvers.body_store import BodyStore
from studies.cli import InputError, guarded
from studies.convergence.variant_file import run_variants
from studies.memory import peak_rss_mb
from studies.position import PositionExtras, solve_position
from studies.settings import RunSettings

#: the sector every variant is read on (the default level's: 0.15 mm read fillets)
READ_LEVEL = 1
#: the paper's moments of any case: bearing tilt moments and LOA moments (N m)
MOMENT_PREFIXES = ("Mx_", "My_", "M_LOA_")
VARIANTS = ("base", "grid", "flank", "flank+grid", "tooth", "fillet_far", "fillet", "body", "next")


def variant_mesh(name: str, level: int) -> tuple[Level, float]:
    """(global sizes, contact grid spacing in mm) of variant ``name`` from ``level``."""
    a, b = LEVELS[level], LEVELS[level + 1]
    sizes = {
        "base": (a, a.fine),
        "grid": (a, b.fine),
        "flank": (replace(a, fine=b.fine), a.fine),
        "flank+grid": (replace(a, fine=b.fine), b.fine),
        "tooth": (replace(a, tooth=b.tooth), a.fine),
        "fillet_far": (replace(a, fillet_far=b.fillet_far), a.fine),
        "fillet": (replace(a, fillet=b.fillet), a.fine),
        "body": (replace(a, coarse=b.coarse, per_circle=b.per_circle), a.fine),
        "next": (b, b.fine),
    }
    return sizes[name]


def solve_variant(study, name: str, level: int, roll: float, comm, log=None) -> dict:
    """One variant's DOFs, moments and root stresses (surface and ISO line, MPa), its wall
    time and the process's peak memory so far; ``log``: called with a line per sector."""
    sizes, spacing = variant_mesh(name, level)
    t0 = time.perf_counter()
    # a store that keeps nothing: one position per variant, so the global factors are freed
    # before the sectors and each sector after its reading (a keeping store held the global
    # factors and all twelve of 2B-GA's level-1 sectors: 22.3 GB, then killed at 23.2 GB)
    out = solve_position(
        study,
        roll,
        comm,
        RunSettings(level=sizes, grid_spacing=spacing),
        store=BodyStore(reuse=False),
        extras=PositionExtras(submodel_levels=(READ_LEVEL,), own_sectors=False, sector_log=log),
    )
    read = out["bending_stress_fillets"]
    bs = next(iter(read.values()))
    keys = list(bs["locations"])
    return {
        "variant": name,
        "dofs": out["dofs"],
        "wall_s": time.perf_counter() - t0,
        "peak_rss_mb": peak_rss_mb(),
        "sizes": {
            "fine": sizes.fine,
            "fillet": sizes.fillet,
            "tooth": sizes.tooth,
            "fillet_far": sizes.fillet_far,
            "coarse": sizes.coarse,
            "per_circle": sizes.per_circle,
            "grid": spacing,
        },
        "read_fillet_mm": float(next(iter(read))),
        "moments": {
            k: v
            for k, v in out.items()
            if k.startswith(MOMENT_PREFIXES) and k not in LOA_ALIASES and isinstance(v, float)
        },
        "surface": {k: bs[k] for k in keys},
        "tangent": {k: bs["tangent"][k] for k in keys},
    }


def report(data: dict) -> str:
    """The study as markdown: per variant its values and change from ``base``, and, with
    ``next`` solved, that change as a share of the whole step."""
    rows = {r["variant"]: r for r in data["variants"]}
    lvl = data["level"]
    lines = [
        f"# Where the root-stress driver error comes from: {data['case']}, level {lvl} -> "
        f"{lvl + 1}, roll {data['roll']:g}",
        "",
        f"The global mesh of level {lvl} with one size set to level {lvl + 1}'s; every root "
        f"stress read on the same sector (level {READ_LEVEL}'s, read fillets "
        f"{data['read_fillet_mm']:g} mm), so only the driver differs. Change from base; in "
        "brackets its share of the whole step (base -> next) where next is solved.",
        "",
    ]
    base = rows.get("base")
    nxt = rows.get("next")
    if base is None:
        return "\n".join([*lines, "base not solved yet."]) + "\n"
    cols = [("moments", k) for k in base["moments"]]
    cols += [("surface", k) for k in base["surface"]]
    cols += [("tangent", k) for k in base["tangent"] if base["tangent"][k] is not None]
    head = [f"{k} ({'N m' if g == 'moments' else 'MPa, ' + g})" for g, k in cols]
    lines += [
        "| variant | DOFs | wall (s) | process peak so far (GB) | " + " | ".join(head) + " |",
        "|---|---|---|---|" + "---|" * len(cols),
    ]
    for name in VARIANTS:
        r = rows.get(name)
        if r is None:
            continue
        cells = []
        for g, k in cols:
            v, v0 = r[g].get(k), base[g][k]
            if v is None:
                cells.append("-")
                continue
            cell = f"{v:.4g}"
            if name != "base":
                d = v - v0
                cell += f" ({d:+.3g}"
                if nxt is not None and name != "next" and nxt[g].get(k) is not None:
                    step = nxt[g][k] - v0
                    cell += f", {d / step:.0%}" if abs(step) > 1e-9 * max(abs(v0), 1.0) else ""
                cell += ")"
            cells.append(cell)
        peak = "-" if r.get("peak_rss_mb") is None else f"{r['peak_rss_mb'] / 1024:.1f}"
        wall = "-" if r.get("wall_s") is None else f"{r['wall_s']:.0f}"
        lines.append(f"| {name} | {r['dofs']} | {wall} | {peak} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def run(args) -> Path:
    if not 0 <= args.level < len(LEVELS) - 1:
        raise InputError(
            f"--level: give 0 to {len(LEVELS) - 2} (a level with a next one), got {args.level}"
        )
    bad = [v for v in args.variants if v not in VARIANTS]
    if bad:
        raise InputError(f"--variants: {', '.join(bad)} unknown (allowed: {', '.join(VARIANTS)})")
    study = load_study_case(args.case)
    if study.numerics.root_stress != "submodel":
        raise InputError(f"--case {args.case}: numerics.root_stress must be 'submodel'")
    return run_variants(
        study,
        args.out,
        "driver_sizes",
        args.level,
        args.roll,
        args.variants,
        solve_variant,
        report,
        on_row=_read_fillet,
    )


def _read_fillet(data: dict, row: dict) -> None:
    """The read sector's fillet size (mm) into the file's head, for the report."""
    data["read_fillet_mm"] = row["read_fillet_mm"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.convergence.driver_sizes", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad)")
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS))
    ap.add_argument("--out", type=Path, default=Path("results/convergence"))
    return guarded(lambda: run(ap.parse_args(argv)))


if __name__ == "__main__":
    sys.exit(main())
