"""The reported scalars of a summary, by dotted key: what a convergence run records.

:func:`summary_scalars` reads every reported scalar of a ``summary.json`` (or a position
record) by a dotted key (``My_pin``, ``bending_stress.sun``,
``contact_stress_cycle.sun_pinion.p_max_MPa``): the top-level scalars of the gear-set kind
and every float under a top-level entry whose name holds ``stress`` (not the ISO closed forms,
not where a maximum sits); whatever keys the summary has, so new stress entries are picked
up. :func:`scalar_kind` and :func:`unit` classify a key.

A run's numbers pass through this module, so it is under the source hash
(:func:`studies.provenance.code_hash`); the reductions of a ladder of runs
(:mod:`studies.convergence.richardson`, :mod:`studies.convergence.reduction`) are not: they are
applied to a study's stored runs when it is written, and again by ``python -m
studies.convergence.driver --reduce-records`` (:func:`studies.convergence.reduction.reduce_study`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from cases.study_case import VARIANT_FIELDS
from postprocess.paper_moments import MEAN_KEYS

# Entries under a stress group that are not discretisation results: where a maximum sits,
# counts, ISO factors, the torque ISO is evaluated at.
_SKIP_PARTS = ("locations", "iso_factors", "iso_driver_torque_Nm")
_SKIP_SUFFIXES = ("_at",)


def scalar_kind(key: str) -> str:
    """``moment`` (N m), ``stress`` (MPa), ``offset`` (mm, um) or ``other`` (load factors,
    line loads, ratios) from the dotted key."""
    group, leaf = key.split(".", 1)[0], key.rsplit(".", 1)[-1]
    if "." in key and "stress" in group:
        if leaf.endswith("_MPa"):
            return "stress"
        other = leaf.startswith("K_") or "_to_" in leaf or leaf.endswith(("_mm", "_Nm", "_N"))
        return "other" if other else "stress"
    if leaf.startswith("M"):
        return "moment"
    if leaf.startswith("Z") or leaf.endswith(("_mm", "_um")):
        return "offset"
    return "other"


def unit(key: str) -> str:
    """The unit of a scalar by its key."""
    leaf = key.rsplit(".", 1)[-1]
    kind = scalar_kind(key)
    if kind == "moment":
        return "N m"
    if kind == "stress":
        return "MPa"
    if leaf.endswith("_um"):
        return "um"
    if kind == "offset":
        return "mm"
    if leaf.endswith("_N_per_mm"):
        return "N/mm"
    return "-"


def _leaves(tree, prefix: str, out: dict[str, float]) -> None:
    if isinstance(tree, Mapping):
        for k, v in tree.items():
            if k in _SKIP_PARTS or k.endswith(_SKIP_SUFFIXES):
                continue
            _leaves(v, f"{prefix}.{k}", out)
    elif isinstance(tree, float) and math.isfinite(tree):  # ints are counts, bools flags
        out[prefix] = tree


def summary_scalars(summary: Mapping, kind: str | None = None) -> dict[str, float]:
    """The reported scalars of a summary (or of a position record) by dotted key: the
    top-level scalars of the gear-set ``kind`` (:data:`postprocess.paper_moments.MEAN_KEYS`;
    all kinds' when None) and every float under a top-level entry named ``*stress*``, except
    where a maximum sits (``*_at``) and the ISO 6336 closed forms (``*iso6336*``)."""
    keys = MEAN_KEYS[kind] if kind else {k for ks in MEAN_KEYS.values() for k in ks}
    out: dict[str, float] = {}
    for k in keys:
        v = summary.get(k)
        if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
            out[k] = float(v)
    for name, tree in summary.items():
        skip = name.endswith(_SKIP_SUFFIXES) or "iso6336" in name  # locations; closed forms
        if "stress" in name and isinstance(tree, Mapping) and not skip:
            _leaves(tree, name, out)
    return out


def lookup(tree: Mapping, key: str):
    """The value at a dotted key of a summary (None where a part is missing)."""
    for part in key.split("."):
        if not isinstance(tree, Mapping) or part not in tree:
            return None
        tree = tree[part]
    return tree


def run_label(
    level: int, degree: int, flank_level: int | None = None, fillet_level: int | None = None
) -> str:
    """``L<level>P<degree>``, with ``F<flank_level>`` for a run whose active flanks and
    contact grid are those of another level and ``R<fillet_level>`` for one whose refined
    (read) fillets are (:func:`meshing.sizing.with_sizes`)."""
    return (
        f"L{level}P{degree}"
        + ("" if flank_level is None else f"F{flank_level}")
        + ("" if fillet_level is None else f"R{fillet_level}")
    )


#: the sizes a run may take from another level (:func:`meshing.sizing.with_sizes`), as a
#: case's ``[model]`` names them
VARIANT_KEYS = VARIANT_FIELDS


def variant(row: Mapping) -> dict[str, int]:
    """The sizes a run row takes from other levels (``flank_level``, ``fillet_level``); empty
    for a run of the ladder's sizes."""
    return {k: row[k] for k in VARIANT_KEYS if row.get(k) is not None}


#: what a run's sizes of another level are, in words (:func:`meshing.sizing.with_sizes`)
VARIANT_WORDS = {"flank_level": "flanks and contact grid", "fillet_level": "refined fillets"}


def sizes_in_words(level: int, variant: Mapping) -> str:
    """``level 1 with level 2's flanks and contact grid and level 2's refined fillets``, or
    ``level 1`` for a level's own sizes (``variant``: :func:`variant` of a row)."""
    other = " and ".join(f"level {v}'s {VARIANT_WORDS[k]}" for k, v in variant.items())
    return f"level {level}" + (f" with {other}" if other else "")


def level_text(row: Mapping) -> str:
    """A report's level cell of a run row or summary: ``1``, or ``1 (level-2 flanks and
    fillets)`` for one whose active flanks and contact grid (``flank_level``) and refined root
    fillets (``fillet_level``) are another level's."""
    v = variant(row)
    if not v:
        return str(row["level"])
    flanks, fillets = v.get("flank_level"), v.get("fillet_level")
    if flanks == fillets:
        return f"{row['level']} (level-{flanks} flanks and fillets)"
    parts = [f"level-{flanks} flanks"] * (flanks is not None)
    parts += [f"level-{fillets} fillets"] * (fillets is not None)
    return f"{row['level']} ({', '.join(parts)})"


def row_label(row: Mapping) -> str:
    """The :func:`run_label` of a convergence study's run row (or a summary)."""
    return run_label(row["level"], row["degree"], row.get("flank_level"), row.get("fillet_level"))
