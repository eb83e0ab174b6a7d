"""The convergence record, read: where a summary's ± come from.

A convergence study (``make convergence``, :mod:`studies.convergence.driver`) writes one
``convergence.json`` per case; a record is such a file kept in the repository
(``studies/records/convergence/<case>/``). This module reads the keys below and nothing
else; it does not reduce the runs again (the study is stored reduced, and a test holds every
shipped record to today's reductions: ``python -m studies.convergence --reduce-records``
rewrites them after a change to the reductions). The format, as read here:

``case``
    the case whose ladder was solved (str).
``match``
    what a case must share with the study to take its ± (:func:`studies.uncertainty.match_key`).
``labels``
    the finished runs (:func:`postprocess.run_scalars.run_label`: ``L1P1``, ``L1P1F2R2``).
``positions``
    the mesh positions each run solved (int).
``code_hash``, ``runs_code_hash``
    the source hash of the code that reduced the study and of the code that solved its runs
    (:func:`studies.provenance.code_hash`).
``scalars.<key>.status``
    how the ladder behaved for that scalar: ``monotone``, ``two-grid``, ``oscillatory``,
    ``divergent``, ``stagnant``, ``zero`` or ``mesh-independent`` (no ± given).
``scalars.<key>.uncertainty.<label>``, ``scalars.<key>.uncertainty_abs.<label>``
    the relative uncertainty U of that scalar at that run (None where the value is about zero)
    and U in the scalar's unit. U is Roache's GCI with factor of safety :data:`SAFETY` from a
    Richardson extrapolation with the observed order (:data:`SAFETY_TWO_GRID` and the formal
    order where only two levels fit), or the spread of the levels where they do not converge
    monotonically.
``runs[*].error``, ``skipped[*].label``
    runs that failed or were skipped: a record with one is not a complete ladder.
``ladder``
    the runs asked for, positions and root-stress split (what ``--unless-recorded`` matches).
``sector_scatter_from``
    the record whose sector scatter a study of this machine took when it was written (it
    floors the sector part of each root stress's U).
``recorded``
    date and commit of a record (absent in a study of this machine's results).
``checksum``
    sha256 of the study's JSON without this key (:func:`checksum`), written with it: a study
    edited by hand or damaged does not match and gives no ± (:func:`checksum_problem`).
``reproduced[*]``
    a run solved again by later code and compared with the record
    (``run``, ``code_hash``, ``date``, ``scalars``, ``identical``, ``max_rel_diff``, ``worst``,
    ``dofs``, ``missing``, ``targets``, ``error``).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Mapping
from pathlib import Path

__all__ = [
    "SAFETY",
    "SAFETY_TWO_GRID",
    "checksum",
    "checksum_problem",
    "convergence_links",
    "missing_runs",
    "reproduced_by",
    "reproduction_text",
    "solved_with",
    "uncertainty_for",
    "uncertainty_note",
]

#: Roache's factor of safety for a three-grid study with the observed order
SAFETY = 1.25
#: Roache's factor of safety when the order is assumed, not observed
SAFETY_TWO_GRID = 3.0


def checksum(conv: Mapping) -> str:
    """sha256 of ``conv`` without its ``checksum``, as canonical JSON (sorted keys, no
    spaces; floats as Python writes them, which read back to the same value)."""
    body = {k: v for k, v in conv.items() if k != "checksum"}
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def checksum_problem(conv: Mapping) -> str | None:
    """Why ``conv`` cannot be trusted as written (its checksum does not match its content:
    edited by hand or damaged), or None. A study without a checksum (written before studies
    carried one) is taken as it is."""
    stored = conv.get("checksum")
    if stored is None:
        return None
    try:
        now = checksum(conv)
    except (TypeError, ValueError) as exc:
        return f"its content cannot be checked ({exc})"
    if stored != now:
        return "its checksum does not match its content (edited by hand or damaged)"
    return None


def missing_runs(conv: Mapping) -> list[str]:
    """Labels of the runs of its ladder a convergence study lacks: held as failed (an
    ``error``: out of memory, a timeout, a solver error) or skipped (``skipped``: too little
    free memory for an in-core run off the ladder, ``--min-free-gb``)."""
    failed = [
        str(r.get("label")) for r in conv.get("runs") or [] if isinstance(r, dict) and "error" in r
    ]
    skipped = [str(r.get("label")) for r in conv.get("skipped") or [] if isinstance(r, dict)]
    return failed + skipped


def solved_with(conv: Mapping) -> list[str]:
    """The source hashes of the code that solved a convergence study's runs (of the code that
    reduced it, for a study that does not list them)."""
    return sorted(set(conv.get("runs_code_hash") or [conv.get("code_hash")]))


def reproduced_by(conv: Mapping, source: str) -> dict | None:
    """The latest of a study's ``reproduced`` entries (a run solved again,
    ``python -m studies.convergence CASE --reproduce L``) by the code of hash ``source``."""
    mine = [e for e in conv.get("reproduced") or [] if e.get("code_hash") == source]
    return mine[-1] if mine else None


def reproduction_text(entry: Mapping) -> str:
    """A record's reproduction (a ``reproduced`` entry: its run, date, code and comparison)
    in words."""
    n, same = entry.get("scalars", 0), entry.get("identical", 0)
    if entry.get("error"):
        how = f"failed ({entry['error']})"
    elif same == n and not entry.get("missing"):
        how = f"every one of its {n} scalars the same to the bit"
    else:
        how = f"{same} of {n} scalars the same to the bit"
        d0, d1 = entry.get("dofs") or (None, None)
        if d0 != d1:
            how += f" (another mesh: {d0} DOFs recorded, {d1} now)"
        if entry.get("max_rel_diff") is not None:
            how += f", the others within {entry['max_rel_diff']:.1e} (largest: {entry['worst']})"
        if entry.get("missing"):
            how += f", {len(entry['missing'])} scalar(s) in one run only"
        for kind, t in sorted((entry.get("targets") or {}).items()):
            kinds = {"stress": "stresses"}.get(kind, f"{kind}s")
            how += f"; the targeted {kinds} within {t['max_rel_diff']:.1e} ({t['key']})"
    return (
        f"its run {entry.get('run')} solved again by code {entry.get('code_hash')} "
        f"({entry.get('date')}): {how}"
    )


def uncertainty_for(study: Mapping, label: str, source: str) -> dict:
    """The ``uncertainty`` entries of a summary solved as the run ``label`` from a convergence
    ``study`` (a convergence.json read from ``source``): ``uncertainty`` {key: relative} for
    every FE scalar (mesh-independent ones left out; None where the value is ~0),
    ``uncertainty_abs`` {key: in the scalar's unit} and ``uncertainty_source``. No run of that
    label: ``uncertainty`` None and a note."""
    src = {
        "convergence_study": source,
        "case": study.get("case"),
        "run": label,
        "positions": study.get("positions"),
        "code_hash": study.get("code_hash"),
    }
    if label not in study.get("labels", []):
        have = ", ".join(study.get("labels", [])) or "none"
        src["note"] = (
            f"the convergence study {source} has no run {label} (it has {have}): no uncertainty"
        )
        return {"uncertainty": None, "uncertainty_abs": None, "uncertainty_source": src}
    rel, absolute = {}, {}
    for key, s in study["scalars"].items():
        if s["status"] == "mesh-independent" or label not in s.get("uncertainty", {}):
            continue
        rel[key] = s["uncertainty"][label]
        absolute[key] = s["uncertainty_abs"][label]
    two = any(s.get("status") == "two-grid" for s in study["scalars"].values())
    src["method"] = "two-grid" if two else "three-grid"
    how = (
        f"Roache's two-grid GCI with Fs {SAFETY_TWO_GRID:g} and the formal order"
        if two
        else f"GCI with Fs {SAFETY}, or the spread of the levels where convergence is not monotone"
    )
    src["note"] = (
        f"relative discretisation uncertainty of each scalar of this run ({how}), "
        "from the study's position(s); a case sharing the gear set, scene and numerics uses "
        "the same study"
    )
    if study.get("sector_scatter_from"):
        src["sector_scatter_from"] = study["sector_scatter_from"]
        src["note"] += (
            "; the sector scatter under its root stresses' U as kept with "
            f"{study['sector_scatter_from']}"
        )
    return {"uncertainty": rel, "uncertainty_abs": absolute, "uncertainty_source": src}


def uncertainty_note(summaries: Mapping[str, Mapping]) -> str:
    """One line for a report: where its ± come from (the convergence study of each case),
    and which cases have none."""
    by_study: dict[str, list[str]] = {}
    without = []
    for name, s in summaries.items():
        src = s.get("uncertainty_source") or {}
        if s.get("uncertainty") and src.get("convergence_study"):
            two = " two levels only" if src.get("method") == "two-grid" else ""
            rec = src.get("recorded")
            if rec:  # a study kept in the repository (studies.uncertainty.RECORDS)
                commit = str(rec.get("git_revision"))[:10]
                two += f", recorded {rec.get('date', '?')} on commit {commit}"
            if src.get("code_changed"):
                two += "; solved by other code than today's"
                if src.get("reproduced"):
                    two += f" ({reproduction_text(src['reproduced'])})"
            label = f"{src['convergence_study']} ({src.get('run')}{two})"
            by_study.setdefault(label, []).append(name)
        else:
            without.append(name)
    parts = [f"{', '.join(names)} from {study}" for study, names in by_study.items()]
    text = (
        "± : discretisation uncertainty of the value at its mesh level (GCI with factor of "
        f"safety {SAFETY:g} from a Richardson extrapolation over mesh levels 0-2, or the spread "
        "of the levels where they do not converge monotonically; where only levels 0-1 fit, "
        f"Roache's two-grid GCI with factor of safety {SAFETY_TWO_GRID:g} and the formal "
        "order; a root stress read on a submodel: the sum of the driver's and the sector's U, "
        "each from its own ladder; an offset's ± as written under its table). The study "
        "solves one mesh position (roll 0): its relative U is carried to the case's means and "
        "cycle maxima; a value with no ± has no U in the study (an input, or within the CG "
        "noise); "
    )
    text += "; ".join(parts) if parts else "no case has one"
    if without and parts:
        text += f"; none for {', '.join(without)} (no convergence study for its gear set, "
        text += "scene and level: make convergence CASE=...)"
    elif without:
        text += " (make convergence CASE=... writes the study)"
    return text + "."


def convergence_links(summaries: Mapping[str, Mapping], report_dir: Path) -> list[str]:
    """Markdown lines for a case report: a link to the report and the speed-against-error
    chart of every convergence study its summaries take their uncertainty from (paths
    relative to ``report_dir``)."""
    studies = []
    for s in summaries.values():
        src = (s.get("uncertainty_source") or {}).get("convergence_study")
        if s.get("uncertainty") and src and Path(src).parent not in studies:
            studies.append(Path(src).parent)
    lines = []
    for folder in studies:
        rel = Path(os.path.relpath(folder.resolve(), Path(report_dir).resolve())).as_posix()
        lines += [f"- [{folder.name}: convergence study]({rel}/report.md)"]
        if (folder / "speed_error.png").is_file():
            lines += ["", f"![{folder.name} speed against error]({rel}/speed_error.png)", ""]
    return lines
