"""Which convergence study holds the discretisation uncertainty of a case's summary.

A convergence study (``<results>/convergence/<case>/convergence.json``, ``make convergence``)
applies to every case with the same gear set (the hash of its resolved data), scene and
numerics other than the degree (penalty factor, contact grid spacing): the bearing and the
load do not change how fine the mesh must be for a given relative error, the gear set, scene
and grid do. :func:`match_key` is what must agree; :func:`summary_uncertainty` finds the study
(the case's own first, then the others in name order) and returns the summary's
``uncertainty`` entries for the run's level and degree
(:func:`postprocess.convergence.uncertainty_for`), or ``uncertainty: None`` and a note saying
what was looked for and where.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from cases.study_case import StudyCase, study_inputs
from postprocess.convergence import uncertainty_for
from studies.files import ResultFileError, read_json

STUDY_FILE = "convergence.json"


def match_key(study: StudyCase) -> dict:
    """What a convergence study and a case must share: gear set name and hash of its
    resolved data, scene, contact model (with its gap limit), penalty factor, contact grid
    spacing, the bodies' linear solver (with its tolerance), the root fillets (refined
    fillets make the teeth more compliant: a coarse-fillet run is not the refined study's) and
    where the root stress is read (submodel or global fillets)."""
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
    }


def summary_uncertainty(study: StudyCase, level: int, degree: int, results: Path) -> dict:
    """The ``uncertainty``, ``uncertainty_abs`` and ``uncertainty_source`` entries of the
    summary of ``study`` solved at ``level``/``degree`` with results under ``results``."""
    folder = Path(results) / "convergence"
    key = match_key(study)
    paths = sorted(
        folder.glob(f"*/{STUDY_FILE}"), key=lambda p: (p.parent.name != study.name, p.parent.name)
    )
    for path in paths:
        try:
            conv = read_json(path)
        except ResultFileError:
            continue
        if isinstance(conv, dict) and conv.get("match") == key and conv.get("scalars"):
            return uncertainty_for(conv, level, degree, str(path))
    return {
        "uncertainty": None,
        "uncertainty_abs": None,
        "uncertainty_source": {
            "note": f"no convergence study for gear set {key['gearset']} in the "
            f"{key['scene']} scene with these numerics under {folder} (make convergence "
            f"CASE={study.name}): no uncertainty given"
        },
    }
