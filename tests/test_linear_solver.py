"""The bodies' linear solvers (solvers.elastic_body.LinearSolver, ``[numerics]
linear_solver``): block low-rank MUMPS and CG/GAMG give the exact LU's contact solution, a
CG that does not converge is an error, out-of-core factors give the in-core answer and leave
no file behind, and the case file's fields are checked.

The measured speed and memory of the three on the case meshes are in ``make bench-linear``.
"""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import numpy as np
import pytest
from mpi4py import MPI

from cases import study_case
from cases.study_case import CaseError, Numerics
from solvers import elastic_body
from solvers.elastic_body import LinearSolver
from solvers.errors import FactorizationError
from solvers.verification import planetary_scene


def _solve(kind: str, comm=MPI.COMM_WORLD, **solver):
    problem, _ = planetary_scene(
        comm,
        torque=9.0e3,
        k_radial=1e6,
        h_min=0.1,
        degree=1,
        body_options={"linear_solver": LinearSolver(kind, **solver)},
    )
    res = problem.solve()
    rigid = np.array([res.rigid[k] for k in sorted(res.rigid)])
    return problem, np.asarray(res.forces), rigid


@pytest.fixture(scope="module")
def exact():
    return _solve("mumps")


@pytest.mark.parametrize("kind", ["mumps-blr", "cg-gamg"])
def test_inexact_solvers_give_the_exact_contact_solution(exact, kind):
    _, f0, q0 = exact
    _, f, q = _solve(kind)
    # BLR drops off-diagonal block entries below 1e-6 (relative), CG stops at a relative
    # residual of 1e-8; on this well-conditioned 2D body (cond ~1e5) the solution error is
    # below 1e-6 relative. Measured: BLR 0 (fronts too small to compress), CG 9e-9 (forces)
    # and 5e-10 (rigid unknowns).
    assert np.abs(f - f0).max() <= 1e-6 * np.abs(f0).max()
    assert np.abs(q - q0).max() <= 1e-6 * np.abs(q0).max()


def test_blr_is_switched_on_in_mumps():
    problem, _, _ = _solve("mumps-blr")
    for body in problem.bodies.values():
        F = body.ksp.getPC().getFactorMatrix()
        assert F.getMumpsIcntl(35) == 2  # BLR in factorization and solve
        assert F.getMumpsCntl(7) == pytest.approx(1e-6)


def test_a_cg_that_does_not_converge_is_an_error():
    problem, _ = planetary_scene(
        MPI.COMM_WORLD,
        torque=9.0e3,
        k_radial=1e6,
        h_min=0.1,
        degree=1,
        body_options={
            "linear_solver": LinearSolver("cg-gamg", 1e-14),
            "petsc_options": {"ksp_max_it": 2},
        },
    )
    with pytest.raises(FactorizationError, match="did not converge"):
        problem.solve()


def test_the_case_file_and_the_solver_know_the_same_solvers():
    assert study_case.LINEAR_SOLVERS == elastic_body.LINEAR_SOLVERS


def _ooc_solve(comm, tmp, monkeypatch):
    monkeypatch.setenv("PLANETARY_OOC_DIR", str(tmp))
    problem, f, q = _solve("mumps", comm, out_of_core=True)
    for body in problem.bodies.values():
        assert body.ksp.getPC().getFactorMatrix().getMumpsIcntl(22) == 1  # factors on disk
    # every body wrote its factor files (this rank's) in its own folder under the root
    folders = [p for p in tmp.iterdir() if p.is_dir()]
    assert len(folders) == len(problem.bodies)
    assert all(any(p.iterdir()) for p in folders)
    for body in problem.bodies.values():
        body.release()
    comm.Barrier()
    return f, q


def _same_solution(f, q, f0, q0):
    # the same LU, its factors read back from disk: the same answer to round-off (measured
    # 2e-14 relative on one rank)
    assert np.abs(f - f0).max() <= 1e-10 * np.abs(f0).max()
    assert np.abs(q - q0).max() <= 1e-10 * np.abs(q0).max()


def test_out_of_core_factors_give_the_in_core_answer_and_are_removed(exact, tmp_path, monkeypatch):
    _, f0, q0 = exact
    f, q = _ooc_solve(MPI.COMM_WORLD, tmp_path, monkeypatch)
    _same_solution(f, q, f0, q0)
    assert not any(tmp_path.iterdir())  # release() removed every body's folder


def test_an_out_of_core_body_never_released_closes_its_factors_cleanly(tmp_path, monkeypatch):
    """A body collected without release() (or still held at exit) destroys its MUMPS solver
    before its folder goes: removing the folder first made MUMPS report INFOG(1) = -90 from
    the solver's destructor at every exit of a study run out of core."""
    import gc
    import sys

    monkeypatch.setenv("PLANETARY_OOC_DIR", str(tmp_path))
    problem, _, _ = _solve("mumps", out_of_core=True)
    assert any(tmp_path.iterdir())
    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)
    del problem
    gc.collect()
    assert unraisable == [] and not any(tmp_path.iterdir())


@pytest.mark.mpi
def test_out_of_core_on_two_ranks_gives_the_serial_answer(tmp_path_factory, monkeypatch):
    comm = MPI.COMM_WORLD
    tmp = tmp_path_factory.mktemp(f"ooc{comm.rank}")  # one folder per rank
    _, f0, q0 = _solve("mumps", comm)
    f, q = _ooc_solve(comm, tmp, monkeypatch)
    _same_solution(f, q, f0, q0)
    assert not any(tmp.iterdir())


def test_bench_runs_the_lu_out_of_core_as_a_solver():
    from studies.benchmarks.linear import _solver_numerics, _tolerance

    num = _solver_numerics("mumps-blr+ooc", {"mumps-blr": 1e-7})
    assert num == {"linear_solver": "mumps-blr", "linear_tolerance": 1e-7, "out_of_core": True}
    assert Numerics(**num).out_of_core and _tolerance("mumps+ooc", None) is None
    assert _solver_numerics("mumps", {})["out_of_core"] is False


def test_bench_refuses_an_iterative_solver_out_of_core(capsys, tmp_path):
    from studies.benchmarks.linear import main

    with pytest.raises(SystemExit) as stop:  # argparse's usage error
        main(["--solvers", "cg-gamg+ooc", "--out", str(tmp_path)])
    assert stop.value.code == 2 and "invalid choice: 'cg-gamg+ooc'" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


@pytest.mark.mpi
def test_an_out_of_core_folder_one_rank_cannot_make_fails_every_rank(tmp_path_factory, monkeypatch):
    """Rank 1 alone is given a folder under a file: every rank raises the same error instead
    of rank 0 waiting in the factorization for a rank that stopped."""
    comm = MPI.COMM_WORLD
    if comm.size < 2:
        pytest.skip("needs a second rank to fail alone")
    tmp = tmp_path_factory.mktemp(f"bad{comm.rank}")
    if comm.rank == 1:
        (tmp / "file").write_text("not a folder")
        monkeypatch.setenv("PLANETARY_OOC_DIR", str(tmp / "file" / "ooc"))
    else:
        monkeypatch.setenv("PLANETARY_OOC_DIR", str(tmp))
    with pytest.raises(FactorizationError, match="no folder for its out-of-core factors"):
        _solve("mumps", comm, out_of_core=True)
    assert not any(p.is_dir() for p in tmp.iterdir())  # rank 0's folder removed again


def test_out_of_core_needs_factors():
    with pytest.raises(ValueError, match="no factors to keep out of core"):
        LinearSolver("cg-gamg", out_of_core=True)
    assert LinearSolver("mumps-blr", out_of_core=True).tolerance == 1e-6


def test_out_of_core_is_not_an_input_of_the_run():
    """Where the factors are kept does not change the answer, so it is not in the inputs
    hash that keys stored results (a run solved in core serves one asked out of core)."""
    from dataclasses import replace

    from cases.study_case import inputs_hash, load_study_case

    study = load_study_case("1-GA")
    ooc = replace(study, numerics=replace(study.numerics, out_of_core=True))
    assert inputs_hash(ooc) == inputs_hash(study)
    other = replace(study, numerics=replace(study.numerics, penalty_factor=10.0))
    assert inputs_hash(other) != inputs_hash(study)


@pytest.mark.parametrize(
    "fields, words",
    [
        ({"out_of_core": 1}, "numerics.out_of_core = 1: must be true or false"),
        ({"out_of_core": True, "linear_solver": "cg-gamg"}, "'cg-gamg' has no factors"),
        ({"linear_solver": "lu"}, "numerics.linear_solver = 'lu': must be one of"),
        ({"linear_tolerance": 1e-6}, "'mumps' is exact and takes no tolerance"),
        ({"linear_solver": "cg-gamg", "linear_tolerance": 0.1}, "must be a number in"),
        ({"linear_solver": "cg-gamg", "linear_tolerance": "tight"}, "must be a number in"),
    ],
)
def test_bad_linear_solver_fields_name_the_field(fields, words):
    with pytest.raises(CaseError, match=words):
        Numerics(**fields)


def test_default_tolerances():
    assert Numerics().linear_tolerance is None
    assert LinearSolver("mumps").tolerance is None
    assert LinearSolver("mumps-blr").tolerance == 1e-6
    assert LinearSolver("cg-gamg").tolerance == 1e-8
    with pytest.raises(ValueError, match="no tolerance"):
        LinearSolver("mumps", 1e-6)


@pytest.mark.mpi
def test_cg_gamg_on_two_ranks_gives_the_exact_solution():
    comm = MPI.COMM_WORLD
    _, f0, q0 = _solve("mumps", comm)
    _, f, q = _solve("cg-gamg", comm)
    # as the serial test: the CG residual 1e-8 bounds the error far below 1e-6; the
    # aggregation differs with the partition, the tolerance does not
    assert np.abs(f - f0).max() <= 1e-6 * np.abs(f0).max()
    assert np.abs(q - q0).max() <= 1e-6 * np.abs(q0).max()


def test_bench_reports_changes_above_the_noise_floor():
    from studies.benchmarks.linear import _changes

    ref = {
        "scalars": {
            "My_pin": 200.0,
            "Mx_pin": 10.0,
            "M_LOA_sun": 90.0,
            "M_LOA_ring": -80.0,
            "Mz_pin": 1e-9,
            "bending_stress.sun": 500.0,
            "label": "x",
        }
    }
    row = {"scalars": {**ref["scalars"], "My_pin": 202.0, "Mz_pin": 3e-9}}
    ch = _changes(row, ref)
    assert ch["My_pin"] == pytest.approx(0.01)
    assert ch["bending_stress.sun"] == 0.0
    assert "Mz_pin" not in ch  # zero by construction: round-off, not a change
    assert "label" not in ch


def test_bench_reports_a_double_pinion_case():
    """The moments of a double-pinion case (My_SP, M_LOA_RP_ring, ...) are found by kind, not
    by a single-pinion name list (the 2B-GA bench once stopped on an empty list)."""
    from studies.benchmarks.linear import _changes, _md

    ref = {
        "scalars": {
            "My_SP": 92.0,
            "Mx_RP": 96.0,
            "M_LOA_RP_ring": -162.0,
            "Mz_SP": 1e-13,
            "bending_stress.ring": 520.0,
        }
    }
    row = {"scalars": {**ref["scalars"], "Mx_RP": 96.96, "bending_stress.ring": 520.52}}
    ch = _changes(row, ref)
    assert ch["Mx_RP"] == pytest.approx(0.01) and "Mz_SP" not in ch
    t = {"factorization": 1.0, "compliance": 1.0, "total": 2.0}
    runs = [
        {
            "level": 1,
            "solver": "mumps",
            "tolerance": None,
            "dofs": 9,
            "time_s": t,
            "peak_rss_mb": 1024.0,
        },
        {
            "level": 1,
            "solver": "mumps+ooc",
            "tolerance": None,
            "dofs": 9,
            "time_s": t,
            "peak_rss_mb": 512.0,
            "change": ch,
        },
    ]
    text = _md("2B-GA", runs)
    assert "| 1 | mumps+ooc | - | 9 | 1.0 | 1.0 | 2.0 | 0.50 | 1.0e-02 | 1.0e-02 |" in text


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--tolerances", "mumps:1e-6"], "'mumps' is exact"),
        (["--tolerances", "mumps-blr=1e-6"], "give SOLVER:VALUE"),
        (["--levels", "9"], "level = 9"),
    ],
)
def test_bench_refuses_bad_input_before_any_run(argv, words, capsys, tmp_path):
    from studies.benchmarks.linear import main

    assert main([*argv, "--out", str(tmp_path)]) == 2
    assert words in capsys.readouterr().err
    assert not (tmp_path / "linear_solver.json").exists()
