"""What the code hash covers (studies.provenance): every module a position's, a summary's or a
convergence run's numbers pass through, and none of the reports, so that a report change
neither discards finished positions nor marks a recorded convergence study as stale."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from studies import provenance
from studies.provenance import PACKAGES, REPO_ROOT, code_hash, numeric_sources


def test_the_solver_path_is_covered_and_the_reports_are_not():
    names = set(numeric_sources())
    # the physics a position solve runs through and the scalars a convergence run records
    for name in (
        "solvers.gear_train",
        "solvers.root_submodel",
        "solvers.contact_grid",
        "meshing.gear_body",
        "meshing.submodel",
        "gears.involute",
        "gears.iso6336_root",
        "postprocess.train_results",
        "postprocess.mesh_stress",
        "postprocess.run_scalars",
        "studies.position",
        "studies.run",
        "cases.study_case",
        "cases/1-GB.toml",
        "cases/gearsets/case2.toml",
    ):
        assert name in names, name
    # reports, and the reductions of a ladder of runs (applied again to the records' runs by
    # python -m studies.convergence --reduce-records): a fix to them keeps the records' runs
    reports = (
        "studies.convergence.richardson",
        "studies.convergence.reduction",
        "studies.paper.case1_report",
        "studies.convergence.report",
        "postprocess.flank_pictures",
        "studies.benchmarks.submodel",
        "studies.cli",
    )
    for name in reports:
        assert name not in names, name


def test_every_module_a_solve_imports_is_covered():
    """The static closure against what Python really imports: load the compute roots in a
    fresh interpreter and list the pipeline modules in sys.modules. A module reached by a
    path the closure does not see (an import through a variable) would show up here."""
    code = (
        "import dolfinx_solver, sys, json\n"
        f"for m in {provenance.COMPUTE_ROOTS!r}: __import__(m)\n"
        f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {PACKAGES!r})))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    ).stdout
    loaded = set(json.loads(out.strip().splitlines()[-1]))
    assert loaded and loaded <= set(numeric_sources()), loaded - set(numeric_sources())


def test_a_renamed_root_or_driver_is_named(monkeypatch):
    """A root or driver that moved would drop out of the hash unseen: it stops the hash."""
    monkeypatch.setattr(provenance, "DRIVERS", ("studies.run", "studies.moved_away"))
    with pytest.raises(RuntimeError, match=r"'studies\.moved_away' is not found"):
        numeric_sources()


def test_no_import_the_closure_cannot_see():
    """The closure reads import statements; a module imported by name at run time
    (importlib.import_module, __import__) would drop out of the hash unseen."""
    pattern = re.compile(r"import_module\(|__import__\(")
    for pkg in PACKAGES:
        for f in (REPO_ROOT / pkg).rglob("*.py"):
            assert not pattern.search(f.read_text()), f


def test_the_hash_follows_a_covered_module_and_ignores_a_report(tmp_path, monkeypatch):
    """A copy of the packages: editing a report keeps the hash, editing a solver changes it."""
    for pkg in PACKAGES:
        src = REPO_ROOT / pkg
        for f in src.rglob("*"):
            if f.suffix in (".py", ".toml") and "__pycache__" not in f.parts:
                dst = tmp_path / f.relative_to(REPO_ROOT)
                dst.parent.mkdir(parents=True, exist_ok=True)
                dst.write_bytes(f.read_bytes())
    monkeypatch.setattr(provenance, "REPO_ROOT", tmp_path)

    def fresh_hash():
        code_hash.cache_clear()
        return code_hash()

    try:
        base = fresh_hash()
        report = tmp_path / "studies" / "paper" / "case1_report.py"
        report.write_text(report.read_text() + "\n# a report edit\n")
        assert fresh_hash() == base
        solver = tmp_path / "solvers" / "root_submodel.py"
        solver.write_text(solver.read_text() + "\n# a solver edit\n")
        assert fresh_hash() != base
        case = tmp_path / "cases" / "1-GB.toml"
        solver.write_text(solver.read_text().replace("\n# a solver edit\n", ""))
        assert fresh_hash() == base
        case.write_text(case.read_text() + "\n# a case edit\n")
        assert fresh_hash() != base
    finally:
        code_hash.cache_clear()


def test_the_records_stamp_follows_the_clock(monkeypatch):
    """A long process (a ladder, then its record and reproduction) dates each entry when it
    is written, not when the first stamp was asked for."""
    import datetime as dt

    times = iter(
        [
            dt.datetime(2026, 11, 30, 1, 5, tzinfo=dt.UTC),
            dt.datetime(2026, 11, 30, 3, 40, tzinfo=dt.UTC),
        ]
    )

    class Clock(dt.datetime):
        @classmethod
        def now(cls, tz=None):
            return next(times)

    monkeypatch.setattr(provenance.datetime, "datetime", Clock)
    assert provenance.utc_stamp() == "2026-11-30 01:05 UTC"
    assert provenance.utc_stamp() == "2026-11-30 03:40 UTC"
