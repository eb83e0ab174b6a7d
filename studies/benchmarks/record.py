"""Keep a benchmark's files in the repository, stamped with where and by what they were measured.

    python -m studies.benchmarks.record results/bench/solver.json results/bench/solver.md ...
    make record-bench BENCH="solver linear_solver"

copies each file to ``studies/records/bench/`` and writes beside them ``recorded.json``:
per file its date, commit, source hash and machine (CPUs, platform). The performance page of
the docs is built from what is there (``docs/_ext/records_table.py``): a figure lives in the
file its benchmark wrote, never in prose. A later recording of the same file replaces it.
Exit status 0, 2 a file that is not there or not a benchmark's (.json, .md, .png).
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import sys
from pathlib import Path

from studies.cli import InputError, guarded
from studies.files import read_json, write_json
from studies.provenance import code_hash, git_revision, utc_stamp

#: where the recorded benchmark files live (kept in the repository)
RECORDS = Path(__file__).resolve().parents[1] / "records" / "bench"
STAMPS = "recorded.json"
KINDS = (".json", ".md", ".png")


def record(files: list[Path], records: Path = RECORDS) -> Path:
    """Copy ``files`` to ``records`` and stamp each in ``recorded.json``; returns its path."""
    for f in files:
        if not f.is_file():
            raise InputError(f"{f}: no such file (run the benchmark first: make help)")
        if f.suffix not in KINDS or f.name == STAMPS:
            raise InputError(f"{f}: a benchmark's file is one of {', '.join(KINDS)}")
    records.mkdir(parents=True, exist_ok=True)
    stamps_path = records / STAMPS
    stamps = read_json(stamps_path) if stamps_path.is_file() else {}
    stamp = {
        "date": utc_stamp(),
        "git_revision": git_revision(),
        "code_hash": code_hash(),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
    }
    for f in files:
        shutil.copyfile(f, records / f.name)
        stamps[f.name] = stamp
        print(f"recorded {records / f.name}")
    write_json(stamps_path, dict(sorted(stamps.items())))
    return stamps_path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m studies.benchmarks.record", description=__doc__.splitlines()[0]
    )
    ap.add_argument("files", nargs="+", type=Path, help="files a benchmark wrote")
    ap.add_argument("--records", type=Path, default=RECORDS, help=argparse.SUPPRESS)

    def run() -> None:
        args = ap.parse_args(argv)
        record(args.files, args.records)

    return guarded(run)


if __name__ == "__main__":
    sys.exit(main())
