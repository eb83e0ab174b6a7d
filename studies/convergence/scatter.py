"""The scatter of a root stress between equally valid sectors, and the floor it puts under the
sector part of the root stress's uncertainty.

The convergence study's sector ladder refines every size of a root-stress sector at once
(:func:`studies.convergence.reduction.root_stress_split`); its three values may agree by
chance. 1-GB's record at level 1 reads the sun's fillet surface 867.3 / 864.6 / 866.5 MPa on
the 0.15 / 0.1 / 0.08 mm sectors (U 0.31 %), while the same global solution read on the sizes
of levels 1, 2 and 3 at one read fillet of 0.1 mm spreads by 1.4 %
(:mod:`studies.convergence.sector_sizes`, ``--variants 1:0.1 2:0.1 3:0.1``). Neither ladder
sees the other's error, so the sector's uncertainty at every read fillet f is the larger of the
two::

    U_sector(f) = max(U_ladder(f), s),   s = (max - min) / |mean|

over the straight-tet variants read at one fillet size with other sizes (the largest s over
the measurements kept with the record: fillet sizes, positions). The floor is measured at one
fillet (0.1 mm by default) and applied at the ladder's coarser and finer fillets alike:
coarser sectors scatter at least as much, and a finer one's floor is then conservative.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from postprocess.run_scalars import variant
from studies.uncertainty import same_match

#: a variant's value groups (:func:`studies.convergence.sector_sizes.solve_variant`) and the
#: convergence study's scalar keys they are read as
#: (:data:`studies.convergence.reduction.SPLIT_PREFIXES`); the recovered values
#: (:mod:`solvers.surface_recovery`) are in variants since 2026-11-30
GROUP_PREFIX = {
    "surface": "bending_stress.",
    "tangent": "bending_stress_tangent.",
    "surface_recovered": "bending_stress_recovered.",
    "tangent_recovered": "bending_stress_tangent_recovered.",
}


def spread(values: Sequence[float]) -> float | None:
    """(max - min) / |mean| of ``values`` (None for fewer than two or a zero mean)."""
    if len(values) < 2:
        return None
    mean = sum(values) / len(values)
    return (max(values) - min(values)) / abs(mean) if mean else None


def other_size_spreads(rows: Iterable[Mapping], geometry_order: int = 1) -> dict[float, dict]:
    """Per read fillet size (mm) solved with more than one set of other sizes on tets of
    ``geometry_order``: the variants' names and the spread of each root stress, keyed as
    the convergence study keys it (``bending_stress.<location>``,
    ``bending_stress_tangent.<location>``)."""
    by_fillet: dict[float, list[Mapping]] = {}
    for r in rows:
        if r.get("geometry_order", 1) == geometry_order:
            by_fillet.setdefault(r["sizes"]["fillet"], []).append(r)
    out = {}
    for f, rs in sorted(by_fillet.items(), reverse=True):
        if len(rs) < 2:
            continue
        spreads = {}
        for group, prefix in GROUP_PREFIX.items():
            for loc in dict.fromkeys(k for r in rs for k in r.get(group, {})):
                s = spread([r[group][loc] for r in rs if r.get(group, {}).get(loc) is not None])
                if s is not None:
                    spreads[prefix + loc] = s
        out[f] = {"variants": [r["variant"] for r in rs], "spread": spreads}
    return out


def scatter_floors(entries: Iterable[Mapping], level: int) -> dict[str, float]:
    """Per scalar key the largest spread over the kept measurements (a record's
    ``sector_scatter``, :func:`studies.convergence.sector_scatter.record_scatter`) made on the
    driver of ``level`` (the case level, whose sector ladder the floor goes under)."""
    floors: dict[str, float] = {}
    for e in entries:
        if e.get("level") != level:
            continue
        for key, s in e["spread"].items():
            floors[key] = max(s, floors.get(key, 0.0))
    return floors


def level_inputs(conv: Mapping, level: int) -> set:
    """The inputs hashes of a study's ladder runs at ``level`` (its ladder degree, the
    level's own sizes: not a run off the ladder at that level, such as L1P1F2 or L1P2)."""
    return {
        (r.get("reuse_key") or {}).get("inputs_hash")
        for r in conv.get("runs") or []
        if r.get("level") == level
        and not variant(r)
        and r.get("degree") == conv.get("ladder_degree", 1)
    }


def case_level_inputs(conv: Mapping) -> set:
    """The inputs hashes of a study's ladder run at its case level (its sector ladder's
    driver)."""
    return level_inputs(conv, conv.get("case_level"))


def carried_scatter(old: Mapping, new: Mapping) -> list[dict]:
    """The sector-scatter measurements of a record ``old`` that a study ``new`` replacing it
    keeps: all of them where both are of one gear set, scene and numerics (``match``) and
    case level, and their case-level runs were solved from the same inputs; else none. The
    scatter is the sectors' (their meshes, which the inputs and level fix, and each entry
    names the code that measured it), so solving the ladder again does not remove it: a
    record that dropped it would print a smaller ± with nothing to show why."""
    if not old.get("sector_scatter") or not same_match(old.get("match"), new.get("match")):
        return []
    if old.get("case_level") != new.get("case_level"):
        return []
    inputs = case_level_inputs(new)
    if None in inputs or len(inputs) != 1 or case_level_inputs(old) != inputs:
        return []
    return list(old["sector_scatter"])
