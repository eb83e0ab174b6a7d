"""The run of a diagnostic that solves named variants in one process
(:mod:`studies.convergence.driver_sizes`, :mod:`studies.convergence.sector_sizes`): a finished
variant is kept while the file's key is the run's (the case's inputs, the source hash, the
diagnostic's own source, which the source hash leaves out and which says what a variant's name
means, the level and the roll), and the file and its report are written after each variant (rank 0,
the outcome shared with every rank), so a run that stops part way keeps what it finished."""

from __future__ import annotations

import hashlib
import inspect
from collections.abc import Callable
from pathlib import Path

from mpi4py import MPI

from cases.study_case import inputs_hash, without_variant
from studies.files import atomic_write_text, on_root, read_json, write_json
from studies.provenance import code_hash


def tool_hash(solve: Callable) -> str:
    """A short hash of the source of the module that defines ``solve``."""
    source = inspect.getsource(inspect.getmodule(solve))
    return hashlib.sha256(source.encode()).hexdigest()[:16]


def variant_path(out: Path, case: str, stem: str, level: int, roll: float) -> Path:
    """``<out>/<case>/<stem>_L<level>.json``, tagged ``_roll<roll>`` for a position other than
    roll 0 (the convergence records'), so that each position keeps its own file."""
    tag = "" if roll == 0 else f"_roll{roll:.6g}"
    return out / case / f"{stem}_L{level}{tag}.json"


def run_variants(
    study,
    out: Path,
    stem: str,
    level: int,
    roll: float,
    names: list[str],
    solve: Callable,
    report: Callable[[dict], str],
    on_row: Callable[[dict, dict], None] | None = None,
) -> Path:
    """Solve the variants ``names`` not yet in their file (:func:`variant_path`) with
    ``solve(study, name, level, roll, comm, log)`` (a row with ``wall_s`` and
    ``peak_rss_mb``), in turn; ``on_row(data, row)`` may add to the file's head before the
    row is kept. Returns the file's path."""
    comm = MPI.COMM_WORLD
    path = variant_path(out, study.name, stem, level, roll)
    # a variant sets its sizes itself: the case's own sizes are not its inputs
    key = {
        "inputs": inputs_hash(without_variant(study)),
        "code_hash": code_hash(),
        "tool": tool_hash(solve),
        "level": level,
        "roll": roll,
    }
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

        def write() -> None:
            path.parent.mkdir(parents=True, exist_ok=True)
            write_json(path, data)
            atomic_write_text(path.with_suffix(".md"), report(data))

        on_root(comm, write, f"writing {path}")
        if comm.rank == 0:
            print(
                f"{name}: {row['wall_s']:.0f} s, peak {row['peak_rss_mb'] / 1024:.1f} GB",
                flush=True,
            )
    return path
