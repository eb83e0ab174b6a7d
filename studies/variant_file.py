"""The run of a diagnostic that solves named variants in one process
(:mod:`studies.driver_sizes`, :mod:`studies.sector_sizes`): a finished variant is kept while
the file's key (the case's inputs, the source hash, the level, the roll) is the run's, and
the file and its report are written after each variant, so a run that stops part way keeps
what it finished."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from mpi4py import MPI

from cases.study_case import inputs_hash
from studies.files import atomic_write_text, read_json, write_json
from studies.provenance import code_hash


def run_variants(study, out: Path, stem: str, level: int, roll: float, names: list[str],
                 solve: Callable, report: Callable[[dict], str],
                 on_row: Callable[[dict, dict], None] | None = None) -> Path:  # fmt: skip
    """Solve the variants ``names`` not yet in ``<out>/<case>/<stem>_L<level>.json`` with
    ``solve(study, name, level, roll, comm, log)`` (a row with ``wall_s`` and
    ``peak_rss_mb``), in turn; ``on_row(data, row)`` may add to the file's head before the
    row is kept. Returns the file's path."""
    comm = MPI.COMM_WORLD
    path = out / study.name / f"{stem}_L{level}.json"
    key = {"inputs": inputs_hash(study), "code_hash": code_hash(), "level": level, "roll": roll}
    data = {"case": study.name, "level": level, "roll": roll, "key": key, "variants": []}
    if path.is_file():
        old = read_json(path)
        if isinstance(old, dict) and old.get("key") == key:
            data = old  # finished variants of these inputs and code kept
        elif comm.rank == 0:
            print(f"{path}: solved from other inputs or code; starting afresh", flush=True)

    def log(line: str) -> None:
        if comm.rank == 0:
            print(line, flush=True)

    done = {r["variant"] for r in data["variants"]}
    for name in names:
        if name in done:
            continue
        row = solve(study, name, level, roll, comm, log)
        if on_row is not None:
            on_row(data, row)
        data["variants"].append(row)
        if comm.rank == 0:
            path.parent.mkdir(parents=True, exist_ok=True)
            write_json(path, data)
            atomic_write_text(path.with_suffix(".md"), report(data))
            print(f"{name}: {row['wall_s']:.0f} s, peak {row['peak_rss_mb'] / 1024:.1f} GB",
                  flush=True)  # fmt: skip
    return path
