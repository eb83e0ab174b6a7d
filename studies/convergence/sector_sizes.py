"""Which of a root-stress sector's sizes its values follow: one global solution (the driver)
read on sectors of other sizes.

    python -m studies.convergence.sector_sizes [--case 1-GB] [--level 1] [--roll 0]
        [--variants 2:0.15 2:0.1 ...] [--out results/convergence]

The convergence study splits a root stress's error into the driver's and the sector's
(:mod:`studies.convergence.driver`, ``--split-root-stress``); its sector ladder refines the whole
sector at once (the sectors of levels L, L + 1, L + 2, :func:`meshing.submodel.submodel_level`),
every size with its own ratio. This study keeps the driver (the global solution of level
``--level``) and reads it on sectors given as ``K:F``: the sizes of level K with the read
fillets at F mm. The default variants, for the sector S = L + 1 of level L and its read
fillet f (:data:`meshing.submodel.SUBMODEL_FILLET`):

    S:f                the sector the case level reads on today
    S:f/1.5, S:f/2.25  the read fillets alone refined, by a constant ratio of 1.5
    S-1:f/1.5, S+1:f/1.5  the other sizes (flanks, teeth, other fillets, body) one level
                       coarser and finer at a fixed read fillet
    S:f:c ... S:f/2.25:c  the read fillet's ladder on curved (second-order) tets, whose
                       fillet is no set of flat facets (:data:`meshing.submodel.
                       SUBMODEL_GEOMETRY_ORDER`)

so the read fillet's ladder (systematic, the other sizes fixed) is seen apart from the
scatter that the other sizes give at one fillet size: what an equally valid sector would
read. Each variant is one :func:`studies.position.solve_position` of its own, with a store
that keeps nothing (the same matrix and right-hand side each time, so the same driver; the
report gives the moments' largest change over the variants as a check), reading the variant's
sectors only (``own_sectors=False``; before 2026-11-30 each variant also read the case
level's own sectors, about 130 s of a 1-GB level-1 variant). A finished variant is
kept in ``<out>/<case>/sector_sizes_L<L>.json`` (``_roll<roll>`` added off roll 0; written
after each) while the case's inputs
(:func:`cases.study_case.inputs_hash`), the source hash (:func:`studies.provenance.code_hash`),
the level and the roll are those it was solved with; otherwise the file starts afresh.
Serial. Exit status 0, 2 invalid input, 3 a file could not be written. A diagnostic: it
asserts nothing.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import meshing.submodel as submodel
from cases.study_case import load_study_case
from meshing.sizing import LEVELS, Level
from meshing.submodel import SECTOR_STEP, SUBMODEL_FILLET
from postprocess.paper_moments import LOA_ALIASES
from solvers.body_store import BodyStore
from studies.cli import InputError, guarded
from studies.convergence.reduction import CG_NOISE, P_CAP
from studies.convergence.richardson import richardson
from studies.convergence.scatter import GROUP_PREFIX, other_size_spreads
from studies.convergence.variant_file import run_variants
from studies.memory import peak_rss_mb
from studies.position import PositionExtras, solve_position
from studies.settings import RunSettings

#: the paper's moments of any case (N m): the driver check
MOMENT_PREFIXES = ("Mx_", "My_", "M_LOA_")
#: the fillet-only ladder's ratio and the read fillet sizes (mm) a variant may ask for
RATIO = 1.5
FILLET_RANGE = (0.03, 1.0)
#: the report's heading of each value group (:data:`studies.convergence.scatter.GROUP_PREFIX`)
GROUP_TITLE = {
    "surface": "Surface maximum, nodal",
    "tangent": "ISO line, nodal",
    "surface_recovered": "Surface maximum, recovered (solvers.surface_recovery)",
    "tangent_recovered": "ISO line, recovered",
}


def default_variants(level: int) -> list[str]:
    """The default ``K:F`` variants of the global ``level`` (module docstring)."""
    s = min(level + SECTOR_STEP, len(LEVELS) - 1)
    f = SUBMODEL_FILLET[s]
    out = [f"{s}:{f:g}", f"{s}:{f / RATIO:.3g}", f"{s}:{f / RATIO**2:.3g}"]
    out += [f"{k}:{f / RATIO:.3g}" for k in (s - 1, s + 1) if 0 <= k < len(LEVELS)]
    return out + [f"{v}:c" for v in out[:3]]


def variant_sizes(spec: str) -> tuple[Level, int]:
    """The sector sizes and geometry order of variant ``K:F`` (level K's sizes, read fillets
    F mm, straight tets) or ``K:F:c`` (curved tets); a clear :class:`InputError` naming the
    variant otherwise."""
    parts = spec.split(":")
    try:
        k, f = int(parts[0]), float(parts[1])
    except (ValueError, IndexError):
        k, f = None, None
    ok = len(parts) == 2 or (len(parts) == 3 and parts[2] == "c")
    if not ok or k is None or not 0 <= k < len(LEVELS) or not math.isfinite(f):
        raise InputError(
            f"--variants {spec!r}: give K:F or K:F:c, K a level 0 to "
            f"{len(LEVELS) - 1}, F the read fillet size in mm and c for curved "
            "tets, e.g. 2:0.1 or 2:0.1:c"
        )
    lo, hi = FILLET_RANGE
    if not lo <= f <= hi:
        raise InputError(f"--variants {spec!r}: the read fillet must be {lo:g} to {hi:g} mm")
    return replace(LEVELS[k], fillet=f), 2 if len(parts) == 3 else 1


def solve_variant(study, spec: str, level: int, roll: float, comm, log=None) -> dict:
    """One variant's sector DOFs, root stresses (surface and ISO line, MPa) and the driver's
    moments, its wall time and the process's peak memory so far."""
    sizes, order = variant_sizes(spec)
    t0 = time.perf_counter()
    kept = submodel.SUBMODEL_GEOMETRY_ORDER
    submodel.SUBMODEL_GEOMETRY_ORDER = order  # read when a sector body is made
    try:
        out = solve_position(
            study,
            roll,
            comm,
            RunSettings(level=level),
            store=BodyStore(reuse=False),
            extras=PositionExtras(submodel_levels=(sizes,), own_sectors=False, sector_log=log),
        )
    finally:
        submodel.SUBMODEL_GEOMETRY_ORDER = kept
    bs = next(iter(out["bending_stress_fillets"].values()))
    keys = [k for k in bs["locations"] if bs[k] is not None]
    rec = {k: bs["locations"][k]["recovered"] for k in keys}
    return {
        "variant": spec,
        "wall_s": time.perf_counter() - t0,
        "peak_rss_mb": peak_rss_mb(),
        "geometry_order": order,
        "sizes": {
            "fine": sizes.fine,
            "fillet": sizes.fillet,
            "tooth": sizes.tooth,
            "fillet_far": sizes.fillet_far,
            "coarse": sizes.coarse,
            "per_circle": sizes.per_circle,
        },
        "sector_dofs": {k: bs["locations"][k]["submodel"]["dofs"] for k in keys},
        "moments": {
            k: v
            for k, v in out.items()
            if k.startswith(MOMENT_PREFIXES) and k not in LOA_ALIASES and isinstance(v, float)
        },
        "surface": {k: bs[k] for k in keys},
        "tangent": {k: bs["tangent"][k] for k in keys},
        "surface_recovered": {k: rec[k]["value"] for k in keys},
        "tangent_recovered": {k: rec[k]["tangent"] for k in keys},
    }


def fillet_ladders(rows: list[dict], cols: list[tuple[str, str]]) -> list[str]:
    """A line per value and ladder of read fillets: the rows of one set of other sizes (the
    ``K`` of ``K:F``) and one geometry with three fillet sizes or more, the three finest
    extrapolated as the convergence study extrapolates its sector ladder
    (:func:`studies.convergence.richardson.richardson`)."""
    groups: dict[tuple[str, int], dict[float, dict]] = {}
    for r in rows:
        key = (r["variant"].split(":")[0], r.get("geometry_order", 1))
        groups.setdefault(key, {})[r["sizes"]["fillet"]] = r
    out = []
    for (k, order), by_f in sorted(groups.items()):
        fillets = sorted(by_f, reverse=True)[-3:]
        if len(fillets) < 3:
            continue
        name = f"level {k}'s sizes, {'curved' if order == 2 else 'straight'}"
        for g, key in cols:
            vals = [by_f[f].get(g, {}).get(key) for f in fillets]
            if any(v is None for v in vals):
                continue
            res = richardson(fillets, vals, p_cap=P_CAP, noise=CG_NOISE)
            order_s = "-" if res.order is None else f"{res.order:.2f}"
            ext = "-" if res.extrapolated is None else f"{res.extrapolated:.1f}"
            u = " / ".join("-" if x is None else f"{x * 100:.2f}" for x in res.uncertainty)
            out.append(
                f"- {name}, {' / '.join(f'{f:g}' for f in fillets)} mm, {key} ({g}): "
                f"{' / '.join(f'{v:.1f}' for v in vals)}; {res.status}, order "
                f"{order_s}, extrapolated {ext}, U {u} %"
            )
    return out


def report(data: dict) -> str:
    """The study as markdown: per variant its values and change from the first variant, the
    spread at each read fillet size over the other sizes, and the driver check."""
    rows = data["variants"]
    lines = [
        f"# Which sizes a root-stress sector follows: {data['case']}, driver level "
        f"{data['level']}, roll {data['roll']:g}",
        "",
        "One global solution read on sectors of other sizes (K:F = level K's sizes with the "
        "read fillets at F mm); change from the first variant in brackets (%).",
        "",
    ]
    if not rows:
        return "\n".join([*lines, "No variant solved yet."]) + "\n"
    first = rows[0]
    cols = [(g, k) for g in GROUP_PREFIX for k in first.get(g, {}) if first[g][k] is not None]
    lines += ["| variant | sector DOFs (largest) | wall (s) | peak (GB) |", "|---|---|---|---|"]
    for r in rows:
        dofs = max(r["sector_dofs"].values(), default=0)
        lines.append(
            f"| {r['variant']} | {dofs} | {r['wall_s']:.0f} | {r['peak_rss_mb'] / 1024:.1f} |"
        )
    for g in GROUP_PREFIX:  # a table per reading: the nodal and the recovered values
        keys = [k for gg, k in cols if gg == g]
        if not keys:
            continue
        head = "| variant | " + " | ".join(keys) + " |"
        lines += ["", f"### {GROUP_TITLE[g]} (MPa)", "", head, "|---|" + "---|" * len(keys)]
        for r in rows:
            cells = []
            for k in keys:
                v, v0 = r.get(g, {}).get(k), first[g][k]
                if v is None:
                    cells.append("-")
                    continue
                cells.append(f"{v:.1f}" if r is first else f"{v:.1f} ({(v / v0 - 1) * 100:+.2f})")
            lines.append(f"| {r['variant']} | " + " | ".join(cells) + " |")
    # the other sizes' scatter: straight variants of one read fillet size, over their levels
    shared = other_size_spreads(rows)
    lines += ["", "## The other sizes at one read fillet", ""]
    if not shared:
        lines.append("No read fillet size was solved with more than one set of other sizes.")
    for f, sc in shared.items():
        spreads = [
            f"{k} ({g}) {sc['spread'][GROUP_PREFIX[g] + k] * 100:.2f} %"
            for g, k in cols
            if GROUP_PREFIX[g] + k in sc["spread"]
        ]
        lines.append(
            f"- {f:g} mm ({', '.join(sc['variants'])}): spread (max - min) / mean: "
            + ", ".join(spreads)
        )
    lines += [
        "",
        "## The read fillet's ladders",
        "",
        "Per set of other sizes and geometry, the three finest read fillets: Richardson "
        "against the fillet size (the convergence study's, order capped at 2 for the "
        "GCI); U of each fillet in %, coarse to fine.",
        "",
    ]
    ladders = fillet_ladders(rows, cols)
    if not ladders:
        lines.append("No set of other sizes was solved with three read fillet sizes.")
    lines += ladders
    moves = [
        abs(r["moments"][m] - first["moments"][m])
        for r in rows
        for m in first["moments"]
        if m in r["moments"]
    ]
    lines += [
        "",
        f"Driver check: the moments' largest change over the variants is "
        f"{max(moves, default=0.0):.3g} N m (0: the same global solution).",
    ]
    return "\n".join(lines) + "\n"


def run(args) -> Path:
    if not 0 <= args.level < len(LEVELS):
        raise InputError(f"--level: give 0 to {len(LEVELS) - 1}, got {args.level}")
    specs = args.variants or default_variants(args.level)
    for spec in specs:
        variant_sizes(spec)  # every variant checked before anything is solved
    study = load_study_case(args.case)
    if study.numerics.root_stress != "submodel":
        raise InputError(f"--case {args.case}: numerics.root_stress must be 'submodel'")
    return run_variants(
        study, args.out, "sector_sizes", args.level, args.roll, specs, solve_variant, report
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.convergence.sector_sizes", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--level", type=int, default=1, help="the driver's (global) level")
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad)")
    ap.add_argument(
        "--variants", nargs="+", default=None, help="K:F sectors (default: module docstring)"
    )
    ap.add_argument("--out", type=Path, default=Path("results/convergence"))
    return guarded(lambda: run(ap.parse_args(argv)))


if __name__ == "__main__":
    sys.exit(main())
