"""Which case summaries are runs of the paper's own study cases, so the one-page report checks
the paper's conclusions on those and on no case file of a user's.

A summary counts as the paper's case when its study case is one of the shipped study-case
files (``cases/<name>.toml``) on one of the analytical study's gear sets
(``cases/analytic/singh2007.toml``) and its inputs (:func:`cases.study_case.study_inputs`)
agree with that file's in everything that defines the paper's case: the gear set (gears,
meshes, torque, modifications), the bearing, the material and the system data. The mesh
level and the numerics may differ: a coarser run of 1-GA is still 1-GA.
"""

from __future__ import annotations

import json
from functools import cache

from cases.analytic_study import load_analytic_study
from cases.gearset import CaseError
from cases.study_case import load_study_case, study_inputs

#: the parts of a summary's inputs that make a study case the paper's, with the word used
PAPER_PARTS = (
    (("gearset",), "gear set"),
    (("study_case", "bearing"), "bearing"),
    (("study_case", "material"), "material"),
    (("study_case", "system"), "system data"),
)


@cache
def _shipped_inputs(name: str) -> dict | str:
    """The JSON form of the shipped study case ``name``'s inputs, or why it is not one of
    the paper's (not shipped, or on another gear set)."""
    try:
        shipped = load_study_case(name)
    except CaseError:
        return "not one of the shipped study cases"
    paper = load_analytic_study()
    if shipped.gearset.name not in (paper.single_pinion.name, paper.double_pinion.name):
        return f"cases/{name}.toml is not on the paper's gear sets"
    return json.loads(json.dumps(study_inputs(shipped)))


def _part(inputs: dict, keys: tuple[str, ...]):
    for k in keys:
        inputs = inputs.get(k) if isinstance(inputs, dict) else None
    return inputs


def paper_case_difference(summary: dict) -> str | None:
    """None where ``summary`` is a run of one of the paper's study cases; otherwise why not
    (not a shipped case, another gear set, or the parts of :data:`PAPER_PARTS` that differ
    from the shipped file)."""
    name = summary.get("case")
    if not isinstance(name, str):
        return "no case name"
    ref = _shipped_inputs(name)
    if isinstance(ref, str):
        return ref
    got = summary.get("inputs") or {}
    differ = [word for keys, word in PAPER_PARTS if _part(got, keys) != _part(ref, keys)]
    if differ:
        return f"its {', '.join(differ)} differ(s) from cases/{name}.toml"
    return None


__all__ = ["PAPER_PARTS", "paper_case_difference"]
