"""Which convergence study holds the discretisation uncertainty of a case's summary.

A convergence study (``<results>/convergence/<case>/convergence.json``, ``make convergence``)
applies to every case with the same gear set (the hash of its resolved data), scene and
numerics other than the degree (penalty factor, contact grid spacing): the bearing and the
load do not change how fine the mesh must be for a given relative error, the gear set, scene
and grid do. :func:`match_key` is what must agree; :func:`summary_uncertainty` finds the study
(the case's own first, then the others in name order) and returns the summary's
``uncertainty`` entries for the run's level and degree
(:func:`postprocess.convergence_record.uncertainty_for`), or ``uncertainty: None`` and a note saying
what was looked for and where.

Where to look: the studies of this machine (``<results>/convergence``) first, then the
recorded ones (:data:`RECORDS`, ``studies/records/convergence/<case>/``, kept in the
repository): the mesh ladders behind the main study's ± take about 155 min on 2 cores, more than
the rest of the study, so ``make convergence-main RECORD=1`` writes their studies there
once and ``make`` runs a ladder only where no record matches (:func:`recorded`). A record
keeps the commit it was solved on and its runs keep their source hash; a summary that takes
its ± from a study (recorded or not) solved by other code says so
(``uncertainty_source.code_changed``, and the reports), since a code change may change the
discretisation error too (the inputs cannot have changed: they are in the match key).

A study is read as it was written, through :mod:`postprocess.convergence_record` (the
record format and its reader): it is stored reduced, and no reduction of its runs is imported
here. Only the code that solved its runs decides ``code_changed``.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from cases.study_case import StudyCase, study_inputs
from postprocess.convergence_record import (
    checksum_problem,
    missing_runs,
    reproduced_by,
    reproduction_text,
    solved_with,
    uncertainty_for,
)
from postprocess.run_scalars import run_label
from studies.files import ResultFileError, read_json
from studies.provenance import code_hash

STUDY_FILE = "convergence.json"
#: the recorded convergence studies (one folder per case: convergence.json, report.md, chart)
RECORDS = Path(__file__).resolve().parent / "records" / "convergence"


def match_key(study: StudyCase) -> dict:
    """What a convergence study and a case must share: gear set name and hash of its
    resolved data, scene, contact model (with its gap limit), penalty factor, contact grid
    spacing, the bodies' linear solver (with its tolerance), the root fillets (refined
    fillets make the teeth more compliant: a coarse-fillet run is not the refined study's) and
    where the root stress is read (submodel or global fillets), and the Poisson ratio
    (linear tetrahedra lock as it nears 0.5: on 1-GB at level 0 P1 and P2 differ by 1.7 % of
    My_pin at 0.3 and 4.3 % at 0.49, so a study at one does not hold the other's error). The
    gap limit is recorded but not compared (:data:`ANSWER_FREE`)."""
    gearset = study_inputs(study)["gearset"]
    text = json.dumps(gearset, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return {
        "gearset": gearset["name"],
        "gearset_hash": hashlib.sha256(text.encode("utf-8")).hexdigest(),
        "scene": study.model.scene,
        "contact_model": study.numerics.contact_model,
        "zone_gap_limit_um": study.numerics.zone_gap_limit_um,
        "penalty_factor": study.numerics.penalty_factor,
        "grid_spacing": study.numerics.grid_spacing,
        "linear_solver": study.numerics.linear_solver,
        "linear_tolerance": study.numerics.linear_tolerance,
        "root_fillets": study.numerics.root_fillets,
        "root_stress": study.numerics.root_stress,
        "poisson_ratio": study.material.poisson_ratio,
    }


#: match-key fields a case may differ in from a study and still take its ±: the zone gap
#: limit sets how many cells a grid holds, not the answer, once every solve has passed its
#: reach check (solvers.zone_reach: the load stays inside half the band; doubling the limit
#: then moves the moments by < 1e-4, tests/test_microgeometry.py)
ANSWER_FREE = ("zone_gap_limit_um",)
#: match-key fields added after studies were written without them, at the value every such
#: study was solved with (the shipped cases' steel, cases.study_case.Material)
KEY_ADDED = {"poisson_ratio": 0.3}


def same_match(a, b) -> bool:
    """Whether the match keys ``a`` and ``b`` agree on every field but ANSWER_FREE."""
    if not isinstance(a, dict) or not isinstance(b, dict):
        return False
    drop = set(ANSWER_FREE)
    a, b = {**KEY_ADDED, **a}, {**KEY_ADDED, **b}
    return {k: v for k, v in a.items() if k not in drop} == {
        k: v for k, v in b.items() if k not in drop
    }


def _studies(folder: Path, name: str, key: dict, unreadable: list[str] | None = None):
    """(path, study) of every readable convergence study under ``folder`` whose match key is
    ``key`` (:func:`same_match`): the one of case ``name`` first, then the others in name
    order. The paths it could not read go to ``unreadable`` (``path: reason``)."""
    paths = sorted(
        Path(folder).glob(f"*/{STUDY_FILE}"), key=lambda p: (p.parent.name != name, p.parent.name)
    )
    for path in paths:
        try:
            conv = read_json(path)
        except ResultFileError as exc:
            if unreadable is not None:
                unreadable.append(f"{path}: {exc}")
            continue
        if isinstance(conv, dict) and same_match(conv.get("match"), key) and conv.get("scalars"):
            problem = checksum_problem(conv)
            if problem is not None:
                if unreadable is not None:
                    unreadable.append(f"{path}: {problem}")
                continue
            yield path, conv


def recorded(study: StudyCase, ladder: dict, records: Path | None = RECORDS) -> Path | None:
    """The record (its convergence.json) of a convergence study of ``study``'s match key
    run with ``ladder`` (levels, extra runs, positions, split root stress; what
    :mod:`studies.convergence.driver` writes as ``ladder``) and every run of it finished, or None.
    A record with a failed run is not one (``--record`` refuses such a study; an older
    record may hold what finished): ``--unless-recorded`` would then never solve the
    missing run; it is named on stdout, as is a record that cannot be read or does not match
    its checksum."""
    if records is None:
        return None
    skipped: list[str] = []
    found = list(_studies(records, study.name, match_key(study), skipped))
    for why in skipped:  # an edited or damaged record is not silently solved again
        print(f"{study.name}: a record is skipped: {why}")
    for path, conv in found:
        if conv.get("ladder") == ladder:
            failed = missing_runs(conv)
            if not failed:
                return path
            print(
                f"{study.name}: the record {path} has this ladder but not the run(s) "
                f"{', '.join(failed)} (failed or skipped when recorded): it does not "
                "count"
            )
    return None


def summary_uncertainty(
    study: StudyCase,
    level: int,
    degree: int,
    results: Path,
    records: Path | None = RECORDS,
    variant: dict | None = None,
) -> dict:
    """The ``uncertainty``, ``uncertainty_abs`` and ``uncertainty_source`` entries of the
    summary of ``study`` solved at ``level``/``degree`` (with the sizes ``variant`` takes from
    other levels: ``flank_level``, ``fillet_level``; the study's run of that label) with
    results under ``results``.

    The studies of its match key under ``<results>/convergence``, then those under
    ``records`` (None: none); the first one solved by today's code, else the first one,
    with ``uncertainty_source.code_changed`` and a note saying the code differs (a study
    left in the results by an earlier make does not silently stand before a current record).
    A record adds ``uncertainty_source.recorded`` (date and commit)."""
    folder = Path(results) / "convergence"
    key = match_key(study)
    unreadable: list[str] = []
    found = list(_studies(folder, study.name, key, unreadable))
    if records is not None:
        found += list(_studies(records, study.name, key, unreadable))
    out = _from_studies(study, run_label(level, degree, **(variant or {})), folder, key, found)
    if unreadable:  # a damaged study must not stand aside unseen
        out["uncertainty_source"]["note"] += "; skipped as unreadable: " + "; ".join(unreadable)
        out["uncertainty_source"]["skipped"] = unreadable
    return out


def _from_studies(study, label: str, folder, key, found) -> dict:
    """:func:`summary_uncertainty` of the run ``label`` from the readable studies ``found``."""
    if found:
        now = [code_hash()]
        # a study whose run at this level failed (a timeout) gives no ± there: the next one
        have = [(p, c) for p, c in found if label in c.get("labels", [])] or found
        path, conv = next(((p, c) for p, c in have if solved_with(c) == now), have[0])
        out = uncertainty_for(conv, label, str(path))
        src = out["uncertainty_source"]
        src["code_changed"] = solved_with(conv) != now
        if conv.get("recorded"):
            src["recorded"] = conv["recorded"]
        if src["code_changed"]:
            src["note"] += (
                f"; its runs were solved by other code (source {', '.join(solved_with(conv))}, "
                f"today {now[0]}): make convergence-main RECORD=1 (or make convergence) "
                "solves the ladder again"
            )
            again = reproduced_by(conv, now[0])
            if again is not None:
                src["reproduced"] = again
                src["note"] += f"; {reproduction_text(again)}"
        return out
    return {
        "uncertainty": None,
        "uncertainty_abs": None,
        "uncertainty_source": {
            "note": f"no convergence study for gear set {key['gearset']} in the "
            f"{key['scene']} scene with these numerics under {folder} or recorded "
            f"(make convergence CASE={study.name}): no uncertainty given"
        },
    }
