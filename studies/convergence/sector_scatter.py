"""Keep a root stress's sector scatter with a case's convergence record.

    python -m studies.convergence.sector_scatter --case 1-GB [--level 1] [--roll 0]
        [--out results/convergence]

reads the variants ``make sector-sizes`` solved at that level and roll
(:func:`studies.convergence.variant_file.variant_path`, :mod:`studies.convergence.sector_sizes`),
takes the spread of each root stress at every read fillet solved with more than one set of other
sizes on straight tets (:func:`studies.convergence.scatter.other_size_spreads`) and keeps it in the
record's
``sector_scatter`` (one entry per driver level, roll and read fillet; a later measurement
replaces an earlier one), then reduces the records again
(:func:`studies.convergence.driver.reduce_records`). From then on the sector part of each root
stress's U is at least that spread, in the record's report and in every summary whose ± come
from the record (:mod:`studies.convergence.scatter`), also after the ladder is recorded again
from the same inputs and case level (:func:`studies.convergence.driver.record`). Solves nothing.

A measurement at another position (``make sector-sizes SECTOR_ROLL=...``) adds an entry: the
floor is the largest spread over every position measured, whether or not the record's ladder
was solved there (the scatter is the sectors', and the reports print the cycle's maximum).
Refused, naming the field, where the file or the record's run of that level was solved from
other inputs than today's case file, or on another driver level than the record's case
level. A file solved by other code
than the record's runs is taken, and its source hash kept and printed beside the scatter: the
scatter between sector sizes is a property of the meshes, which that hash names. Exit status
0, 2 invalid input, 3 a file could not be read or written.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cases.study_case import inputs_hash, load_study_case, without_variant
from studies.cli import InputError, guarded
from studies.convergence.driver import (
    reduce_records,
    with_recorded_scatter,
    write_reduced,
    write_study,
)
from studies.convergence.scatter import level_inputs, other_size_spreads
from studies.convergence.variant_file import variant_path
from studies.files import ResultFileError, read_json
from studies.provenance import git_revision, utc_stamp
from studies.uncertainty import RECORDS, STUDY_FILE


def scatter_entries(sizes: dict) -> list[dict]:
    """The record entries of a ``sector_sizes`` file: one per read fillet with a spread."""
    key = sizes["key"]
    date = utc_stamp()
    return [
        {
            "level": sizes["level"],
            "roll": sizes["roll"],
            "fillet_mm": f,
            "variants": s["variants"],
            "geometry_order": 1,
            "code_hash": key["code_hash"],
            "spread": s["spread"],
            "recorded": {"date": date, "git_revision": git_revision()},
        }
        for f, s in other_size_spreads(sizes["variants"]).items()
    ]


def record_scatter(
    case: str, level: int, out: Path, records: Path = RECORDS, roll: float = 0.0
) -> Path:
    """Check the ``sector_sizes`` file of ``case``, ``level`` and ``roll`` against the case
    file and its record, keep its scatter in the record and reduce the records again;
    returns the record's path."""
    study = load_study_case(case)
    src = variant_path(out, study.name, "sector_sizes", level, roll)
    if not src.is_file():
        raise InputError(
            f"--level {level} --roll {roll:g}: no {src}; run make sector-sizes "
            f"CASE={study.name} SECTOR_LEVEL={level} SECTOR_ROLL={roll:g} "
            "first"
        )
    path = records / study.name / STUDY_FILE
    if not path.is_file():
        raise InputError(f"--case {study.name}: no convergence record in {records}")
    sizes, conv = read_json(src), read_json(path)
    inputs = inputs_hash(without_variant(study))  # the runs set their sizes themselves
    if sizes.get("key", {}).get("inputs") != inputs:
        raise InputError(
            f"{src}: solved from other inputs than today's case file "
            f"{study.name}; run make sector-sizes again"
        )
    if level_inputs(conv, level) != {inputs}:
        raise InputError(
            f"--case {study.name}: the record's level-{level} run was solved from "
            "other inputs than today's case file; record it again first"
        )
    if level != conv.get("case_level"):
        raise InputError(
            f"--level {level}: the record of {study.name} is of case level "
            f"{conv.get('case_level')}; its sector ladder is read on that "
            "level's driver"
        )
    new = scatter_entries(sizes)
    if not new:
        raise InputError(
            f"{src}: no read fillet was solved with more than one set of other "
            "sizes; add variants such as 1:0.1 2:0.1 3:0.1"
        )

    def same(a: dict, b: dict) -> bool:
        return (a["level"], a["roll"], a["fillet_mm"]) == (b["level"], b["roll"], b["fillet_mm"])

    kept = [e for e in conv.get("sector_scatter", []) if not any(same(e, n) for n in new)]
    write_study(path, {**conv, "sector_scatter": kept + new})
    reduce_records(records)
    carry_to_this_machine(out / study.name / STUDY_FILE, records)
    return path


def carry_to_this_machine(study_file: Path, records: Path) -> None:
    """The case's study of this machine's results (it stands before the record in the ±
    lookup, :mod:`studies.uncertainty`) takes the scatter just kept with the record, and is
    reduced again with it; a study that cannot be read is named and left."""
    if not study_file.is_file():
        return
    try:
        conv = read_json(study_file)
    except ResultFileError as exc:
        print(f"{study_file}: cannot be read ({exc}); it keeps no sector scatter")
        return
    if not isinstance(conv, dict) or "case_level" not in conv:
        return
    bare = {k: v for k, v in conv.items() if k not in ("sector_scatter", "sector_scatter_from")}
    carried = with_recorded_scatter(bare, records)
    if carried is not bare:
        write_reduced(carried, study_file.parent)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.convergence.sector_scatter", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--case", default="1-GB")
    ap.add_argument("--level", type=int, default=1, help="the driver's (global) level")
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad)")
    ap.add_argument("--out", type=Path, default=Path("results/convergence"))
    ap.add_argument("--records", type=Path, default=RECORDS, help=argparse.SUPPRESS)

    def run() -> None:
        args = ap.parse_args(argv)
        path = record_scatter(args.case, args.level, args.out, args.records, args.roll)
        for e in read_json(path)["sector_scatter"]:
            worst = max(e["spread"].items(), key=lambda kv: kv[1])
            print(
                f"{path}: level {e['level']}, roll {e['roll']:g}, {e['fillet_mm']:g} mm "
                f"({', '.join(e['variants'])}, code {e['code_hash']}): largest spread "
                f"{worst[0]} {worst[1]:.2%}"
            )

    return guarded(run)


if __name__ == "__main__":
    sys.exit(main())
