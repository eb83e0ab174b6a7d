"""Convergence study of any case: h-levels and an element-degree step, Richardson
extrapolation of every reported scalar, the error and uncertainty of each run, the level to
use, a speed-against-error chart.

    python -m studies.convergence 1-GB [--levels 0 1 2] [--extra 0:2 ...] [--positions 1]
        [--out results/convergence] [--min-free-gb 16] [--no-reuse] [--split-root-stress]
        [--reduce-only] [--out-of-core 2 0:2] [--record] [--unless-recorded]
    python -m studies.convergence 1-GB --reproduce 0

Every (level, degree) run solves the case's first ``--positions`` mesh positions (equally
spaced over one base pitch, as ``studies.run``) in a fresh child process
(:mod:`studies.convergence.position_runs`), so the wall time and peak memory are those of the run
alone, and reduces them to the summary's scalars (means over the positions, stress maxima over
them). A run is written to ``<out>/<case>/runs/<run>.json`` and reused by a later study only
when it was solved from the same inputs, code, level, degree and positions. Two levels
(where the third does not fit in memory or time) give Roache's two-grid GCI
(:func:`studies.convergence.richardson.two_grid`), no extrapolation. ``--extra`` runs
(another degree) are compared with the h-ladder's extrapolation; each one is started only if
``MemAvailable`` is at least ``--min-free-gb`` (a level-0 P2 run of a case-1 branch peaks at
about 14 GB; a run out of core is not gated: 2B-GA's level-0 P2 peaks at 4.5 GB so) and is
otherwise skipped with the reason in the report. A run that fails (out
of memory, timeout, error) is recorded and the study goes on. ``--split-root-stress``: the
ladder runs also read the root stress on other sectors at their own global solution
(:func:`submodel_levels`), and the study splits the error of every root stress read on a
submodel into the driver's and the submodel's
(:func:`studies.convergence.reduction.root_stress_split`); in the main ``make`` for 1-GB
and 2B-GA (the case level's run reads the two finer sectors per loaded fillet, 0.1 and
0.08 mm: a 0.08 mm sector holds 4.3M P2 DOFs, about 10 min to mesh, set up and solve).
``--out-of-core L L:D ...``: these runs (a ladder level, or level:degree) keep their LU
factors on disk (``numerics.out_of_core``: the same answer, less memory, slower solves;
2B-GA's level 2: 23 GB of factors, a 5.7 GB peak).
``--reduce-only`` solves nothing: it reduces the stored runs of the same inputs again, from
whatever code solved them (after a change to the reduction alone: targets, extrapolation,
report), and the report names the code the runs came from.

``--record`` also copies the study (convergence.json with the date, commit and source hash
it was solved with, report.md, the chart) to ``studies/records/convergence/<case>/``, where
summaries find it when ``<out>`` has none (:mod:`studies.uncertainty`); ``--unless-recorded``
runs nothing when a record of the same match key and ladder exists (the main ``make``).
``--reproduce L`` solves a record's level-L run again by today's code and adds the comparison
of every scalar to the record (:func:`reproduce`): the cheap evidence that a record solved by
other code still stands (a level-0 run: 2-15 min, against hours for the ladder).

Writes ``<out>/<case>/convergence.json`` (:mod:`studies.convergence.reduction`: per scalar
the values, status, observed order, extrapolated value, error and uncertainty of every run;
the recommended run; what a summary must share to use the study, :mod:`studies.uncertainty`),
``report.md`` and ``speed_error.png`` (:mod:`studies.convergence.report`). Exit status:
0 done (runs may have failed: see the report), 2 invalid input, 3 a file could not be
written.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import sys
from pathlib import Path

from cases.study_case import MAX_POSITIONS, inputs_hash, load_study_case, without_variant
from meshing import sizing
from meshing.submodel import submodel_level
from postprocess.convergence_record import checksum, missing_runs, reproduction_text
from postprocess.run_scalars import VARIANT_KEYS, run_label
from studies.cli import InputError, StudyFailed, guarded
from studies.convergence.position_runs import print_row, run_child, solve_run
from studies.convergence.reduction import compare_runs, reduce_study
from studies.convergence.report import CHART, speed_error_chart, write_report
from studies.convergence.scatter import carried_scatter
from studies.files import ResultFileError, read_json, write_json
from studies.memory import mem_available_gb
from studies.provenance import code_hash, git_revision, utc_stamp
from studies.uncertainty import RECORDS, STUDY_FILE, match_key, recorded, same_match

LADDER_DEGREE = 1
POSITIONS_NOTE = {
    1: "One mesh position (sun angle 0). The discretisation error of a mean moment is set by "
    "the element and grid sizes on the flanks, the same at every position, so its relative "
    "error at one position stands for the mean over the positions (1-GB, level 0 to 1: the "
    "change of My_pin and the LOA moments at one position is within 0.3 points of the change "
    "of their five-position means). The cycle maxima of the contact and root stresses are a "
    "weaker case: which grid point or fillet carries the maximum changes from position to "
    "position, so their one-position errors only indicate the size; `--positions 5` "
    "(`make convergence POSITIONS=5`) studies exactly the summary's means and maxima.",
}


#: a run of a study: (level, degree, flank level, fillet level), the last two None for the
#: ladder's own sizes (:func:`meshing.sizing.with_sizes`)
Run = tuple[int, int, int | None, int | None]


def _variant(run: Run) -> dict[str, int]:
    """The sizes ``run`` takes from other levels, as its row keeps them."""
    return {k: v for k, v in zip(VARIANT_KEYS, run[2:], strict=True) if v is not None}


def _reuse_key(study, run: Run, positions: int, split: bool = False, ooc: bool = False) -> dict:
    level, degree, flank, fillet = run
    return {
        # a run sets its sizes itself: the case's own (model.flank_level, ...) are not its inputs
        "inputs_hash": inputs_hash(without_variant(study)),
        "code_hash": code_hash(),
        "level": level,
        "degree": degree,
        "flank_level": flank,
        "fillet_level": fillet,
        "positions": positions,
        "submodel_levels": list(submodel_levels(study, run) if split else ()),
        # the same answer, but another time and memory on the chart
        "out_of_core": ooc,
    }


def submodel_levels(study, run: Run) -> tuple[int, ...]:
    """The submodels (global levels whose sector, :func:`meshing.submodel.submodel_level`,
    is read) a ladder run also reads the root stress on, at its own global solution
    (:func:`studies.convergence.reduction.root_stress_split`): the run at the case's level
    the two sectors above its own where both exist (the submodel ladder at a fixed driver:
    the whole sector refined, fillet, flank and tooth), else the nearest finer one and the
    nearest coarser one, or the two coarser ones at the finest; every other ladder run the
    case level's sector (the driver ladder at a fixed submodel). None off the ladder or
    without submodels.

    Above, not around: Richardson and the GCI hold only on grids in the asymptotic range,
    and level 0's sector (0.2 mm fillets) is not (it scatters by up to 3 % when one of its
    sizes changes, :data:`meshing.submodel.SECTOR_STEP`). 1-GB at roll 0, level-1 driver,
    sun on ISO's 30 deg line: 788 / 822 / 810 MPa on the 0.2 / 0.15 / 0.1 mm sectors
    (oscillatory, U the whole 4.1 % spread), 822 / 810 / 807 MPa on the 0.15 / 0.1 /
    0.08 mm ones (monotone, observed order 1.8, GCI 3.4 %). ``run``: (level, degree, flank
    level, fillet level), :data:`Run`.

    The whole sector, not its fillet alone: 1-GB at roll 0, sun fillet on a 0.2 mm
    submodel, its other sizes those of level 1 / level 2: 844 / 857 MPa on the level-1
    driver, 838 / 850 MPa on the level-2 driver; a fillet-only ladder would leave that
    part of the submodel's error in the driver's."""
    level, degree = run[:2]
    if degree != LADDER_DEGREE or _variant(run) or study.numerics.root_stress != "submodel":
        return ()
    own = study.model.level
    if level != own:
        return (own,)
    top = len(sizing.LEVELS) - 1
    fillets = {submodel_level(own).fillet}
    picked = []
    for k in (own + 1, own + 2, own - 1, own - 2, own - 3):  # finer first, then coarser
        if 0 <= k <= top and submodel_level(k).fillet not in fillets and len(picked) < 2:
            fillets.add(submodel_level(k).fillet)
            picked.append(k)
    return tuple(sorted(picked))


def _parse_extra(text: str, option: str = "--extra") -> Run:
    """``L:D`` (level L, degree D), ``L:D:F`` (with the active flanks and contact grid of
    level F) or ``L:D:F:R`` (and the refined fillets of level R; :func:`meshing.sizing.
    with_sizes`), checked."""
    try:
        parts = [int(v) for v in text.split(":")]
        if not 2 <= len(parts) <= 4:
            raise ValueError(text)
    except ValueError as exc:
        raise InputError(
            f"{option} {text!r}: must be LEVEL:DEGREE, e.g. 0:2, LEVEL:DEGREE:FLANK_LEVEL, "
            "e.g. 1:1:2 (level 1 with level 2's flanks and contact grid), or "
            "LEVEL:DEGREE:FLANK_LEVEL:FILLET_LEVEL, e.g. 1:1:2:2 (and level 2's refined fillets)"
        ) from exc
    level, degree, flank, fillet = (*parts, None, None)[:4]
    # a size of the run's own level is no variant: 1:1:1 is L1P1, 1:1:2:1 is L1P1F2
    if degree not in (1, 2):
        raise InputError(f"{option} {text!r}: the degree must be 1 or 2")
    for name, lv in (("level", level), ("flank level", flank), ("fillet level", fillet)):
        if lv is None:
            continue
        try:
            sizing.check_level(lv)
        except ValueError as exc:
            raise InputError(f"{option} {text!r}: the {name}: {exc}") from exc
    return (level, degree, *(None if k == level else k for k in (flank, fillet)))


def _check(args) -> list[Run]:
    """The runs of the study (ladder, then extras), checked; InputError names the option."""
    for lv in args.levels:
        try:
            sizing.check_level(lv)
        except ValueError as exc:
            raise InputError(f"--levels: {exc}") from exc
    if args.reduce_only and args.no_reuse:
        raise InputError("--reduce-only and --no-reuse: give one (nothing would be left to reduce)")
    if len(set(args.levels)) < 2:
        raise InputError(
            f"--levels {args.levels}: give at least two different levels (three for "
            "Richardson extrapolation; two give Roache's two-grid GCI only)"
        )
    if not 1 <= args.positions <= MAX_POSITIONS:
        raise InputError(f"--positions {args.positions}: must be 1 to {MAX_POSITIONS}")
    runs = [(lv, LADDER_DEGREE, None, None) for lv in sorted(set(args.levels))]
    for e in args.extra:
        run = _parse_extra(e)
        if run not in runs:
            runs.append(run)
    args.ooc_runs = set()
    for item in args.out_of_core:
        run = (
            (int(item), LADDER_DEGREE, None, None)
            if item.isdigit()
            else _parse_extra(item, "--out-of-core")
        )
        if run not in runs:
            raise InputError(
                f"--out-of-core {item}: not a run of this study "
                f"({', '.join(run_label(*r) for r in runs)})"
            )
        args.ooc_runs.add(run)
    return runs


def _reused(args, study, run: Run, folder: Path) -> dict | None:
    """The finished run in ``runs/<run>.json`` if it was solved with this study's key (with
    ``--reduce-only``: with this study's key but for the code's hash, which the row keeps)."""
    path = folder / "runs" / f"{run_label(*run)}.json"
    if args.no_reuse or not path.is_file():
        return None
    try:
        old = read_json(path)
    except ResultFileError:
        return None
    key = _reuse_key(study, run, args.positions, args.split_root_stress, run in args.ooc_runs)
    if not isinstance(old, dict) or "error" in old or not isinstance(old.get("reuse_key"), dict):
        return None
    ignored = ("code_hash",) if args.reduce_only else ()
    # runs stored before the options
    stored = {"out_of_core": False, "flank_level": None, "fillet_level": None, **old["reuse_key"]}
    stored = {k: v for k, v in stored.items() if k not in ignored}
    if stored == {k: v for k, v in key.items() if k not in ignored}:
        old["reused"] = True
        return old
    return None


def _one_run(args, study, run: Run, folder: Path) -> dict:
    """The row of one run: reused (:func:`_reused`), else solved in a child process and
    written to ``runs/<run>.json``."""
    old = _reused(args, study, run, folder)
    if old is not None:
        return old
    level, degree = run[:2]
    label = run_label(*run)
    if args.reduce_only:
        raise InputError(
            f"--reduce-only: no finished run {label} in {folder / 'runs'} solved from these "
            "inputs, positions and submodel readings; run the study without --reduce-only"
        )
    child = ["--one", args.case, str(level), str(degree), str(args.positions)]
    subs = submodel_levels(study, run) if args.split_root_stress else ()
    if subs:
        child += ["--submodels", *(str(k) for k in subs)]
    for key, v in _variant(run).items():
        child += [f"--{key.replace('_', '-')}", str(v)]
    ooc = run in args.ooc_runs
    if ooc:
        child += ["--out-of-core-run"]
    log = folder / "runs" / f"{label}.log"  # the child's progress, a line per submodel
    row = run_child("studies.convergence.driver", child, level, degree, args.timeout, log)
    row.update(_variant(run))  # a failed child's row lacks them
    row["label"], row["reused"] = label, False
    row["reuse_key"] = _reuse_key(study, run, args.positions, args.split_root_stress, ooc)
    write_json(folder / "runs" / f"{label}.json", row)
    return row


def _say(row: dict) -> None:
    if "error" in row:
        print(f"{row['label']}: FAILED {row['error']}", flush=True)
        return
    t = row["time_s"]
    print(
        f"{row['label']}: {row['dofs']} DOFs, {t['total']:.1f} s (factorization "
        f"{t['factorization']:.1f}, compliance {t['compliance']:.1f}), "
        f"{row['peak_rss_mb'] / 1024:.1f} GB" + (" (reused)" if row.get("reused") else ""),
        flush=True,
    )


def ladder(args, runs: list[tuple[int, int]]) -> dict:
    """What a record must share with a study to stand for it (:func:`studies.uncertainty.recorded`):
    the runs asked for, the positions and the root-stress split (out of core or not gives the
    same answer)."""
    return {
        "runs": [run_label(*r) for r in runs],
        "positions": args.positions,
        "split_root_stress": bool(args.split_root_stress),
    }


def record(folder: Path, conv: dict, records: Path = RECORDS) -> Path:
    """Copy the study in ``folder`` to ``<records>/<case>/`` with the date and commit it was
    recorded on (``recorded``; the source hash of its runs is the study's ``runs_code_hash``);
    returns the record's convergence.json. The sector-scatter measurements of the record it
    replaces stay where they are of the same sectors
    (:func:`studies.convergence.scatter.carried_scatter`), and the record is reduced with
    them; a record it replaces that cannot be read carries nothing (said on stdout: ``make
    sector-scatter`` keeps them again)."""
    dest = records / conv["case"]
    dest.mkdir(parents=True, exist_ok=True)
    prev = dest / STUDY_FILE
    kept = []
    if prev.is_file():
        try:
            kept = carried_scatter(read_json(prev), conv)
        except ResultFileError as exc:
            print(
                f"{conv['case']}: the record it replaces cannot be read ({exc}): no sector "
                "scatter carried over (make sector-scatter keeps it again)"
            )
    rec = {
        **{k: v for k, v in conv.items() if k != "sector_scatter_from"},  # its own now
        "recorded": {
            "date": utc_stamp(),
            "git_revision": git_revision(),
        },
    }
    if kept:
        return write_reduced({**rec, "sector_scatter": kept}, dest)
    write_study(dest / STUDY_FILE, rec)  # reduced, reported and charted in ``folder``
    for name in ("report.md", CHART):
        if (folder / name).is_file():
            shutil.copyfile(folder / name, dest / name)
    return dest / STUDY_FILE


def write_reduced(rec: dict, dest: Path) -> Path:
    """Reduce ``rec`` by today's code and write it, its chart and report to ``dest``."""
    rec = reduce_study(rec)
    write_study(dest / STUDY_FILE, rec)
    if not speed_error_chart(rec, dest / CHART):
        (dest / CHART).unlink(missing_ok=True)
    write_report(rec, dest)
    return dest / STUDY_FILE


def write_study(path: Path, conv: dict) -> None:
    """Write a study (a convergence.json) with its checksum
    (:func:`postprocess.convergence_record.checksum`), so the ± lookup knows an edited or
    damaged one."""
    write_json(path, {**conv, "checksum": checksum(conv)})


def with_recorded_scatter(conv: dict, records: Path = RECORDS) -> dict:
    """``conv`` (a study of this machine, not yet reduced) with the sector scatter a record of
    its match key keeps for the same sectors (:func:`studies.convergence.scatter.carried_scatter`:
    one match key, case level and case-level inputs). The summaries read a study as written
    (:mod:`postprocess.convergence_record`) and this machine's study stands before the record:
    without the carry its root stresses' ± would lack the floor the record's have."""
    if conv.get("sector_scatter") or records is None:
        return conv
    for path in sorted(Path(records).glob(f"*/{STUDY_FILE}")):
        try:
            rec = read_json(path)
        except ResultFileError:
            continue  # a damaged record lends nothing; the ± lookup names it
        kept = carried_scatter(rec, conv) if isinstance(rec, dict) else []
        if kept:
            print(
                f"{conv['case']}: the sector scatter kept with {path} floors its root stresses' U"
            )
            return {**conv, "sector_scatter": kept, "sector_scatter_from": str(path)}
    return conv


def reduce_records(records: Path = RECORDS) -> list[Path]:
    """Reduce every record under ``records`` again by today's code (after a change to the
    reductions, :func:`studies.convergence.reduction.reduce_study`): its convergence.json's
    ``scalars`` and ``recommendation``, its report and chart; its runs and their source
    hash stay. A record written before the study kept ``case_level`` takes its case's level
    from the case file. Returns the records' convergence.json files."""
    done = []
    for path in sorted(Path(records).glob(f"*/{STUDY_FILE}")):
        conv = read_json(path)
        if "case_level" not in conv:
            conv["case_level"] = load_study_case(conv["case"]).model.level
        done.append(write_reduced(conv, path.parent))
    return done


def _record_of(case, records: Path, option: str) -> tuple[Path, dict]:
    """(path, study) of ``case``'s record under ``records``, which must have its match key;
    :class:`InputError` naming ``option`` otherwise."""
    path = Path(records) / case.name / STUDY_FILE
    if not path.is_file():
        raise InputError(f"{option}: no record of {case.name} in {records}")
    rec = read_json(path)
    if not same_match(rec.get("match"), match_key(case)):
        raise InputError(
            f"{option}: the record {path} is of another gear set, scene or numerics than "
            f"{case.name}'s (record it again)"
        )
    return path, rec


def _same_inputs(case, row: dict, option: str) -> None:
    """:class:`InputError` unless the record's run ``row`` was solved from ``case``'s inputs."""
    have = (row.get("reuse_key") or {}).get("inputs_hash")
    today = inputs_hash(without_variant(case))
    if have != today:
        raise InputError(
            f"{option}: {case.name}'s inputs changed since the record (its inputs hash "
            f"{(have or '?')[:12]}, today's {today[:12]}): record it again"
        )


def _solve_as_recorded(args, case, rec: dict, run: Run, ooc: bool) -> dict:
    """The row of ``run`` solved (or reused, :func:`_one_run`) as the record ``rec``'s ladder
    was (its positions and root-stress readings), its factors on disk with ``ooc``."""
    lad = rec["ladder"]
    args.positions, args.split_root_stress = lad["positions"], lad["split_root_stress"]
    args.ooc_runs = {run} if ooc else set()
    args.reduce_only = False
    folder = args.out / case.name
    (folder / "runs").mkdir(parents=True, exist_ok=True)
    row = _one_run(args, case, run, folder)
    _say(row)
    return row


def reproduce(args) -> dict:
    """Solve the recorded run at level ``args.reproduce`` again by today's code, as the
    record solved it (its positions, submodel readings, out of core or not), compare every
    scalar (:func:`studies.convergence.reduction.compare_runs`) and add the comparison to the
    record's ``reproduced`` list (one entry per run and source hash, the latest kept). A
    record solved by other code stands for today's only as far as this shows: summaries
    quote it beside the record's ± (:mod:`studies.uncertainty`). The run is kept under
    ``<out>/<case>/runs`` and reused by the next full study of the same code."""
    case = load_study_case(args.case)
    path, rec = _record_of(case, args.records, "--reproduce")
    label = run_label(args.reproduce, LADDER_DEGREE)
    old = next((r for r in rec.get("runs", []) if r.get("label") == label), None)
    if old is None or "error" in old:
        have = ", ".join(r.get("label", "?") for r in rec.get("runs", []) if "error" not in r)
        raise InputError(
            f"--reproduce {args.reproduce}: the record has no finished run {label} (it has {have})"
        )
    _same_inputs(case, old, "--reproduce")
    run = (args.reproduce, LADDER_DEGREE, None, None)
    row = _solve_as_recorded(args, case, rec, run, bool(old["reuse_key"].get("out_of_core")))
    now = utc_stamp()
    entry = {"run": label, "code_hash": code_hash(), "git_revision": git_revision(), "date": now}
    if "error" in row:
        entry.update(error=row["error"], scalars=0, identical=0)
    else:
        entry.update(compare_runs(old, row))
    keep = [
        e
        for e in rec.get("reproduced") or []
        if (e.get("run"), e.get("code_hash")) != (label, entry["code_hash"])
    ]
    rec["reproduced"] = [*keep, entry]
    write_study(path, rec)
    write_report(rec, path.parent)
    print(f"{case.name}: {reproduction_text(entry)}; written to {path}", flush=True)
    return entry


def add_to_record(args) -> Path:
    """Solve the off-ladder run ``args.add_to_record`` (``L:D`` or ``L:D:F``) by today's code
    as the record's ladder was solved (its positions and root-stress readings; out of core
    with ``--out-of-core L:D[:F]`` naming it) and add it to the record: its runs and
    labels, its ``ladder`` (so that ``--unless-recorded`` with this run among the
    ``--extra`` finds the record) and the source hashes of its runs; then reduce the record
    again (the run judged against the ladder's extrapolation,
    :func:`studies.convergence.reduction.scalar_table`). The ladder keeps the code that
    solved it, which the report names; that it stands for today's is what the record's
    reproductions (``--reproduce``) show. A run of the record with this label is replaced;
    a run that fails adds nothing (exit 1)."""
    case = load_study_case(args.case)
    option = "--add-to-record"
    path, rec = _record_of(case, args.records, option)
    run = _parse_extra(args.add_to_record, option)
    label = run_label(*run)
    if run[1] == LADDER_DEGREE and not _variant(run):
        raise InputError(
            f"{option} {args.add_to_record}: {label} is a ladder run (give "
            "another degree, or a flank or fillet level)"
        )
    finished = [r for r in rec.get("runs", []) if "error" not in r]
    if not finished:
        raise InputError(f"{option}: the record {path} has no finished run")
    _same_inputs(case, finished[0], option)
    ooc = [
        x for x in args.out_of_core if not x.isdigit() and _parse_extra(x, "--out-of-core") == run
    ]
    lad = rec["ladder"]
    row = _solve_as_recorded(args, case, rec, run, bool(ooc))
    if "error" in row:
        log = args.out / case.name / "runs" / f"{label}.log"
        raise StudyFailed(
            f"{label} failed ({row['error']}; its log: {log}): nothing added to {path}"
        )
    runs = [r for r in rec["runs"] if r.get("label") != label] + [row]
    rec.update(
        runs=runs,
        labels=[r["label"] for r in runs if "error" not in r],
        ladder={**lad, "runs": [*(x for x in lad["runs"] if x != label), label]},
        runs_code_hash=sorted({r["reuse_key"]["code_hash"] for r in runs if "reuse_key" in r}),
        code_hash=code_hash(),
        skipped=[x for x in rec.get("skipped") or [] if x.get("label") != label],
    )
    added = {
        **rec.get("added", {}),
        label: {"date": utc_stamp(), "git_revision": git_revision(), "code_hash": code_hash()},
    }
    rec["added"] = added
    out = write_reduced(rec, path.parent)
    print(f"added {label} to {out}", flush=True)
    return out


def study(args) -> Path | None:
    """Run (or reuse) every run, then write convergence.json, the chart and the report
    (and the record, ``--record``); nothing with ``--unless-recorded`` and a record."""
    case = load_study_case(args.case)
    runs = _check(args)
    if args.unless_recorded:
        have = recorded(case, ladder(args, runs), args.records)
        if have is not None:
            print(
                f"{case.name}: the recorded study {have} has this gear set, scene, numerics "
                "and ladder: nothing to run (make convergence-main RECORD=1 runs it again)"
            )
            return None
    folder = args.out / case.name
    (folder / "runs").mkdir(parents=True, exist_ok=True)
    rows, skipped = [], []
    for run in runs:
        level, degree = run[:2]
        label = run_label(*run)
        extra = degree != LADDER_DEGREE or bool(_variant(run))
        free = mem_available_gb()
        which = {"label": label, "level": level, "degree": degree, **_variant(run)}
        if extra and args.reduce_only and _reused(args, case, run, folder) is None:
            why = "no stored run of these inputs to reduce (--reduce-only)"
            skipped.append({**which, "why": why})
            print(f"{label}: skipped, {why}", flush=True)
            continue
        in_core = run not in args.ooc_runs  # out of core: a few GB, no gate
        if (
            extra
            and in_core
            and free < args.min_free_gb
            and _reused(args, case, run, folder) is None
        ):
            why = (
                f"MemAvailable {free:.1f} GB < {args.min_free_gb:g} GB asked for (--min-free-gb;"
                " a level-0 P2 run of a case-1 branch peaks at about 14 GB)"
            )
            skipped.append({**which, "why": why})
            print(f"{label}: skipped, {why}", flush=True)
            continue
        row = _one_run(args, case, run, folder)
        rows.append(row)
        _say(row)
    conv = {
        "case": case.name,
        "description": case.description,
        "case_level": case.model.level,
        "match": match_key(case),
        "code_hash": code_hash(),
        "runs_code_hash": sorted({r["reuse_key"]["code_hash"] for r in rows if "reuse_key" in r}),
        "positions": args.positions,
        "positions_note": POSITIONS_NOTE.get(
            args.positions,
            f"{args.positions} mesh positions over one base pitch (means and maxima over them).",
        ),
        "ladder_degree": LADDER_DEGREE,
        "ladder": ladder(args, runs),
        "labels": [r["label"] for r in rows if "error" not in r],
        "runs": rows,
        "skipped": skipped,
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
    }
    conv = reduce_study(with_recorded_scatter(conv, args.records))
    write_study(folder / STUDY_FILE, conv)
    if not speed_error_chart(conv, folder / CHART):
        (folder / CHART).unlink(missing_ok=True)
    report = write_report(conv, folder)
    print(f"{conv['recommendation']['note']}\nwrote {folder / STUDY_FILE} and {report}")
    if args.record:
        failed = missing_runs(conv)
        if failed:
            raise InputError(
                f"--record: run(s) {', '.join(failed)} failed or skipped ({report}); a record "
                "needs every run of its ladder, so nothing was recorded (the study stays in "
                f"{folder})"
            )
        print(f"recorded {record(folder, conv, args.records)}")
    return report


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.convergence", description=__doc__.splitlines()[0]
    )
    ap.add_argument("case", nargs="?", help="case name (cases/<name>.toml) or case file path")
    ap.add_argument(
        "--levels",
        type=int,
        nargs="+",
        default=[0, 1, 2],
        help="h-levels at degree 1 (the three finest are extrapolated; two: the two-grid GCI)",
    )
    ap.add_argument(
        "--extra",
        nargs="*",
        default=["0:2"],
        metavar="L:D",
        help="runs off the ladder, e.g. 0:2 (level 0, P2), 1:1:2 (level 1 with level 2's "
        "flanks and contact grid) or 1:1:2:2 (and level 2's refined fillets); none: --extra",
    )
    ap.add_argument("--positions", type=int, default=1, help="mesh positions per run")
    ap.add_argument("--out", type=Path, default=Path("results/convergence"))
    ap.add_argument(
        "--min-free-gb",
        type=float,
        default=16.0,
        help="start an --extra run only with this much memory available",
    )
    ap.add_argument("--timeout", type=float, default=3600.0, help="per run (s)")
    ap.add_argument("--no-reuse", action="store_true", help="solve every run again")
    ap.add_argument(
        "--reduce-only",
        action="store_true",
        help="solve nothing: reduce the stored runs of these inputs again, whatever code "
        "solved them (after a change to the reduction; the report names the runs' code)",
    )
    ap.add_argument(
        "--split-root-stress",
        action="store_true",
        help="study the root stress's driver and submodel errors apart (extra submodel readings)",
    )
    ap.add_argument(
        "--out-of-core",
        nargs="*",
        default=[],
        metavar="L|L:D",
        help="solve these runs with the LU factors on disk (numerics.out_of_core: the same "
        "answer, less memory, slower solves)",
    )
    ap.add_argument(
        "--record",
        action="store_true",
        help="copy the study to studies/records/convergence/<case>/ (summaries use it where "
        "the results folder has no study)",
    )
    ap.add_argument(
        "--unless-recorded",
        action="store_true",
        help="run nothing when a record of this gear set, scene, numerics and ladder exists",
    )
    ap.add_argument(
        "--reduce-records",
        action="store_true",
        help="solve nothing: reduce every recorded study again by today's code (after a change "
        "to the reductions; the records' runs stay)",
    )
    ap.add_argument(
        "--reproduce",
        type=int,
        metavar="L",
        help="solve the record's level-L run again by today's code (as recorded) and add "
        "the comparison of every scalar to the record (a record solved by other code)",
    )
    ap.add_argument(
        "--add-to-record",
        metavar="L:D[:F[:R]]",
        help="solve this off-ladder run by today's code as the record's ladder was solved "
        "and add it to the record (e.g. 1:1:2: level 1 with level 2's flanks and contact grid; "
        "with --out-of-core naming it too: its factors on disk)",
    )
    ap.add_argument("--records", type=Path, default=RECORDS, help=argparse.SUPPRESS)
    ap.add_argument("--traceback", action="store_true", help="print tracebacks of errors")
    ap.add_argument("--out-of-core-run", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--one", nargs=4, metavar=("CASE", "L", "D", "N"), help=argparse.SUPPRESS)
    ap.add_argument("--submodels", type=int, nargs="*", default=[], help=argparse.SUPPRESS)
    ap.add_argument("--flank-level", type=int, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--fillet-level", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        case, level, degree, n = args.one
        return guarded(
            lambda: print_row(
                solve_run(
                    case,
                    int(level),
                    int(degree),
                    int(n),
                    numerics={"out_of_core": True} if args.out_of_core_run else None,
                    submodel_levels=tuple(args.submodels),
                    flank_level=args.flank_level,
                    fillet_level=args.fillet_level,
                )
            ),
            traceback=True,
        )
    if args.reduce_records:

        def reduce_and_say() -> None:
            for path in reduce_records(args.records):
                print(f"reduced again: {path}")

        return guarded(reduce_and_say)
    if not args.case:
        ap.error("give the case: python -m studies.convergence 1-GB")
    if args.reproduce is not None:
        return guarded(lambda: reproduce(args), traceback=args.traceback)
    if args.add_to_record is not None:
        return guarded(lambda: add_to_record(args), traceback=args.traceback)
    return guarded(lambda: study(args), traceback=args.traceback)


if __name__ == "__main__":
    sys.exit(main())
