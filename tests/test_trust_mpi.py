"""MPI-safe failure of the study driver (run by ``make test-mpi`` under ``mpiexec -n 2``).

Issue 15: under ``mpiexec -n 2`` an error on rank 0 only (output folder not writable, disk
full) hung the job until it was killed. Here one rank fails, before any FE solve (the solver
is the stub of tests/test_trust_driver.py), and every rank must end with the same error. A
watchdog aborts the job if a test does not finish in ``DEADLINE_S`` seconds, so a hang is a
failure, not a stuck CI job. (A rank that fails while the others are inside a collective
call is tested in test_trust_driver.py, in a job of its own: it ends with MPI_Abort.)
"""

import errno
import json
import os
import sys
import threading
from pathlib import Path

import pytest
from mpi4py import MPI
from test_trust_driver import Stub

from studies import run as study_run
from studies.case_options import CaseOptions
from studies.cli import StudyFailed
from studies.files import ResultFileError

COMM = MPI.COMM_WORLD
# Each test needs about a second (stubbed solves); 60 s means something waits for ever.
DEADLINE_S = 60.0


@pytest.fixture
def deadline():
    def expire():
        sys.stderr.write(f"rank {COMM.rank}: test did not finish in {DEADLINE_S} s: a hang\n")
        sys.stderr.flush()
        COMM.Abort(9)

    timer = threading.Timer(DEADLINE_S, expire)
    timer.daemon = True
    timer.start()
    yield
    timer.cancel()


@pytest.fixture
def shared_tmp(tmp_path):
    """One folder for every rank (rank 0's pytest tmp_path)."""
    return Path(COMM.bcast(str(tmp_path), root=0))


@pytest.fixture
def stub(monkeypatch, shared_tmp):
    s = Stub()
    s.out = shared_tmp / "out" / "1-GA"
    monkeypatch.setattr(study_run, "solve_position", s)
    monkeypatch.setattr(study_run, "draw_contact_patterns", lambda *a: None)
    monkeypatch.setattr(study_run, "loaded_scene_picture", lambda *a: None)
    return s


def _raised_everywhere(exc: BaseException) -> str:
    """The message of ``exc``, checked to be the same on every rank."""
    text = f"{type(exc).__name__}: {exc}"
    assert COMM.allgather(text) == [text] * COMM.size
    return text


@pytest.mark.mpi
def test_rank0_disk_full_ends_every_rank(stub, shared_tmp, monkeypatch, deadline):
    """Rank 0 alone writes the position files; the disk fills at position 2. Every rank
    raises the same error naming the file, and position 1 is on disk."""
    real = study_run.write_json

    def full(path, data):
        if Path(path).name == "1.json":
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        real(path, data)

    if COMM.rank == 0:
        monkeypatch.setattr(study_run, "write_json", full)
    with pytest.raises(ResultFileError) as err:
        study_run.run_study(
            "1-GA", shared_tmp / "out", options=CaseOptions(level=0, positions=2), comm=COMM
        )
    text = _raised_everywhere(err.value)
    assert "No space left on device" in text and "positions/1.json" in text
    assert (stub.out / "positions" / "0.json").is_file()
    assert not (stub.out / "summary.json").exists()


@pytest.mark.mpi
def test_output_folder_is_a_file_on_every_rank(stub, shared_tmp, deadline):
    if COMM.rank == 0:
        (shared_tmp / "out").write_text("a file")
    COMM.barrier()
    with pytest.raises(ResultFileError) as err:
        study_run.run_study(
            "1-GA", shared_tmp / "out", options=CaseOptions(level=0, positions=1), comm=COMM
        )
    assert "is a file, not a folder" in _raised_everywhere(err.value)
    assert stub.rolls == []


@pytest.mark.mpi
def test_solve_error_on_one_rank_is_shared(stub, shared_tmp, deadline):
    """A PETSc/DOLFINx error raised on rank 1 only, in position 2: every rank records the
    same failed position (rank 0 solved it fine, its result is dropped), writes the same
    summary with position 1, and raises the same StudyFailed."""
    if COMM.rank == COMM.size - 1:
        stub.fail_calls = {1}
    with pytest.raises(StudyFailed) as err:
        study_run.run_study(
            "1-GA", shared_tmp / "out", options=CaseOptions(level=0, positions=2), comm=COMM
        )
    text = _raised_everywhere(err.value)
    assert "1 of 2 positions failed" in text and "active set did not converge" in text
    summary = json.loads((stub.out / "summary.json").read_text())
    assert [p["roll"] for p in summary["positions"]] == [0.0]
    assert summary["failed_positions"][0]["position"] == 1
    assert not (stub.out / "positions" / "1.json").exists()


@pytest.mark.mpi
def test_exit_code_and_one_message_from_rank_0(stub, shared_tmp, capsys, deadline):
    code = study_run.main(["1-GA", "--positions", "0", "--out", str(shared_tmp / "out")])
    assert COMM.allgather(code) == [2] * COMM.size
    err = capsys.readouterr().err
    if COMM.rank == 0:
        assert err.startswith("error: 1-GA: --positions 0") and err.count("\n") == 1
    else:
        assert err == ""
