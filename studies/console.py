"""The console command ``planetary-fe`` (``[project.scripts]``)::

    planetary-fe run CASE [CASE ...] [options]   solve cases (python -m studies.run)
    planetary-fe sweep CASE --set FIELD=V1,V2    one field over several values (studies.sweep)
    planetary-fe check CASE [CASE ...]           validate case files, solve nothing
    planetary-fe report [--results DIR]          the one-page report of results/
    planetary-fe COMMAND --help

``run`` under MPI: ``mpiexec -n 2 planetary-fe run CASE``. Exit codes are those of
:mod:`studies.cli` (0 ok, 1 a position failed, 2 invalid input, 3 files, 4 MPI ranks out of
step, 5 unexpected, 130 interrupted). The heavy modules (DOLFINx, gmsh) are imported only by
the command that needs them, so ``check`` and ``--help`` answer at once.
"""

from __future__ import annotations

import argparse
import sys
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from studies.cli import EXIT_INVALID_INPUT, EXIT_OK, exit_code, guarded, one_line, with_path

PROG = "planetary-fe"
COMMANDS = {
    "run": "solve one or more cases: mesh positions -> summary.json, contact patterns, pictures",
    "sweep": "one field of a case or its gear set over several values: a table and a plot",
    "check": "validate case files (and their gear sets) without solving",
    "report": "write the one-page report of everything under the results folder",
}


def _version() -> str:
    try:
        return version("planetary-fe")
    except PackageNotFoundError:  # run from a source tree that was not installed
        return "unknown"


def _usage() -> str:
    width = max(map(len, COMMANDS))
    rows = "\n".join(f"  {c:<{width}}  {text}" for c, text in COMMANDS.items())
    return (
        f"usage: {PROG} COMMAND [options]\n\ncommands:\n{rows}\n\n"
        f"'{PROG} COMMAND --help' for the options of one; "
        f"MPI: mpiexec -n N {PROG} run CASE\n"
    )


def run(argv: list[str]) -> int:
    from studies.run import main  # imports DOLFINx

    return main(argv, prog=f"{PROG} run")


def sweep(argv: list[str]) -> int:
    from studies.sweep import main  # imports DOLFINx

    return main(argv, prog=f"{PROG} sweep")


def report(argv: list[str]) -> int:
    from studies.paper_report import main

    return guarded(lambda: main(argv, prog=f"{PROG} report"))


def _describe(study) -> str:
    """One line of what a valid case will solve."""
    from cases.study_case import case_sizes
    from postprocess.run_scalars import run_label

    gs = study.gearset
    level, other = case_sizes(study)
    label = run_label(
        level, study.numerics.degree, other.get("flank_level"), other.get("fillet_level")
    )
    return (
        f"{study.name}: valid: gear set {gs.name} ({gs.kind.replace('_', ' ')}, {gs.planets} "
        f"planets, {gs.input_torque:g} N m on the sun), scene {study.model.scene}, sizes "
        f"{label}, {study.model.positions} positions, {study.numerics.contact_model} contact"
    )


def check(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(
        prog=f"{PROG} check",
        description="Validate study-case files and the gear sets they name; nothing is "
        "solved. Exit 0 when every case is valid, 2 otherwise (one line per invalid case).",
    )
    ap.add_argument("cases", nargs="+", help="case names (cases/<name>.toml) or case file paths")
    args = ap.parse_args(argv)
    from studies.run import prepare_study  # the run's own checks before meshing

    status = EXIT_OK
    for name in args.cases:
        try:
            print(_describe(prepare_study(name, Path("results"))[0]))
        except Exception as exc:
            print(f"error: {with_path(one_line(exc), name)}", file=sys.stderr)
            status = max(status, exit_code(exc))
    return status


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] in ("-h", "--help"):
        sys.stdout.write(_usage())
        return EXIT_OK
    if argv and argv[0] == "--version":
        print(f"{PROG} {_version()}")
        return EXIT_OK
    if not argv or argv[0] not in COMMANDS:
        what = f"unknown command {argv[0]!r}" if argv else "no command given"
        sys.stderr.write(_usage() + f"error: {what} (one of: {', '.join(COMMANDS)})\n")
        return EXIT_INVALID_INPUT
    command = {"run": run, "sweep": sweep, "check": check, "report": report}[argv[0]]
    return command(argv[1:])


if __name__ == "__main__":
    sys.exit(main())
